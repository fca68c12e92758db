//! What can be checked before a stage runs: the coefficients the configuration, the analytic
//! formulas and the enabled stages will provide, and what each stage would refuse in the
//! inputs read before it fits (the same checks the stage makes, run early). `hydroid check`
//! and `hydroid run` both call [`preflight`], so that check runs every validation run does
//! before its work starts.

use super::inputs::InputsByStage;
use crate::app::results::LoadedInput;
use crate::base::error::{ConfigProblem, Error};
use crate::base::warning::Warning;
use crate::config::{Config, LoadedConfig};
use crate::io::record::Record;
use crate::model::coefficients::{Coefficient, CoefficientSet, Source, SYMMETRY};
use crate::stages::{captive, hekf, polar, surge};

/// Coefficient names that the configuration, the analytic formulas and the enabled stages
/// will provide (so that a stage's needs can be checked before anything runs).
pub fn available_coefficients(cfg: &Config) -> Vec<String> {
    let mut names: Vec<String> = cfg.coefficients.keys().cloned().collect();
    if cfg.vehicle.diameter.is_some() {
        names.extend(["Xud", "Yvd", "Zwd", "Nrd", "Mqd", "Kpd", "Yrd", "Nvd"].map(String::from));
    }
    if let Some(pc) = cfg.polar.as_ref().filter(|c| c.enabled) {
        names.extend(polar::provides(pc).iter().map(|n| n.to_string()));
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        names.extend(surge::provides(sc).iter().map(|n| n.to_string()));
    }
    if let Some(cc) = cfg.captive.as_ref().filter(|c| c.enabled) {
        names.extend(captive::provides(cc));
    }
    names.sort();
    names.dedup();
    names
}

/// The coefficients the captive stage will find known when it starts, as the pipeline builds
/// them: the configuration's, the polar stage's, and, when the surge stage runs, those
/// completed by symmetry before it and its own (no analytic values: the captive fit does not
/// take them).
fn known_before_captive(cfg: &Config) -> Vec<String> {
    let mut set = CoefficientSet::new();
    let add = |set: &mut CoefficientSet, name: &str| {
        set.insert(Coefficient::new(name, 0.0, None, Source::Config));
    };
    for name in cfg.coefficients.keys() {
        add(&mut set, name);
    }
    if let Some(pc) = cfg.polar.as_ref().filter(|c| c.enabled) {
        for name in polar::provides(pc) {
            add(&mut set, name);
        }
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        set.complete(SYMMETRY, cfg.vehicle.yaw_moment);
        for name in surge::provides(sc) {
            add(&mut set, name);
        }
    }
    set.iter().map(|c| c.name.clone()).collect()
}

/// What can be checked with the inputs read, before any stage runs.
#[derive(Debug, Default)]
pub struct Preflight {
    /// Problems of the configuration: what a stage would miss (coefficients nothing provides,
    /// estimated coefficients a relation derives or the model lacks, inputs or columns a run
    /// lacks) and the clear mistakes the plausibility checks of the HEKF's runs find (a unit,
    /// a sign, a column). Exit code 2.
    pub problems: Vec<ConfigProblem>,
    /// What the polar or surge stage would stop at in its runs (too few samples of a surge
    /// run in its time window, no polar point within the fitting range, too few distinct
    /// angles), as the stage says it, with the exit code it has (1).
    pub refusals: Vec<Error>,
    /// The plausibility checks' warnings about the captive tables (the stage repeats them
    /// with its result).
    pub captive_warnings: Vec<Warning>,
    /// The plausibility checks' warnings about the HEKF's fit runs (the stage repeats them
    /// with its result) ...
    pub fit_warnings: Vec<Warning>,
    /// ... and about its validation runs.
    pub validation_warnings: Vec<Warning>,
}

impl Preflight {
    /// A model stage's refusal (captive, HEKF) as a problem of the configuration, keyed by
    /// the stage: a coefficient without a value, a column the model needs.
    fn problem(&mut self, loaded: &LoadedConfig, stage: &str, e: Error) {
        let message = match e {
            Error::Config(problems) => {
                self.problems.extend(problems);
                return;
            }
            Error::Numerical { stage: s, message } if s == stage => message,
            e => e.to_string(),
        };
        self.problems.push(ConfigProblem {
            file: loaded.path.clone(),
            line: None,
            key: Some(stage.into()),
            message,
        });
    }

    /// The error `hydroid run` stops with: every configuration problem, else the first
    /// refusal; None when the run may start.
    pub fn into_error(self) -> Option<Error> {
        if !self.problems.is_empty() {
            return Some(Error::Config(self.problems));
        }
        self.refusals.into_iter().next()
    }
}

/// What the configuration and its inputs show before anything runs: every check each
/// enabled stage makes of its runs before it fits (polar, surge, captive), what the HEKF
/// would miss and the plausibility checks of its runs. `hydroid check` and `hydroid run`
/// both call it, so that check runs every validation run does.
pub fn preflight(loaded: &LoadedConfig, inputs: &InputsByStage<LoadedInput>) -> Preflight {
    let cfg = &loaded.config;
    let mut out = Preflight::default();
    let records = |l: &[LoadedInput]| l.iter().map(|i| i.record.clone()).collect::<Vec<_>>();
    let available = available_coefficients(cfg);
    if let Some(pc) = cfg.polar.as_ref().filter(|c| c.enabled) {
        let found = polar::preflight(pc, &cfg.vehicle, &cfg.fluid, &records(&inputs.polar));
        out.refusals.extend(found);
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        let xuu = known_before_captive(cfg).iter().any(|n| n == "Xuu");
        out.refusals
            .extend(surge::preflight(sc, &records(&inputs.surge), xuu));
    }
    if let Some(cc) = cfg.captive.as_ref().filter(|c| c.enabled) {
        let runs: Vec<&Record> = inputs.captive.iter().map(|i| &i.record).collect();
        let known = known_before_captive(cfg);
        let found = captive::preflight(cc, &loaded.vehicle, &known, &cfg.coefficients, &runs);
        if let Some(e) = found.error {
            out.problem(loaded, "captive", e);
        }
        for m in found.problems {
            out.problem(loaded, "captive", Error::numerical("captive", m));
        }
        out.captive_warnings = found.warnings;
    }
    let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) else {
        return out;
    };
    // what the stage refuses in a fit run before it filters (named by the key to fix)
    for i in &inputs.hekf_fit {
        if let Some(p) = hekf::fit_run_problem(hc, &loaded.vehicle, &i.record) {
            let key = p
                .run_key
                .map_or_else(|| "hekf.measure".to_string(), |k| format!("{}.{k}", i.key));
            if !out.problems.iter().any(|q| q.message == p.message) {
                out.problems.push(ConfigProblem {
                    file: loaded.path.clone(),
                    line: None,
                    key: Some(key),
                    message: p.message,
                });
            }
        }
    }
    let runs: Vec<&Record> = inputs.hekf_all().map(|i| &i.record).collect();
    let found = hekf::preflight(hc, &loaded.vehicle, &available, &cfg.coefficients, &runs);
    let fit_names: Vec<&str> = inputs
        .hekf_fit
        .iter()
        .map(|i| i.record.name.as_str())
        .collect();
    let (fit_warnings, validation_warnings) = found
        .warnings
        .into_iter()
        .partition(|w| w.run.as_deref().is_some_and(|r| fit_names.contains(&r)));
    for m in found.problems {
        out.problem(loaded, "hekf", Error::numerical("hekf", m));
    }
    out.fit_warnings = fit_warnings;
    out.validation_warnings = validation_warnings;
    out
}
