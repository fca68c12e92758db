//! What can be checked before a stage runs: the coefficients the configuration, the analytic
//! formulas and the enabled stages will provide, and what the HEKF stage would miss with the
//! inputs read.

use super::inputs::InputsByStage;
use crate::config::{Config, LoadedConfig};
use crate::error::ConfigProblem;
use crate::record::Record;
use crate::results::LoadedInput;
use crate::stages::{captive, hekf, polar, surge};
use crate::warning::Warning;

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

/// What can be checked with the inputs read, before any stage runs.
#[derive(Debug, Clone, Default)]
pub struct Preflight {
    /// Problems of the configuration: what the HEKF stage would miss (coefficients nothing
    /// provides, estimated coefficients a relation derives, inputs a run lacks) and the
    /// clear mistakes the plausibility checks of its runs find (a unit, a sign, a column).
    pub problems: Vec<ConfigProblem>,
    /// The plausibility checks' warnings about the HEKF's fit runs (the stage repeats them
    /// with its result) ...
    pub fit_warnings: Vec<Warning>,
    /// ... and about its validation runs.
    pub validation_warnings: Vec<Warning>,
}

/// What the configuration and its inputs show before anything runs: `hydroid check` and
/// `hydroid run` both call it, so that check runs every validation run does.
pub fn preflight(loaded: &LoadedConfig, inputs: &InputsByStage<LoadedInput>) -> Preflight {
    let cfg = &loaded.config;
    let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) else {
        return Preflight::default();
    };
    let runs: Vec<&Record> = inputs.hekf_all().map(|i| &i.record).collect();
    let found = hekf::preflight(
        hc,
        &cfg.vehicle,
        &cfg.fluid,
        &available_coefficients(cfg),
        &cfg.coefficients,
        &runs,
    );
    let fit_names: Vec<&str> = inputs
        .hekf_fit
        .iter()
        .map(|i| i.record.name.as_str())
        .collect();
    let (fit_warnings, validation_warnings) = found
        .warnings
        .into_iter()
        .partition(|w| w.run.as_deref().is_some_and(|r| fit_names.contains(&r)));
    Preflight {
        problems: found
            .problems
            .into_iter()
            .map(|message| ConfigProblem {
                file: loaded.path.clone(),
                line: None,
                key: Some("hekf".into()),
                message,
            })
            .collect(),
        fit_warnings,
        validation_warnings,
    }
}
