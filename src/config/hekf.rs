//! `[hekf]` configuration.

use super::{yes, Constant, InputSpec, Problems};
use crate::base::quantity::Quantity;
use crate::model::models::{ModelName, RunVehicle};
pub use crate::numerics::estimation::FilterKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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

/// How the HEKF uses the coefficients earlier stages (polar, surge, captive) estimated that
/// it estimates too.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// The HEKF estimates them from its own prior (their stage values are not used), and
    /// the stages' uncertainty of the coefficients it holds fixed is carried into its sigmas
    /// (the consider analysis).
    #[default]
    Consider,
    /// An earlier stage's estimate and covariance is the prior of each such coefficient: one
    /// estimate from all the data.
    Joint,
}

impl Mode {
    fn is_default(&self) -> bool {
        *self == Mode::default()
    }

    /// The name a configuration writes (`hekf.mode`).
    pub fn name(self) -> &'static str {
        match self {
            Mode::Consider => "consider",
            Mode::Joint => "joint",
        }
    }
}

/// The innovation gate when `hekf.gate` is not given, in standard deviations: far beyond
/// any Gaussian innovation (p ~ 1e-15) even when the innovations are twice as large as the
/// noise model says, yet far below a spike cell.
pub const DEFAULT_GATE: f64 = 8.0;

/// What to do with gross outliers of the measured quantities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outliers {
    /// Leave them out of the filter and the noise estimate, and report their lines.
    #[default]
    Exclude,
    /// Use them.
    Keep,
}

impl Outliers {
    fn is_default(&self) -> bool {
        *self == Outliers::default()
    }
}

/// What the stage does when a run's approach is not an equilibrium of the model's surge
/// equation (the logged propeller against the resistance the configuration holds).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Balance {
    /// Estimate the coefficient that sets the balance (the model's `surge_balance`, R'_0
    /// for mmg3) with the others, and say so.
    #[default]
    Estimate,
    /// Keep it as configured; warn with the unbalanced force.
    Hold,
}

impl Balance {
    fn is_default(&self) -> bool {
        *self == Balance::default()
    }
}

/// What a failed plausibility check does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Checks {
    /// A clear mistake (a frame, unit or sign that the data contradict) stops the run.
    #[default]
    Error,
    /// Warn and run anyway.
    Warn,
}

impl Checks {
    fn is_default(&self) -> bool {
        *self == Checks::default()
    }
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
    /// Which form of the extended Kalman filter runs: `hybrid` (continuous-discrete, the
    /// default), `discrete` (explicit Euler between samples, the Nomoto wave-filter paper) or
    /// `continuous` (Kalman-Bucy, the NPS AUV paper); docs/hekf.md, "Filter forms".
    #[serde(default, skip_serializing_if = "FilterKind::is_default")]
    pub filter: FilterKind,
    /// The coefficients to estimate (the rest are held fixed).
    pub estimate: Vec<String>,
    /// `consider` (default) or `joint`: whether an earlier stage's estimate of a coefficient
    /// the HEKF estimates too is its prior (docs/hekf.md, "Joint estimate").
    #[serde(default, skip_serializing_if = "Mode::is_default")]
    pub mode: Mode,
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
    /// Initial variance of every model state, SI^2 (a paper's `P0 = c I` for the states);
    /// default: a measured state's measurement noise variance, 1 for an unmeasured one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_variance: Option<f64>,
    /// Measurement noise standard deviation per measured quantity (`"0.05 deg"`, or a number
    /// in SI); quantities not listed get an estimate from the data.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub noise: BTreeMap<Quantity, Constant>,
    /// Process noise spectral density per state or coefficient name (SI per second);
    /// overrides the preset.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub process_noise: BTreeMap<String, f64>,
    /// Match the process noise of the measured velocity states to the innovations, run by
    /// run (default true with the hydroid preset, false with the paper's); a state given in
    /// `process_noise` keeps its value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adapt_noise: Option<bool>,
    /// A run whose approach the model's surge equation does not hold steady: estimate the
    /// coefficient that sets the balance (`estimate`, the default) or keep it (`hold`).
    #[serde(default, skip_serializing_if = "Balance::is_default")]
    pub balance: Balance,
    /// Innovation gate in standard deviations: a measurement whose innovation exceeds this
    /// many standard deviations of its predicted spread is rejected and reported with its
    /// file line (default [`DEFAULT_GATE`]; 0 switches the gate off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gate: Option<f64>,
    /// Gross outliers of the measured quantities: left out and reported (`exclude`, the
    /// default) or used (`keep`).
    #[serde(default, skip_serializing_if = "Outliers::is_default")]
    pub outliers: Outliers,
    /// Plausibility checks of the runs before filtering (frames, units, signs, inputs):
    /// `error` (default) stops on a clear mistake, `warn` only warns.
    #[serde(default, skip_serializing_if = "Checks::is_default")]
    pub checks: Checks,
    /// Which quantities to use as measurements (default: every model output in the file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measure: Option<Vec<Quantity>>,
    /// CFD motion histories used for identification (coefficients shared, states per run).
    pub runs: Vec<InputSpec>,
    /// Runs used only to check the identified model by re-simulation.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub validation: Vec<InputSpec>,
}

