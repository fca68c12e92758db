//! Reading the output folder an FMU is exported from: its model and coefficients, the
//! initial state of its first fit run, and the files the FMU must never be written onto (the
//! run's inputs and configurations, which the folder's config.toml, inputs.json and rerun.json
//! record).

use super::{assemble::from_parts, spec::FmuSpec};
use crate::app::report::{RerunManifest, CONFIG_TOML, INPUTS_JSON, RERUN_JSON, RESULTS_JSON};
use crate::base::error::{Error, Result};
use crate::io::output::exports::Guarded;
use crate::model::coefficients::{Coefficient, CoefficientSet, Source};
use std::path::{Path, PathBuf};

/// Where the FMU's start values come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Starts {
    /// The smoothed states at the first sample of this state series (`states/NAME.csv`).
    Smoothed(PathBuf),
    /// The filtered states there: the run's smoother was off.
    Filtered(PathBuf),
    /// Zero: the folder holds no states of its first fit run (no series, or none in it).
    Zero,
}

impl std::fmt::Display for Starts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Starts::Smoothed(p) => write!(
                f,
                "the smoothed states at the first sample of {}",
                p.display()
            ),
            Starts::Filtered(p) => write!(
                f,
                "the filtered states at the first sample of {} (the run's smoother was off)",
                p.display()
            ),
            Starts::Zero => write!(f, "zero (the folder holds no states of its first fit run)"),
        }
    }
}

/// What an output folder gives an FMU.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The FMU's model.
    pub spec: FmuSpec,
    /// Where its start values come from.
    pub starts: Starts,
    /// The files the FMU must never be written onto: the run's inputs (of every stage,
    /// enabled or not) and its source configuration.
    pub guarded: Vec<Guarded>,
}

/// Refuses the folder when one of `names` was edited since hydroid wrote it (its marker says).
fn unedited(dir: &Path, names: &[&str]) -> Result<()> {
    let edited = crate::io::output::marker::edited(dir, names)?;
    if edited.is_empty() {
        return Ok(());
    }
    Err(not_output(
        dir,
        &format!(
            "{} edited since hydroid wrote it; export packages what a run identified",
            edited.join(", ")
        ),
    ))
}

fn not_output(dir: &Path, why: &str) -> Error {
    Error::Usage(format!(
        "{}: {why} (give an output folder of `hydroid run`)",
        dir.display()
    ))
}

/// The model an output folder of `hydroid run` identified: its HEKF model with the folder's
/// coefficients, vehicle and yaw-moment reading (config.toml), the initial states of its
/// first fit run's series (states/: the smoothed ones, the filtered ones when the smoother was
/// off, zero without it) and the inputs starting at zero; `max_step` is the longest RK4 step
/// the FMU takes, s. The files hydroid wrote there that it reads (and those that say what to
/// protect) must be as it wrote them.
pub fn read_folder(dir: &Path, max_step: f64) -> Result<Exported> {
    unedited(dir, &[RESULTS_JSON, CONFIG_TOML, INPUTS_JSON, RERUN_JSON])?;
    let results_path = dir.join(RESULTS_JSON);
    if !results_path.is_file() {
        return Err(not_output(dir, "no results.json"));
    }
    let text = crate::config::read(&results_path)?;
    let results: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        Error::Usage(format!(
            "{}: not a hydroid results file: {e}",
            results_path.display()
        ))
    })?;
    let hekf = &results["stages"]["hekf"];
    let first_run = hekf["runs"][0]["name"]
        .as_str()
        .map(|name| crate::stages::hekf::states::file_names(&[name.to_string()]).remove(0));
    if let Some(file) = &first_run {
        unedited(dir, &[file])?;
    }
    let Some(model) = hekf["model"].as_str() else {
        return Err(Error::Usage(format!(
            "{}: the run has no HEKF stage (`stages.hekf.model`): only a model identified in \
             time (a [hekf] section) can be exported as an FMU",
            results_path.display()
        )));
    };
    let mut set = CoefficientSet::new();
    for c in results["coefficients"].as_array().into_iter().flatten() {
        if let (Some(n), Some(v)) = (c["name"].as_str(), c["value"].as_f64()) {
            set.insert(Coefficient::new(n, v, None, Source::Config));
        }
    }
    let loaded = recorded_config(dir)?;
    let (values, starts) = match first_run {
        Some(file) => initial_states(&dir.join(file))?,
        None => (Vec::new(), Starts::Zero),
    };
    let title = loaded.config.title.clone();
    let spec = from_parts(model, &loaded.vehicle, &set, &values, max_step, title);
    let spec = spec.map_err(|e| match e {
        Error::Usage(m) => Error::Usage(format!("{}: {m}", dir.display())),
        e => e,
    })?;
    Ok(Exported {
        spec,
        starts,
        guarded: run_files(dir, &loaded)?,
    })
}

