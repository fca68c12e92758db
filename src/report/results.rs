//! results.json: the versioned, documented record of a run (schema in docs/results.md).

use crate::coefficients::{Coefficient, CoefficientSet, Correlation};
use crate::config::{Config, LoadedConfig, ReferenceConfig};
use crate::pipeline::LoadedInput;
use crate::resim::ResimMetrics;
use crate::stages::hekf::HekfResult;
use crate::stages::polar::PolarResult;
use crate::stages::surge::SurgeResult;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Version of the results.json layout; bumped on any incompatible change.
pub const SCHEMA: &str = "hydroid-results/2";

/// Relative standard deviation above which a coefficient is flagged as uncertain.
pub const UNCERTAIN: f64 = 0.1;

/// Correlation above which two estimates are flagged as not separately identifiable.
pub const CORRELATED: f64 = 0.9;

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
    /// Published values named by the configuration.
    pub reference: Option<ReferenceConfig>,
    /// Coefficient-by-coefficient comparison.
    pub comparison: Vec<ComparisonRow>,
    /// Each stage's detailed result.
    pub stages: StageResults,
    /// The identified model re-simulated against each run.
    pub resimulation: Vec<ResimMetrics>,
    /// Everything the user should know, from every stage and input, with what it means.
    pub warnings: Vec<crate::warning::Warning>,
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

/// One input file.
#[derive(Debug, Clone, Serialize)]
pub struct InputSummary {
    /// Configuration key.
    pub key: String,
    /// Name for reports.
    pub name: String,
    /// Path relative to the configuration file.
    pub file: String,
    /// Layout it was read as.
    pub format: String,
    /// Data rows.
    pub rows: usize,
    /// SHA-256 of the file.
    pub sha256: String,
    /// First and last time, s.
    pub time_span: Option<[f64; 2]>,
    /// Quantities read and the unit each was read in.
    pub quantities: BTreeMap<String, String>,
    /// Constants from the configuration (SI).
    pub constants: BTreeMap<String, f64>,
}

impl InputSummary {
    /// Summary of a loaded input; the file path is written relative to `base`.
    pub fn from_loaded(i: &LoadedInput, base: &Path) -> Self {
        let r = &i.record;
        let file = crate::record::report_path(&r.source, base);
        InputSummary {
            key: i.key.clone(),
            name: r.name.clone(),
            file,
            format: r.format.name().to_string(),
            rows: r.rows(),
            sha256: i.sha256.clone(),
            time_span: r.time().and_then(|t| Some([*t.first()?, *t.last()?])),
            quantities: r
                .units
                .iter()
                .map(|(q, u)| (q.key().to_string(), u.clone()))
                .collect(),
            constants: r
                .constants
                .iter()
                .map(|(q, v)| (q.key().to_string(), *v))
                .collect(),
        }
    }
}

/// One line of the comparison table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ComparisonRow {
    /// Coefficient.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// hydroid's value.
    pub value: f64,
    /// Its standard deviation.
    pub sigma: Option<f64>,
    /// Where it came from.
    pub source: String,
    /// Fossen's analytic value.
    pub analytic: Option<f64>,
    /// (value - analytic) / |analytic|, percent (None when the analytic value is 0).
    pub error_vs_analytic_pct: Option<f64>,
    /// The reference (paper) value.
    pub reference: Option<f64>,
    /// (value - reference) / |reference|, percent.
    pub error_vs_reference_pct: Option<f64>,
    /// Warnings: large sigma, strong correlation.
    pub flags: Vec<String>,
    /// The sigma by the stage its uncertainty comes from (they add in quadrature): `polar`,
    /// `surge`, `hekf`; empty for values without uncertainty directions.
    pub budget: BTreeMap<String, f64>,
}

/// Builds the comparison of every coefficient with the analytic and reference values.
pub fn compare(
    set: &CoefficientSet,
    analytic: &[Coefficient],
    reference: Option<&ReferenceConfig>,
) -> Vec<ComparisonRow> {
    let pct = |v: f64, r: f64| (r != 0.0).then(|| 100.0 * (v - r) / r.abs());
    set.iter()
        .map(|c| {
            let a = analytic.iter().find(|x| x.name == c.name).map(|x| x.value);
            let r = reference.and_then(|r| r.values.get(&c.name).copied());
            let mut flags = Vec::new();
            if let Some(s) = c.sigma {
                flags.extend(uncertain(c.value, s));
            }
            if let Some(corr) = &set.correlation {
                if let Some(i) = corr.names.iter().position(|n| *n == c.name) {
                    for (j, other) in corr.names.iter().enumerate() {
                        let rho = corr.matrix[i][j];
                        if j != i && rho.abs() > CORRELATED {
                            flags.push(format!(
                                "not separately identifiable from this run: correlation {rho:+.2} with {other}"
                            ));
                        }
                    }
                }
            }
            ComparisonRow {
                name: c.name.clone(),
                unit: c.unit.clone(),
                value: c.value,
                sigma: c.sigma,
                source: c.source.to_string(),
                analytic: a,
                error_vs_analytic_pct: a.and_then(|a| pct(c.value, a)),
                reference: r,
                error_vs_reference_pct: r.and_then(|r| pct(c.value, r)),
                flags,
                budget: set.budget(&c.name),
            }
        })
        .collect()
}

/// The flag of a coefficient whose sigma is large next to its value, if it is.
fn uncertain(value: f64, sigma: f64) -> Option<String> {
    // a value of exactly 0 has no relative sigma
    if sigma <= 0.0 || !sigma.is_finite() || value == 0.0 {
        return None;
    }
    let r = sigma / value.abs();
    let consequence = if r > 10.0 {
        ": the value is not distinguishable from zero"
    } else if r >= 1.0 {
        ": zero is within one sigma"
    } else {
        ""
    };
    (r > UNCERTAIN).then(|| {
        format!(
            "uncertain: sigma is {} the value{consequence}",
            crate::numfmt::proportion(r)
        )
    })
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
        warnings: Vec<crate::warning::Warning>,
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
            reference: c.reference.clone(),
            comparison,
            stages,
            resimulation,
            warnings,
            configuration: c.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::uncertain;

    #[test]
    fn uncertain_flags_read_sensibly() {
        assert_eq!(uncertain(-1.760, 0.05), None);
        assert_eq!(
            uncertain(-1.760, 0.2859).as_deref(),
            Some("uncertain: sigma is 16 % of the value")
        );
        assert_eq!(
            uncertain(0.5, 1.2).as_deref(),
            Some("uncertain: sigma is 240 % of the value: zero is within one sigma")
        );
        assert_eq!(
            uncertain(1e-10, 0.131003125175).as_deref(),
            Some(
                "uncertain: sigma is 1.3e9 times the value: the value is not distinguishable \
                 from zero"
            )
        );
        assert_eq!(uncertain(0.0, 1.0), None);
    }
}
