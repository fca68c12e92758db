//! `hydroid check CONFIG`: validate a configuration and every input it names.

use super::{json, CmdResult};
use crate::app::pipeline;
use crate::app::results::{InputSummary, LoadedInput};
use crate::base::error::{ConfigProblem, Error};
use crate::base::warning::Warning;
use crate::config;
use crate::config::LoadedConfig;
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

/// What `check` found: the problems, the inputs read and the warnings.
#[derive(Default)]
struct Findings {
    /// Problems of the configuration (exit code 2).
    config_problems: Vec<ConfigProblem>,
    /// Problems of the inputs, each with the key naming it (exit code 1).
    input_problems: Vec<(String, Error)>,
    /// The inputs that could be read.
    usable: pipeline::InputsByStage<LoadedInput>,
    /// Each input for `--json`.
    inputs_json: Vec<Value>,
    /// The plausibility checks' warnings, and the output folder's.
    warnings: Vec<Warning>,
}

impl Findings {
    /// Nothing stands in the way of a run.
    fn ok(&self) -> bool {
        self.config_problems.is_empty() && self.input_problems.is_empty()
    }

    /// The exit code `run` would stop with: 2 for a configuration problem, 1 for inputs only.
    fn exit_code(&self) -> i32 {
        if self.ok() {
            0
        } else if self.config_problems.is_empty() {
            Error::numerical("check", "").exit_code()
        } else {
            Error::Config(Vec::new()).exit_code()
        }
    }
}

/// Runs the command.
pub fn run(args: Args, stdout: &mut impl Write) -> CmdResult {
    let text = config::read(&args.config)?;
    let (loaded, config_problems) = config::load_lenient(&args.config, &text, &args.set);
    let mut found = Findings {
        config_problems,
        ..Findings::default()
    };
    // the text is printed at the end, unless --json prints JSON instead
    let mut text = Vec::new();
    if let Some(l) = &loaded {
        summary(&mut text, l)?;
        read_inputs(&mut text, l, &mut found)?;
        // the stage checks need every key usable: with a placeholder they would mislead
        if l.unusable.is_empty() {
            stage_checks(l, &mut found);
        }
        match output_check(l, args.out.as_deref()) {
            Ok(None) => {}
            Ok(Some(w)) => found.warnings.push(w),
            Err(p) => found.config_problems.push(p),
        }
    }
    let code = found.exit_code();
    if args.json {
        json::write(stdout, &json_report(&args, loaded.as_ref(), found))?;
        return Ok(code);
    }
    stdout.write_all(&text)?;
    print_warnings(stdout, &found.warnings)?;
    if found.ok() {
        writeln!(stdout, "ok: the configuration and every input are usable")?;
        return Ok(0);
    }
    let total = found.config_problems.len() + found.input_problems.len();
    eprintln!(
        "{total} problem{} found:",
        if total == 1 { "" } else { "s" }
    );
    for p in &found.config_problems {
        eprintln!("  - {p}");
    }
    for (_, e) in &found.input_problems {
        eprintln!("  - {e}");
    }
    Ok(code)
}

/// What would run: the configuration, title, vehicle, stages and the HEKF's model.
fn summary(out: &mut impl Write, l: &LoadedConfig) -> std::io::Result<()> {
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
    Ok(())
}

/// Reads every input the configuration names, saying what was read of each.
fn read_inputs(
    out: &mut impl Write,
    l: &LoadedConfig,
    found: &mut Findings,
) -> std::io::Result<()> {
    writeln!(out, "inputs:")?;
    found.usable = pipeline::stage_inputs(&l.config)
        .try_map(|p| read_input(out, l, &p, found))?
        .present();
    Ok(())
}

