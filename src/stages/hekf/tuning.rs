//! Filter tuning: hydroid's defaults (which converge without hand tuning) and the paper's
//! preset, and the estimate of measurement noise from the data.

use super::config::{HekfConfig, Preset};
use crate::quantity::Quantity;

/// Measurement noise standard deviation of a sampled signal, estimated from its fourth
/// differences: for white noise of variance s^2, d4 = y[k+2] - 4y[k+1] + 6y[k] - 4y[k-1] +
/// y[k-2] has variance 70 s^2, while a smooth signal contributes only ~ y'''' dt^4. The
/// median absolute value (times 1.4826, its ratio to sigma for a normal variable) makes the
/// estimate robust to a few outliers. Returns None for fewer than 5 samples.
pub fn noise_sigma(y: &[f64]) -> Option<f64> {
    if y.len() < 5 {
        return None;
    }
    let mut d: Vec<f64> = y
        .windows(5)
        .map(|w| (w[4] - 4.0 * w[3] + 6.0 * w[2] - 4.0 * w[1] + w[0]).abs())
        .collect();
    let mid = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    Some(1.4826 * *median / 70f64.sqrt())
}

/// The smallest measurement standard deviation hydroid uses for a signal: a part in 10^8 of
/// its largest magnitude (and 1e-12 absolute), so that noise-free synthetic data do not make
/// the innovation covariance singular.
pub fn noise_floor(y: &[f64]) -> f64 {
    let peak = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    (1e-8 * peak).max(1e-12)
}

/// The settings that follow from the preset and the explicit keys.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// Filter passes.
    pub passes: usize,
    /// RK4 sub-steps per sample (None: from the sampling interval).
    pub substeps: Option<usize>,
    /// Smoother on the last pass.
    pub smoother: bool,
    /// Measurement noise variance used for every measurement (paper), or None (configured
    /// or estimated per quantity).
    pub fixed_r: Option<f64>,
    /// Initial variance of measured states: None = the measurement noise variance.
    pub p0_measured: Option<f64>,
    /// Prior sigma of coefficients: None = the coefficient's typical magnitude.
    pub prior_sigma: Option<f64>,
    /// Process noise of the states (spectral density, SI^2/s).
    pub q_states: f64,
    /// When set, each dynamic state also gets process noise of this fraction of its
    /// measurement noise variance per sample interval (1 SI unit^2 for unmeasured states).
    /// A part per million keeps the covariance numerically positive definite where the
    /// dynamics make some state combination almost exactly known, without changing the
    /// estimates measurably.
    pub state_jitter: Option<f64>,
    /// Process noise of the coefficients.
    pub q_coefficients: f64,
    /// Prior of repeated passes, in units of the previous sigma.
    pub repeat_prior_factor: Option<f64>,
}

impl Resolved {
    /// The preset's values, with explicit configuration keys applied on top.
    pub fn from_config(c: &HekfConfig) -> Self {
        let mut r = match c.preset {
            Preset::Hydroid => Resolved {
                passes: 3,
                substeps: None,
                smoother: true,
                fixed_r: None,
                p0_measured: None,
                prior_sigma: None,
                q_states: 0.0,
                state_jitter: Some(1e-6),
                q_coefficients: 0.0,
                repeat_prior_factor: Some(100.0),
            },
            // Rasekh & Mahdi 2020, section 4: Q = 1e-4 I, R = 1e-6 I, P0 = 0 for the measured
            // states (1e-12 here, so that P is positive definite) and 1 for the coefficients.
            Preset::Paper => Resolved {
                passes: 1,
                substeps: Some(1),
                smoother: true,
                fixed_r: Some(1e-6),
                p0_measured: Some(1e-12),
                prior_sigma: Some(1.0),
                q_states: 1e-4,
                state_jitter: None,
                q_coefficients: 1e-4,
                repeat_prior_factor: None,
            },
        };
        if let Some(p) = c.passes {
            r.passes = p;
        }
        if let Some(s) = c.substeps {
            r.substeps = Some(s);
        }
        if let Some(s) = c.smoother {
            r.smoother = s;
        }
        r
    }

    /// Sub-steps for a sampling interval `dt`: the configured number, else enough to keep
    /// each RK4 step at or below 10 ms.
    pub fn substeps_for(&self, dt: f64) -> usize {
        self.substeps
            .unwrap_or_else(|| ((dt / 0.01) - 1e-9).ceil().max(1.0) as usize)
    }
}

/// A measurement noise setting and where it came from, for the report.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct NoiseChoice {
    /// Measured quantity.
    pub quantity: Quantity,
    /// Standard deviation used, SI.
    pub sigma: f64,
    /// `configured`, `estimated from the data`, `floor` or `paper preset`.
    pub source: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    #[test]
    fn noise_of_a_smooth_signal_is_recovered() {
        let mut rng = StdRng::seed_from_u64(3);
        let n = Normal::new(0.0, 1e-3).unwrap();
        let y: Vec<f64> = (0..2000)
            .map(|k| {
                let t = k as f64 * 0.01;
                3.0 * (0.3 * t).sin() + 0.5 * t + n.sample(&mut rng)
            })
            .collect();
        let s = noise_sigma(&y).unwrap();
        assert!((s / 1e-3 - 1.0).abs() < 0.1, "{s}");
        let clean: Vec<f64> = (0..2000).map(|k| (k as f64 * 0.01).sin()).collect();
        // a noise-free sine sampled at 10 ms: only its fourth derivative, ~ dt^4 = 1e-8
        assert!(noise_sigma(&clean).unwrap() < 1e-8);
        assert_eq!(noise_sigma(&[1.0, 2.0]), None);
    }

    #[test]
    fn substeps_follow_the_sampling() {
        let r = Resolved {
            passes: 3,
            substeps: None,
            smoother: true,
            fixed_r: None,
            p0_measured: None,
            prior_sigma: None,
            q_states: 0.0,
            state_jitter: None,
            q_coefficients: 0.0,
            repeat_prior_factor: None,
        };
        assert_eq!(r.substeps_for(0.01), 1);
        assert_eq!(r.substeps_for(0.05), 5);
        assert_eq!(r.substeps_for(0.001), 1);
    }
}
