//! `[captive]` configuration: steady captive runs (static drift, drift with rudder, circular
//! motion) whose measured forces give a model's coefficients.

use super::{si, yes, InputSpec, Problems};
use crate::model::models::{ModelName, RunVehicle};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// `[captive]` configuration (docs/stages.md, "Captive runs").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaptiveConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The vehicle model whose steady forces are fitted (it must give forces for a
    /// prescribed motion: `hydroid coefficients MODEL` says so).
    pub model: ModelName,
    /// The coefficients to fit (the rest are held at their known values).
    pub estimate: Vec<String>,
    /// Starting values of the fit, SI (default 0): a nonlinear model may need one near the
    /// answer.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub start: BTreeMap<String, f64>,
    /// Sign constraints of fitted coefficients (`Yvd = "negative"`: an added mass; `Nrr =
    /// "negative"`: damping): each Gauss-Newton step is the constrained least-squares step
    /// (clarabel), and one that ends on its bound is reported there, without variance.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub signs: BTreeMap<String, Sign>,
    /// The prime system of tables given non-dimensional (`drift`, `speed`, `r_prime`,
    /// `x_prime`, `y_prime`, `n_prime` columns): X' = X / (0.5 rho A U^2),
    /// N' = N / (0.5 rho A L U^2), r' = r L / U.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prime: Option<PrimeSystem>,
    /// Runs given as force histories of one held motion each (a CFD solver's force output):
    /// every run is averaged from this time on, s, into one condition whose force
    /// uncertainty is the standard error of the averaged part. Default: each row is a
    /// condition.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Time>",
        skip_serializing_if = "Option::is_none"
    )]
    pub average_after: Option<f64>,
    /// The prescribed oscillation of harmonic runs whose files hold the forces only (an
    /// OpenFOAM force.dat): by run name, each velocity as mean + amplitude
    /// sin(2 pi f t + phase) with t the file's time (the mean is the run's constant, e.g.
    /// `constants = { u = "2 m/s" }`, else 0).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub oscillations: BTreeMap<String, Oscillation>,
    /// Tables of steady conditions, one row each: the held motion (`u`, `v`, `r`, or
    /// `speed`, `drift` and `r_prime`), the inputs (`rudder`, `rpm`; columns or constants)
    /// and the measured forces (`fx`, `fy`, `mz` in SI about the model's origin, or
    /// `x_prime`, `y_prime`, `n_prime`).
    pub runs: Vec<InputSpec>,
    /// What a clear mistake the plausibility checks find in a table does (a unit, a sign,
    /// swapped columns that the data contradict: docs/stages.md, "Captive plausibility"):
    /// `error` (the default) stops the run, `warn` warns and fits anyway.
    #[serde(default, skip_serializing_if = "is_default_checks")]
    pub checks: super::hekf::Checks,
}

fn is_default_checks(c: &super::hekf::Checks) -> bool {
    *c == super::hekf::Checks::default()
}

/// The normalisation of non-dimensional captive results.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrimeSystem {
    /// L, m: of the yaw rate r' = r L / U and the moment N' = N / (0.5 rho A L U^2)
    /// (L_pp for the MMG method).
    #[serde(deserialize_with = "si::value::<_, si::Length>")]
    pub length: f64,
    /// A, m^2: of the forces X' = X / (0.5 rho A U^2) (L_pp d for the MMG method, L^2 for
    /// the Abkowitz prime system).
    #[serde(deserialize_with = "si::value::<_, si::Area>")]
    pub area: f64,
}

/// The sign a fitted coefficient must keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Sign {
    /// >= 0.
    Positive,
    /// <= 0.
    Negative,
}

/// A prescribed harmonic motion (a PMM's): v = A sin(2 pi f t + phase).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Oscillation {
    /// Amplitude of each oscillating velocity (`v = "0.25 m/s"`, `r = "15 deg/s"`).
    pub amplitude: BTreeMap<crate::base::quantity::Quantity, super::Constant>,
    /// Frequency, Hz.
    #[serde(deserialize_with = "si::value::<_, si::Frequency>")]
    pub frequency: f64,
    /// Phase at t = 0 (default 0; a sway displacement y_a sin(2 pi f t) has a velocity of
    /// phase 90 deg).
    #[serde(default, deserialize_with = "si::value::<_, si::Angle>")]
    pub phase: f64,
}

/// What the captive stage's model says of the configuration: (key, problem) pairs.
struct ModelCheck<'a> {
    estimate: &'a [String],
}

