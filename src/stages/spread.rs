//! How much several estimates of one quantity disagree (polar speeds, surge speed bins).

use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The spread of several estimates of one quantity, and whether it is more than their
/// standard errors explain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spread {
    /// What is compared (a coefficient name).
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// The estimates, in order (speed or speed bin).
    pub values: Vec<f64>,
    /// Their standard errors, when known.
    pub sigmas: Vec<Option<f64>>,
    /// Smallest estimate.
    pub min: f64,
    /// Largest estimate.
    pub max: f64,
    /// max - min.
    pub range: f64,
    /// Inverse-variance weighted mean when every standard error is known and positive,
    /// else the plain mean.
    pub mean: f64,
    /// range / |mean| (None when the mean is zero).
    pub relative_range: Option<f64>,
    /// sum ((x_i - mean) / sigma_i)^2, when every standard error is known and positive.
    pub chi2: Option<f64>,
    /// Degrees of freedom of chi2 (estimates - 1).
    pub dof: usize,
    /// Probability of a chi2 at least this large if all estimates measured the same value
    /// (small: the estimates really differ, e.g. a Reynolds-number effect).
    pub p_value: Option<f64>,
}

/// The spread of `estimates` (value, standard error); None for fewer than two.
pub fn spread(name: &str, unit: &str, estimates: &[(f64, Option<f64>)]) -> Option<Spread> {
    if estimates.len() < 2 {
        return None;
    }
    let values: Vec<f64> = estimates.iter().map(|e| e.0).collect();
    let sigmas: Vec<Option<f64>> = estimates.iter().map(|e| e.1).collect();
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let all_sigmas: Option<Vec<f64>> = sigmas
        .iter()
        .map(|s| s.filter(|v| *v > 0.0 && v.is_finite()))
        .collect();
    let dof = values.len() - 1;
    let (mean, chi2) = match &all_sigmas {
        Some(s) => {
            let w: Vec<f64> = s.iter().map(|v| 1.0 / (v * v)).collect();
            let wsum: f64 = w.iter().sum();
            let mean = values.iter().zip(&w).map(|(x, w)| x * w).sum::<f64>() / wsum;
            let chi2 = values
                .iter()
                .zip(s)
                .map(|(x, s)| ((x - mean) / s).powi(2))
                .sum::<f64>();
            (mean, Some(chi2))
        }
        None => (values.iter().sum::<f64>() / values.len() as f64, None),
    };
    let p_value = chi2.and_then(|c| {
        ChiSquared::new(dof as f64)
            .ok()
            .map(|d| (1.0 - d.cdf(c)).clamp(0.0, 1.0))
    });
    Some(Spread {
        name: name.to_string(),
        unit: unit.to_string(),
        values,
        sigmas,
        min,
        max,
        range: max - min,
        mean,
        relative_range: (mean != 0.0).then(|| (max - min) / mean.abs()),
        chi2,
        dof,
        p_value,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consistent_and_inconsistent_estimates() {
        // Two estimates 1 sigma apart each side of the mean: chi2 = 2 with 1 dof.
        let s = spread("Xud", "kg", &[(1.0, Some(1.0)), (3.0, Some(1.0))]).unwrap();
        assert_eq!(s.mean, 2.0);
        assert_eq!(s.chi2, Some(2.0));
        assert!((s.p_value.unwrap() - 0.157_299_207).abs() < 1e-6);
        // Ten sigma apart: clearly different.
        let s = spread("Xud", "kg", &[(1.0, Some(0.1)), (3.0, Some(0.1))]).unwrap();
        assert!(s.p_value.unwrap() < 1e-10);
        assert_eq!(s.range, 2.0);
        assert!(spread("Xud", "kg", &[(1.0, None)]).is_none());
    }
}
