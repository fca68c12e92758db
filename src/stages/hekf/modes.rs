//! The joint estimate beside the consider one (`hekf.mode = "joint"`): for each estimated
//! coefficient the earlier stage's estimate, what the free-running runs give on their own
//! (consider mode: the HEKF from its own prior), the joint result, and which of the two
//! pins it, in the words a naval architect uses (docs/hekf.md, "Joint estimate").

use super::HekfResult;
use crate::model::coefficients::{Coefficient, CoefficientSet};
use serde::Serialize;

/// One coefficient in both modes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeRow {
    /// Coefficient name.
    pub name: String,
    /// The earlier stage that estimated it (`captive`, `polar`, `surge`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stage: Option<String>,
    /// That stage's value and sigma (SI).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stage_estimate: Option<(f64, f64)>,
    /// Consider mode: the free-running runs from the HEKF's own prior (value, sigma).
    pub consider: (f64, f64),
    /// Joint mode (value, sigma).
    pub joint: (f64, f64),
    /// Whether consider mode found it undetermined by the runs (its identifiability advice).
    pub undetermined_by_runs: bool,
    /// Which data pin it: the earlier stage, the free-running runs, or both alike.
    pub pinned_by: String,
}

/// Both modes, coefficient by coefficient.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeComparison {
    /// One row per estimated coefficient, in estimation order.
    pub rows: Vec<ModeRow>,
}

/// Compares the joint result with the consider one; `known` holds the earlier stages'
/// estimates.
pub fn compare(
    joint: &HekfResult,
    consider: &HekfResult,
    known: &CoefficientSet,
) -> ModeComparison {
    let pair = |c: &Coefficient| (c.value, c.sigma.unwrap_or(0.0));
    let rows = joint
        .coefficients
        .iter()
        .filter_map(|j| {
            let c = consider.coefficients.iter().find(|c| c.name == j.name)?;
            let earlier = known.get(&j.name).filter(|e| {
                matches!(
                    e.source,
                    crate::model::coefficients::Source::Polar
                        | crate::model::coefficients::Source::Surge
                        | crate::model::coefficients::Source::Captive
                )
            });
            let undetermined = consider
                .identifiability
                .iter()
                .any(|a| a.coefficient == j.name);
            let stage_sigma = earlier.and_then(|e| e.sigma);
            let runs_sigma = c.sigma.unwrap_or(f64::INFINITY);
            let pinned_by = match (stage_sigma, earlier) {
                (Some(s), Some(e)) if undetermined && s < runs_sigma => format!(
                    "{} stage: free-running data alone do not determine it",
                    e.source
                ),
                (Some(_), Some(e)) if undetermined => format!(
                    "{} stage and runs together: neither determines it alone",
                    e.source
                ),
                (Some(s), Some(e)) if s < 0.5 * runs_sigma => format!("{} stage", e.source),
                (Some(s), Some(e)) if runs_sigma < 0.5 * s => {
                    format!("free-running runs (the {} stage's is wider)", e.source)
                }
                (Some(_), Some(e)) => format!("both ({} stage and runs)", e.source),
                _ if undetermined => {
                    "nothing: free-running data alone do not determine it".to_string()
                }
                _ => "free-running runs".to_string(),
            };
            Some(ModeRow {
                name: j.name.clone(),
                stage: earlier.map(|e| e.source.to_string()),
                stage_estimate: earlier.map(pair),
                consider: pair(c),
                joint: pair(j),
                undetermined_by_runs: undetermined,
                pinned_by,
            })
        })
        .collect();
    ModeComparison { rows }
}