/// Reads one input: None when its configuration has a problem, it is missing, or it cannot
/// be used (then the problem is recorded).
fn read_input(
    out: &mut impl Write,
    l: &LoadedConfig,
    p: &pipeline::PlannedInput,
    found: &mut Findings,
) -> std::io::Result<Option<LoadedInput>> {
    let (key, spec) = (p.key.clone(), p.spec);
    if l.touches_unusable(&key) {
        // a key of this input could not be used: already a configuration problem
        writeln!(out, "  {key}: not read (its configuration has a problem)")?;
        return Ok(None);
    }
    if crate::io::formats::input::check_regular(&l.resolve(&spec.file)).is_err() {
        // already a configuration problem
        writeln!(out, "  {key}: {} (missing)", spec.file.display())?;
        let missing = json!({ "key": key, "file": spec.file, "status": "missing" });
        found.inputs_json.push(missing);
        return Ok(None);
    }
    let li = match pipeline::load_input(l, p) {
        Ok(li) => li,
        Err(e) => {
            writeln!(out, "  {key}: {} (cannot be used)", spec.file.display())?;
            let unusable = json!({ "key": key, "file": spec.file, "status": "unusable" });
            found.inputs_json.push(unusable);
            found.input_problems.push((key, e));
            return Ok(None);
        }
    };
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
        serde_json::to_value(InputSummary::from_loaded(&li, &l.base_dir)).unwrap_or_default();
    summary["status"] = "usable".into();
    summary["warnings"] = json!(r.warnings);
    found.inputs_json.push(summary);
    Ok(Some(li))
}

/// The checks `run` makes before its work starts ([`pipeline::preflight`], the same code):
/// what each stage would refuse in its runs, the plausibility checks' findings.
fn stage_checks(l: &LoadedConfig, found: &mut Findings) {
    let pre = pipeline::preflight(l, &found.usable);
    // what the configuration's own checks said already is said once
    for p in pre.problems {
        if !found.config_problems.iter().any(|q| q.message == p.message) {
            found.config_problems.push(p);
        }
    }
    for e in pre.refusals {
        // named by the key of the input it is in, else by the stage
        let key = match &e {
            Error::Input(i) => found
                .usable
                .iter()
                .find(|u| u.record.source == i.place.file),
            _ => None,
        }
        .map_or_else(|| stage_of(&e), |u| u.key.clone());
        found.input_problems.push((key, e));
    }
    found.warnings.extend(pre.fit_warnings);
    found.warnings.extend(pre.validation_warnings);
    // the autopilot's recorded disturbance, read as `run` reads it before any stage
    if let Some(a) = &l.config.autopilot {
        if let Err(e) = pipeline::autopilot::load_seas(a, &l.base_dir) {
            found
                .input_problems
                .push(("autopilot.disturbance_file".to_string(), e));
        }
        if let Err(e) = pipeline::autopilot::load_plant(a, &l.config, &l.base_dir) {
            found
                .input_problems
                .push(("autopilot.plant.vehicle_file".to_string(), e));
        }
    }
}

/// The `--json` document: what would run, every input, the warnings and the problems.
fn json_report(args: &Args, loaded: Option<&LoadedConfig>, found: Findings) -> Value {
    let problems: Vec<Value> = found
        .config_problems
        .iter()
        .map(json::config_problem)
        .chain(
            found
                .input_problems
                .iter()
                .map(|(k, e)| json::input_problem(k, e)),
        )
        .collect();
    let plan = loaded.map(|l| {
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
    json!({
        "configuration": args.config,
        "ok": found.ok(),
        "would_run": plan,
        "inputs": found.inputs_json,
        "warnings": found.warnings,
        "problems": problems,
    })
}

/// The checks `run` makes of the output folder before it starts, without writing: a place
/// never written to is a problem (key `output.dir`), a hydroid output changed since it was
/// written a warning (a run replaces it only with `--force`).
fn output_check(
    l: &LoadedConfig,
    out: Option<&std::path::Path>,
) -> Result<Option<Warning>, ConfigProblem> {
    use crate::io::output::{Protected, Staging};
    let dir = out.map_or_else(|| l.resolve(&l.config.output.dir), PathBuf::from);
    match Staging::preview(&dir, &Protected::for_config(l)) {
        Ok(None) => Ok(None),
        Ok(Some(why)) => Ok(Some(Warning::new(
            "output",
            why,
            "`hydroid run` would refuse to replace the output folder without --force",
        ))),
        Err(e) => Err(ConfigProblem {
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
fn print_warnings(out: &mut impl Write, warnings: &[Warning]) -> std::io::Result<()> {
    if warnings.is_empty() {
        return Ok(());
    }
    writeln!(out, "warnings:")?;
    for w in warnings {
        writeln!(out, "  - {}", w.to_string().replace('\n', "\n    "))?;
    }
    Ok(())
}
