//! The TOML run configuration: schema, loading with every problem listed, `--set` overrides,
//! and validation. Every key is documented in docs/config.md. Each stage's section
//! ([`polar`], [`surge`], [`hekf`]) lives here, so that the stages depend on the
//! configuration and not the other way round.

pub mod autopilot;
pub mod autopilot_adaptive;
pub mod autopilot_plant;
pub mod captive;
mod collect;
pub mod hekf;
mod input_checks;
mod load;
pub mod motion_limits;
mod overrides;
mod paths;
pub mod polar;
mod problems;
mod protected;
mod reference;
pub mod surge;

pub use crate::base::si::Constant;
pub(crate) use crate::io::input_spec::quantity_key;
pub use crate::io::input_spec::{
    Between, ColumnSpec, DataSource, FormatSetting, InputSpec, ManoeuvreSpec, Step, VelocityFrame,
};
pub(crate) use collect::read_collecting;
pub use load::{load, load_lenient, load_str, read, LoadedConfig};
pub use problems::Problems;
pub use reference::{ReferenceConfig, References};

use crate::base::{si, words};
use crate::model::coefficients::YawMoment;
use crate::model::models::RunVehicle;
use hekf::HekfConfig;
use polar::PolarConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;
use surge::SurgeConfig;

/// A whole run configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// A title for reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    /// The vehicle: mass, inertia, geometry and reference quantities.
    pub vehicle: VehicleConfig,
    /// The fluid.
    pub fluid: FluidConfig,
    /// Where and what to write.
    #[serde(default)]
    pub output: OutputConfig,
    /// Coefficients known beforehand (SI), used where no stage provides them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub coefficients: BTreeMap<String, f64>,
    /// Published values to compare with (e.g. the source paper's tables): one set or several.
    #[serde(default, skip_serializing_if = "References::is_empty")]
    pub reference: References,
    /// Static polar stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polar: Option<PolarConfig>,
    /// Surge acceleration stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surge: Option<SurgeConfig>,
    /// Captive runs stage (steady forces of a held motion).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub captive: Option<captive::CaptiveConfig>,
    /// Hybrid EKF stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hekf: Option<HekfConfig>,
    /// The autopilot tuned from the identified Nomoto model, closed around it in waves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub autopilot: Option<autopilot::AutopilotConfig>,
}

/// The vehicle. All values SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleConfig {
    /// Name for reports.
    #[serde(default = "default_vehicle_name")]
    pub name: String,
    /// Mass, kg.
    #[serde(deserialize_with = "si::value::<_, si::Mass>")]
    pub mass: f64,
    /// Overall length, m.
    #[serde(deserialize_with = "si::value::<_, si::Length>")]
    pub length: f64,
    /// Maximum diameter (twice the minor semi-axis for a spheroid), m.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Length>",
        skip_serializing_if = "Option::is_none"
    )]
    pub diameter: Option<f64>,
    /// Roll moment of inertia about the origin, kg m^2.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Inertia>",
        skip_serializing_if = "Option::is_none"
    )]
    pub ixx: Option<f64>,
    /// Pitch moment of inertia about the origin, kg m^2.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Inertia>",
        skip_serializing_if = "Option::is_none"
    )]
    pub iyy: Option<f64>,
    /// Yaw moment of inertia about the origin, kg m^2.
    #[serde(deserialize_with = "si::value::<_, si::Inertia>")]
    pub izz: f64,
    /// Reference area for force coefficients, m^2 (the paper uses the frontal area pi b^2).
    #[serde(deserialize_with = "si::value::<_, si::Area>")]
    pub reference_area: f64,
    /// Reference length for moment coefficients, m (C_M = M / (0.5 rho U^2 A_ref L_ref)).
    #[serde(deserialize_with = "si::value::<_, si::Length>")]
    pub reference_length: f64,
    /// Buoyancy, N (defaults to the weight: neutrally buoyant).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Force>",
        skip_serializing_if = "Option::is_none"
    )]
    pub buoyancy: Option<f64>,
    /// Height of the centre of buoyancy above the centre of gravity (BG), m.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Length>",
        skip_serializing_if = "Option::is_none"
    )]
    pub bg: Option<f64>,
    /// Scale ratio lambda = L_ship / L_model of the data (1 at full scale): the IMO
    /// 10/10 zig-zag overshoot limits depend on the full-scale L/V and are judged only when
    /// it is known (MSC.137(76) 5.3.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// What a particular model needs besides the above (`[vehicle.particulars]`: a ship's
    /// beam, draught, propeller and rudder data ...), read and checked by the model.
    #[serde(default, skip_serializing_if = "toml::Table::is_empty")]
    pub particulars: toml::Table,
    /// The run's yaw-moment reading, not a key: resolved once when the configuration is
    /// loaded (`polar.moment.part` when a polar stage runs, else the known coefficients:
    /// [`Config::yaw_moment`]) and given to every model built for the vehicle.
    #[serde(skip)]
    pub yaw_moment: YawMoment,
}

