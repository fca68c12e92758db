//! The zig-zag (Kempf) manoeuvre (MSC.137(76), annex, 4.2.5-4.2.9; MSC/Circ.1053, annex,
//! 1.3.2; ITTC 7.5-04-02-01, 2.2.2): first and second overshoot angles, initial turning time,
//! time to check yaw, period.
//!
//! A delta/psi zig-zag is measured at its nominal angles (given, or inferred from the run:
//! [`super::nominal`]). The executes: the first is the rudder order; the second, third and
//! fourth are the moments the heading change reaches the nominal check angle psi,
//! alternately to the side of the first turn and to the other, when the rudder is to be
//! reversed (4.2.6). An overshoot angle is the heading change beyond psi after the second
//! (first overshoot, 4.2.7) or third execute (second overshoot, 4.2.8), so a rudder reversed a
//! little late does not move it by the lateness.

use super::history::{first_reaching, At, History, HistoryError};
use super::measure::{Kind, Measure, Named, Side};
use super::nominal::{nominal, AngleSource, STANDARD_CHECK_DEG, STANDARD_RUDDER_DEG};
use super::rudder::first_hold;
use super::turning::approach_speed;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// What the zig-zag analysis may be told instead of finding it in the data (rad, s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ZigZagOptions {
    /// The time of the first rudder order, s; by default found in the rudder history.
    pub execute_time: Option<f64>,
    /// The test's nominal rudder angle (10 deg in a 10/10), rad; by default the angle the
    /// rudder is held at in its first excursion, rounded to a standard angle within reach.
    pub rudder_angle: Option<f64>,
    /// The nominal check (execute heading) angle (the second 10 of a 10/10), rad; by
    /// default the heading change at the first rudder reversal, rounded to a standard angle
    /// within reach.
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
    /// The test's nominal rudder angle, rad (magnitude).
    pub rudder_angle: Measure,
    /// Where the nominal rudder angle comes from (absent when it is missing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rudder_angle_from: Option<AngleSource>,
    /// The nominal check (execute heading) angle, rad (magnitude).
    pub heading_angle: f64,
    /// Where the nominal check angle comes from.
    pub heading_angle_from: AngleSource,
    /// Time from the first execute until the heading change reaches the check angle, s.
    pub initial_turning_time: Measure,
    /// Distance travelled from the first execute until then, m (IMO initial turning ability).
    pub initial_turning_distance: Measure,
    /// Largest heading change past the check angle in the first swing, rad.
    pub first_overshoot: Measure,
    /// Time from the second execute to the first swing's largest heading change, s.
    pub time_to_check_yaw: Measure,
    /// Largest heading change past the check angle in the second swing, rad.
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
            n(
                "rudder_angle",
                "rudder angle (nominal)",
                Kind::Angle,
                &self.rudder_angle,
            ),
            n(
                "heading_angle",
                "check angle (nominal)",
                Kind::Angle,
                &Measure::Value(self.heading_angle),
            ),
        ]
    }

    /// The test's name from its nominal angles, e.g. "20/10".
    pub fn test_name(&self) -> String {
        let deg = |a: f64| crate::base::numfmt::fixed_trimmed(a.to_degrees(), 1);
        match self.rudder_angle.value() {
            Some(r) => format!("{}/{}", deg(r), deg(self.heading_angle)),
            None => format!("?/{}", deg(self.heading_angle)),
        }
    }

    /// Where the nominal angles come from, in words: "rudder angle nominal 20 deg, given;
    /// check angle nominal 10 deg, inferred from the reversal at 10.7 deg".
    pub fn nominal_text(&self) -> String {
        let rudder = match (self.rudder_angle.value(), self.rudder_angle_from) {
            (Some(a), Some(from)) => from.describe(a, "the rudder held"),
            _ => "missing".to_string(),
        };
        format!(
            "rudder angle {rudder}; check angle {}",
            self.heading_angle_from
                .describe(self.heading_angle, "the reversal")
        )
    }
}

