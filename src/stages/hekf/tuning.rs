//! Filter tuning: hydroid's defaults (which converge without hand tuning) and the paper's
//! preset.

use super::config::{HekfConfig, Preset};
use crate::base::quantity::Quantity;

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
    /// Initial variance of every state, measured or not (`hekf.state_variance`): overrides
    /// `p0_measured` and the unit variance of unmeasured states.
    pub p0_states: Option<f64>,
    /// Prior sigma of coefficients: None = the coefficient's typical magnitude.
    pub prior_sigma: Option<f64>,
    /// Process noise of the states (spectral density, SI^2/s).
    pub q_states: f64,
    /// When set, each dynamic state also gets process noise of this fraction of its
    /// measurement noise variance per sample interval (1 SI unit^2 for unmeasured states).
    /// A part per million keeps the covariance numerically positive definite where the
    /// dynamics make some state combination almost exactly known. For a model measured
    /// through outputs the variance is chosen per state (`prepare::jitter_variance`).
    pub state_jitter: Option<f64>,
    /// Process noise of the coefficients.
    pub q_coefficients: f64,
    /// Prior of repeated passes, in units of the previous sigma.
    pub repeat_prior_factor: Option<f64>,
    /// Innovation gate in standard deviations (0: none).
    pub gate: f64,
    /// Match the process noise of the measured velocities to the innovations
    /// (`hekf.adapt_noise`; `super::adapt`).
    pub adapt_noise: bool,
}

impl Resolved {
    /// A preset's values.
    pub fn preset(preset: Preset) -> Self {
        match preset {
            Preset::Hydroid => Resolved {
                passes: 3,
                substeps: None,
                smoother: true,
                fixed_r: None,
                p0_measured: None,
                p0_states: None,
                prior_sigma: None,
                q_states: 0.0,
                state_jitter: Some(1e-6),
                q_coefficients: 0.0,
                repeat_prior_factor: Some(100.0),
                gate: super::config::DEFAULT_GATE,
                adapt_noise: true,
            },
            // Rasekh & Mahdi 2020, section 4: Q = 1e-4 I, R = 1e-6 I, P0 = 0 for the measured
            // states (1e-12 here, so that P is positive definite) and 1 for the coefficients.
            Preset::Paper => Resolved {
                passes: 1,
                substeps: Some(1),
                smoother: true,
                fixed_r: Some(1e-6),
                p0_measured: Some(1e-12),
                p0_states: None,
                prior_sigma: Some(1.0),
                q_states: 1e-4,
                state_jitter: None,
                q_coefficients: 1e-4,
                repeat_prior_factor: None,
                // the paper gates nothing
                gate: 0.0,
                adapt_noise: false,
            },
        }
    }

    /// The preset's values, with explicit configuration keys applied on top.
    pub fn from_config(c: &HekfConfig) -> Self {
        let mut r = Self::preset(c.preset);
        if let Some(p) = c.passes {
            r.passes = p;
        }
        if let Some(s) = c.substeps {
            r.substeps = Some(s);
        }
        if let Some(s) = c.smoother {
            r.smoother = s;
        }
        if let Some(g) = c.gate {
            r.gate = g;
        }
        if let Some(v) = c.state_variance {
            r.p0_states = Some(v);
        }
        if let Some(a) = c.adapt_noise {
            r.adapt_noise = a;
        }
        r
    }

    /// Sub-steps for a sampling interval `dt`: the configured number, else enough to keep
    /// each RK4 step at or below 10 ms.
    pub fn substeps_for(&self, dt: f64) -> usize {
        self.substeps.unwrap_or_else(|| {
            crate::numerics::ode::steps_for(dt, crate::numerics::ode::DEFAULT_MAX_STEP)
                .unwrap_or(crate::numerics::ode::MAX_STEPS_PER_INTERVAL)
        })
    }
}

/// A measurement noise setting and where it came from, for the report.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct NoiseChoice {
    /// Measured quantity.
    pub quantity: Quantity,
    /// Standard deviation used, SI.
    pub sigma: f64,
    /// `configured`, `estimated from the data`, `floor`, `paper preset`, or the related
    /// channel it was judged against.
    pub source: String,
    /// RMS rounding error of the printed values (print step / sqrt 12), SI, added to each
    /// sample's variance at its own step, when the channel is printed with so few digits
    /// that it matters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rounding: Option<f64>,
    /// Variance that an estimated noise's own error adds to the channel's mean normalised
    /// innovation (0 for a configured, preset or held noise); widens the NIS test's bounds.
    #[serde(skip)]
    pub estimate_variance: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substeps_follow_the_sampling() {
        let r = Resolved {
            passes: 3,
            substeps: None,
            smoother: true,
            fixed_r: None,
            p0_measured: None,
            p0_states: None,
            prior_sigma: None,
            q_states: 0.0,
            state_jitter: None,
            q_coefficients: 0.0,
            repeat_prior_factor: None,
            gate: 0.0,
            adapt_noise: false,
        };
        assert_eq!(r.substeps_for(0.01), 1);
        assert_eq!(r.substeps_for(0.05), 5);
        assert_eq!(r.substeps_for(0.001), 1);
    }
}
