//! The vehicle data a model is built from: what the configuration's `[vehicle]` and `[fluid]`
//! sections give, in SI units, already checked for plausibility; each model takes what it
//! needs and says what it misses.

use super::coefficient::{AddedMass, Scales};
use crate::model::coefficients::YawMoment;

/// A vehicle and the water it moves in. All values SI (serialised as such in an exported
/// FMU's model.json, docs/fmu.md).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vehicle {
    /// Mass, kg.
    pub mass: f64,
    /// Overall length, m.
    pub length: f64,
    /// Maximum diameter, m (a body of revolution).
    pub diameter: Option<f64>,
    /// Roll moment of inertia about the origin, kg m^2.
    pub ixx: Option<f64>,
    /// Pitch moment of inertia about the origin, kg m^2.
    pub iyy: Option<f64>,
    /// Yaw moment of inertia about the origin, kg m^2.
    pub izz: f64,
    /// Reference area of the force coefficients, m^2.
    pub reference_area: f64,
    /// Buoyancy, N (None: neutrally buoyant).
    pub buoyancy: Option<f64>,
    /// Distance of the centre of gravity below the centre of buoyancy, m.
    pub bg: Option<f64>,
    /// Water density, kg/m^3.
    pub rho: f64,
    /// The model's own data (`[vehicle.particulars]`), read by [`Vehicle::particulars`].
    pub particulars: toml::Table,
}

/// The vehicle as a run of hydroid models it: its data and the run's conventions, the one
/// place a run's yaw-moment reading is held (`VehicleConfig::for_model` makes it), so that
/// every model built in the run reads its coefficients the same way.
#[derive(Debug, Clone, PartialEq)]
pub struct RunVehicle {
    /// The vehicle data.
    pub vehicle: Vehicle,
    /// What the linear yaw-moment coefficients hold (total or lift-only N_uv).
    pub yaw_moment: YawMoment,
}

/// What a model is built from ([`with_model`](super::with_model)): the vehicle data and the
/// yaw-moment reading of the run.
pub trait BuildFrom {
    /// The vehicle data.
    fn vehicle(&self) -> &Vehicle;
    /// The yaw-moment reading the model is built in.
    fn yaw_moment(&self) -> YawMoment;
}

impl BuildFrom for RunVehicle {
    fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }
    fn yaw_moment(&self) -> YawMoment {
        self.yaw_moment
    }
}

/// A bare vehicle (examples, the catalogue, the conformance suite) is read as the seed paper
/// reads it: lift-only.
impl BuildFrom for Vehicle {
    fn vehicle(&self) -> &Vehicle {
        self
    }
    fn yaw_moment(&self) -> YawMoment {
        YawMoment::LiftOnly
    }
}

/// A problem of the vehicle data for a model: the `vehicle.*` key and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VehicleProblem {
    /// The key (`vehicle.ixx`).
    pub key: String,
    /// What is wrong or missing.
    pub message: String,
}

impl VehicleProblem {
    /// A missing key the model `model` needs.
    pub fn missing(model: &str, key: &str, what: &str) -> Self {
        VehicleProblem {
            key: format!("vehicle.{key}"),
            message: format!("the {model} model needs {what}: give `{key}`"),
        }
    }
}

impl Vehicle {
    /// The paper's 6:1 prolate spheroid in sea water (Rasekh & Mahdi 2020, Table 1: m = 50 kg,
    /// L = 1.2 m, D = 0.2 m, Izz = 3.7 kg m^2, A_ref = pi D^2 / 4), with Ixx = 0.2 kg m^2 and
    /// Iyy = Izz, neutrally buoyant with CG at CB.
    pub fn paper_spheroid() -> Self {
        Vehicle {
            mass: 50.0,
            length: 1.2,
            diameter: Some(0.2),
            ixx: Some(0.2),
            iyy: Some(3.7),
            izz: 3.7,
            reference_area: std::f64::consts::PI * 0.01,
            buoyancy: None,
            bg: Some(0.0),
            rho: 1025.0,
            particulars: toml::Table::new(),
        }
    }

    /// For a model that reads no particulars: `[vehicle.particulars]` must be empty (a key
    /// there would otherwise be silently ignored).
    pub fn no_particulars(&self, model: &str) -> Result<(), Vec<VehicleProblem>> {
        if self.particulars.is_empty() {
            return Ok(());
        }
        let keys: Vec<&str> = self.particulars.keys().map(String::as_str).collect();
        Err(vec![VehicleProblem {
            key: "vehicle.particulars".into(),
            message: format!(
                "the {model} model reads no particulars, so {} would be ignored: remove them \
                 or choose the model they are for",
                keys.join(", ")
            ),
        }])
    }

