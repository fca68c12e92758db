//! The pipeline: configuration -> inputs -> polar -> surge -> hekf -> completed coefficient
//! set -> re-simulation -> comparison. Each step is a plain function of data to data.

use crate::coefficients::{Coefficient, CoefficientSet, Source, SYMMETRY};
use crate::config::{InputSpec, LoadedConfig};
use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::record::{self, Needs, Record};
use crate::report::results::{compare, InputSummary, RunResult, StageResults};
use crate::resim::{resimulate, ResimTrace};
use crate::stages::hekf::{self, ModelName};
use crate::warning::Warning;
use sha2::{Digest, Sha256};
use std::path::Path;

/// Everything a run produced: the serialisable result and the traces plots need.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// What goes into results.json.
    pub result: RunResult,
    /// Re-simulated trajectories, per run (fit runs first, then validation runs).
    pub resim_traces: Vec<(Record, ResimTrace)>,
}

/// A loaded input with its key path and hash.
#[derive(Debug, Clone)]
pub struct LoadedInput {
    /// Configuration key of the input (`hekf.runs[0]`).
    pub key: String,
    /// The record.
    pub record: Record,
    /// SHA-256 of the file, hex.
    pub sha256: String,
}

/// Every input of every enabled stage with its key and what the stage needs from it.
pub fn stage_inputs(cfg: &crate::config::Config) -> Vec<(String, &InputSpec, Needs<'static>)> {
    let mut v = Vec::new();
    if let Some(c) = cfg.polar.as_ref().filter(|c| c.enabled) {
        let n = crate::stages::polar::needs(c);
        v.extend(c.inputs().into_iter().map(|(k, s)| (k, s, n)));
    }
    if let Some(c) = cfg.surge.as_ref().filter(|c| c.enabled) {
        let n = crate::stages::surge::needs(c);
        v.extend(c.inputs().into_iter().map(|(k, s)| (k, s, n)));
    }
    if let Some(c) = cfg.hekf.as_ref().filter(|c| c.enabled) {
        let n = hekf::needs(c);
        v.extend(c.inputs().into_iter().map(|(k, s)| (k, s, n)));
    }
    v
}

/// Loads one input file for a stage.
pub fn load_input(
    loaded: &LoadedConfig,
    key: &str,
    spec: &InputSpec,
    needs: &Needs,
) -> Result<LoadedInput> {
    let record = record::load(spec, &loaded.base_dir, needs)?;
    let sha256 = file_sha256(&record.source)?;
    Ok(LoadedInput {
        key: key.to_string(),
        record,
        sha256,
    })
}

/// SHA-256 of a file, hex. The file is read like every input (`formats::input`: a regular
/// file within the size limit), in chunks.
pub fn file_sha256(path: &Path) -> Result<String> {
    use crate::formats::input::{stream, Limits};
    let mut hasher = Sha256::new();
    stream(path, &Limits::for_file(path)?, |chunk| {
        hasher.update(chunk);
        Ok(())
    })?;
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// Analytic added mass of the vehicle when its geometry is a prolate spheroid (length and
/// diameter given): Lamb's k-factors (Fossen 1994).
pub fn analytic_added_mass(loaded: &LoadedConfig) -> Result<Vec<Coefficient>> {
    let v = &loaded.config.vehicle;
    match v.diameter {
        Some(d) => Ok(crate::analytic::Spheroid::from_length_diameter(
            v.length,
            d,
            loaded.config.fluid.rho,
        )?
        .coefficients()),
        None => Ok(Vec::new()),
    }
}

/// Coefficient names that the configuration, the analytic formulas and the enabled stages
/// will provide (so that a stage's needs can be checked before anything runs).
pub fn available_coefficients(cfg: &crate::config::Config) -> Vec<String> {
    let mut names: Vec<String> = cfg.coefficients.keys().cloned().collect();
    if cfg.vehicle.diameter.is_some() {
        names.extend(["Xud", "Yvd", "Zwd", "Nrd", "Mqd", "Kpd", "Yrd", "Nvd"].map(String::from));
    }
    if cfg.polar.as_ref().is_some_and(|c| c.enabled) {
        names.extend(
            crate::stages::polar::provides()
                .iter()
                .map(|n| n.to_string()),
        );
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        names.extend(
            crate::stages::surge::provides(sc)
                .iter()
                .map(|n| n.to_string()),
        );
    }
    names.sort();
    names.dedup();
    names
}

/// Problems of the configuration that only show with the inputs read: what the HEKF stage
/// would miss (coefficients nothing provides, estimated coefficients a relation derives,
/// inputs a run lacks).
pub fn preflight(
    loaded: &LoadedConfig,
    inputs: &[LoadedInput],
) -> Vec<crate::error::ConfigProblem> {
    let cfg = &loaded.config;
    let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) else {
        return Vec::new();
    };
    let runs: Vec<&Record> = inputs
        .iter()
        .filter(|i| i.key.starts_with("hekf.runs[") || i.key.starts_with("hekf.validation["))
        .map(|i| &i.record)
        .collect();
    hekf::preflight(
        hc,
        &cfg.vehicle,
        &cfg.fluid,
        &available_coefficients(cfg),
        &runs,
    )
    .into_iter()
    .map(|message| crate::error::ConfigProblem {
        file: loaded.path.clone(),
        line: None,
        key: Some("hekf".into()),
        message,
    })
    .collect()
}

