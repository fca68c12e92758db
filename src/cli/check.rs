//! `hydroid check CONFIG`: validate a configuration and every input it names.

use super::CmdResult;
use hydroid::error::Error;
use hydroid::{config, pipeline};
use std::io::Write;
use std::path::PathBuf;

/// Validate the configuration and every input file it names; print what would run.
///
/// Every problem is listed, not only the first. Exit code 2 when the configuration has
/// problems, 1 when only input files do, 0 when all is well.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration (TOML).
    config: PathBuf,
    /// Override a configuration key, e.g. `--set hekf.passes=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let text = config::read(&args.config)?;
    let (loaded, mut config_problems) = config::load_lenient(&args.config, &text, &args.set);
    let mut input_problems = Vec::new();
    let mut usable = Vec::new();
    if let Some(l) = &loaded {
        let c = &l.config;
        writeln!(out, "configuration: {}", l.path.display())?;
        if let Some(t) = &c.title {
            writeln!(out, "title: {t}")?;
        }
        if l.touches_unusable("vehicle") {
            writeln!(out, "vehicle: (see the problems below)")?;
        } else {
            writeln!(
                out,
                "vehicle: {} (m = {} kg, L = {} m, A_ref = {} m^2, L_ref = {} m)",
                c.vehicle.name,
                c.vehicle.mass,
                c.vehicle.length,
                c.vehicle.reference_area,
                c.vehicle.reference_length
            )?;
        }
        let stages = c.enabled_stages();
        writeln!(
            out,
            "stages: {}",
            if stages.is_empty() {
                "none enabled".to_string()
            } else {
                stages.join(" -> ")
            }
        )?;
        if let Some(h) = c.hekf.as_ref().filter(|h| h.enabled) {
            writeln!(
                out,
                "hekf: {} model, {} preset, estimating {}",
                h.model,
                h.preset,
                h.estimate.join(", ")
            )?;
        }
        writeln!(out, "inputs:")?;
        for (key, spec, needs) in pipeline::stage_inputs(c) {
            if l.touches_unusable(&key) {
                // a key of this input could not be used: already a configuration problem
                writeln!(out, "  {key}: not read (its configuration has a problem)")?;
                continue;
            }
            let full = l.resolve(&spec.file);
            if !full.is_file() {
                // already a configuration problem
                writeln!(out, "  {key}: {} (missing)", spec.file.display())?;
                continue;
            }
            match pipeline::load_input(l, &key, spec, &needs) {
                Ok(li) => {
                    let r = &li.record;
                    let span = r
                        .time()
                        .and_then(|t| Some(format!(", t = {} .. {} s", t.first()?, t.last()?)))
                        .unwrap_or_default();
                    let qs: Vec<String> = r
                        .units
                        .iter()
                        .map(|(q, u)| format!("{q} [{u}]"))
                        .chain(
                            r.constants
                                .iter()
                                .map(|(q, v)| format!("{q} = {v} (constant)")),
                        )
                        .collect();
                    writeln!(
                        out,
                        "  {key}: {} ({}, {} rows{span})\n      {}",
                        spec.file.display(),
                        r.format,
                        r.rows(),
                        qs.join(", ")
                    )?;
                    for w in &r.warnings {
                        writeln!(out, "      warning: {w}")?;
                    }
                    usable.push(li);
                }
                Err(e) => {
                    writeln!(out, "  {key}: {} (cannot be used)", spec.file.display())?;
                    input_problems.push(e);
                }
            }
        }
    }
    // the stage checks need every key usable: with a placeholder they would mislead
    if let Some(l) = loaded.as_ref().filter(|l| l.unusable.is_empty()) {
        config_problems.extend(pipeline::preflight(l, &usable));
    }
    if config_problems.is_empty() && input_problems.is_empty() {
        writeln!(out, "ok: the configuration and every input are usable")?;
        return Ok(0);
    }
    let total = config_problems.len() + input_problems.len();
    eprintln!(
        "{total} problem{} found:",
        if total == 1 { "" } else { "s" }
    );
    for p in &config_problems {
        eprintln!("  - {p}");
    }
    for e in &input_problems {
        eprintln!("  - {e}");
    }
    let code = if config_problems.is_empty() {
        Error::numerical("check", "").exit_code()
    } else {
        Error::Config(Vec::new()).exit_code()
    };
    Ok(code)
}
