//! `[autopilot.plant]`: the ship the autopilot steers when it is not the identified model
//! (docs/models/nomoto.md, "Plants"): any registered model with a rudder, built from a
//! vehicle file, its other inputs held, and optionally changed once mid-run
//! (`[autopilot.plant.change]`: a ship that slows down).

use super::{motion_limits, Constant, Problems};
use crate::base::quantity::Quantity;
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
    /// Held inputs other than the rudder, by quantity name: a bare number in the model's
    /// internal unit (`rpm` in rev/s), or a string with a unit (`"108 rpm"`): the
    /// approach's. Unnamed inputs are held at zero.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, Constant>,
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
    /// Held inputs over the plant's from then on (as [`PlantConfig::inputs`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, Constant>,
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
        known(p, name, "autopilot.plant.coefficients", &self.coefficients);
        inputs(p, name, "autopilot.plant.inputs", &self.inputs);
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
            let Some(v) = v else { continue };
            let key = format!("autopilot.plant.{key}");
            if v.is_finite() && v <= 0.0 {
                p.add(
                    &key,
                    format!(
                        "{} m/s: a ship at rest does not answer its rudder (its force grows \
                         with the speed squared); give the speed it keeps its course at",
                        crate::base::numfmt::short(v)
                    ),
                );
            } else if let Some(m) = motion_limits::speed(v) {
                p.add(&key, m);
            }
        }
        if let Some(ch) = &self.change {
            known(
                p,
                name,
                "autopilot.plant.change.coefficients",
                &ch.coefficients,
            );
            inputs(p, name, "autopilot.plant.change.inputs", &ch.inputs);
            if !(ch.at > 0.0 && ch.at < duration) {
                p.add(
                    "autopilot.plant.change.at",
                    format!(
                        "{} s is not inside the run: after 0 s and before its end at \
                         autopilot.duration = {duration} s (a change at or after the end never \
                         happens)",
                        crate::base::numfmt::short(ch.at)
                    ),
                );
            }
        }
    }

    fn change_speed(&self) -> Option<f64> {
        self.change.as_ref().and_then(|c| c.speed)
    }
}

/// Each coefficient of `map` (under `key`) is one of the `name` model's, and finite.
fn known(p: &mut Problems, name: ModelName, key: &str, map: &BTreeMap<String, f64>) {
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
}

/// Each held input of `map` (under `key`) is an input of the `name` model other than the
/// rudder, with a unit of its quantity and a plausible value ([`held_input`]).
fn inputs(p: &mut Problems, name: ModelName, key: &str, map: &BTreeMap<String, Constant>) {
    for (n, v) in map {
        let held = name
            .inputs()
            .iter()
            .map(|i| i.quantity)
            .find(|q| q.key() == n && *q != Quantity::Rudder);
        if let Some(q) = held {
            held_input(p, &format!("{key}.{n}"), q, v);
            continue;
        }
        let names: Vec<&str> = name
            .inputs()
            .iter()
            .map(|i| i.quantity.key())
            .filter(|q| *q != "rudder")
            .collect();
        let names = if names.is_empty() {
            "it has none".to_string()
        } else {
            names.join(", ")
        };
        p.add(
            &format!("{key}.{n}"),
            format!(
                "an input of the {name} model other than the rudder (the autopilot's): {names}"
            ),
        );
    }
}

/// A held input `c` of quantity `q` in the model's internal unit (rev/s for `rpm`): a bare
/// number as it is, a value with a unit converted.
pub fn internal(q: Quantity, c: &Constant) -> f64 {
    match c.unit {
        Some(_) => c.si / q.internal_unit().factor,
        None => c.si,
    }
}

/// Checks the held input `c` of quantity `q` at `key`: a unit of its dimension, a magnitude
/// any such input can have, and a propeller turning ahead (a negative rpm or thrust is a
/// crash stop, not a course kept).
fn held_input(p: &mut Problems, key: &str, q: Quantity, c: &Constant) {
    if let Err(m) = c.expect_dim(q.dim()) {
        return p.add(key, m);
    }
    let value = internal(q, c);
    let unit = q.si_symbol();
    let shown = match c.unit {
        Some(_) => format!("{} ({} {unit})", c.text, crate::base::numfmt::num(value)),
        None => format!("{} {unit}", c.text),
    };
    if let Some(m) = motion_limits::magnitude(q, value * q.internal_unit().factor, &shown) {
        return p.add(key, m);
    }
    if matches!(q, Quantity::Rpm | Quantity::Thrust) && value < 0.0 {
        p.add(
            key,
            format!(
                "{shown} drives the ship astern while the autopilot steers it ahead: a sign \
                 mistake? (held inputs are the approach's, ahead)"
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problems(plant: &str) -> Vec<String> {
        let cfg: PlantConfig = toml::from_str(plant).unwrap();
        let mut p = Problems::new(std::path::Path::new("c.toml"), "");
        cfg.validate(600.0, &mut p);
        p.list.iter().map(|c| c.to_string()).collect()
    }

    #[test]
    fn held_inputs_take_units_and_refuse_a_wrong_unit_magnitude_or_sign() {
        let ship = "model = \"ship_linear\"\nspeed = 8.0\n";
        let cfg: PlantConfig =
            toml::from_str(&format!("{ship}inputs = {{ rpm = \"108 rpm\" }}")).unwrap();
        let rev_s = internal(Quantity::Rpm, &cfg.inputs["rpm"]);
        assert!((rev_s - 1.8).abs() < 1e-12, "{rev_s}");
        let bare: PlantConfig = toml::from_str(&format!("{ship}inputs = {{ rpm = 1.8 }}")).unwrap();
        assert_eq!(internal(Quantity::Rpm, &bare.inputs["rpm"]), 1.8);
        assert!(problems(&format!("{ship}inputs = {{ rpm = \"108 rpm\" }}")).is_empty());
        let e = problems(&format!("{ship}inputs = {{ rpm = \"1.8 m/s\" }}")).join("\n");
        assert!(
            e.contains("autopilot.plant.inputs.rpm") && e.contains("m/s"),
            "{e}"
        );
        let e = problems(&format!("{ship}inputs = {{ rpm = -1.8 }}")).join("\n");
        assert!(e.contains("-1.8 rev/s") && e.contains("astern"), "{e}");
        let e = problems(&format!("{ship}inputs = {{ rpm = 1e6 }}")).join("\n");
        assert!(e.contains("beyond any plausible"), "{e}");
        let e = problems("model = \"ship_linear\"\nspeed = 0.0\n").join("\n");
        assert!(
            e.contains("autopilot.plant.speed") && e.contains("at rest"),
            "{e}"
        );
        let e = problems(&format!("{ship}[change]\nat = 600.0\n")).join("\n");
        assert!(
            e.contains("before its end") && e.contains("never happens"),
            "{e}"
        );
    }
}
