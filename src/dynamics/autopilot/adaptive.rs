//! The adaptive autopilot of the paper (Dinh, Hoang & Pham 2016, ../shared/docs/
//! nomoto-wave-ekf.md: "the estimates of 1/T and K are updated regularly as the input for the
//! controller design"): the online wave filter with K, 1/T and the rudder bias (and
//! optionally w0) appended as random-walk states estimates them while it steers, and the PID
//! is re-placed from the running estimates (the same pole placement, Fossen 2011), with a
//! guard (the last trusted gains are held while the estimates' relative sigmas exceed a
//! threshold) and a limit on how fast a gain may change.

use super::{Autopilot, Gains};
use serde::Serialize;

/// Settings of the adaptive feed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Adaptive {
    /// Interval between two re-placements of the gains, s.
    pub retune_every: f64,
    /// Largest relative sigma of K/T for the estimates to be trusted.
    pub guard: f64,
    /// Largest relative change of each gain per second, 1/s.
    pub gain_rate: f64,
    /// Random walk of K and 1/T, relative to their starting values per square root of a
    /// second (how fast the filter lets them move: a ship's speed or loading changes).
    pub drift: f64,
    /// Starting standard deviation of K and 1/T relative to their identified values.
    pub prior_sigma: f64,
    /// Starting standard deviation of the rudder bias, rad.
    pub bias_sigma: f64,
    /// Estimate the wave frequency w0 too.
    pub estimate_w0: bool,
}

impl Default for Adaptive {
    fn default() -> Self {
        Adaptive {
            retune_every: 10.0,
            guard: 0.1,
            gain_rate: 0.02,
            drift: 0.003,
            prior_sigma: 0.3,
            bias_sigma: 2f64.to_radians(),
            estimate_w0: false,
        }
    }
}

/// The estimates at one time, with the gains then in use.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// Time, s.
    pub t: f64,
    /// K, 1/s, and its sigma.
    pub k: f64,
    /// Sigma of K.
    pub k_sigma: f64,
    /// T, s (1 / the estimated 1/T), and its sigma (first order).
    pub t_const: f64,
    /// Sigma of T.
    pub t_sigma: f64,
    /// K/T, 1/s^2 (what the proportional gain depends on), and its sigma.
    pub ratio: f64,
    /// Sigma of K/T.
    pub ratio_sigma: f64,
    /// The rudder bias, rad.
    pub delta0: f64,
    /// The wave frequency w0, rad/s, and its sigma, when the feed estimates it
    /// (`estimate_w0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub w0: Option<(f64, f64)>,
    /// Whether the estimates passed the guard.
    pub trusted: bool,
    /// The guard they were held to (largest relative sigma).
    pub guard: f64,
    /// The gains in use.
    pub gains: Gains,
}

impl Estimate {
    /// The estimate from K, 1/T and delta0 (in that order, then w0 when there are four) and
    /// their covariance (3 x 3 at least, row-major over `ne` entries) at time `t`: T = 1/(1/T)
    /// and K/T = K (1/T) with first-order sigmas (the delta method).
    pub fn from_filter(t: f64, values: &[f64], cov: &[f64], ne: usize, gains: Gains) -> Self {
        let (k, inv_t) = (values[0], values[1]);
        let (vk, vi, cki) = (cov[0], cov[ne + 1], cov[1]);
        let ratio_var = inv_t * inv_t * vk + k * k * vi + 2.0 * k * inv_t * cki;
        Estimate {
            t,
            k,
            k_sigma: vk.max(0.0).sqrt(),
            t_const: 1.0 / inv_t,
            t_sigma: vi.max(0.0).sqrt() / (inv_t * inv_t),
            ratio: k * inv_t,
            ratio_sigma: ratio_var.max(0.0).sqrt(),
            delta0: values[2],
            w0: (ne > 3 && values.len() > 3).then(|| (values[3], cov[3 * ne + 3].max(0.0).sqrt())),
            trusted: false,
            guard: f64::INFINITY,
            gains,
        }
    }

    /// Whether K/T (what the gains depend on: K_p = w_n^2 / (K/T), K_d = (2 zeta w_n -
    /// 1/T) / (K/T)) is known within `guard` relatively, with K and T positive.
    pub fn passes(&self, guard: f64) -> bool {
        self.k > 0.0 && self.t_const > 0.0 && self.ratio_sigma / self.ratio <= guard
    }