impl crate::model::models::ModelVisitor for ModelCheck<'_> {
    type Output = Vec<(String, String)>;

    fn visit<M: crate::model::models::Model>(self, model: &M) -> Self::Output {
        let mut out = Vec::new();
        if model.force_quantities().is_empty() {
            out.push((
                "captive.model".to_string(),
                format!(
                    "the {} model gives no forces for a prescribed motion, so captive runs \
                     cannot be fitted with it (mmg3 does)",
                    model.name()
                ),
            ));
        }
        for (i, n) in self.estimate.iter().enumerate() {
            let known = crate::model::models::registry::coefficient(n).is_some();
            let message = match model.coefficient_index(n) {
                // an unknown name is reported by its catalogue check
                None if known => format!("the {} model has no coefficient {n}", model.name()),
                Some(_) if model.is_derived(n) => format!(
                    "{n} is derived by a relation of the {} model and cannot be fitted",
                    model.name()
                ),
                _ => continue,
            };
            out.push((format!("captive.estimate[{i}]"), message));
        }
        out
    }
}

impl CaptiveConfig {
    /// The model's checks, as the stage makes them before it fits: what it needs of the
    /// vehicle (`[vehicle.particulars]`), forces to fit, the estimated coefficients its own.
    fn validate_model(&self, vehicle: &RunVehicle, p: &mut Problems) {
        let check = ModelCheck {
            estimate: &self.estimate,
        };
        match crate::model::models::with_model(self.model, vehicle, check) {
            Ok(found) => {
                for (key, message) in found {
                    p.add(&key, message);
                }
            }
            Err(problems) => {
                for vp in problems {
                    p.add(&vp.key, vp.message);
                }
            }
        }
    }

    /// Adds every problem with this section to `p`.
    pub fn validate(&self, vehicle: &RunVehicle, p: &mut Problems) {
        self.validate_model(vehicle, p);
        if self.estimate.is_empty() {
            p.add("captive.estimate", "lists no coefficient to fit");
        }
        for (i, name) in self.estimate.iter().enumerate() {
            p.known_coefficient(&format!("captive.estimate[{i}]"), name);
        }
        p.no_duplicates("captive.estimate", self.estimate.iter().map(String::as_str));
        for (name, v) in &self.start {
            let key = format!("captive.start.{name}");
            if !self.estimate.contains(name) {
                p.add(
                    &key,
                    format!("'{name}' has a start value but is not in captive.estimate"),
                );
            }
            p.coefficient_sized(&key, *v);
        }
        for name in self.signs.keys() {
            if !self.estimate.contains(name) {
                p.add(
                    &format!("captive.signs.{name}"),
                    format!("'{name}' has a sign but is not in captive.estimate"),
                );
            }
        }
        for (name, v) in &self.start {
            let ok = match self.signs.get(name) {
                Some(Sign::Positive) => *v >= 0.0,
                Some(Sign::Negative) => *v <= 0.0,
                None => true,
            };
            if !ok {
                p.add(
                    &format!("captive.start.{name}"),
                    format!("{v} breaks its sign (captive.signs.{name})"),
                );
            }
        }
        if let Some(t) = self.average_after {
            if !(t.is_finite() && t >= 0.0) {
                p.add(
                    "captive.average_after",
                    format!("must be a time from 0 s, got {t}"),
                );
            }
        }
        if let Some(ps) = &self.prime {
            p.positive("captive.prime.length", ps.length, "m");
            p.positive("captive.prime.area", ps.area, "m^2");
        }
        if self.runs.is_empty() {
            p.add("captive.runs", "no table of captive conditions");
        }
        let names: Vec<String> = self.runs.iter().map(InputSpec::display_name).collect();
        for (run, o) in &self.oscillations {
            let key = format!("captive.oscillations.{}", super::paths::key_text(run));
            if !names.contains(run) {
                p.add(
                    &key,
                    format!(
                        "names no run of captive.runs{} (they are: {})",
                        crate::base::suggest::did_you_mean(run, names.iter().map(String::as_str)),
                        names.join(", ")
                    ),
                );
            }
            if self.average_after.is_none() {
                p.add(
                    &key,
                    "a harmonic run is a force history: give captive.average_after (the end \
                     of its start-up transient, s)",
                );
            }
            p.positive(&format!("{key}.frequency"), o.frequency, "Hz");
            if o.amplitude.is_empty() {
                p.add(&format!("{key}.amplitude"), "names no oscillating velocity");
            }
            for (q, c) in &o.amplitude {
                let k = format!("{key}.amplitude.{q}");
                if !crate::base::quantity::Quantity::MOTION[..6].contains(q) {
                    p.add(&k, "an oscillation moves a velocity: u, v, w, p, q or r");
                } else if let Err(m) = c.expect_quantity(*q) {
                    p.add(&k, m);
                }
            }
        }
        p.inputs(&self.inputs());
    }

    /// The input files this section names.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("captive.runs[{i}]"), r))
            .collect()
    }
}
