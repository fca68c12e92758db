//! What the autopilot sees, feed by feed: the raw compass and gyro, the compass and its
//! difference, the wave filter's psi_L and r_L, an ordinary low-pass filter's heading and its
//! difference, the adaptive filter's (with K, 1/T and the rudder bias estimated and the gains
//! re-placed from them), or the plant's true heading.

use super::adaptive::{Estimate, Tuner};
use super::closed_loop::{LoopError, Scenario};
use super::lowpass::LowPass;
use super::wave_filter::WaveFilter;
use super::{Autopilot, Feed};
use crate::model::models::Model;

/// The feed's state.
pub(super) enum Sight {
    /// Raw compass and gyro.
    Raw,
    /// Compass and its backward difference: the last compass reading.
    Differentiated(Option<f64>),
    /// The wave filter.
    Filter(Box<WaveFilter>),
    /// The ordinary low-pass filter on the compass.
    LowPass(LowPass),
    /// The adaptive filter and its tuner, with how many coefficients it estimates.
    Adaptive(Box<WaveFilter>, Box<Tuner>, usize),
    /// The plant's own heading.
    True,
}

/// Where the loop reads the identified model: heading and yaw-rate states, compass output.
pub(super) type Indices = (usize, usize, usize);

impl Sight {
    /// The feed `feed` on the identified `model` with coefficients `c`.
    pub(super) fn new<M: Model>(
        feed: Feed,
        model: &M,
        c: &[f64],
        at: Indices,
        s: &Scenario,
    ) -> Result<Self, LoopError> {
        Ok(match feed {
            Feed::Raw => Sight::Raw,
            Feed::Differentiated => Sight::Differentiated(None),
            Feed::True => Sight::True,
            Feed::Filter => Sight::Filter(Box::new(WaveFilter::new(model, c, at, s)?)),
            Feed::LowPass => {
                let w = super::series::cutoff(model, c, s).ok_or(LoopError::Missing(
                    "low-pass cut-off above 0 and below the Nyquist frequency pi / dt: a \
                     wave frequency w0 to place it at w0 / 4, or autopilot.lowpass_cutoff",
                ))?;
                Sight::LowPass(LowPass::new(w, s.dt))
            }
            Feed::Adaptive => {
                let mut f = WaveFilter::new(model, c, at, s)?;
                let a = s.adaptive;
                let mut names = vec!["K", "inv_T", "delta0"];
                if a.estimate_w0 {
                    names.push("w0");
                }
                let est = names
                    .iter()
                    .map(|n| model.coefficient_index(n))
                    .collect::<Option<Vec<usize>>>()
                    .ok_or(LoopError::Missing(
                        "K, inv_T, delta0 (and w0) coefficients the adaptive feed estimates \
                         (a nomoto_wave model)",
                    ))?;
                let values: Vec<f64> = est.iter().map(|i| c[*i]).collect();
                // Dinh, Hoang & Pham 2016, eq. 20-22: the parameters as random-walk states
                let sigma: Vec<f64> = names
                    .iter()
                    .zip(&values)
                    .map(|(n, v)| match *n {
                        "delta0" => a.bias_sigma,
                        _ => a.prior_sigma * v.abs(),
                    })
                    .collect();
                let q: Vec<f64> = names
                    .iter()
                    .zip(&sigma)
                    .zip(&values)
                    .map(|((n, sg), v)| match *n {
                        "delta0" => (a.drift * sg).powi(2),
                        _ => (a.drift * v).powi(2),
                    })
                    .collect();
                f.augment(est, &values, &sigma, &q);
                let ne = names.len();
                Sight::Adaptive(Box::new(f), Box::new(Tuner::new(a, s.gains)), ne)
            }
        })
    }

    /// The heading and yaw rate the autopilot sees at sample `k` (time `t`) from the
    /// `compass` and `gyro` readings, the plant's true `(psi, r)` and the rudder `delta` held
    /// over the interval ending at `t`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn see<M: Model>(
        &mut self,
        (k, t, dt): (usize, f64, f64),
        model: &M,
        c: &[f64],
        delta: f64,
        (compass, gyro): (f64, f64),
        truth: (f64, f64),
    ) -> Result<(f64, f64), LoopError> {
        Ok(match self {
            Sight::Raw => (compass, gyro),
            // backward difference of the compass (none before the second sample)
            Sight::Differentiated(last) => {
                let rate = last.map_or(0.0, |p: f64| (compass - p) / dt);
                *last = Some(compass);
                (compass, rate)
            }
            Sight::Filter(f) | Sight::Adaptive(f, _, _) => {
                f.read((k, t, dt), model, c, delta, compass)?
            }
            Sight::LowPass(f) => f.step(compass),
            Sight::True => truth,
        })
    }

    /// The adaptive feed's retuning after the sample at `t`; nothing for the others.
    pub(super) fn retune(&mut self, t: f64, dt: f64, ap: &mut Autopilot) {
        if let Sight::Adaptive(f, tuner, ne) = self {
            let (values, cov) = f.estimates();
            tuner.step(t, dt, (&values, &cov, *ne), ap);
        }
    }

    /// The adaptive feed's estimates over time (empty for the others).
    pub(super) fn history(self) -> Vec<Estimate> {
        match self {
            Sight::Adaptive(_, tuner, _) => tuner.history,
            _ => Vec::new(),
        }
    }
}
