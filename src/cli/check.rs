//! `hydroid check CONFIG`: validate a configuration and every input it names.

use super::{json, CmdResult};
use hydroid::error::Error;
use hydroid::results::{InputSummary, LoadedInput};
use hydroid::{config, pipeline};
use serde_json::{json, Value};
use std::io::Write;
use std::path::PathBuf;

/// Validate the configuration and every input file it names; print what would run.
///
/// Every problem is listed, not only the first, and the plausibility checks' warnings about
/// the runs. Exit code 2 when the configuration has problems (a clear mistake the
/// plausibility checks find in a run is one), 1 when only input files do, 0 when all is
/// well (warnings or not).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration (TOML).
    config: PathBuf,
    /// Override a configuration key, e.g. `--set hekf.passes=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// The output folder `run --out DIR` would write, checked as run checks it (default:
    /// `output.dir` of the configuration).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print machine-readable JSON on stdout: what would run, every input, and the problems
    /// as {file, line, column, key, message}; the exit code is the same.
    #[arg(long)]
    pub(super) json: bool,
}

/// Runs the command.
pub fn run(args: Args, stdout: &mut impl Write) -> CmdResult {
    let text = config::read(&args.config)?;
    let (loaded, mut config_problems) = config::load_lenient(&args.config, &text, &args.set);
    let mut input_problems = Vec::new();
    let mut usable = pipeline::InputsByStage::default();
    // the text is printed at the end, unless --json prints JSON instead
    let mut text = Vec::new();
    let out = &mut text;
    let mut inputs_json = Vec::new();
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
        usable = pipeline::stage_inputs(c)
            .try_map(|p| -> std::io::Result<Option<LoadedInput>> {
                let (key, spec) = (p.key.clone(), p.spec);
                if l.touches_unusable(&key) {
                    // a key of this input could not be used: already a configuration problem
                    writeln!(out, "  {key}: not read (its configuration has a problem)")?;
                    return Ok(None);
                }
                let full = l.resolve(&spec.file);
                if hydroid::formats::input::check_regular(&full).is_err() {
                    // already a configuration problem
                    writeln!(out, "  {key}: {} (missing)", spec.file.display())?;
                    inputs_json.push(json!({ "key": key, "file": spec.file, "status": "missing" }));
                    return Ok(None);
                }
                match pipeline::load_input(l, &p) {
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
                        let mut summary =
                            serde_json::to_value(InputSummary::from_loaded(&li, &l.base_dir))
                                .unwrap_or_default();
                        summary["status"] = "usable".into();
                        summary["warnings"] = json!(r.warnings);
                        inputs_json.push(summary);
                        Ok(Some(li))
                    }
                    Err(e) => {
                        writeln!(out, "  {key}: {} (cannot be used)", spec.file.display())?;
                        inputs_json
                            .push(json!({ "key": key, "file": spec.file, "status": "unusable" }));
                        input_problems.push((key, e));
                        Ok(None)
                    }
                }
            })?
            .present();
    }
    // the stage checks need every key usable: with a placeholder they would mislead
    let mut warnings = Vec::new();
    if let Some(l) = loaded.as_ref().filter(|l| l.unusable.is_empty()) {
        let found = pipeline::preflight(l, &usable);
        // what the configuration's own checks said already is said once
        for p in found.problems {
            if !config_problems.iter().any(|q| q.message == p.message) {
                config_problems.push(p);
            }
        }
        for e in found.refusals {
            // named by the key of the input it is in, else by the stage
            let key = match &e {
                Error::Input(i) => usable.iter().find(|u| u.record.source == i.place.file),
                _ => None,
            }
            .map_or_else(|| stage_of(&e), |u| u.key.clone());
            input_problems.push((key, e));
        }
        warnings.extend(found.fit_warnings);
        warnings.extend(found.validation_warnings);
    }
    if let Some(l) = &loaded {
        match output_check(l, args.out.as_deref()) {
            Ok(None) => {}
            Ok(Some(w)) => warnings.push(w),
            Err(p) => config_problems.push(p),
        }
    }
    let ok = config_problems.is_empty() && input_problems.is_empty();
    let code = if ok {
        0
    } else if config_problems.is_empty() {
        Error::numerical("check", "").exit_code()
    } else {
        Error::Config(Vec::new()).exit_code()
    };
    if args.json {
        let problems: Vec<Value> = config_problems
            .iter()
            .map(json::config_problem)
            .chain(
                input_problems
                    .iter()
                    .map(|(k, e)| json::input_problem(k, e)),
            )
            .collect();
        let plan = loaded.as_ref().map(|l| {
            let c = &l.config;
            json!({
                "title": c.title,
                "vehicle": c.vehicle,
                "stages": c.enabled_stages(),
                "hekf": c.hekf.as_ref().filter(|h| h.enabled).map(|h| json!({
                    "model": h.model,
                    "preset": h.preset,
                    "estimate": h.estimate,
                })),
            })
        });
        let report = json!({
            "configuration": args.config,
            "ok": ok,
            "would_run": plan,
            "inputs": inputs_json,
            "warnings": warnings,
            "problems": problems,
        });
        json::write(stdout, &report)?;
        return Ok(code);
    }
    stdout.write_all(&text)?;
    print_warnings(stdout, &warnings)?;
    if ok {
        writeln!(stdout, "ok: the configuration and every input are usable")?;
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
    for (_, e) in &input_problems {
        eprintln!("  - {e}");
    }
    Ok(code)
}

/// The checks `run` makes of the output folder before it starts, without writing: a place
/// never written to is a problem (key `output.dir`), a hydroid output changed since it was
/// written a warning (a run replaces it only with `--force`).
fn output_check(
    l: &hydroid::config::LoadedConfig,
    out: Option<&std::path::Path>,
) -> Result<Option<hydroid::warning::Warning>, hydroid::error::ConfigProblem> {
    use hydroid::output::{Protected, Staging};
    let dir = out.map_or_else(|| l.resolve(&l.config.output.dir), PathBuf::from);
    match Staging::preview(&dir, &Protected::for_config(l)) {
        Ok(None) => Ok(None),
        Ok(Some(why)) => Ok(Some(hydroid::warning::Warning::new(
            "output",
            why,
            "`hydroid run` would refuse to replace the output folder without --force",
        ))),
        Err(e) => Err(hydroid::error::ConfigProblem {
            file: l.path.clone(),
            line: None,
            key: Some(if out.is_some() { "--out" } else { "output.dir" }.to_string()),
            message: e.to_string(),
        }),
    }
}

/// The stage an error comes from, as a key for `--json`'s problems.
fn stage_of(e: &Error) -> String {
    match e {
        Error::Numerical { stage, .. } => stage.clone(),
        _ => "inputs".into(),
    }
}

/// The plausibility checks' warnings, under `warnings:`, each with its meaning indented.
fn print_warnings(
    out: &mut impl Write,
    warnings: &[hydroid::warning::Warning],
) -> std::io::Result<()> {
    if warnings.is_empty() {
        return Ok(());
    }
    writeln!(out, "warnings:")?;
    for w in warnings {
        writeln!(out, "  - {}", w.to_string().replace('\n', "\n    "))?;
    }
    Ok(())
}