/// The nominal rudder and check angles of the run: given, or inferred from the rudder's first
/// hold (its angle, and the heading change where it ends).
fn nominal_angles(
    history: &History,
    options: &ZigZagOptions,
    exec: At,
    change: &[f64],
) -> Result<(Measure, Option<AngleSource>, f64, AngleSource), HistoryError> {
    const WHAT: &str = "the zig-zag";
    let hold = history.rudder().map(|r| first_hold(r, exec));
    let (rudder_angle, rudder_from) = match (options.rudder_angle, &hold) {
        (None, None) => (
            Measure::missing("the history has no rudder angle and none was given"),
            None,
        ),
        (given, hold) => {
            let held = hold.map_or(0.0, |h| h.angle);
            let (a, from) = nominal(given, held, &STANDARD_RUDDER_DEG);
            (Measure::Value(a), Some(from))
        }
    };
    let reversal = hold.and_then(|h| h.released).map(|i| change[i]);
    let (check, check_from) = match (options.heading_angle, reversal, &hold) {
        (Some(a), ..) => (a.abs(), AngleSource::Given),
        (None, Some(c), _) => nominal(None, c, &STANDARD_CHECK_DEG),
        (None, None, Some(_)) => {
            return Err(HistoryError::Execute(format!(
                "{WHAT}: the rudder is never reversed, so the check (execute heading) angle cannot be read; give it"
            )))
        }
        (None, None, None) => {
            return Err(HistoryError::Lacks {
                what: WHAT,
                series: "rudder angle (or the check angle: the execute heading angle)",
            })
        }
    };
    if check <= 0.0 {
        return Err(HistoryError::Execute(format!(
            "{WHAT}: the check angle is zero"
        )));
    }
    Ok((rudder_angle, rudder_from, check, check_from))
}

/// The zig-zag measures of `history`. Measures the run does not reach are
/// [`Measure::Missing`] with the reason.
pub fn zigzag(history: &History, options: &ZigZagOptions) -> Result<ZigZag, HistoryError> {
    let time = history.time();
    let exec = history.execute(options.execute_time, "the zig-zag")?;
    let t0 = exec.of(time);
    let psi0 = exec.of(history.heading());
    let change: Vec<f64> = history.heading().iter().map(|p| p - psi0).collect();
    let (rudder_angle, rudder_angle_from, heading_angle, heading_angle_from) =
        nominal_angles(history, options, exec, &change)?;

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
        rudder_angle_from,
        heading_angle,
        heading_angle_from,
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

/// Distinct values of the signal, the largest first, that the window of a peak's fit reaches
/// down to: on a heading printed with few digits (MARIN's logs: 0.1 deg steps from 10 deg,
/// 1 deg from 100 deg) the maximum is a plateau of many samples, and the fit spans it and
/// three quantisation steps below it on either side; on a smooth heading, the few samples
/// around the largest.
const PEAK_LEVELS: usize = 4;

/// The largest value of `signal` between `a` and `b` and its time: the vertex of the
/// least-squares parabola through the samples around the maximum down to the
/// [`PEAK_LEVELS`]-th largest distinct value (exact for a sampled parabola; on a quantised
/// heading, centred on the plateau of the maximum rather than at its first sample). Where
/// no parabola opening downwards peaks inside that window, the middle of the plateau of the
/// maximum.
fn peak(time: &[f64], signal: &[f64], a: At, b: At) -> (f64, f64) {
    let lo = a.next_index().min(signal.len() - 1);
    let hi = b.index.max(lo).min(signal.len() - 1);
    let m = signal[lo..=hi].iter().copied().fold(f64::MIN, f64::max);
    let first = (lo..=hi).find(|&i| signal[i] == m).unwrap_or(lo);
    let last = (lo..=hi).rev().find(|&i| signal[i] == m).unwrap_or(first);
    let mut levels: Vec<f64> = signal[lo..=hi].to_vec();
    levels.sort_by(|x, y| y.total_cmp(x));
    levels.dedup();
    let floor = levels[(PEAK_LEVELS - 1).min(levels.len() - 1)];
    let (mut i, mut j) = (first, last);
    while i > lo && signal[i - 1] >= floor {
        i -= 1;
    }
    while j < hi && signal[j + 1] >= floor {
        j += 1;
    }
    let mid = 0.5 * (time[first] + time[last]);
    match parabola(&time[i..=j], &signal[i..=j], mid, m) {
        Some((c0, c1, c2)) if c2 < 0.0 => {
            let tau = -c1 / (2.0 * c2);
            if tau >= time[i] - mid && tau <= time[j] - mid {
                (mid + tau, m + c0 + c1 * tau + c2 * tau * tau)
            } else {
                (mid, m)
            }
        }
        _ => (mid, m),
    }
}

/// The least-squares parabola `y - y0 = c0 + c1 tau + c2 tau^2`, `tau = t - t0`, through the
/// points; None for fewer than three points or a singular fit.
fn parabola(t: &[f64], y: &[f64], t0: f64, y0: f64) -> Option<(f64, f64, f64)> {
    if t.len() < 3 {
        return None;
    }
    let mut a = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    for (&ti, &yi) in t.iter().zip(y) {
        let tau = ti - t0;
        let row = Vector3::new(1.0, tau, tau * tau);
        a += row * row.transpose();
        b += row * (yi - y0);
    }
    let c = a.lu().solve(&b)?;
    c.iter()
        .all(|v| v.is_finite())
        .then_some((c[0], c[1], c[2]))
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