fn default_vehicle_name() -> String {
    "vehicle".to_string()
}

/// The fluid. All values SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidConfig {
    /// Density, kg/m^3.
    #[serde(deserialize_with = "si::value::<_, si::Density>")]
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    #[serde(deserialize_with = "si::value::<_, si::Viscosity>")]
    pub mu: f64,
}

impl FluidConfig {
    /// Kinematic viscosity, m^2/s.
    pub fn nu(&self) -> f64 {
        self.mu / self.rho
    }
}

/// Output settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Output folder, relative to the configuration file (`--out` overrides it).
    #[serde(default = "default_out_dir")]
    pub dir: PathBuf,
    /// Write plots (SVG and PNG).
    #[serde(default = "yes")]
    pub plots: bool,
}

impl Default for OutputConfig {
    fn default() -> Self {
        OutputConfig {
            dir: default_out_dir(),
            plots: true,
        }
    }
}

fn default_out_dir() -> PathBuf {
    PathBuf::from("out")
}

pub(crate) fn yes() -> bool {
    true
}

/// Plausible ranges: values outside them are almost surely a unit or typing mistake (a
/// density of 1.025 given in t/m^3, a viscosity of 1e-6 that is the kinematic one). hydroid
/// models vehicles moving in water, so the fluid ranges are those of water, fresh to brine,
/// 0 to 100 deg C (documented in docs/config.md).
pub mod plausible {
    /// Vehicle mass, kg: a 1 g model to a 1 million tonne ship.
    pub const MASS: (f64, f64) = (1e-3, 1e9);
    /// Vehicle length, m.
    pub const LENGTH: (f64, f64) = (0.01, 1000.0);
    /// Vehicle diameter, m (and smaller than the length).
    pub const DIAMETER: (f64, f64) = (1e-3, 500.0);
    /// Water density, kg/m^3.
    pub const RHO: (f64, f64) = (500.0, 2000.0);
    /// Dynamic viscosity of water, Pa s (2.8e-4 at 100 deg C, 1.8e-3 at 0 deg C).
    pub const MU: (f64, f64) = (1e-4, 0.1);
    /// Reference area as a multiple of length^2 (a frontal area is about 1e-2 L^2).
    pub const AREA_PER_L2: (f64, f64) = (1e-6, 100.0);
    /// Reference length as a multiple of the length.
    pub const LREF_PER_L: (f64, f64) = (1e-3, 100.0);
    /// Radius of gyration sqrt(I / m) as a multiple of the length.
    pub const GYRATION_PER_L: (f64, f64) = (1e-4, 1.0);
    /// Buoyancy as a multiple of the weight.
    pub const BUOYANCY_PER_WEIGHT: (f64, f64) = (0.1, 10.0);
}

/// Standard gravity, m/s^2 (the weight that buoyancy is compared with).
const G: f64 = 9.80665;