/// The output folder's config.toml as loaded: the input files it names are not needed (the
/// model is built from the vehicle and the identified coefficients), so a missing one is
/// not a problem here; any other problem is.
fn recorded_config(dir: &Path) -> Result<crate::config::LoadedConfig> {
    let path = dir.join(CONFIG_TOML);
    let (loaded, problems) = crate::config::load_lenient(&path, &crate::config::read(&path)?, &[]);
    let problems: Vec<_> = problems
        .into_iter()
        .filter(|p| !p.key.as_deref().is_some_and(|k| k.ends_with(".file")))
        .collect();
    match loaded {
        Some(l) if problems.is_empty() => Ok(l),
        _ => Err(Error::Config(problems)),
    }
}

/// The files of the run an output folder records, which an FMU exported from it must never
/// replace: its source configuration (rerun.json), every input file its config.toml names
/// (every stage's, enabled or not) and every input inputs.json lists, resolved from the
/// configuration's folder as the run resolved them. An output of an earlier hydroid without
/// rerun.json gives none (there is no folder to resolve them from).
fn run_files(dir: &Path, loaded: &crate::config::LoadedConfig) -> Result<Vec<Guarded>> {
    let manifest_path = dir.join(RERUN_JSON);
    if !manifest_path.is_file() {
        return Ok(Vec::new());
    }
    let bad = |path: &Path, e: serde_json::Error| {
        not_output(dir, &format!("{}: not a hydroid file: {e}", path.display()))
    };
    let text = crate::config::read(&manifest_path)?;
    let manifest: RerunManifest =
        serde_json::from_str(&text).map_err(|e| bad(&manifest_path, e))?;
    let run = dir.display();
    let mut guarded = Vec::new();
    if let Some(name) = manifest.config.file_name() {
        guarded.push(Guarded {
            path: manifest.base_dir.join(name),
            what: format!("the configuration of the run recorded in {run}"),
        });
    }
    let mut input = |file: &Path, key: &str| {
        guarded.push(Guarded {
            path: manifest.base_dir.join(file),
            what: format!("an input of the run recorded in {run} ({key})"),
        })
    };
    for (key, spec) in loaded.config.inputs() {
        input(&spec.file, &key);
    }
    #[derive(serde::Deserialize)]
    struct Recorded {
        key: String,
        file: PathBuf,
    }
    let inputs_path = dir.join(INPUTS_JSON);
    if inputs_path.is_file() {
        let text = crate::config::read(&inputs_path)?;
        let recorded: Vec<Recorded> =
            serde_json::from_str(&text).map_err(|e| bad(&inputs_path, e))?;
        for r in recorded {
            input(&r.file, &r.key);
        }
    }
    Ok(guarded)
}

/// The most of a state series read for its first sample (its header and first row).
const FIRST_ROWS_BYTES: u64 = 4 << 20;

/// The state at the first sample of a state series (states/NAME.csv), by state name: the
/// smoothed columns (`u_smoothed [m/s]`) when the file has them, else the filtered ones
/// (`u_filtered [m/s]`: the smoother was off); nothing when there is no such file.
fn initial_states(path: &Path) -> Result<(Vec<(String, f64)>, Starts)> {
    if !path.is_file() {
        return Ok((Vec::new(), Starts::Zero));
    }
    let bad = |why: String| Error::Usage(format!("{}: {why}", path.display()));
    // the header and the first row are a few kB: a bounded read, whatever the file holds
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = csv::Reader::from_reader(std::io::Read::take(file, FIRST_ROWS_BYTES));
    let header = reader.headers().map_err(|e| bad(e.to_string()))?.clone();
    let Some(row) = reader.records().next() else {
        return Ok((Vec::new(), Starts::Zero));
    };
    let row = row.map_err(|e| bad(e.to_string()))?;
    // `u_smoothed [m/s]` -> `u_smoothed`; the sigma columns end in `_sigma`
    let name = |h: &str| h.split(' ').next().unwrap_or_default().to_string();
    let smoothed = header.iter().any(|h| name(h).ends_with("_smoothed"));
    let (suffix, starts) = if smoothed {
        ("_smoothed", Starts::Smoothed(path.to_path_buf()))
    } else {
        ("_filtered", Starts::Filtered(path.to_path_buf()))
    };
    let mut out = Vec::new();
    for (h, v) in header.iter().zip(row.iter()) {
        let Some(state) = name(h).strip_suffix(suffix).map(str::to_string) else {
            continue;
        };
        let value: f64 = v
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| bad(format!("column {h}: {v} is not a number")))?;
        out.push((state, value));
    }
    if out.is_empty() {
        return Ok((out, Starts::Zero));
    }
    Ok((out, starts))
}
