//! The TOML run configuration: schema, loading with every problem listed, `--set` overrides,
//! and validation. Every key is documented in docs/config.md.

mod input;
mod load;
mod problems;

pub use input::{ColumnSpec, Constant, FormatSetting, InputSpec, Step, VelocityFrame};
pub use load::{load, load_lenient, load_str, read, LoadedConfig};
pub use problems::Problems;

use crate::coefficients;
use crate::stages::hekf::HekfConfig;
use crate::stages::polar::PolarConfig;
use crate::stages::surge::SurgeConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

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
    /// Published values to compare with (e.g. the source paper's tables).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<ReferenceConfig>,
    /// Static polar stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polar: Option<PolarConfig>,
    /// Surge acceleration stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surge: Option<SurgeConfig>,
    /// Hybrid EKF stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hekf: Option<HekfConfig>,
}

/// The vehicle. All values SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleConfig {
    /// Name for reports.
    #[serde(default = "default_vehicle_name")]
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Overall length, m.
    pub length: f64,
    /// Maximum diameter (twice the minor semi-axis for a spheroid), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// Roll moment of inertia about the origin, kg m^2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ixx: Option<f64>,
    /// Pitch moment of inertia about the origin, kg m^2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iyy: Option<f64>,
    /// Yaw moment of inertia about the origin, kg m^2.
    pub izz: f64,
    /// Reference area for force coefficients, m^2 (the paper uses the frontal area pi b^2).
    pub reference_area: f64,
    /// Reference length for moment coefficients, m (C_M = M / (0.5 rho U^2 A_ref L_ref)).
    pub reference_length: f64,
    /// Buoyancy, N (defaults to the weight: neutrally buoyant).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub buoyancy: Option<f64>,
    /// Height of the centre of buoyancy above the centre of gravity (BG), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bg: Option<f64>,
}

fn default_vehicle_name() -> String {
    "vehicle".to_string()
}

/// The fluid. All values SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidConfig {
    /// Density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
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

/// Published coefficient values to compare with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceConfig {
    /// Citation shown in reports.
    pub name: String,
    /// Coefficient values, SI.
    pub values: BTreeMap<String, f64>,
}

impl Config {
    /// Checks values and names (not input files) and adds every problem to `p`.
    pub fn validate(&self, p: &mut Problems) {
        let v = &self.vehicle;
        p.positive("vehicle.mass", v.mass, "kg");
        p.positive("vehicle.length", v.length, "m");
        p.positive("vehicle.izz", v.izz, "kg m^2");
        p.positive("vehicle.reference_area", v.reference_area, "m^2");
        p.positive("vehicle.reference_length", v.reference_length, "m");
        if let Some(d) = v.diameter {
            p.positive("vehicle.diameter", d, "m");
            if d >= v.length && v.length > 0.0 {
                p.add(
                    "vehicle.diameter",
                    format!(
                        "diameter {d} m is not smaller than the length {} m",
                        v.length
                    ),
                );
            }
        }
        for (key, val) in [("ixx", v.ixx), ("iyy", v.iyy), ("buoyancy", v.buoyancy)] {
            if let Some(x) = val {
                p.positive(&format!("vehicle.{key}"), x, "SI");
            }
        }
        if let Some(bg) = v.bg {
            p.finite("vehicle.bg", bg);
        }
        p.positive("fluid.rho", self.fluid.rho, "kg/m^3");
        p.positive("fluid.mu", self.fluid.mu, "Pa s");
        for (name, val) in &self.coefficients {
            let key = format!("coefficients.{name}");
            p.known_coefficient(&key, name);
            p.finite(&key, *val);
        }
        if let Some(r) = &self.reference {
            for (name, val) in &r.values {
                let key = format!("reference.values.{name}");
                p.known_coefficient(&key, name);
                p.finite(&key, *val);
            }
        }
        if let Some(s) = &self.polar {
            s.validate(self, p);
        }
        if let Some(s) = &self.surge {
            s.validate(self, p);
        }
        if let Some(s) = &self.hekf {
            s.validate(self, p);
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
        if let Some(s) = &self.hekf {
            v.extend(s.inputs());
        }
        v
    }
}

/// Checks a coefficient name against the catalogue.
pub(crate) fn check_coefficient_name(name: &str) -> Result<(), String> {
    if coefficients::info(name).is_some() {
        Ok(())
    } else {
        Err(format!(
            "unknown coefficient '{name}'{}",
            crate::suggest::did_you_mean(name, coefficients::CATALOG.iter().map(|c| c.name))
        ))
    }
}