impl VehicleConfig {
    /// The vehicle and the fluid as a model is built from them, with the run's yaw-moment
    /// reading.
    pub fn for_model(&self, fluid: &FluidConfig) -> RunVehicle {
        RunVehicle {
            vehicle: self.vehicle_data(fluid),
            yaw_moment: self.yaw_moment,
        }
    }

    /// The vehicle data alone (SI).
    pub fn vehicle_data(&self, fluid: &FluidConfig) -> crate::model::models::Vehicle {
        crate::model::models::Vehicle {
            mass: self.mass,
            length: self.length,
            diameter: self.diameter,
            ixx: self.ixx,
            iyy: self.iyy,
            izz: self.izz,
            reference_area: self.reference_area,
            buoyancy: self.buoyancy,
            bg: self.bg,
            rho: fluid.rho,
            particulars: self.particulars.clone(),
        }
    }

    /// Adds every problem with the vehicle (keys `vehicle.*`) to `p`.
    pub fn validate(&self, p: &mut Problems) {
        let ok = |p: &Problems, k: &str| !p.is_poisoned(k);
        let m_ok = p.plausible("vehicle.mass", self.mass, plausible::MASS, "kg", "")
            && ok(p, "vehicle.mass");
        let l_ok = p.plausible("vehicle.length", self.length, plausible::LENGTH, "m", "")
            && ok(p, "vehicle.length");
        let (l, m) = (self.length, self.mass);
        if let Some(d) = self.diameter {
            if p.plausible("vehicle.diameter", d, plausible::DIAMETER, "m", "") && l_ok && d >= l {
                p.add(
                    "vehicle.diameter",
                    format!("diameter {d} m is not smaller than the length {l} m"),
                );
            }
        }
        for (key, val) in [
            ("ixx", self.ixx),
            ("iyy", self.iyy),
            ("izz", Some(self.izz)),
        ] {
            let Some(i) = val else { continue };
            let key = format!("vehicle.{key}");
            p.positive(&key, i, "kg m^2");
            let (lo, hi) = plausible::GYRATION_PER_L;
            let k = (i / m).sqrt();
            if i.is_finite() && i > 0.0 && m_ok && l_ok && !(k >= lo * l && k <= hi * l) {
                p.add(
                    &key,
                    format!(
                        "{i} kg m^2 gives a radius of gyration sqrt(I/m) = {k:.3e} m, outside \
                         the plausible {lo} to {hi} times the length ({:.3e} to {:.3e} m); \
                         check the value and its unit",
                        lo * l,
                        hi * l
                    ),
                );
            }
        }
        let relative = |range: (f64, f64), scale: f64| {
            if l_ok {
                (range.0 * scale, range.1 * scale)
            } else {
                (f64::MIN_POSITIVE, f64::MAX)
            }
        };
        p.plausible(
            "vehicle.reference_area",
            self.reference_area,
            relative(plausible::AREA_PER_L2, l * l),
            "m^2",
            "",
        );
        p.plausible(
            "vehicle.reference_length",
            self.reference_length,
            relative(plausible::LREF_PER_L, l),
            "m",
            "",
        );
        if let Some(b) = self.buoyancy {
            let w = m * G;
            let range = if m_ok {
                let (lo, hi) = plausible::BUOYANCY_PER_WEIGHT;
                (lo * w, hi * w)
            } else {
                (f64::MIN_POSITIVE, f64::MAX)
            };
            p.plausible(
                "vehicle.buoyancy",
                b,
                range,
                "N",
                "buoyancy is compared with the weight m g",
            );
        }
        if let Some(lambda) = self.scale {
            if let Err(m) = check_scale(lambda) {
                p.add("vehicle.scale", m.to_string());
            }
        }
        if let Some(bg) = self.bg {
            p.finite("vehicle.bg", bg);
            if bg.is_finite() && l_ok && bg.abs() >= l {
                p.add(
                    "vehicle.bg",
                    format!("|bg| = {} m is not smaller than the length {l} m", bg.abs()),
                );
            }
        }
    }
}

