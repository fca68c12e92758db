//! `[autopilot.plant]`: the ship the autopilot steers when it is not the identified model
//! (docs/models/nomoto.md, "Plants"): any registered model with a rudder, built from a
//! vehicle file, its other inputs held, and optionally changed once mid-run
//! (`[autopilot.plant.change]`: a ship that slows down).

use super::Problems;
use crate::base::si;
use crate::model::models::ModelName;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The plant's model name that keeps the identified model as the plant.
pub const IDENTIFIED: &str = "identified";

/// `[autopilot.plant]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlantConfig {
    /// `identified` (the identified model and coefficients, the default without this section)
    /// or a registered model with a rudder input (`mmg3`, `ship_linear`, `nomoto_wave` ...).
    pub model: String,
    /// A vehicle file (`[vehicle]`, `[vehicle.particulars]`, optional `[fluid]` and
    /// `[coefficients]`, as configs/vehicles/*.toml), relative to the configuration's folder;
    /// without one, the run's `[vehicle]` and `[fluid]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vehicle_file: Option<PathBuf>,
    /// Coefficient values (SI) over the vehicle file's.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub coefficients: BTreeMap<String, f64>,
    /// Held inputs other than the rudder, by quantity name, in the model's internal unit
    /// (`rpm` in rev/s): the approach's. Unnamed inputs are held at zero.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, f64>,
    /// The surge speed the plant starts at (models with a surge state; default 0).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Speed>",
        skip_serializing_if = "Option::is_none"
    )]
    pub speed: Option<f64>,
    /// A change mid-run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub change: Option<PlantChange>,
}

/// `[autopilot.plant.change]`: from `at` on, these coefficients, held inputs and surge speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlantChange {
    /// When, s from the start of the run.
    #[serde(deserialize_with = "si::value::<_, si::Time>")]
    pub at: f64,
    /// Coefficient values (SI) over the plant's from then on.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub coefficients: BTreeMap<String, f64>,
    /// Held inputs over the plant's from then on.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, f64>,
    /// The surge speed set at the change (default: the state goes on).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Speed>",
        skip_serializing_if = "Option::is_none"
    )]
    pub speed: Option<f64>,
}

impl PlantConfig {
    /// The plant's model, None for `identified`; Err with the message when the name is
    /// neither.
    pub fn model_name(&self) -> Result<Option<ModelName>, String> {
        if self.model == IDENTIFIED {
            return Ok(None);
        }
        ModelName::from_name(&self.model).map(Some).ok_or_else(|| {
            format!(
                "unknown model `{}`: `{IDENTIFIED}` or one of {}",
                self.model,
                ModelName::NAMES.join(", ")
            )
        })
    }

    /// Adds every problem to `p` (keys `autopilot.plant.*`); `duration` is the run's.
    pub fn validate(&self, duration: f64, p: &mut Problems) {
        let name = match self.model_name() {
            Ok(n) => n,
            Err(m) => return p.add("autopilot.plant.model", m),
        };
        let Some(name) = name else {
            let extra = self.vehicle_file.is_some()
                || !self.coefficients.is_empty()
                || !self.inputs.is_empty()
                || self.speed.is_some()
                || self.change.is_some();
            if extra {
                p.add(
                    "autopilot.plant",
                    "the identified plant takes no vehicle_file, coefficients, inputs, speed \
                     or change: name a model to give them",
                );
            }
            return;
        };
        let known = |p: &mut Problems, key: &str, map: &BTreeMap<String, f64>| {
            for (n, v) in map {
                if !name.coefficients().iter().any(|c| c.name == n) {
                    p.add(
                        &format!("{key}.{n}"),
                        format!("not a coefficient of the {name} model"),
                    );
                } else if !v.is_finite() {
                    p.add(&format!("{key}.{n}"), "a finite number");
                }
            }
        };
        let inputs = |p: &mut Problems, key: &str, map: &BTreeMap<String, f64>| {
            for (n, v) in map {
                let held = name
                    .inputs()
                    .iter()
                    .map(|i| i.quantity)
                    .any(|q| q.key() == n);
                if !held || n == "rudder" {
                    let names: Vec<&str> = name
                        .inputs()
                        .iter()
                        .map(|i| i.quantity.key())
                        .filter(|q| *q != "rudder")
                        .collect();
                    p.add(
                        &format!("{key}.{n}"),
                        format!(
                            "an input of the {name} model other than the rudder (the \
                             autopilot's): {}",
                            if names.is_empty() {
                                "it has none".to_string()
                            } else {
                                names.join(", ")
                            }
                        ),
                    );
                } else if !v.is_finite() {
                    p.add(&format!("{key}.{n}"), "a finite number");
                }
            }
        };
        known(p, "autopilot.plant.coefficients", &self.coefficients);
        inputs(p, "autopilot.plant.inputs", &self.inputs);
        if !name
            .inputs()
            .iter()
            .map(|i| i.quantity)
            .any(|q| q.key() == "rudder")
        {
            p.add(
                "autopilot.plant.model",
                format!("the {name} model has no rudder input: the autopilot cannot steer it"),
            );
        }
        for (key, v) in [("speed", self.speed), ("change.speed", self.change_speed())] {
            if let Some(v) = v {
                p.in_range(
                    &format!("autopilot.plant.{key}"),
                    v,
                    (0.0, 100.0),
                    "m/s",
                    "a ship's speed",
                );
            }
        }
        if let Some(ch) = &self.change {
            known(p, "autopilot.plant.change.coefficients", &ch.coefficients);
            inputs(p, "autopilot.plant.change.inputs", &ch.inputs);
            if !(ch.at > 0.0 && ch.at < duration) {
                p.add(
                    "autopilot.plant.change.at",
                    format!("within the run: between 0 and autopilot.duration = {duration} s"),
                );
            }
        }
    }

    fn change_speed(&self) -> Option<f64> {
        self.change.as_ref().and_then(|c| c.speed)
    }
}
