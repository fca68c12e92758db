//! `hydroid manoeuvre CONFIG`: the turning-circle or zig-zag measures of every HEKF run of a
//! configuration (fit and validation runs, read as the run reads them), with the IMO criteria
//! when the full-scale length and speed are known (docs/manoeuvres.md).

use super::CmdResult;
use hydroid::manoeuvre::{self, ComparisonTable};
use hydroid::record::Record;
use hydroid::{config, pipeline, Error};
use std::io::Write;
use std::path::PathBuf;

/// Turning-circle or zig-zag measures of the HEKF runs of a configuration.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration whose `hekf.runs` and `hekf.validation` are measured.
    config: PathBuf,
    /// Override a configuration key, e.g. `--set hekf.runs[0].columns.rudder.scale=-1`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Scale ratio lambda of model-scale runs (1 for full-scale data): the IMO criteria are
    /// judged at full scale (distances in ship lengths; overshoot limits at the full-scale
    /// L/V, sqrt(lambda) times the run's).
    #[arg(long, value_name = "LAMBDA")]
    scale: Option<f64>,
    /// Print machine-readable JSON instead of text.
    #[arg(long)]
    json: bool,
}

/// What one run gave.
#[derive(Debug, serde::Serialize)]
struct RunMeasures {
    run: String,
    file: String,
    #[serde(flatten)]
    measures: manoeuvre::RunMeasures,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    if let Some(l) = args.scale {
        if !(l.is_finite() && l >= 1.0) {
            return Err(Error::Usage(format!(
                "--scale must be a scale ratio of at least 1 (1 for full scale), got {l}"
            ))
            .into());
        }
    }
    let loaded = config::load(&args.config, &args.set)?;
    let planned = pipeline::stage_inputs(&loaded.config);
    let runs: Vec<_> = planned
        .hekf_fit
        .iter()
        .chain(&planned.hekf_validation)
        .collect();
    if runs.is_empty() {
        return Err(Error::Usage(format!(
            "{}: no [hekf] runs to measure (hydroid manoeuvre reads `hekf.runs` and \
             `hekf.validation`)",
            args.config.display()
        ))
        .into());
    }
    let length = loaded.config.vehicle.length;
    let scale = args.scale.or(loaded.config.vehicle.scale);
    let mut all = Vec::new();
    for p in runs {
        let input = pipeline::load_input(&loaded, p)?;
        all.push(measure(&input.record, length, scale)?);
    }
    if args.json {
        let text = serde_json::to_string_pretty(&all)
            .map_err(|e| Error::Usage(format!("cannot write the measures as JSON: {e}")))?;
        writeln!(out, "{text}")?;
        return Ok(0);
    }
    for m in &all {
        let measures = m.measures.measures();
        if measures.is_empty() {
            continue;
        }
        writeln!(out, "{} ({}): {}", m.run, m.file, m.measures.kind())?;
        let table = ComparisonTable::new(&measures, None, &m.measures.checks, &[]);
        writeln!(out, "{table}")?;
    }
    if scale.is_none() {
        writeln!(
            out,
            "10/10 zig-zag overshoot limits not judged: they depend on the full-scale L/V; give \
             --scale or vehicle.scale (1 for full-scale data)"
        )?;
    }
    Ok(0)
}

/// The measures of one run (a zig-zag when its rudder reverses at least twice, else a
/// turning circle).
fn measure(rec: &Record, length: f64, scale: Option<f64>) -> Result<RunMeasures, Error> {
    let fail = |e: manoeuvre::HistoryError| {
        Error::Usage(format!(
            "run '{}' ({}): {e}",
            rec.name,
            rec.source.display()
        ))
    };
    let h = manoeuvre::history_of(|q| rec.channel(q).map(<[f64]>::to_vec))
        .map_err(fail)?
        .ok_or_else(|| {
            Error::Usage(format!(
                "run '{}' ({}): the measures need the time and the heading (yaw) of the run",
                rec.name,
                rec.source.display()
            ))
        })?;
    Ok(RunMeasures {
        run: rec.name.clone(),
        file: rec.source.display().to_string(),
        measures: manoeuvre::measure_history(&h, length, scale).map_err(fail)?,
    })
}