impl FluidConfig {
    /// Adds every problem with the fluid (keys `fluid.*`) to `p`.
    pub fn validate(&self, p: &mut Problems) {
        p.plausible(
            "fluid.rho",
            self.rho,
            plausible::RHO,
            "kg/m^3",
            "water is 998 to 1030 kg/m^3; a value near 1 is in g/cm^3 or t/m^3",
        );
        p.plausible(
            "fluid.mu",
            self.mu,
            plausible::MU,
            "Pa s",
            "water is 2.8e-4 to 1.8e-3 Pa s; a value near 1e-6 is the kinematic viscosity nu \
             in m^2/s",
        );
    }
}

impl Config {
    /// The run's yaw-moment reading, the one source every model of the run is built in:
    /// `polar.moment.part` when a polar stage runs, else what the known coefficients imply
    /// (`[coefficients]` and the captive and HEKF estimates: Nuv without Nuvl is the total
    /// moment, otherwise lift-only). Err((key, message)) when Nuv and Nuvl are both given,
    /// which would over-determine Nuv = Nuva + Nuvl (paper eq. 2).
    pub fn yaw_moment(&self) -> std::result::Result<YawMoment, (String, String)> {
        let polar = self.polar.as_ref().filter(|p| p.enabled);
        let mut given: Vec<(&str, String)> = Vec::new();
        if let Some(p) = polar {
            let part = p.moment_part();
            given.push((
                part.polar_coefficient(),
                format!("polar.moment.part = \"{part}\""),
            ));
        }
        given.extend(
            self.coefficients
                .keys()
                .map(|n| (n.as_str(), format!("coefficients.{n}"))),
        );
        for (stage, estimate) in [
            (
                "captive",
                self.captive
                    .as_ref()
                    .filter(|c| c.enabled)
                    .map(|c| &c.estimate),
            ),
            (
                "hekf",
                self.hekf
                    .as_ref()
                    .filter(|h| h.enabled)
                    .map(|h| &h.estimate),
            ),
        ] {
            for n in estimate.into_iter().flatten() {
                given.push((n.as_str(), format!("{stage}.estimate")));
            }
        }
        let from = |name: &str| given.iter().find(|(n, _)| *n == name).map(|(_, k)| k);
        if let (Some(nuv), Some(nuvl)) = (from("Nuv"), from("Nuvl")) {
            return Err((nuvl.clone(), YawMoment::both_given(nuv, nuvl)));
        }
        Ok(match polar {
            Some(p) => p.moment_part(),
            None => {
                YawMoment::of_names(given.iter().map(|(n, _)| *n)).unwrap_or(YawMoment::LiftOnly)
            }
        })
    }

    /// Checks values and names (not input files) and adds every problem to `p`; `vehicle`
    /// is the run's vehicle built from this configuration (the models check it).
    pub fn validate(&self, vehicle: &RunVehicle, p: &mut Problems) {
        self.vehicle.validate(p);
        self.fluid.validate(p);
        for (name, val) in &self.coefficients {
            let key = format!("coefficients.{name}");
            p.known_coefficient(&key, name);
            p.coefficient_sized(&key, *val);
        }
        let several = self.reference.0.len() > 1;
        for (i, r) in self.reference.iter().enumerate() {
            for (name, val) in &r.values {
                let key = if several {
                    format!("reference[{i}].values.{name}")
                } else {
                    format!("reference.values.{name}")
                };
                p.known_coefficient(&key, name);
                p.coefficient_sized(&key, *val);
            }
        }
        if let Some(s) = &self.polar {
            s.validate(self, p);
        }
        if let Some(s) = &self.surge {
            s.validate(self, p);
        }
        if let Some(s) = &self.captive {
            s.validate(vehicle, p);
        }
        if let Some(s) = &self.hekf {
            s.validate(vehicle, p);
        }
        if let Some(a) = &self.autopilot {
            a.validate(p);
            if !self.hekf.as_ref().is_some_and(|h| h.enabled) {
                p.add(
                    "autopilot",
                    "the autopilot is tuned from and closed around the HEKF's identified model: \
                     add the [hekf] stage",
                );
            }
        }
        let model_stage = self.hekf.as_ref().is_some_and(|h| h.enabled)
            || self.captive.as_ref().is_some_and(|c| c.enabled);
        if !self.vehicle.particulars.is_empty() && !model_stage {
            // only a model reads them: without a model's stage they would be ignored
            p.add(
                "vehicle.particulars",
                "only a model reads [vehicle.particulars], and no stage here uses one (no \
                 [hekf] or [captive] stage): remove them or add the stage",
            );
        }
        let stage_unusable = ["polar", "surge", "captive", "hekf"]
            .iter()
            .any(|s| p.is_poisoned(s) || p.is_poisoned(&format!("{s}.enabled")));
        if self.enabled_stages().is_empty() && !stage_unusable {
            p.add_unplaced(
                None,
                "nothing to run: enable at least one of polar, surge, captive, hekf (a \
                 [polar], [surge], [captive] or [hekf] section with enabled = true, the \
                 default)",
            );
        }
    }

