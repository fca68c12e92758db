//! What can be checked before a stage runs: the coefficients the configuration, the analytic
//! formulas and the enabled stages will provide, and what the HEKF stage would miss with the
//! inputs read.

use super::inputs::InputsByStage;
use crate::config::{Config, LoadedConfig};
use crate::error::ConfigProblem;
use crate::record::Record;
use crate::results::LoadedInput;
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

/// Problems of the configuration that only show with the inputs read: what the HEKF stage
/// would miss (coefficients nothing provides, estimated coefficients a relation derives,
/// inputs a run lacks).
pub fn preflight(loaded: &LoadedConfig, inputs: &InputsByStage<LoadedInput>) -> Vec<ConfigProblem> {
    let cfg = &loaded.config;
    let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) else {
        return Vec::new();
    };
    let runs: Vec<&Record> = inputs.hekf_all().map(|i| &i.record).collect();
    hekf::preflight(
        hc,
        &cfg.vehicle,
        &cfg.fluid,
        &available_coefficients(cfg),
        &runs,
    )
    .into_iter()
    .map(|message| ConfigProblem {
        file: loaded.path.clone(),
        line: None,
        key: Some("hekf".into()),
        message,
    })
    .collect()
}
