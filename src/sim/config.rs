//! The `hydroid simulate` configuration: a model, its coefficients, a manoeuvre, seeded noise
//! and the export layout. Documented in docs/simulate.md.

use crate::config::{Constant, FluidConfig, VehicleConfig};
use crate::error::{ConfigProblem, Error, Result};
use crate::formats::Format;
use crate::quantity::Quantity;
use crate::stages::hekf::ModelName;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A whole simulation configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    /// Title written into the export's header where the layout has one.
    #[serde(default)]
    pub title: Option<String>,
    /// The model that plays the CFD solver.
    #[serde(default)]
    pub model: ModelName,
    /// The vehicle.
    pub vehicle: VehicleConfig,
    /// The fluid.
    pub fluid: FluidConfig,
    /// The "true" coefficients (SI); symmetry relations complete them.
    pub coefficients: BTreeMap<String, f64>,
    /// What to simulate.
    pub manoeuvre: Manoeuvre,
    /// Measurement noise added to the export.
    #[serde(default)]
    pub noise: NoiseConfig,
    /// How to write it.
    pub export: ExportConfig,
}

/// The manoeuvre.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum Manoeuvre {
    /// A time history from an initial state with constant or stepped inputs.
    TimeHistory {
        /// Duration, s.
        duration: f64,
        /// Sampling interval of the export, s.
        dt: f64,
        /// RK4 steps per sample (default 10).
        #[serde(default = "ten")]
        substeps: usize,
        /// Initial state by quantity (SI or with units); missing states start at 0.
        #[serde(default)]
        initial: BTreeMap<Quantity, Constant>,
        /// Inputs at the start, by quantity.
        #[serde(default)]
        inputs: BTreeMap<Quantity, Constant>,
        /// Input changes: at `time`, the listed inputs take new values.
        #[serde(default)]
        steps: Vec<Step>,
    },
    /// Steady polars implied by the coefficients (paper eq. 5 inverted) over a sweep of
    /// angles of attack and speeds, one row per (speed, angle).
    PolarSweep {
        /// Angles of attack, degrees.
        alpha_deg: Vec<f64>,
        /// Flow speeds, m/s.
        speeds: Vec<f64>,
        /// Moment reference length used to define C_M, m.
        moment_reference_length: f64,
        /// Cubic terms added to C_L and C_M (per rad^3), to mimic nonlinear polars.
        #[serde(default)]
        cubic: BTreeMap<Quantity, f64>,
    },
}

fn ten() -> usize {
    10
}

/// An input change (the same as a run configuration's `steps`).
pub use crate::config::Step;

/// Seeded Gaussian noise per exported quantity.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct NoiseConfig {
    /// Random seed (fixed, so exports are reproducible).
    #[serde(default)]
    pub seed: u64,
    /// Standard deviation per quantity (SI or with units).
    #[serde(flatten)]
    pub sigma: BTreeMap<Quantity, Constant>,
}

/// How the export is written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportConfig {
    /// Output file, relative to the simulation configuration (`--out` overrides).
    pub file: PathBuf,
    /// Layout: delimited, cfx, starccm, fluent or openfoam-sixdof.
    pub layout: String,
    /// Columns in order.
    pub columns: Vec<ExportColumn>,
    /// Write Euler angles wrapped to (-180, 180] deg as CFD codes do (default true).
    #[serde(default = "crate::config::yes")]
    pub wrap_angles: bool,
    /// Significant digits (default 10).
    #[serde(default = "default_digits")]
    pub digits: usize,
    /// Separator for the delimited layout (default ",").
    #[serde(default)]
    pub separator: Option<String>,
}

fn default_digits() -> usize {
    10
}

/// One exported column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportColumn {
    /// The quantity.
    pub quantity: Quantity,
    /// Column name in the file.
    pub name: String,
    /// Unit to write in (default SI).
    #[serde(default)]
    pub unit: Option<String>,
}

/// Loaded simulation configuration.
#[derive(Debug, Clone)]
pub struct LoadedSim {
    /// The configuration.
    pub config: SimConfig,
    /// Its folder.
    pub base_dir: PathBuf,
    /// The export layout.
    pub layout: Format,
}

/// Reads and checks a simulation configuration.
pub fn load(path: &Path) -> Result<LoadedSim> {
    let problem = |line: Option<usize>, key: Option<&str>, message: String| ConfigProblem {
        file: path.to_path_buf(),
        line,
        key: key.map(str::to_string),
        message,
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Config(vec![problem(None, None, format!("cannot read: {e}"))]))?;
    let config: SimConfig = toml::from_str(&text).map_err(|e| {
        let line = e.span().map(|s| text[..s.start].matches('\n').count() + 1);
        Error::Config(vec![problem(line, None, e.message().trim().to_string())])
    })?;
    let mut problems = Vec::new();
    let layout = match Format::from_name(&config.export.layout) {
        Some(
            f @ (Format::Delimited
            | Format::Cfx
            | Format::StarCcm
            | Format::Fluent
            | Format::OpenFoamSixDof),
        ) => f,
        _ => {
            problems.push(problem(
                None,
                Some("export.layout"),
                format!(
                    "cannot write layout '{}'; choose delimited, cfx, starccm, fluent or \
                     openfoam-sixdof",
                    config.export.layout
                ),
            ));
            Format::Delimited
        }
    };
    for (name, v) in &config.coefficients {
        if let Err(m) = crate::config::check_coefficient_name(name) {
            problems.push(problem(None, Some(&format!("coefficients.{name}")), m));
        }
        if !v.is_finite() {
            problems.push(problem(
                None,
                Some(&format!("coefficients.{name}")),
                "not finite".into(),
            ));
        }
    }
    if let Manoeuvre::TimeHistory { duration, dt, .. } = &config.manoeuvre {
        if !(*dt > 0.0 && *duration > *dt) {
            problems.push(problem(
                None,
                Some("manoeuvre"),
                format!("need 0 < dt < duration, got dt = {dt}, duration = {duration}"),
            ));
        }
    }
    for c in &config.export.columns {
        if let Some(u) = &c.unit {
            match crate::units::Unit::parse(u) {
                Ok(unit) if unit.dim == c.quantity.dim() => {}
                Ok(unit) => problems.push(problem(
                    None,
                    Some("export.columns"),
                    format!(
                        "unit '{u}' ({}) does not fit {}",
                        crate::units::dim_to_string(unit.dim),
                        c.quantity
                    ),
                )),
                Err(e) => problems.push(problem(None, Some("export.columns"), e.to_string())),
            }
        }
    }
    if !problems.is_empty() {
        return Err(Error::Config(problems));
    }
    Ok(LoadedSim {
        config,
        base_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        layout,
    })
}