    /// The stages that are configured and enabled, in pipeline order.
    pub fn enabled_stages(&self) -> Vec<&'static str> {
        let mut s = Vec::new();
        if self.polar.as_ref().is_some_and(|c| c.enabled) {
            s.push("polar");
        }
        if self.surge.as_ref().is_some_and(|c| c.enabled) {
            s.push("surge");
        }
        if self.captive.as_ref().is_some_and(|c| c.enabled) {
            s.push("captive");
        }
        if self.hekf.as_ref().is_some_and(|c| c.enabled) {
            s.push("hekf");
        }
        s
    }

    /// Every input file the configuration names, with its key path.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        let mut v = Vec::new();
        if let Some(s) = &self.polar {
            v.extend(s.inputs());
        }
        if let Some(s) = &self.surge {
            v.extend(s.inputs());
        }
        if let Some(s) = &self.captive {
            v.extend(s.inputs());
        }
        if let Some(s) = &self.hekf {
            v.extend(s.inputs());
        }
        v
    }
}

/// The scale ratios lambda = L_ship / L_model hydroid accepts (`vehicle.scale`, `hydroid
/// manoeuvre --scale`): 1 (full scale) to 1000.
pub const SCALE_RANGE: (f64, f64) = (1.0, 1000.0);

/// Checks a scale ratio against [`SCALE_RANGE`]; the error says what was expected.
pub fn check_scale(lambda: f64) -> std::result::Result<(), ScaleOutOfRange> {
    let (lo, hi) = SCALE_RANGE;
    if lambda.is_finite() && (lo..=hi).contains(&lambda) {
        Ok(())
    } else {
        Err(ScaleOutOfRange(lambda))
    }
}

/// A scale ratio outside [`SCALE_RANGE`].
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "{0} is not a scale ratio L_ship / L_model: expected a number from {lo} (full scale) to {hi}",
    lo = SCALE_RANGE.0,
    hi = SCALE_RANGE.1
)]
pub struct ScaleOutOfRange(pub f64);

/// Checks a coefficient name against the catalogue.
pub(crate) fn check_coefficient_name(name: &str) -> Result<(), UnknownCoefficient> {
    if crate::model::models::registry::coefficient(name).is_some() {
        Ok(())
    } else {
        Err(UnknownCoefficient(name.to_string()))
    }
}

/// A coefficient name the catalogue does not hold; the message suggests the nearest names.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("unknown coefficient '{0}'{hint}", hint = nearest_coefficients(.0))]
pub struct UnknownCoefficient(pub String);

/// "did you mean" with the catalogue's coefficient names nearest to `name`.
fn nearest_coefficients(name: &str) -> String {
    crate::base::suggest::did_you_mean(
        name,
        crate::model::models::registry::all_coefficients()
            .iter()
            .map(|c| c.name),
    )
}
