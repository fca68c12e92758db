//! `[autopilot.adaptive]` (the adaptive feed's settings) and `[[autopilot.orders]]` (course
//! orders after the first course change), docs/models/nomoto.md "The adaptive autopilot".

use super::Problems;
use crate::base::si;
use crate::dynamics::autopilot::adaptive::Adaptive;
use serde::{Deserialize, Serialize};

fn d() -> Adaptive {
    Adaptive::default()
}
fn retune_every() -> f64 {
    d().retune_every
}
fn guard() -> f64 {
    d().guard
}
fn gain_rate() -> f64 {
    d().gain_rate
}
fn drift() -> f64 {
    d().drift
}
fn prior_sigma() -> f64 {
    d().prior_sigma
}
fn bias_sigma() -> f64 {
    d().bias_sigma
}

/// `[autopilot.adaptive]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveConfig {
    /// Interval between re-placements of the gains (default 10 s).
    #[serde(
        default = "retune_every",
        deserialize_with = "si::value::<_, si::Time>"
    )]
    pub retune_every: f64,
    /// Largest relative sigma of K and T to trust the estimates (default 0.1).
    #[serde(default = "guard")]
    pub guard: f64,
    /// Largest relative change of a gain per second (default 0.02 1/s).
    #[serde(default = "gain_rate")]
    pub gain_rate: f64,
    /// Random walk of K and 1/T, relative per square root of a second (default 0.003).
    #[serde(default = "drift")]
    pub drift: f64,
    /// Starting sigma of K and 1/T relative to the identified values (default 0.3).
    #[serde(default = "prior_sigma")]
    pub prior_sigma: f64,
    /// Starting sigma of the rudder bias (default 2 deg).
    #[serde(default = "bias_sigma", deserialize_with = "si::value::<_, si::Angle>")]
    pub bias_sigma: f64,
    /// Estimate the wave frequency w0 too (default false).
    #[serde(default)]
    pub estimate_w0: bool,
}

impl Default for AdaptiveConfig {
    fn default() -> Self {
        let a = d();
        AdaptiveConfig {
            retune_every: a.retune_every,
            guard: a.guard,
            gain_rate: a.gain_rate,
            drift: a.drift,
            prior_sigma: a.prior_sigma,
            bias_sigma: a.bias_sigma,
            estimate_w0: a.estimate_w0,
        }
    }
}

impl AdaptiveConfig {
    /// The settings the closed loop takes.
    pub fn settings(&self) -> Adaptive {
        Adaptive {
            retune_every: self.retune_every,
            guard: self.guard,
            gain_rate: self.gain_rate,
            drift: self.drift,
            prior_sigma: self.prior_sigma,
            bias_sigma: self.bias_sigma,
            estimate_w0: self.estimate_w0,
        }
    }

    /// Adds every problem to `p` (keys `autopilot.adaptive.*`).
    pub fn validate(&self, dt: f64, p: &mut Problems) {
        let deg = std::f64::consts::PI / 180.0;
        for (key, v, range, unit, why) in [
            (
                "retune_every",
                self.retune_every,
                (dt.max(1e-3), 1e5),
                "s",
                "at least one sample",
            ),
            ("guard", self.guard, (1e-4, 1.0), "-", "a relative sigma"),
            (
                "gain_rate",
                self.gain_rate,
                (1e-6, 10.0),
                "1/s",
                "a relative rate",
            ),
            (
                "drift",
                self.drift,
                (0.0, 1.0),
                "1/sqrt(s)",
                "a relative random walk",
            ),
            (
                "prior_sigma",
                self.prior_sigma,
                (1e-3, 10.0),
                "-",
                "a relative sigma",
            ),
            (
                "bias_sigma",
                self.bias_sigma,
                (1e-3 * deg, 30.0 * deg),
                "rad",
                "up to 30 deg",
            ),
        ] {
            p.in_range(&format!("autopilot.adaptive.{key}"), v, range, unit, why);
        }
    }
}

/// `[[autopilot.orders]]`: a course ordered from a time on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CourseOrder {
    /// When, s.
    #[serde(deserialize_with = "si::value::<_, si::Time>")]
    pub at: f64,
    /// The heading ordered (from the initial course).
    #[serde(deserialize_with = "si::value::<_, si::Angle>")]
    pub course: f64,
}

/// Adds the problems of `orders` to `p`: each within the run, after the first course change
/// and the one before it, at most 180 deg.
pub fn validate_orders(orders: &[CourseOrder], change_at: f64, duration: f64, p: &mut Problems) {
    let mut last = change_at;
    for (i, o) in orders.iter().enumerate() {
        let key = format!("autopilot.orders[{i}]");
        if !(o.at > last && o.at <= duration) {
            p.add(
                &format!("{key}.at"),
                format!(
                    "after the previous order ({last} s; the first after autopilot.change_at) \
                     and within the run ({duration} s)"
                ),
            );
        }
        p.in_range(
            &format!("{key}.course"),
            o.course.abs(),
            (0.0, std::f64::consts::PI),
            "rad",
            "at most 180 deg",
        );
        last = o.at.max(last);
    }
}