    /// The model's own data from `[vehicle.particulars]`, read into `T` (a serde type of the
    /// model's, with `deny_unknown_fields` and units checked as every configuration number:
    /// `crate::base::si`); every problem names its key under `vehicle.particulars`.
    pub fn particulars<T: serde::de::DeserializeOwned>(
        &self,
        model: &str,
    ) -> Result<T, Vec<VehicleProblem>> {
        // read through TOML text, so that an error's span names the key it is about
        let text = toml::to_string(&self.particulars).unwrap_or_default();
        toml::from_str::<T>(&text).map_err(|e| {
            let message = e.message().to_string();
            // serde names a missing or unknown field in the message; a bad value is on the
            // line its span points at, `key = value`
            let quoted = message
                .split('`')
                .nth(1)
                .filter(|_| {
                    message.starts_with("missing field") || message.starts_with("unknown field")
                })
                .map(str::to_string);
            let spanned = e.span().and_then(|span| {
                let start = text[..span.start.min(text.len())]
                    .rfind('\n')
                    .map_or(0, |i| i + 1);
                let line = text[start..].lines().next()?;
                let key = line.split('=').next()?.trim().trim_matches('"');
                (!key.is_empty() && line.contains('=')).then(|| key.to_string())
            });
            let field = quoted
                .or(spanned)
                .map(|f| format!(".{f}"))
                .unwrap_or_default();
            // in the configuration's words, not serde's
            let message = crate::base::words::translate(&message, false);
            vec![VehicleProblem {
                key: format!("vehicle.particulars{field}"),
                message: format!("the {model} model: {message}"),
            }]
        })
    }

    /// The prime-system scales of the vehicle: q = 0.5 rho A_ref, its length, and Lamb's
    /// added masses when it is a prolate spheroid of the given diameter (Fossen 1994,
    /// section 2.4.1).
    pub fn spheroid_scales(&self) -> Scales {
        let added = self.diameter.and_then(|d| {
            let s =
                crate::model::analytic::Spheroid::from_length_diameter(self.length, d, self.rho)
                    .ok()?;
            Some(AddedMass {
                xud: s.xud(),
                yvd: s.yvd(),
                nrd: s.nrd(),
            })
        });
        Scales {
            q: 0.5 * self.rho * self.reference_area,
            length: self.length,
            added,
        }
    }
}

impl crate::base::error::Error {
    /// What the vehicle data lacks for a model (found by the configuration's validation
    /// first, so met here only by library callers that skip it).
    pub fn vehicle(problems: Vec<VehicleProblem>) -> Self {
        Self::Usage(
            problems
                .iter()
                .map(|p| format!("{}: {}", p.key, p.message))
                .collect::<Vec<_>>()
                .join("; "),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::si;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Ship {
        #[serde(deserialize_with = "si::value::<_, si::Length>")]
        beam: f64,
        #[serde(deserialize_with = "si::value::<_, si::Length>")]
        draught: f64,
    }

    fn with(text: &str) -> Vehicle {
        Vehicle {
            particulars: toml::from_str(text).unwrap(),
            ..Vehicle::paper_spheroid()
        }
    }

    #[test]
    fn particulars_are_read_with_units_and_name_their_key() {
        let s: Ship = with("beam = \"58 m\"\ndraught = 20.8")
            .particulars("ship")
            .unwrap();
        assert_eq!((s.beam, s.draught), (58.0, 20.8));
        let e = with("beam = 58.0").particulars::<Ship>("ship").unwrap_err();
        assert_eq!(e[0].key, "vehicle.particulars.draught", "{e:?}");
        let e = with("beam = 58.0\ndraught = 1.0\nbeem = 2.0")
            .particulars::<Ship>("ship")
            .unwrap_err();
        assert_eq!(e[0].key, "vehicle.particulars.beem", "{e:?}");
        let e = with("beam = \"58 kg\"\ndraught = 1.0")
            .particulars::<Ship>("ship")
            .unwrap_err();
        assert!(e[0].message.contains("kg"), "{e:?}");
        assert_eq!(e[0].key, "vehicle.particulars.beam", "{e:?}");
        let e = with("beam = 1.0\ndraught = \"1 s\"")
            .particulars::<Ship>("ship")
            .unwrap_err();
        assert_eq!(e[0].key, "vehicle.particulars.draught", "{e:?}");
        let e = with("beam = 1.0\ndraught = \"\"")
            .particulars::<Ship>("ship")
            .unwrap_err();
        assert!(!e[0].message.contains("f64"), "in words: {e:?}");
    }

    #[test]
    fn a_model_without_particulars_refuses_them() {
        assert!(with("").no_particulars("spheroid3").is_ok());
        let e = with("beam = 58.0").no_particulars("spheroid3").unwrap_err();
        assert!(e[0].message.contains("beam would be ignored"), "{e:?}");
    }
}
