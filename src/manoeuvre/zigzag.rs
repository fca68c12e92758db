//! The zig-zag (Kempf) manoeuvre (IMO MSC/Circ.1053, 3.4.2; ITTC 7.5-04-02-01, 2.2): first
//! and second overshoot angles, initial turning time, time to check yaw, period.
//!
//! The executes: the first is the rudder order; the second, third and fourth are the
//! moments the heading change reaches the execute heading angle, alternately to the side of
//! the first turn and to the other, when the rudder is reversed.

use super::history::{first_reaching, rudder_execute_sign, At, History, HistoryError};
use super::measure::{Kind, Measure, Named, Side};
use super::turning::approach_speed;
use serde::{Deserialize, Serialize};

/// What the zig-zag analysis may be told instead of finding it in the data (rad, s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ZigZagOptions {
    /// The time of the first rudder order, s; by default found in the rudder history.
    pub execute_time: Option<f64>,
    /// The rudder angle of the test (10 deg in a 10/10), rad; by default the rudder's first
    /// excursion rounded to a whole degree.
    pub rudder_angle: Option<f64>,
    /// The execute heading angle (the second 10 of a 10/10), rad; by default the heading
    /// change at the first rudder reversal rounded to a whole degree.
    pub heading_angle: Option<f64>,
}

/// A zig-zag's measures. Angles are positive magnitudes; `side` is the first turn's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZigZag {
    /// The side of the first turn, from the heading change.
    pub side: Side,
    /// Time of the first rudder order (first execute), s.
    pub execute_time: f64,
    /// Heading at the first execute (the original course), rad.
    pub approach_heading: f64,
    /// Speed at the first execute, m/s.
    pub approach_speed: Measure,
    /// The test's rudder angle, rad (magnitude).
    pub rudder_angle: Measure,
    /// Whether the rudder angle was read from the data (true) or given.
    pub rudder_angle_detected: bool,
    /// The execute heading angle, rad (magnitude).
    pub heading_angle: f64,
    /// Whether the execute heading angle was read from the data (true) or given.
    pub heading_angle_detected: bool,
    /// Time from the first execute until the heading change reaches the execute heading, s.
    pub initial_turning_time: Measure,
    /// Distance travelled from the first execute until then, m (IMO initial turning ability).
    pub initial_turning_distance: Measure,
    /// Largest heading change past the execute heading in the first swing, rad.
    pub first_overshoot: Measure,
    /// Time from the second execute to the first swing's largest heading change, s.
    pub time_to_check_yaw: Measure,
    /// Largest heading change past the execute heading in the second swing, rad.
    pub second_overshoot: Measure,
    /// Time from the second to the fourth execute (one full heading oscillation), s.
    pub period: Measure,
}

impl ZigZag {
    /// The measures in the order a table lists them.
    pub fn measures(&self) -> Vec<Named> {
        let n = Named::new;
        vec![
            n(
                "first_overshoot",
                "first overshoot angle",
                Kind::Angle,
                &self.first_overshoot,
            ),
            n(
                "second_overshoot",
                "second overshoot angle",
                Kind::Angle,
                &self.second_overshoot,
            ),
            n(
                "initial_turning_time",
                "initial turning time",
                Kind::Time,
                &self.initial_turning_time,
            ),
            n(
                "initial_turning_distance",
                "distance to the execute heading",
                Kind::Length,
                &self.initial_turning_distance,
            ),
            n(
                "time_to_check_yaw",
                "time to check yaw",
                Kind::Time,
                &self.time_to_check_yaw,
            ),
            n("period", "period", Kind::Time, &self.period),
            n(
                "approach_speed",
                "approach speed",
                Kind::Speed,
                &self.approach_speed,
            ),
        ]
    }
}

/// Rounds an angle to a whole degree (tests are named by whole degrees: 10/10, 20/20).
fn whole_degrees(a: f64) -> f64 {
    a.to_degrees().round().to_radians()
}