    /// Whether K and T are each known within `guard` too: the run separates them.
    pub fn separates(&self, guard: f64) -> bool {
        self.passes(guard) && self.k_sigma / self.k <= guard && self.t_sigma / self.t_const <= guard
    }
}

/// The retuning: at every `retune_every` the estimates are read, the gains placed from them
/// when they pass the guard become the target, and the autopilot's gains move towards the
/// target at most `gain_rate` (relative) per second.
pub(super) struct Tuner {
    settings: Adaptive,
    omega_n: f64,
    zeta: f64,
    next: f64,
    target: Gains,
    current: Gains,
    /// Every estimate read, one per `retune_every`.
    pub(super) history: Vec<Estimate>,
}

impl Tuner {
    /// The tuner starting at the gains `start` (placed on the identified K and T).
    pub(super) fn new(settings: Adaptive, start: Gains) -> Self {
        Tuner {
            settings,
            omega_n: start.omega_n,
            zeta: start.zeta,
            next: 0.0,
            target: start,
            current: start,
            history: Vec::new(),
        }
    }

    /// One sample at `t`: reads the estimates (`values`, `cov` over `ne` appended
    /// coefficients) when a retune is due, then moves the gains of `ap`.
    pub(super) fn step(
        &mut self,
        t: f64,
        dt: f64,
        (values, cov, ne): (&[f64], &[f64], usize),
        ap: &mut Autopilot,
    ) {
        if t + 1e-9 >= self.next {
            self.next = t + self.settings.retune_every;
            let mut e = Estimate::from_filter(t, values, cov, ne, self.current);
            e.guard = self.settings.guard;
            e.trusted = e.passes(self.settings.guard);
            if e.trusted {
                if let Ok(g) = Gains::pole_placement(e.k, e.t_const, self.omega_n, self.zeta) {
                    self.target = g;
                } else {
                    e.trusted = false;
                }
            }
            self.history.push(e);
        }
        // each gain towards its target, at most gain_rate relative per second
        let most = self.settings.gain_rate * dt;
        let toward = |now: f64, to: f64| {
            let limit = most * now.abs().max(1e-12);
            now + (to - now).clamp(-limit, limit)
        };
        self.current.kp = toward(self.current.kp, self.target.kp);
        self.current.kd = toward(self.current.kd, self.target.kd);
        self.current.ki = toward(self.current.ki, self.target.ki);
        ap.set_gains(self.current);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K/T's sigma by the delta method: with K and 1/T uncorrelated, (s_r / r)^2 =
    /// (s_K / K)^2 + (s_i / i)^2; T's sigma is s_i / i^2.
    #[test]
    fn the_ratio_and_time_constant_sigmas_follow_the_delta_method() {
        let g = Gains::pole_placement(0.1, 50.0, 0.05, 0.9).unwrap();
        let cov = [1e-6, 0.0, 0.0, 0.0, 4e-8, 0.0, 0.0, 0.0, 1e-6];
        let e = Estimate::from_filter(0.0, &[0.1, 0.02, 0.0], &cov, 3, g);
        assert!((e.t_const - 50.0).abs() < 1e-12);
        assert!((e.t_sigma - 2e-4 / 4e-4).abs() < 1e-12);
        let rel = ((1e-3f64 / 0.1).powi(2) + (2e-4f64 / 0.02).powi(2)).sqrt();
        assert!((e.ratio_sigma / e.ratio - rel).abs() < 1e-12);
        assert!(e.passes(0.02) && !e.passes(0.005));
        assert!(e.separates(0.02));
        // K and 1/T anticorrelated (-0.9): K/T known to 0.45 % while K and T only to 1 %
        let c = -0.9 * 1e-3 * 2e-4;
        let cov = [1e-6, c, 0.0, c, 4e-8, 0.0, 0.0, 0.0, 1e-6];
        let e = Estimate::from_filter(0.0, &[0.1, 0.02, 0.0], &cov, 3, g);
        assert!((e.ratio_sigma / e.ratio - 0.2f64.sqrt() * 1e-2).abs() < 1e-12);
        assert!(e.passes(0.008) && !e.separates(0.008));
    }
}