/// Runs every enabled stage, telling `progress` how it goes.
pub fn run(loaded: &LoadedConfig, progress: &mut dyn Progress) -> Result<RunOutput> {
    let cfg = &loaded.config;
    // every input first: a bad file stops the run before any stage has run
    let mut inputs: Vec<LoadedInput> = Vec::new();
    for (key, spec, needs) in stage_inputs(cfg) {
        inputs.push(load_input(loaded, &key, spec, &needs)?);
    }
    let problems = preflight(loaded, &inputs);
    if !problems.is_empty() {
        return Err(Error::Config(problems));
    }
    let records = |prefix: &str| -> Vec<Record> {
        inputs
            .iter()
            .filter(|i| i.key.starts_with(prefix))
            .map(|i| i.record.clone())
            .collect()
    };
    // every warning is said as soon as it arises, and kept for results.json and the report
    let mut warnings = Vec::new();
    say(
        &mut warnings,
        progress,
        inputs.iter().flat_map(|i| {
            i.record.warnings.iter().map(|w| {
                Warning::new(
                    "input",
                    w.clone(),
                    "hydroid read the file as described here; check that this is what the \
                     export meant",
                )
                .for_run(&i.record.name)
            })
        }),
    );
    let mut known = CoefficientSet::new();
    for (name, v) in &cfg.coefficients {
        known.insert(Coefficient::new(name, *v, None, Source::Config));
    }
    let analytic = analytic_added_mass(loaded)?;
    let mut stages = StageResults::default();

    if let Some(pc) = cfg.polar.as_ref().filter(|c| c.enabled) {
        let recs = records("polar.");
        let r = crate::stages::polar::run(pc, &cfg.vehicle, &cfg.fluid, &recs)?;
        known.merge_stage(r.coefficients(), r.directions.clone());
        progress.stage(&format!(
            "polar: {} coefficients from {} steady points",
            r.coefficients.len(),
            r.pooled.n_points
        ));
        say(&mut warnings, progress, r.warnings.iter().cloned());
        stages.polar = Some(r);
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        let recs = records("surge.");
        known.complete(SYMMETRY);
        let r = crate::stages::surge::run(sc, &cfg.vehicle, &known, &recs)?;
        r.merge_into(&mut known);
        progress.stage(&format!(
            "surge: Xud from {} run{}",
            recs.len(),
            if recs.len() == 1 { "" } else { "s" }
        ));
        say(&mut warnings, progress, r.warnings.iter().cloned());
        stages.surge = Some(r);
    }
    let mut resim_traces = Vec::new();
    let mut resim_metrics = Vec::new();
    let mut model_name = None;
    if let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) {
        let fit = records("hekf.runs[");
        let validation = records("hekf.validation[");
        // fixed coefficients: stages and configuration first, analytic values where nothing
        // else gives one
        let mut for_filter = known.clone();
        for c in &analytic {
            if !for_filter.contains(&c.name) {
                for_filter.insert(c.clone());
            }
        }
        for_filter.complete(SYMMETRY);
        let stage_inputs = hekf::StageInputs {
            vehicle: &cfg.vehicle,
            fluid: &cfg.fluid,
            known: &for_filter,
            runs: &fit,
            base_dir: &loaded.base_dir,
        };
        let r = hekf::run(hc, &stage_inputs, progress)?;
        progress.stage(&format!(
            "hekf: {} coefficients from {} run{} ({} passes)",
            r.estimated.len(),
            fit.len(),
            if fit.len() == 1 { "" } else { "s" },
            r.settings.passes
        ));
        say(
            &mut warnings,
            progress,
            r.runs
                .iter()
                .flat_map(|run| run.warnings.iter().cloned())
                .chain(r.warnings.iter().cloned()),
        );
        let mut final_set = for_filter.clone();
        final_set.merge_stage(r.coefficients(), r.directions.clone());
        final_set.correlation = Some(r.correlation.clone());
        complete_for(&mut final_set, hc.model);
        let vehicle = cfg.vehicle.for_model(&cfg.fluid);
        for (rec, used) in fit
            .iter()
            .map(|r| (r, true))
            .chain(validation.iter().map(|r| (r, false)))
        {
            let (m, t) = resimulate(hc.model, &vehicle, &final_set, rec, used)?;
            say(&mut warnings, progress, crate::resim::warnings(&m, rec));
            resim_metrics.push(m);
            resim_traces.push((rec.clone(), t));
        }
        known.merge_stage(r.coefficients(), r.directions.clone());
        known.correlation = Some(r.correlation.clone());
        model_name = Some(hc.model);
        stages.hekf = Some(r);
    }
    // the reported set: what the stages and the configuration gave, completed by symmetry
    match model_name {
        Some(m) => complete_for(&mut known, m),
        None => {
            let incomplete = known.complete(SYMMETRY).into_iter().map(|w| {
                Warning::new(
                    "coefficients",
                    w,
                    "the coefficient set is incomplete: a re-simulation with it is not possible",
                )
            });
            say(&mut warnings, progress, incomplete);
        }
    }
    let comparison = compare(&known, &analytic, cfg.reference.as_ref());
    let result = RunResult::new(
        loaded,
        inputs
            .iter()
            .map(|i| InputSummary::from_loaded(i, &loaded.base_dir))
            .collect(),
        known,
        analytic,
        comparison,
        stages,
        resim_metrics,
        warnings,
    );
    Ok(RunOutput {
        result,
        resim_traces,
    })
}

/// Says each warning to `progress` as it arises and keeps it in `list`.
fn say(
    list: &mut Vec<Warning>,
    progress: &mut dyn Progress,
    warnings: impl IntoIterator<Item = Warning>,
) {
    for w in warnings {
        progress.warning(&w);
        list.push(w);
    }
}

/// Completes the reported set by the relations the model declares (symmetry, axisymmetry).
fn complete_for(set: &mut CoefficientSet, model: ModelName) {
    for relations in model.completing_relations() {
        set.complete(relations);
    }
}
