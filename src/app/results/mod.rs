//! The run's result: what a run of the stages produced, in the form results.json records it
//! (schema in docs/results.md), with the traces the figures need. The pipeline
//! ([`crate::app::pipeline`]) builds it; the report (report/) and the command line only read it.

pub mod comparison;
pub mod inputs;

pub use crate::model::coefficients::{CORRELATED, UNCERTAIN};
pub use comparison::{compare, ComparisonRow};
pub use inputs::{data_word, InputSummary, LoadedInput};

pub use crate::app::resim::{ResimMetrics, ResimTrace};
use crate::config::{Config, LoadedConfig, ReferenceConfig};
use crate::io::record::Record;
use crate::model::coefficients::{Coefficient, CoefficientSet, Correlation};
use crate::stages::hekf::HekfResult;
use crate::stages::polar::PolarResult;
use crate::stages::surge::SurgeResult;
use serde::Serialize;

/// Version of the results.json layout; bumped on any incompatible change.
pub const SCHEMA: &str = "hydroid-results/2";

/// Everything a run produced: the serialisable result and the traces plots need.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// What goes into results.json.
    pub result: RunResult,
    /// Re-simulated trajectories, per run (fit runs first, then validation runs).
    pub resim_traces: Vec<(Record, ResimTrace)>,
    /// The coefficients the identified model was re-simulated with (the HEKF's final set,
    /// completed by the model's relations); None without the HEKF stage.
    pub resim_set: Option<crate::model::coefficients::CoefficientSet>,
}

/// The whole result of a run.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    /// Layout version.
    pub schema: &'static str,
    /// hydroid version that wrote it.
    pub hydroid_version: &'static str,
    /// Title from the configuration.
    pub title: Option<String>,
    /// Vehicle, fluid and the reference quantities used.
    pub vehicle: VehicleSummary,
    /// Every input file with its hash.
    pub inputs: Vec<InputSummary>,
    /// The final coefficient set.
    pub coefficients: Vec<Coefficient>,
    /// Correlations of the coefficients estimated together.
    pub correlation: Option<Correlation>,
    /// Fossen's analytic values (Lamb's k-factors), when the geometry gives them.
    pub analytic: Vec<Coefficient>,
    /// Published values named by the configuration (the first set).
    pub reference: Option<ReferenceConfig>,
    /// Further sets to compare with (`[[reference]]` after the first).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub other_references: Vec<ReferenceConfig>,
    /// Coefficient-by-coefficient comparison.
    pub comparison: Vec<ComparisonRow>,
    /// Each stage's detailed result.
    pub stages: StageResults,
    /// The identified model re-simulated against each run.
    pub resimulation: Vec<ResimMetrics>,
    /// Nomoto's indices of the identified model (a model with a rudder; ships).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steering: Option<crate::dynamics::course_stability::SteeringIndices>,
    /// The autopilot tuned from the identified Nomoto model, closed around it in waves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub autopilot: Option<crate::dynamics::autopilot::AutopilotResult>,
    /// Everything the user should know, from every stage and input, with what it means.
    pub warnings: Vec<crate::base::warning::Warning>,
    /// The effective configuration (defaults and overrides applied).
    pub configuration: Config,
}

/// Per-stage results.
#[derive(Debug, Clone, Default, Serialize)]
pub struct StageResults {
    /// Static polar stage.
    pub polar: Option<PolarResult>,
    /// Surge stage.
    pub surge: Option<SurgeResult>,
    /// Captive runs stage.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub captive: Option<crate::stages::captive::CaptiveResult>,
    /// Hybrid EKF stage.
    pub hekf: Option<HekfResult>,
}

/// Vehicle and fluid as used.
#[derive(Debug, Clone, Serialize)]
pub struct VehicleSummary {
    /// Name.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Diameter, m.
    pub diameter: Option<f64>,
    /// Yaw inertia, kg m^2.
    pub izz: f64,
    /// Reference area of force coefficients, m^2.
    pub reference_area: f64,
    /// Reference length of moment coefficients, m.
    pub reference_length: f64,
    /// Density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub mu: f64,
    /// q = 0.5 rho A_ref, kg/m.
    pub q: f64,
}

impl RunResult {
    /// Assembles the result.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        loaded: &LoadedConfig,
        inputs: Vec<InputSummary>,
        set: CoefficientSet,
        analytic: Vec<Coefficient>,
        comparison: Vec<ComparisonRow>,
        stages: StageResults,
        resimulation: Vec<ResimMetrics>,
        warnings: Vec<crate::base::warning::Warning>,
    ) -> Self {
        let c = &loaded.config;
        let v = &c.vehicle;
        RunResult {
            schema: SCHEMA,
            hydroid_version: env!("CARGO_PKG_VERSION"),
            title: c.title.clone(),
            vehicle: VehicleSummary {
                name: v.name.clone(),
                mass: v.mass,
                length: v.length,
                diameter: v.diameter,
                izz: v.izz,
                reference_area: v.reference_area,
                reference_length: v.reference_length,
                rho: c.fluid.rho,
                mu: c.fluid.mu,
                q: 0.5 * c.fluid.rho * v.reference_area,
            },
            inputs,
            correlation: set.correlation.clone(),
            coefficients: set.iter().cloned().collect(),
            analytic,
            reference: c.reference.primary().cloned(),
            other_references: c.reference.others().to_vec(),
            comparison,
            stages,
            resimulation,
            steering: None,
            autopilot: None,
            warnings,
            configuration: c.clone(),
        }
    }
}
