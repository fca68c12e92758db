//! A heading autopilot tuned from Nomoto's K and T: a PID controller placed on the
//! first-order Nomoto model (Fossen 2011, Handbook of Marine Craft Hydrodynamics and Motion
//! Control, PID pole placement for the Nomoto ship: m = T/K, d = 1/K, K_p = m w_n^2,
//! K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10), fed by a third-order reference model of the
//! commanded heading (Fossen 2011, 10.2.1: a low-pass filter cascaded with a mass-damper-
//! spring), with the rudder limited in angle and rate as a steering gear is.

pub mod adaptive;
pub mod closed_loop;
mod pid;
pub mod plant;
mod reference;
pub mod seas;
mod sight;
pub mod wave_filter;

pub use closed_loop::{ClosedLoop, Feed};
pub use pid::{Autopilot, Gains, RudderLimits, TuningError};
pub use reference::ReferenceModel;

/// What the autopilot step gave.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AutopilotResult {
    /// Nomoto K of the identified model, 1/s.
    pub k: f64,
    /// Nomoto T of the identified model, s.
    pub t: f64,
    /// The PID gains placed from them.
    pub gains: Gains,
    /// One closed-loop run per feed, in the order asked for.
    pub feeds: Vec<ClosedLoop>,
    /// The plant steered and its own Nomoto indices.
    pub plant: PlantIndices,
}

/// The plant the loop closed around and its own Nomoto indices (Fossen 2011, 7.2: from the
/// course-stability linearisation, or a Nomoto model's coefficients).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlantIndices {
    /// The plant's model (`nomoto_wave`, `ship_linear` ...).
    pub model: String,
    /// Its indices at the start.
    pub before: crate::dynamics::course_stability::Nomoto,
    /// Its indices after its change mid-run, if it changes.
    pub after: Option<crate::dynamics::course_stability::Nomoto>,
    /// When it changes, s.
    pub change_at: Option<f64>,
}

impl PlantIndices {
    /// The identified model `model` as its own plant, with its K and T.
    pub fn identified(model: &str, k: f64, t: f64) -> Self {
        PlantIndices {
            model: model.to_string(),
            before: crate::dynamics::course_stability::Nomoto {
                speed: None,
                k,
                t,
                t1: Some(t),
                t2: None,
                t3: 0.0,
                course_stable: t > 0.0,
            },
            after: None,
            change_at: None,
        }
    }

    /// The plant in words.
    pub fn line(&self) -> String {
        let at = |n: &crate::dynamics::course_stability::Nomoto| {
            let speed = n.speed.map_or(String::new(), |u| format!(" at {u:.2} m/s"));
            format!("K = {:.4} 1/s, T = {:.2} s{speed}", n.k, n.t)
        };
        let mut s = format!("plant {}: {}", self.model, at(&self.before));
        if let (Some(after), Some(t)) = (&self.after, self.change_at) {
            s.push_str(&format!("; from {t:.0} s: {}", at(after)));
        }
        s
    }
}

impl AutopilotResult {
    /// The run fed `feed`, if it was asked for.
    pub fn feed(&self, feed: Feed) -> Option<&ClosedLoop> {
        self.feeds.iter().find(|c| c.feed == feed)
    }

    /// The plant and the comparison in words, one line per feed.
    pub fn lines(&self) -> Vec<String> {
        std::iter::once(self.plant.line())
            .chain(self.feeds.iter().map(|c| {
                format!(
                    "{}: heading error RMS {:.3} deg, rudder RMS {:.3} deg, rudder rate RMS \
                     {:.3} deg/s",
                    c.feed.describe(),
                    c.heading_error_rms.to_degrees(),
                    c.rudder_rms.to_degrees(),
                    c.rudder_rate_rms.to_degrees()
                )
            }))
            .collect()
    }

    /// Warnings: the filter that does not calm the rudder a tenfold against the raw feed
    /// (the point of a wave filter is one to two orders of magnitude).
    pub fn warnings(&self) -> Vec<crate::base::warning::Warning> {
        let (Some(raw), Some(filtered)) = (self.feed(Feed::Raw), self.feed(Feed::Filter)) else {
            return Vec::new();
        };
        if filtered.rudder_rate_rms <= 0.1 * raw.rudder_rate_rms {
            return Vec::new();
        }
        vec![crate::base::warning::Warning::new(
            "autopilot",
            format!(
                "fed the wave filter, the rudder rate RMS is {:.2} deg/s against {:.2} deg/s \
                 raw: less than a tenfold reduction",
                filtered.rudder_rate_rms.to_degrees(),
                raw.rudder_rate_rms.to_degrees()
            ),
            "the wave filter does not take the wave-frequency motion out of what the \
             autopilot sees as well as it should: check the wave frequency, the wave \
             process noise, the compass noise and rate_noise",
        )]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 deg course change of the first-order Nomoto frigate (K = 0.18 1/s, T = 27 s, Van
    /// Amerongen at 9 m/s) under the tuned autopilot: the heading follows the reference
    /// model within a degree and settles on the new course.
    #[test]
    fn a_course_change_follows_the_reference() {
        let (k, t) = (0.18, 27.0);
        let gains = Gains::pole_placement(k, t, 0.15, 0.9).unwrap();
        let mut ap = Autopilot::new(
            gains,
            RudderLimits {
                angle: 35f64.to_radians(),
                rate: 2.32f64.to_radians(),
                lag: 0.0,
            },
        );
        let mut reference = ReferenceModel::new(0.05, 1.0, 0.0);
        let (mut psi, mut r, dt) = (0.0f64, 0.0f64, 0.1);
        let target = 20f64.to_radians();
        let mut worst: f64 = 0.0;
        for _ in 0..3000 {
            reference.step(target, dt);
            let delta = ap.step(psi - reference.heading, r - reference.rate, dt);
            // T r_dot + r = K delta (explicit Euler at 0.1 s is fine against T = 27 s)
            r += dt * (k * delta - r) / t;
            psi += dt * r;
            worst = worst.max((psi - reference.heading).abs());
        }
        assert!((psi - target).abs() < 1e-3, "settles: {}", psi.to_degrees());
        assert!(
            worst < 1f64.to_radians(),
            "tracking error {} deg",
            worst.to_degrees()
        );
    }
}
