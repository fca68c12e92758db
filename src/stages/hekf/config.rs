//! `[hekf]` configuration.

use crate::config::{yes, Config, Constant, InputSpec, Problems};
use crate::quantity::Quantity;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Which vehicle model the filter identifies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelName {
    /// Horizontal-plane spheroid (paper eq. 2): u, v, r, x, y, psi.
    #[default]
    Spheroid3,
    /// Axisymmetric 6-DOF spheroid: heave and pitch mirror sway and yaw.
    Spheroid6,
}

impl std::fmt::Display for ModelName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModelName::Spheroid3 => "spheroid3",
            ModelName::Spheroid6 => "spheroid6",
        })
    }
}

impl std::fmt::Display for Preset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Preset::Hydroid => "hydroid",
            Preset::Paper => "paper",
        })
    }
}

/// A tuning preset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// hydroid's defaults: P0 of measured states from the measurement noise, R from the
    /// configured or estimated noise, priors scaled to each coefficient's expected size,
    /// several passes.
    #[default]
    Hydroid,
    /// The paper's tuning: Q = 1e-4 I, R = 1e-6 I, P0 = 0 for the measured states and 1 for
    /// the coefficients, one pass, coefficients starting at 0.
    Paper,
}

/// Prior for one estimated coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Prior {
    /// Initial value, SI (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<f64>,
    /// Prior standard deviation, SI (default: the coefficient's expected size).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
}

/// `[hekf]` configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HekfConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The vehicle model.
    #[serde(default)]
    pub model: ModelName,
    /// Tuning preset; explicit keys below override it.
    #[serde(default)]
    pub preset: Preset,
    /// The coefficients to estimate (the rest are held fixed).
    pub estimate: Vec<String>,
    /// Filter passes, each restarting from the last estimate (hydroid: 3, paper: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passes: Option<usize>,
    /// RK4 sub-steps between samples (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substeps: Option<usize>,
    /// Run the Rauch-Tung-Striebel smoother after the last pass (default true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smoother: Option<bool>,
    /// Use every N-th sample of each run (default 1: every sample); for runs too long for
    /// the memory (see `memory_limit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decimate: Option<usize>,
    /// Memory the run may take (`"4 GB"`, `"512 MiB"`; default: what the system has
    /// available); the run stops before the filter starts when its estimate exceeds it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_limit: Option<String>,
    /// Per-coefficient initial value and prior sigma.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub prior: BTreeMap<String, Prior>,
    /// Measurement noise standard deviation per measured quantity (`"0.05 deg"`, or a number
    /// in SI); quantities not listed get an estimate from the data.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub noise: BTreeMap<Quantity, Constant>,
    /// Process noise spectral density per state or coefficient name (SI per second);
    /// overrides the preset.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub process_noise: BTreeMap<String, f64>,
    /// Which quantities to use as measurements (default: every model output in the file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measure: Option<Vec<Quantity>>,
    /// CFD motion histories used for identification (coefficients shared, states per run).
    pub runs: Vec<InputSpec>,
    /// Runs used only to check the identified model by re-simulation.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub validation: Vec<InputSpec>,
}

impl HekfConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, config: &Config, p: &mut Problems) {
        if self.model == ModelName::Spheroid6 {
            for (key, v) in [("ixx", config.vehicle.ixx), ("iyy", config.vehicle.iyy)] {
                if v.is_none() {
                    p.add(
                        &format!("vehicle.{key}"),
                        format!("the spheroid6 model needs vehicle.{key} (kg m^2)"),
                    );
                }
            }
        }
        if self.estimate.is_empty() {
            p.add("hekf.estimate", "lists no coefficient to estimate");
        }
        for (i, name) in self.estimate.iter().enumerate() {
            p.known_coefficient(&format!("hekf.estimate[{i}]"), name);
        }
        for (name, prior) in &self.prior {
            let key = format!("hekf.prior.{name}");
            if !self.estimate.contains(name) {
                p.add(
                    &key,
                    format!("'{name}' has a prior but is not in hekf.estimate"),
                );
            }
            if let Some(s) = prior.sigma {
                p.positive(&format!("{key}.sigma"), s, "SI");
            }
            if let Some(v) = prior.initial {
                p.finite(&format!("{key}.initial"), v);
            }
        }
        if let Some(n) = self.passes {
            p.within("hekf.passes", n as f64, 1.0, 100.0);
        }
        if let Some(n) = self.substeps {
            p.within("hekf.substeps", n as f64, 1.0, 1000.0);
        }
        if let Some(n) = self.decimate {
            p.within("hekf.decimate", n as f64, 1.0, 1e6);
        }
        if let Some(Err(m)) = self.memory_limit.as_deref().map(super::memory::parse_size) {
            p.add("hekf.memory_limit", m);
        }
        for (q, c) in &self.noise {
            p.positive(&format!("hekf.noise.{q}"), c.si, "SI");
        }
        for (name, q) in &self.process_noise {
            if !(q.is_finite() && *q >= 0.0) {
                p.add(
                    &format!("hekf.process_noise.{name}"),
                    format!("must be zero or positive, got {q}"),
                );
            }
        }
        if self.runs.is_empty() {
            p.add("hekf.runs", "no run to identify from");
        }
        for (key, r) in self.inputs() {
            p.existing_file(&format!("{key}.file"), &r.file);
        }
    }

    /// The input files this section names.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        let runs = self
            .runs
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("hekf.runs[{i}]"), r));
        let val = self
            .validation
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("hekf.validation[{i}]"), r));
        runs.chain(val).collect()
    }
}