/// Most filter passes (`hekf.passes`).
pub const MAX_PASSES: u64 = 100;
/// Most RK4 sub-steps per sample (`hekf.substeps`).
pub const MAX_SUBSTEPS: u64 = 1000;

impl HekfConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, vehicle: &RunVehicle, p: &mut Problems) {
        // the model says what it needs of the vehicle
        struct Built;
        impl crate::model::models::ModelVisitor for Built {
            type Output = ();
            fn visit<M: crate::model::models::Model>(self, _: &M) {}
        }
        if let Err(problems) = crate::model::models::with_model(self.model, vehicle, Built) {
            for vp in problems {
                p.add(&vp.key, vp.message);
            }
        }
        if self.estimate.is_empty() {
            p.add("hekf.estimate", "lists no coefficient to estimate");
        }
        for (i, name) in self.estimate.iter().enumerate() {
            p.known_coefficient(&format!("hekf.estimate[{i}]"), name);
        }
        p.no_duplicates("hekf.estimate", self.estimate.iter().map(String::as_str));
        if let Some(m) = &self.measure {
            p.no_duplicates("hekf.measure", m.iter().map(|q| q.key()));
        }
        let estimate_known = !p.is_poisoned("hekf.estimate");
        for (name, prior) in &self.prior {
            let key = format!("hekf.prior.{name}");
            if estimate_known && !self.estimate.contains(name) {
                p.add(
                    &key,
                    format!("'{name}' has a prior but is not in hekf.estimate"),
                );
            }
            if let Some(s) = prior.sigma {
                p.positive(&format!("{key}.sigma"), s, "SI");
                p.coefficient_sized(&format!("{key}.sigma"), s);
            }
            if let Some(v) = prior.initial {
                p.coefficient_sized(&format!("{key}.initial"), v);
            }
        }
        if let Some(v) = self.state_variance {
            p.positive("hekf.state_variance", v, "SI^2");
            p.coefficient_sized("hekf.state_variance", v);
        }
        if let Some(n) = self.passes {
            p.count_within(
                "hekf.passes",
                n as u64,
                1,
                MAX_PASSES,
                "each pass runs the filter over every run",
            );
        }
        if let Some(n) = self.substeps {
            p.count_within(
                "hekf.substeps",
                n as u64,
                1,
                MAX_SUBSTEPS,
                "RK4 steps per sample; more only cost time",
            );
        }
        if let Some(g) = self.gate {
            if !(g.is_finite() && (g == 0.0 || g >= 3.0)) {
                p.add(
                    "hekf.gate",
                    format!(
                        "must be 0 (no gate) or at least 3 standard deviations, got {g}: a \
                         tighter gate rejects good measurements"
                    ),
                );
            }
        }
        if let Some(n) = self.decimate {
            p.within("hekf.decimate", n as f64, 1.0, 1e6);
        }
        if let Some(Err(m)) = self.memory_limit.as_deref().map(parse_memory_size) {
            p.add("hekf.memory_limit", m);
        }
        for (q, c) in &self.noise {
            let key = format!("hekf.noise.{q}");
            match c.expect_quantity(*q) {
                Ok(()) => p.positive(&key, c.si, q.si_symbol()),
                Err(m) => p.add(&key, m),
            }
        }
        for (name, q) in &self.process_noise {
            let key = format!("hekf.process_noise.{name}");
            if !(q.is_finite() && *q >= 0.0) {
                p.add(&key, format!("must be zero or positive, got {q}"));
            } else {
                p.coefficient_sized(&key, *q);
            }
        }
        if self.runs.is_empty() {
            p.add("hekf.runs", "no run to identify from");
        }
        p.inputs(&self.inputs());
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

/// A memory size as written in the configuration: a number with B, kB, MB, GB, TB (powers
/// of 1000) or KiB, MiB, GiB, TiB (powers of 1024), e.g. `"4 GB"`, `"512 MiB"`.
pub fn parse_memory_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let factor: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "b" => 1,
        "kb" => 1_000,
        "mb" => 1_000_000,
        "gb" => 1_000_000_000,
        "tb" => 1_000_000_000_000,
        "kib" => 1 << 10,
        "mib" => 1 << 20,
        "gib" => 1 << 30,
        "tib" => 1 << 40,
        _ => {
            return Err(format!(
                "'{text}' is not a memory size: expected a number and a unit, e.g. \"4 GB\" \
                 or \"512 MiB\" (B, kB, MB, GB, TB, KiB, MiB, GiB, TiB)"
            ))
        }
    };
    match num.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok((v * factor as f64).round() as u64),
        _ => Err(format!(
            "'{text}' is not a memory size: expected a positive number before the unit, \
             e.g. \"4 GB\""
        )),
    }
}
