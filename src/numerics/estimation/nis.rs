//! Normalised innovation squared (NIS) and its chi-square consistency bounds
//! (Bar-Shalom, Li & Kirubarajan 2001, section 5.4), widened for a measurement noise that
//! was itself estimated from the data.
//!
//! The chi-square bounds hold for a filter whose noise covariance is known. When the noise
//! variance R_j of channel j is estimated (from the same run), each channel's normalised
//! innovation e^2 / R_j carries the estimate's relative error too: the mean NIS of k samples
//! has the variance 2 m / k of the chi-square law plus the sum over the channels of the
//! estimate's own contribution (`noise_estimate_variance`). The bounds keep the chi-square
//! shape around m, their half-widths scaled by sqrt(1 + extra k / (2 m)) (the ratio of the
//! two standard deviations). Using the whole relative error of R_j for channel j is the
//! conservative side: when the state's uncertainty H P H^T is a large part of the
//! innovation's variance, an error of R_j moves the NIS less.

use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// NIS statistics of one filter pass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NisSummary {
    /// Measurements per sample (degrees of freedom of one NIS value).
    pub dof: usize,
    /// Number of samples.
    pub samples: usize,
    /// Mean NIS; a consistent filter gives about `dof`.
    pub mean: f64,
    /// Two-sided 95 % bounds on the mean NIS for a consistent filter (widened for the
    /// measurement noise's estimation error).
    pub mean_bounds: [f64; 2],
    /// Variance of the mean NIS added by the measurement noise's estimation error (0 when
    /// every channel's noise is given, not estimated).
    pub noise_estimate_variance: f64,
    /// Two-sided 95 % bounds on a single NIS value.
    pub sample_bounds: [f64; 2],
    /// Fraction of samples outside `sample_bounds` (about 0.05 when consistent).
    pub fraction_outside: f64,
    /// Whether the mean lies within its bounds.
    pub consistent: bool,
}

/// Two-sided 95 % interval of a chi-square variable with `dof` degrees of freedom.
pub fn chi2_bounds(dof: f64) -> [f64; 2] {
    match ChiSquared::new(dof) {
        Ok(c) => [c.inverse_cdf(0.025), c.inverse_cdf(0.975)],
        Err(_) => [f64::NAN, f64::NAN],
    }
}

/// One-sided 95 % bound of a sample variance over the true one when the sample variance has
/// `dof` degrees of freedom: chi2_{dof, 0.95} / dof (a variance ratio above it says more
/// than chance; infinite without degrees of freedom).
pub fn variance_ratio_bound(dof: f64) -> f64 {
    variance_ratio_bound_of(dof, 1)
}

/// The bound of [`variance_ratio_bound`] for one of `tests` variance ratios tested together,
/// at the Sidak level 0.95^(1/tests) each, so that a record of white noise passes all of them
/// 95 % of the time (Sidak 1967, JASA 62(318)); one test gives the plain bound. Testing every
/// value of a record at 95 % alone widens some value of most records of white noise.
pub fn variance_ratio_bound_of(dof: f64, tests: usize) -> f64 {
    let level = 0.95f64.powf(1.0 / tests.max(1) as f64);
    match ChiSquared::new(dof) {
        Ok(c) if dof > 0.0 => c.inverse_cdf(level) / dof,
        _ => f64::INFINITY,
    }
}

/// Two-sided 95 % bounds on the mean of `k` NIS values of `dof` degrees of freedom: the
/// chi-square bounds of their sum over `k`, their half-widths about `dof` widened by
/// sqrt(1 + extra k / (2 dof)) for the variance `extra` that an estimated noise adds (module
/// documentation).
pub fn mean_bounds(dof: usize, k: usize, extra: f64) -> [f64; 2] {
    let total = chi2_bounds((k * dof) as f64);
    let (m, k) = (dof as f64, k.max(1) as f64);
    let widen = (1.0 + extra.max(0.0) * k / (2.0 * m)).sqrt();
    [
        (m - (m - total[0] / k) * widen).max(0.0),
        m + (total[1] / k - m) * widen,
    ]
}

/// Summarises per-sample NIS values, each with `dof` degrees of freedom; `extra` is the
/// variance of their mean that the estimation of the measurement noise adds (0 for a noise
/// that is given).
pub fn summarize(nis: &[f64], dof: usize, extra: f64) -> Option<NisSummary> {
    if nis.is_empty() || dof == 0 {
        return None;
    }
    let k = nis.len();
    let mean = nis.iter().sum::<f64>() / k as f64;
    let mean_bounds = mean_bounds(dof, k, extra);
    let sample_bounds = chi2_bounds(dof as f64);
    let outside = nis
        .iter()
        .filter(|v| **v < sample_bounds[0] || **v > sample_bounds[1])
        .count();
    Some(NisSummary {
        dof,
        samples: k,
        mean,
        mean_bounds,
        noise_estimate_variance: extra.max(0.0),
        sample_bounds,
        fraction_outside: outside as f64 / k as f64,
        consistent: mean >= mean_bounds[0] && mean <= mean_bounds[1],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, StandardNormal};

    #[test]
    fn variance_ratio_bounds() {
        // chi2_{4, 0.95} = 9.4877, chi2_{10, 0.95} = 18.307 (tables)
        assert!((variance_ratio_bound(4.0) - 9.4877 / 4.0).abs() < 1e-4);
        assert!((variance_ratio_bound(10.0) - 1.8307).abs() < 1e-4);
        assert!(variance_ratio_bound(0.0).is_infinite());
        // one test is the plain bound; 21 tests at 0.95^(1/21) = 0.997560 each: the
        // chi-square 99.756 % quantile at 4 dof is 16.61 (from the closed form of the
        // 4-dof cdf, 1 - (1 + x/2) exp(-x/2))
        assert_eq!(variance_ratio_bound_of(4.0, 1), variance_ratio_bound(4.0));
        let x = 4.0 * variance_ratio_bound_of(4.0, 21);
        let cdf = 1.0 - (1.0 + x / 2.0) * (-x / 2.0f64).exp();
        assert!((cdf - 0.95f64.powf(1.0 / 21.0)).abs() < 1e-9, "{x} {cdf}");
    }

    #[test]
    fn chi2_quantiles() {
        // tables: chi2_1(0.975) = 5.0239, chi2_6(0.025) = 1.2373, chi2_6(0.975) = 14.4494
        assert!((chi2_bounds(1.0)[1] - 5.0239).abs() < 1e-3);
        let b = chi2_bounds(6.0);
        assert!((b[0] - 1.2373).abs() < 1e-3 && (b[1] - 14.4494).abs() < 1e-3);
    }

    #[test]
    fn consistent_innovations_pass_and_inflated_ones_fail() {
        let mut rng = StdRng::seed_from_u64(7);
        let nis: Vec<f64> = (0..2000)
            .map(|_| {
                (0..3)
                    .map(|_| {
                        let z: f64 = StandardNormal.sample(&mut rng);
                        z * z
                    })
                    .sum()
            })
            .collect();
        let s = summarize(&nis, 3, 0.0).unwrap();
        assert!(s.consistent, "{s:?}");
        assert!((s.fraction_outside - 0.05).abs() < 0.02);
        let inflated: Vec<f64> = nis.iter().map(|v| 1.5 * v).collect();
        assert!(!summarize(&inflated, 3, 0.0).unwrap().consistent);
    }
}
