//! `hydroid manoeuvre CONFIG`: the turning-circle or zig-zag measures of every HEKF run of a
//! configuration (fit and validation runs, read as the run reads them), at the nominal angles
//! given (`--rudder`, `--check`, or a run's `manoeuvre` key) or inferred from each run, with
//! the IMO criteria when the full-scale length and speed are known (docs/manoeuvres.md).

use super::CmdResult;
use crate::app::pipeline;
use crate::dynamics::manoeuvre::{self, ComparisonTable, Nominal};
use crate::io::record::Record;
use crate::{config, Error};
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
    /// Nominal rudder angle of every run, deg (35 for a 35 deg turning circle, 20 for a 20/10
    /// zig-zag), over a run's `manoeuvre.rudder`; by default each run's, else inferred from
    /// the run.
    #[arg(long, value_name = "DEG")]
    rudder: Option<f64>,
    /// Nominal check (execute heading) angle of every zig-zag, deg (10 for a 20/10), over a
    /// run's `manoeuvre.check`; by default each run's, else inferred from the run.
    #[arg(long, value_name = "DEG")]
    check: Option<f64>,
    /// Print machine-readable JSON instead of text.
    #[arg(long)]
    pub(super) json: bool,
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
        config::check_scale(l).map_err(|m| Error::Usage(format!("--scale {l}: {m}")))?;
    }
    let given = Nominal {
        rudder: nominal_option("--rudder", args.rudder)?,
        check: nominal_option("--check", args.check)?,
    };
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
        let configured = p
            .spec
            .manoeuvre
            .as_ref()
            .map(crate::dynamics::manoeuvre::Nominal::given);
        let nominal = given.or(configured.unwrap_or_default());
        all.push(measure(&input.record, length, scale, nominal)?);
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
        let table = ComparisonTable::new(&measures, None, &m.measures.checks, &[])
            .with_notes(m.measures.notes("measured"));
        writeln!(out, "{table}")?;
    }
    Ok(0)
}

/// A nominal angle given on the command line (deg) in rad; a usage error unless above 0 and
/// at most 90 deg.
fn nominal_option(name: &str, deg: Option<f64>) -> Result<Option<f64>, Error> {
    match deg {
        None => Ok(None),
        Some(d) if d.is_finite() && d > 0.0 && d <= 90.0 => Ok(Some(d.to_radians())),
        Some(d) => Err(Error::Usage(format!(
            "{name} must be an angle in degrees above 0 and at most 90, got {d}"
        ))),
    }
}

/// The measures of one run (a zig-zag when its rudder reverses at least twice, else a
/// turning circle) at the `nominal` angles given.
fn measure(
    rec: &Record,
    length: f64,
    scale: Option<f64>,
    nominal: Nominal,
) -> Result<RunMeasures, Error> {
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
        measures: manoeuvre::measure_history(&h, length, scale, nominal).map_err(fail)?,
    })
}
