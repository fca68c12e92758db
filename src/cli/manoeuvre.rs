//! `hydroid manoeuvre CONFIG`: the turning-circle or zig-zag measures of every HEKF run of a
//! configuration (fit and validation runs, read as the run reads them), with the IMO criteria
//! when the full-scale length and speed are known (docs/manoeuvres.md).

use super::CmdResult;
use hydroid::manoeuvre::{self, ComparisonTable, History, Ship, TurningOptions, ZigZagOptions};
use hydroid::quantity::Quantity;
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
    #[serde(skip_serializing_if = "Option::is_none")]
    turning_circle: Option<manoeuvre::TurningCircle>,
    #[serde(skip_serializing_if = "Option::is_none")]
    zigzag: Option<manoeuvre::ZigZag>,
    checks: Vec<manoeuvre::Check>,
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
    let mut all = Vec::new();
    for p in runs {
        let input = pipeline::load_input(&loaded, p)?;
        all.push(measure(&input.record, length, args.scale)?);
    }
    if args.json {
        let text = serde_json::to_string_pretty(&all)
            .map_err(|e| Error::Usage(format!("cannot write the measures as JSON: {e}")))?;
        writeln!(out, "{text}")?;
        return Ok(0);
    }
    for m in &all {
        let (kind, measures) = match (&m.turning_circle, &m.zigzag) {
            (_, Some(z)) => ("zig-zag", z.measures()),
            (Some(t), None) => ("turning circle", t.measures()),
            (None, None) => continue,
        };
        writeln!(out, "{} ({}): {kind}", m.run, m.file)?;
        let table = ComparisonTable::new(&measures, None, &m.checks, &[]);
        writeln!(out, "{table}")?;
    }
    if args.scale.is_none() {
        writeln!(
            out,
            "IMO criteria not checked: give --scale (1 for full-scale data) so that they are \
             judged at full scale"
        )?;
    }
    Ok(0)
}

/// The measures of one run: a zig-zag when its rudder reverses at least twice, else a
/// turning circle.
fn measure(rec: &Record, length: f64, scale: Option<f64>) -> Result<RunMeasures, Error> {
    let fail = |e: manoeuvre::HistoryError| {
        Error::Usage(format!(
            "run '{}' ({}): {e}",
            rec.name,
            rec.source.display()
        ))
    };
    let column = |q: Quantity| rec.channel(q).map(<[f64]>::to_vec);
    let (Some(time), Some(heading)) = (column(Quantity::Time), column(Quantity::Yaw)) else {
        return Err(Error::Usage(format!(
            "run '{}' ({}): the measures need the time and the heading (yaw) of the run",
            rec.name,
            rec.source.display()
        )));
    };
    let mut h = History::new(time, heading).map_err(fail)?;
    if let (Some(x), Some(y)) = (column(Quantity::X), column(Quantity::Y)) {
        h = h.with_track(x, y).map_err(fail)?;
    }
    if let (Some(u), Some(v)) = (column(Quantity::U), column(Quantity::V)) {
        h = h.with_velocity(u, v).map_err(fail)?;
    }
    let rudder = column(Quantity::Rudder);
    let reversals = rudder.as_deref().map_or(0, reversals);
    if let Some(r) = rudder {
        h = h.with_rudder(r).map_err(fail)?;
    }
    // The criteria in lengths (advance <= 4.5 L ...) are Froude-invariant and are judged on
    // the run's own scale; those in L/V (the overshoot limits) need the full-scale
    // L/V = sqrt(lambda) L/U: a ship of the run's length at speed U / sqrt(lambda) has it.
    let ship = |u: Option<f64>| {
        let (lambda, u) = (scale?, u?);
        Ship::new(length, u / lambda.sqrt()).ok()
    };
    let mut m = RunMeasures {
        run: rec.name.clone(),
        file: rec.source.display().to_string(),
        turning_circle: None,
        zigzag: None,
        checks: Vec::new(),
    };
    if reversals >= 2 {
        let z = manoeuvre::zigzag(&h, &ZigZagOptions::default()).map_err(fail)?;
        if let Some(s) = ship(z.approach_speed.value()) {
            m.checks = manoeuvre::imo::zigzag_checks(&z, &s);
        }
        m.zigzag = Some(z);
    } else {
        let t = manoeuvre::turning_circle(&h, &TurningOptions::default()).map_err(fail)?;
        if let Some(s) = ship(t.approach_speed.value()) {
            m.checks = manoeuvre::imo::turning_checks(&t, &s);
        }
        m.turning_circle = Some(t);
    }
    Ok(m)
}

/// How often the rudder changes side (sign, ignoring amidships).
fn reversals(rudder: &[f64]) -> usize {
    let mut last = 0.0f64;
    let mut n = 0;
    for &d in rudder {
        if d.abs() < 1e-6 {
            continue;
        }
        if last != 0.0 && d.signum() != last.signum() {
            n += 1;
        }
        last = d;
    }
    n
}
