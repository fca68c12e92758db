//! What the autopilot step gives: the gains, one closed loop per feed, the plant's own
//! Nomoto indices, and the comparison in words and warnings.

use super::closed_loop::{ClosedLoop, Stats};
use super::{Feed, Gains};

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

    /// The plant's indices last in force, in words.
    pub fn last_line(&self) -> String {
        let n = self.after.as_ref().unwrap_or(&self.before);
        format!("K = {:.4} 1/s, T = {:.1} s", n.k, n.t)
    }
}

impl AutopilotResult {
    /// The run fed `feed`, if it was asked for.
    pub fn feed(&self, feed: Feed) -> Option<&ClosedLoop> {
        self.feeds.iter().find(|c| c.feed == feed)
    }

    /// The plant and the comparison in words, one line per feed (with its statistics
    /// before and after the plant's change, and the adaptive feed's last estimates).
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![self.plant.line()];
        for c in &self.feeds {
            let mut line = format!(
                "{}: heading error RMS {:.3} deg, rudder RMS {:.3} deg, rudder rate RMS \
                 {:.3} deg/s",
                c.feed.describe(),
                c.heading_error_rms.to_degrees(),
                c.rudder_rms.to_degrees(),
                c.rudder_rate_rms.to_degrees()
            );
            if let (Some(b), Some(a)) = (c.before_change, c.after_change) {
                line.push_str(&format!(
                    "; before the change {}, after {}",
                    triple(&b),
                    triple(&a)
                ));
            }
            lines.push(line);
            if let Some(e) = c.final_estimate {
                lines.push(format!(
                    "adaptive estimates at {:.0} s: K = {:.4} +- {:.4} 1/s, T = {:.1} +- {:.1} \
                     s, K/T = {:.3e} +- {:.1e} 1/s^2 (plant's own: {})",
                    e.t,
                    e.k,
                    e.k_sigma,
                    e.t_const,
                    e.t_sigma,
                    e.ratio,
                    e.ratio_sigma,
                    self.plant.last_line()
                ));
            }
        }
        lines
    }

    /// Warnings: the filter that does not calm the rudder a tenfold against the raw feed
    /// (the point of a wave filter is one to two orders of magnitude).
    pub fn warnings(&self) -> Vec<crate::base::warning::Warning> {
        let mut out = self.separation_warning();
        let (Some(raw), Some(filtered)) = (self.feed(Feed::Raw), self.feed(Feed::Filter)) else {
            return out;
        };
        if filtered.rudder_rate_rms <= 0.1 * raw.rudder_rate_rms {
            return out;
        }
        out.push(crate::base::warning::Warning::new(
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
        ));
        out
    }

    /// The adaptive feed's last estimates that know K/T but not K and T apart: the run does
    /// not separate them (a small course change on a slow ship), the gains then held.
    fn separation_warning(&self) -> Vec<crate::base::warning::Warning> {
        let Some(a) = self.feed(Feed::Adaptive) else {
            return Vec::new();
        };
        let Some(e) = a.final_estimate else {
            return Vec::new();
        };
        let mut out = Vec::new();
        let own = self.plant.after.as_ref().unwrap_or(&self.plant.before);
        let off = |v: f64, s: f64, truth: f64| (v - truth).abs() > 2.0 * s;
        if off(e.k, e.k_sigma, own.k) || off(e.t_const, e.t_sigma, own.t) {
            out.push(crate::base::warning::Warning::new(
                "autopilot",
                format!(
                    "the adaptive autopilot's last K = {:.4} +- {:.4} 1/s and T = {:.1} +- {:.1} \
                     s do not cover the plant's own K = {:.4} 1/s, T = {:.1} s within two \
                     sigmas (K/T {:.3e} against {:.3e} 1/s^2)",
                    e.k,
                    e.k_sigma,
                    e.t_const,
                    e.t_sigma,
                    own.k,
                    own.t,
                    e.ratio,
                    own.k / own.t
                ),
                "the first-order Nomoto model fitted in the closed loop is not the plant's \
                 low-frequency K and T (T1 + T2 - T3) when the plant is a sway-yaw ship: the \
                 loop excites it near w_n, where its second-order response differs; K/T, what \
                 the gains depend on, is the comparable number",
            ));
        }
        let guard = e.guard;
        if e.separates(guard) {
            return out;
        }
        let what = if e.passes(guard) {
            format!(
                "K/T is known within {:.1} % but K ({:.1} %) and T ({:.1} %) are not: the run \
                 does not separate them",
                100.0 * e.ratio_sigma / e.ratio,
                100.0 * e.k_sigma / e.k,
                100.0 * e.t_sigma / e.t_const
            )
        } else {
            format!(
                "K/T ({:.1} %) is not known within the guard",
                100.0 * e.ratio_sigma / e.ratio
            )
        };
        out.push(crate::base::warning::Warning::new(
            "autopilot",
            format!("the adaptive autopilot's last estimates: {what}"),
            "K and T apart are not what the gains were placed from when K/T is known (their \
             sigmas say how far each may be); larger or more course changes (or zig-zags) \
             excite the ship enough to tell them apart; an unknown K/T holds the last trusted \
             gains",
        ));
        out
    }
}

/// Heading error, rudder and rudder-rate RMS in words.
fn triple(s: &Stats) -> String {
    format!(
        "{:.3} deg, {:.3} deg, {:.3} deg/s",
        s.heading_error_rms.to_degrees(),
        s.rudder_rms.to_degrees(),
        s.rudder_rate_rms.to_degrees()
    )
}
