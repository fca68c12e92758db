//! `hydroid calibrate OUTDIR`: the parametric bootstrap of an output folder's run
//! (docs/calibrate.md): replicas of every fitted run made from the identified model with
//! the run's own noise, identified again, their spread against the reported sigmas.

use super::{warning, CmdResult, Say};
use crate::app::calibrate::{self, write, Calibration, Settings};
use crate::app::pipeline::{self, Scope};
use crate::app::report;
use crate::app::results::RunOutput;
use crate::base::error::Error;
use crate::base::progress::Silent;
use crate::io::output::Claim;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Check the reported sigmas of a run: make replicas of every fitted run from the
/// identified model with the runs' own noise, identify each again with the run's settings,
/// and compare their spread with the reported sigmas (calibration.json and calibration.md
/// in the output folder).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// An output folder written by `hydroid run`, unchanged since.
    outdir: PathBuf,
    /// Number of replicas.
    #[arg(long, default_value_t = calibrate::DEFAULT_REPLICAS as u32, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    replicas: u32,
    /// Seed of replica 0 (replica k uses SEED + k): the same seed gives the same output.
    #[arg(long, default_value_t = calibrate::DEFAULT_SEED)]
    seed: u64,
    /// Print calibration.json on stdout instead of the table.
    #[arg(long)]
    pub(super) json: bool,
    /// Exit with status 3 when the check fails (a coefficient's spread outside 0.67-1.5
    /// reported sigmas by more than its own uncertainty, a replica more than 5 sigmas off,
    /// or the 2-sigma coverage below 90 %). The files are written as without it.
    #[arg(long)]
    strict: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    crate::io::output::clean_up_on_signals()?;
    let dir = &args.outdir;
    let claim = Claim::open(dir, "calibrate", super::rerun::READ)?;
    let (loaded, _) = super::rerun::load_recorded(dir, false, false)?;
    let inputs = pipeline::load_inputs(&loaded, pipeline::stage_inputs(&loaded.config))?;
    let original = pipeline::run_on(&loaded, &inputs, &mut Silent, Scope::Full)?;
    check_matches(dir, &original)?;
    let settings = Settings {
        replicas: args.replicas as usize,
        seed: args.seed,
    };
    say.note(&format!(
        "calibrate: {} replicas of {}",
        settings.replicas,
        dir.display()
    ));
    // a line at every tenth of the replicas (the count, not the order, is certain)
    let step = (settings.replicas / 10).max(1);
    let done = |k: usize| {
        if k.is_multiple_of(step) || k == settings.replicas {
            say.note(&format!(
                "calibrate: {k} of {} replicas identified",
                settings.replicas
            ));
        }
    };
    let cal = calibrate::calibrate(&loaded, &inputs, &original, settings, &done)?;
    write::write(&claim, &cal)?;
    if args.json {
        out.write_all(&crate::io::output::to_json(&cal)?)?;
        writeln!(out)?;
    } else {
        print_table(out, &cal)?;
    }
    for w in &cal.warnings {
        warning(&format!("{} ({})", w.message, w.meaning));
    }
    Ok(super::warnings::exit_status(args.strict, &cal.warnings))
}

fn print_table(out: &mut impl Write, cal: &Calibration) -> std::io::Result<()> {
    writeln!(
        out,
        "{} replicas, {} identified, {} failed",
        cal.replicas,
        cal.converged,
        cal.failed.len()
    )?;
    write!(out, "{}", write::table(cal))?;
    if !cal.settings.variants.is_empty() {
        writeln!(
            out,
            "\nsettings: {} variants (inputs read the other way, runs left out)",
            cal.settings.variants.len()
        )?;
        write!(out, "{}", write::settings_table(cal))?;
    }
    Ok(())
}

/// Refuses a folder whose results.json does not hold the coefficients its configuration
/// gives now (another hydroid version wrote it): the replicas would not check those.
fn check_matches(dir: &Path, original: &RunOutput) -> crate::Result<()> {
    let path = dir.join(report::RESULTS_JSON);
    let text = crate::config::read(&path)?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        Error::Usage(format!(
            "{}: not a hydroid results file: {e}",
            path.display()
        ))
    })?;
    let recorded = json["coefficients"].as_array().cloned().unwrap_or_default();
    for c in &original.result.coefficients {
        let value = recorded
            .iter()
            .find(|r| r["name"] == c.name.as_str())
            .and_then(|r| r["value"].as_f64());
        let same = value.is_some_and(|v| (v - c.value).abs() <= 1e-9 * c.value.abs().max(1e-300));
        if !same {
            return Err(Error::Usage(format!(
                "{}: {} is {}, but identifying the folder's config.toml again gives {}: the \
                 folder was written by another hydroid; `hydroid rerun {}` first",
                path.display(),
                c.name,
                value.map_or_else(|| "missing".to_string(), |v| v.to_string()),
                c.value,
                dir.display()
            )));
        }
    }
    Ok(())
}