/// The zig-zag measures of `history`. Measures the run does not reach are
/// [`Measure::Missing`] with the reason.
pub fn zigzag(history: &History, options: &ZigZagOptions) -> Result<ZigZag, HistoryError> {
    const WHAT: &str = "the zig-zag";
    let time = history.time();
    let exec = history.execute(options.execute_time, WHAT)?;
    let t0 = exec.of(time);
    let psi0 = exec.of(history.heading());
    let change: Vec<f64> = history.heading().iter().map(|p| p - psi0).collect();

    // The rudder's first excursion and its reversal (the second execute as ordered).
    let excursion = history.rudder().map(|r| first_excursion(r, exec));
    let rudder_angle = match (options.rudder_angle, &excursion) {
        (Some(a), _) => Measure::Value(a.abs()),
        (None, Some(e)) => Measure::Value(whole_degrees(e.angle)),
        (None, None) => Measure::missing("the history has no rudder angle and none was given"),
    };
    let heading_angle = match (options.heading_angle, &excursion) {
        (Some(a), _) => a.abs(),
        (None, Some(Excursion { reversal: Some(at), .. })) => whole_degrees(at.of(&change).abs()),
        (None, Some(_)) => {
            return Err(HistoryError::Execute(format!(
                "{WHAT}: the rudder is never reversed, so the execute heading angle cannot be read; give it"
            )))
        }
        (None, None) => {
            return Err(HistoryError::Lacks {
                what: WHAT,
                series: "rudder angle (or the execute heading angle)",
            })
        }
    };
    if heading_angle <= 0.0 {
        return Err(HistoryError::Execute(format!(
            "{WHAT}: the execute heading angle is zero"
        )));
    }

    let first = (exec.next_index()..change.len()).find(|&i| change[i].abs() >= heading_angle);
    let side = first.map_or(Side::Starboard, |i| Side::of(change[i]));
    let turned: Vec<f64> = change.iter().map(|c| side.sign() * c).collect();
    let back: Vec<f64> = turned.iter().map(|c| -c).collect();
    let max_change = change[exec.next_index()..]
        .iter()
        .fold(0.0f64, |m, c| m.max(c.abs()));
    let never = |n: &str| {
        format!(
            "the heading never reaches the {n} execute ({:.1} deg to the {}; it changes by {:.1} deg at most)",
            heading_angle.to_degrees(),
            if n == "third" { "other side" } else { "side of the first turn" },
            max_change.to_degrees()
        )
    };
    let e2 = first_reaching(&turned, heading_angle, exec).ok_or_else(|| never("second"));
    let e3 = e2
        .clone()
        .and_then(|e| first_reaching(&back, heading_angle, e).ok_or_else(|| never("third")));
    let e4 = e3
        .clone()
        .and_then(|e| first_reaching(&turned, heading_angle, e).ok_or_else(|| never("fourth")));
    let at = |e: &Result<At, String>| e.clone().map(|a| a.of(time));
    let (t2, t4) = (at(&e2), at(&e4));

    let to_measure = |r: Result<f64, String>| r.map_or_else(Measure::Missing, Measure::Value);
    let first_peak = e2
        .clone()
        .and_then(|a| e3.clone().map(|b| peak(time, &turned, a, b)));
    let second_peak = e3
        .clone()
        .and_then(|a| e4.clone().map(|b| peak(time, &back, a, b)));
    Ok(ZigZag {
        side,
        execute_time: t0,
        approach_heading: psi0,
        approach_speed: approach_speed(history, exec),
        rudder_angle,
        rudder_angle_detected: options.rudder_angle.is_none(),
        heading_angle,
        heading_angle_detected: options.heading_angle.is_none(),
        initial_turning_time: to_measure(t2.clone().map(|t| t - t0)),
        initial_turning_distance: match &e2 {
            Ok(e) => distance(history, exec, *e),
            Err(r) => Measure::missing(r.clone()),
        },
        first_overshoot: to_measure(first_peak.clone().map(|(_, a)| a - heading_angle)),
        time_to_check_yaw: to_measure(first_peak.and_then(|(t, _)| t2.clone().map(|t2| t - t2))),
        second_overshoot: to_measure(second_peak.map(|(_, a)| a - heading_angle)),
        period: to_measure(t4.and_then(|t4| t2.map(|t2| t4 - t2))),
    })
}

