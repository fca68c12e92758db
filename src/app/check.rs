//! What `hydroid check CONFIG` finds, without printing it: every problem of a configuration
//! and of the inputs it names, the plausibility checks' warnings and the output folder's
//! state, in the form `check --json` prints (problems as {file, line, column, key, message}).
//! The command line and the Python package (python/) both call [`check`].

use crate::app::pipeline;
use crate::app::results::{InputSummary, LoadedInput};
use crate::base::error::{ConfigProblem, Error};
use crate::base::warning::Warning;
use crate::config;
use crate::config::LoadedConfig;
use serde_json::{json, Value};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What `check` found: the problems, the inputs read and the warnings.
#[derive(Default)]
pub struct Findings {
    /// Problems of the configuration (exit code 2).
    pub config_problems: Vec<ConfigProblem>,
    /// Problems of the inputs, each with the key naming it (exit code 1).
    pub input_problems: Vec<(String, Error)>,
    /// The inputs that could be read.
    pub usable: pipeline::InputsByStage<LoadedInput>,
    /// Each input for `--json`.
    pub inputs_json: Vec<Value>,
    /// The plausibility checks' warnings, and the output folder's.
    pub warnings: Vec<Warning>,
}

impl Findings {
    /// Nothing stands in the way of a run.
    pub fn ok(&self) -> bool {
        self.config_problems.is_empty() && self.input_problems.is_empty()
    }

    /// The exit code `run` would stop with: 2 for a configuration problem, 1 for inputs only.
    pub fn exit_code(&self) -> i32 {
        if self.ok() {
            0
        } else if self.config_problems.is_empty() {
            Error::numerical("check", "").exit_code()
        } else {
            Error::Config(Vec::new()).exit_code()
        }
    }
}

/// Checks the configuration at `path` with the overrides `set` (`KEY=VALUE`) and every input
/// it names, as `run` would before its work starts; `out` is the output folder `run --out`
/// would write (default: `output.dir`). What would run and what was read of each input is
/// written to `text` as `hydroid check` prints it. Fails only when the configuration file
/// cannot be read at all; every other problem is in the findings.
pub fn check(
    path: &Path,
    set: &[String],
    out: Option<&Path>,
    text: &mut Vec<u8>,
) -> crate::Result<(Option<LoadedConfig>, Findings)> {
    let source = config::read(path)?;
    let (loaded, config_problems) = config::load_lenient(path, &source, set);
    let mut found = Findings {
        config_problems,
        ..Findings::default()
    };
    if let Some(l) = &loaded {
        // writing to memory cannot fail
        let _ = summary(text, l);
        let _ = read_inputs(text, l, &mut found);
        // the stage checks need every key usable: with a placeholder they would mislead
        if l.unusable.is_empty() {
            stage_checks(l, &mut found);
        }
        match output_check(l, out) {
            Ok(None) => {}
            Ok(Some(w)) => found.warnings.push(w),
            Err(p) => found.config_problems.push(p),
        }
    }
    Ok((loaded, found))
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
    found.warnings.extend(pre.captive_warnings);
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

/// The `check --json` document: what would run, every input, the warnings and the problems.
pub fn json_report(config: &Path, loaded: Option<&LoadedConfig>, found: Findings) -> Value {
    let problems: Vec<Value> = found
        .config_problems
        .iter()
        .map(config_problem)
        .chain(
            found
                .input_problems
                .iter()
                .map(|(k, e)| input_problem(k, e)),
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
        "configuration": config,
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

/// A configuration problem (placed by line and key; no column).
pub fn config_problem(p: &ConfigProblem) -> Value {
    json!({
        "file": p.file,
        "line": p.line,
        "column": null,
        "column_name": null,
        "key": p.key,
        "message": p.message,
    })
}

/// A problem with the input file that the configuration key `key` names.
pub fn input_problem(key: &str, e: &Error) -> Value {
    input_problem_at(Some(key), e)
}

/// A problem with an input file, or any error, in the form of [`config_problem`]; `key` the
/// configuration key naming the input, if any.
pub fn input_problem_at(key: Option<&str>, e: &Error) -> Value {
    let (file, line, column, column_name, message) = match e {
        Error::Input(i) => (
            Some(i.place.file.clone()),
            i.place.line,
            i.place.column,
            i.place.column_name.clone(),
            match &i.expected {
                Some(x) => format!("{} (expected {x})", i.message),
                None => i.message.clone(),
            },
        ),
        Error::Io { path, source } | Error::Write { path, source } => (
            Some(path.clone()),
            None,
            None,
            None,
            crate::base::error::io_reason(source),
        ),
        Error::Numerical { message, .. } => (None, None, None, None, message.clone()),
        other => (None, None, None, None, other.to_string()),
    };
    json!({
        "file": file,
        "line": line,
        "column": column,
        "column_name": column_name,
        "key": key,
        "message": message,
    })
}
