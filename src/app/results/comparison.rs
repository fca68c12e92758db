//! The comparison of every coefficient with Fossen's analytic value and the reference
//! (paper) value, with the flags of a large sigma or a strong correlation.

use crate::config::References;
use crate::model::coefficients::{Coefficient, CoefficientSet, CORRELATED, UNCERTAIN};
use serde::Serialize;
use std::collections::BTreeMap;

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
    /// The further reference sets (`[[reference]]` after the first), in order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub other_references: Vec<OtherReference>,
    /// Warnings: large sigma, strong correlation.
    pub flags: Vec<String>,
    /// The sigma by the stage its uncertainty comes from (they add in quadrature): `polar`,
    /// `surge`, `hekf`; empty for values without uncertainty directions.
    pub budget: BTreeMap<String, f64>,
}

/// A coefficient's value in a further reference set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OtherReference {
    /// The set's name (citation).
    pub name: String,
    /// Its value, when the set has one.
    pub value: Option<f64>,
    /// (value - reference) / |reference|, percent.
    pub error_pct: Option<f64>,
}

/// (v - r) / |r| in percent; none when r is 0.
fn pct(v: f64, r: f64) -> Option<f64> {
    (r != 0.0).then(|| 100.0 * (v - r) / r.abs())
}

/// Builds the comparison of every coefficient with the analytic and reference values.
pub fn compare(
    set: &CoefficientSet,
    analytic: &[Coefficient],
    references: &References,
) -> Vec<ComparisonRow> {
    set.iter()
        .map(|c| {
            let a = analytic.iter().find(|x| x.name == c.name).map(|x| x.value);
            let r = references
                .primary()
                .and_then(|r| r.values.get(&c.name).copied());
            let other_references = references
                .others()
                .iter()
                .map(|o| {
                    let value = o.values.get(&c.name).copied();
                    OtherReference {
                        name: o.name.clone(),
                        value,
                        error_pct: value.and_then(|r| pct(c.value, r)),
                    }
                })
                .collect();
            let mut flags = Vec::new();
            if let Some(s) = c.sigma {
                flags.extend(uncertain(c.value, s));
            }
            if c.is_held() {
                flags.push(crate::model::coefficients::HELD.to_string());
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
                other_references,
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
            crate::base::numfmt::proportion(r)
        )
    })
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