/// The rudder's first excursion from its approach angle: its size and the place of the
/// reversal (the last sample at the excursion's extreme before the rudder moves back).
struct Excursion {
    angle: f64,
    reversal: Option<At>,
}

fn first_excursion(rudder: &[f64], exec: At) -> Excursion {
    let start = exec.of(rudder);
    let from = exec.next_index();
    let sign = rudder_execute_sign(rudder, from, start);
    let moved: Vec<f64> = rudder.iter().map(|d| sign * (d - start)).collect();
    let mut top = 0.0f64;
    for i in from..moved.len() {
        let threshold = (0.1 * top).max(1f64.to_radians());
        if top > threshold && moved[i] < top - threshold {
            let last = (from..i)
                .rev()
                .find(|&j| moved[j] >= top - 0.25 * threshold)
                .unwrap_or(from);
            return Excursion {
                angle: top,
                reversal: Some(At::sample(last)),
            };
        }
        top = top.max(moved[i]);
    }
    Excursion {
        angle: top,
        reversal: None,
    }
}

/// The largest value of `signal` between `a` and `b` and its time, refined by the parabola
/// through the largest sample and its neighbours (exact for a sampled parabola).
fn peak(time: &[f64], signal: &[f64], a: At, b: At) -> (f64, f64) {
    let lo = a.next_index();
    let hi = b.index.max(lo);
    let p = (lo..=hi)
        .max_by(|&i, &j| signal[i].total_cmp(&signal[j]))
        .unwrap_or(lo);
    if p == 0 || p + 1 >= signal.len() {
        return (time[p], signal[p]);
    }
    let (h1, h2) = (time[p] - time[p - 1], time[p + 1] - time[p]);
    let s1 = (signal[p] - signal[p - 1]) / h1;
    let s2 = (signal[p + 1] - signal[p]) / h2;
    let curvature = 2.0 * (s2 - s1) / (h1 + h2);
    let slope = (s1 * h2 + s2 * h1) / (h1 + h2);
    if curvature >= 0.0 {
        return (time[p], signal[p]);
    }
    let tau = (-slope / curvature).clamp(-h1, h2);
    (
        time[p] + tau,
        signal[p] + slope * tau + 0.5 * curvature * tau * tau,
    )
}

/// Distance travelled from `a` to `b`: along the track if the history has it (chords between
/// samples), otherwise the speed from u, v integrated by the trapezoidal rule.
fn distance(history: &History, a: At, b: At) -> Measure {
    let time = history.time();
    let (ta, tb) = (a.of(time), b.of(time));
    let inner: Vec<usize> = (a.next_index()..=b.index)
        .filter(|&i| time[i] > ta && time[i] < tb)
        .collect();
    if let Some((x, y)) = history.track() {
        let mut pts = vec![(a.of(x), a.of(y))];
        pts.extend(inner.iter().map(|&i| (x[i], y[i])));
        pts.push((b.of(x), b.of(y)));
        return Measure::Value(
            pts.windows(2)
                .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
                .sum(),
        );
    }
    if let Some(speed) = history.speed() {
        let mut pts = vec![(ta, a.of(&speed))];
        pts.extend(inner.iter().map(|&i| (time[i], speed[i])));
        pts.push((tb, b.of(&speed)));
        return Measure::Value(
            pts.windows(2)
                .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
                .sum(),
        );
    }
    Measure::missing("the history has neither the track nor u, v")
}
