//! The turning circle (IMO MSC/Circ.1053, 3.4.1; ITTC 7.5-04-02-01, 2.1): advance and
//! transfer at 90 deg change of heading, tactical diameter (transfer at 180 deg), steady
//! turning diameter, speed loss, times to 90 and 180 deg.

use super::circle_fit::fit_circle;
use super::history::{first_reaching, At, History, HistoryError};
use super::measure::{Kind, Measure, Named, Side};
use serde::{Deserialize, Serialize};

/// Heading change from which the turn is taken as steady (MSC/Circ.1053 reads the steady
/// turning diameter once the heading has changed well past 180 deg), rad.
pub const STEADY_FROM: f64 = std::f64::consts::PI;

/// Arc of steady turning the fitted circle needs at the least, rad (90 deg).
pub const STEADY_ARC_MIN: f64 = std::f64::consts::FRAC_PI_2;

/// Samples before the execute that give the approach speed.
const APPROACH_SAMPLES: usize = 10;

/// What the turning-circle analysis may be told instead of finding it in the data.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TurningOptions {
    /// The time of the rudder order, s; by default the last sample before the rudder moves.
    pub execute_time: Option<f64>,
}

/// A turning circle's measures. Distances and the speed ratio are positive whichever side
/// the ship turns to; `side` says which.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TurningCircle {
    /// The side of the turn, from the heading change.
    pub side: Side,
    /// Time of the rudder order (execute), s.
    pub execute_time: f64,
    /// Heading at the execute (the original course), rad.
    pub approach_heading: f64,
    /// Speed at the execute, m/s.
    pub approach_speed: Measure,
    /// Rudder angle held in the turn (median after the execute), rad, in the run's sign.
    pub rudder_angle: Measure,
    /// Time from the execute until the rudder reaches its angle, s.
    pub rudder_time: Measure,
    /// Largest heading change reached, rad (positive).
    pub max_heading_change: f64,
    /// Distance along the original course from the execute to 90 deg heading change, m.
    pub advance: Measure,
    /// Distance across the original course, towards the turn, at 90 deg heading change, m.
    pub transfer: Measure,
    /// Time from the execute to 90 deg heading change, s.
    pub time_to_90: Measure,
    /// Distance across the original course at 180 deg heading change, m.
    pub tactical_diameter: Measure,
    /// Time from the execute to 180 deg heading change, s.
    pub time_to_180: Measure,
    /// Diameter of the circle fitted to the track past 180 deg heading change, m.
    pub steady_diameter: Measure,
    /// Mean speed in the steady turn, m/s.
    pub steady_speed: Measure,
    /// Steady speed over approach speed, - (the speed loss is one minus this).
    pub speed_ratio: Measure,
}

impl TurningCircle {
    /// The measures in the order a table lists them.
    pub fn measures(&self) -> Vec<Named> {
        let n = Named::new;
        vec![
            n("advance", "advance", Kind::Length, &self.advance),
            n("transfer", "transfer", Kind::Length, &self.transfer),
            n(
                "tactical_diameter",
                "tactical diameter",
                Kind::Length,
                &self.tactical_diameter,
            ),
            n(
                "steady_diameter",
                "steady turning diameter",
                Kind::Length,
                &self.steady_diameter,
            ),
            n("time_to_90", "time to 90 deg", Kind::Time, &self.time_to_90),
            n(
                "time_to_180",
                "time to 180 deg",
                Kind::Time,
                &self.time_to_180,
            ),
            n(
                "approach_speed",
                "approach speed",
                Kind::Speed,
                &self.approach_speed,
            ),
            n(
                "steady_speed",
                "steady turning speed",
                Kind::Speed,
                &self.steady_speed,
            ),
            n(
                "speed_ratio",
                "steady / approach speed",
                Kind::Ratio,
                &self.speed_ratio,
            ),
        ]
    }
}

/// The turning circle of `history`, which must have the track. Measures the run does not
/// reach are [`Measure::Missing`] with the reason.
pub fn turning_circle(
    history: &History,
    options: &TurningOptions,
) -> Result<TurningCircle, HistoryError> {
    const WHAT: &str = "the turning circle";
    let (x, y) = history.track().ok_or(HistoryError::Lacks {
        what: WHAT,
        series: "track (x, y)",
    })?;
    let time = history.time();
    let exec = history.execute(options.execute_time, WHAT)?;
    let t0 = exec.of(time);
    let psi0 = exec.of(history.heading());
    let (x0, y0) = (exec.of(x), exec.of(y));
    let after = exec.next_index();
    let change: Vec<f64> = history.heading().iter().map(|p| p - psi0).collect();
    let peak = (after..change.len())
        .max_by(|&a, &b| change[a].abs().total_cmp(&change[b].abs()))
        .unwrap_or(after);
    let side = Side::of(change[peak]);
    let s = side.sign();
    let turned: Vec<f64> = change.iter().map(|c| s * c).collect();
    let max_heading_change = turned[peak].max(0.0);

    // Advance along the original course, transfer across it towards the turn.
    let (cos0, sin0) = (psi0.cos(), psi0.sin());
    let along = |at: At| (at.of(x) - x0) * cos0 + (at.of(y) - y0) * sin0;
    let across = |at: At| s * (-(at.of(x) - x0) * sin0 + (at.of(y) - y0) * cos0);
    let reach = |deg: f64| {
        first_reaching(&turned, deg.to_radians(), exec).ok_or_else(|| {
            format!(
                "the heading changes by {:.1} deg at most after the execute; this needs {deg} deg",
                max_heading_change.to_degrees()
            )
        })
    };
    let measure = |r: &Result<At, String>, f: &dyn Fn(At) -> f64| match r {
        Ok(at) => Measure::Value(f(*at)),
        Err(reason) => Measure::missing(reason.clone()),
    };
    let at90 = reach(90.0);
    let at180 = reach(180.0);
    let since = |at: At| at.of(time) - t0;

    let approach_speed = approach_speed(history, exec);
    let (steady_diameter, steady_speed) = steady_turn(history, &turned, max_heading_change);
    let speed_ratio = match (&steady_speed, &approach_speed) {
        (Measure::Value(s), Measure::Value(a)) if *a > 0.0 => Measure::Value(s / a),
        (Measure::Missing(r), _) | (_, Measure::Missing(r)) => Measure::missing(r.clone()),
        _ => Measure::missing("the approach speed is zero"),
    };
    let (rudder_angle, rudder_time) = rudder_held(history, exec, t0);
    Ok(TurningCircle {
        side,
        execute_time: t0,
        approach_heading: psi0,
        approach_speed,
        rudder_angle,
        rudder_time,
        max_heading_change,
        advance: measure(&at90, &along),
        transfer: measure(&at90, &across),
        time_to_90: measure(&at90, &since),
        tactical_diameter: measure(&at180, &across),
        time_to_180: measure(&at180, &since),
        steady_diameter,
        steady_speed,
        speed_ratio,
    })
}

/// The approach speed: from u and v, their mean over the samples up to the execute; from the
/// track alone, the straight distance over those samples by their time span.
pub(super) fn approach_speed(history: &History, exec: At) -> Measure {
    let end = exec.index;
    let start = end.saturating_sub(APPROACH_SAMPLES);
    if let Some(speed) = history.speed() {
        let n = (end - start + 1) as f64;
        return Measure::Value(speed[start..=end].iter().sum::<f64>() / n);
    }
    let Some((x, y)) = history.track() else {
        return Measure::missing("the history has neither u, v nor the track");
    };
    let (a, b) = if end > start { (start, end) } else { (0, 1) };
    let t = history.time();
    Measure::Value((x[b] - x[a]).hypot(y[b] - y[a]) / (t[b] - t[a]))
}

/// Steady turning diameter and speed from the samples past [`STEADY_FROM`] heading change:
/// the diameter of the circle fitted to the track, the speed as the mean of u, v or, without
/// them, the arc swept about the fitted centre by its time.
fn steady_turn(history: &History, turned: &[f64], max_change: f64) -> (Measure, Measure) {
    let needed = STEADY_FROM + STEADY_ARC_MIN;
    if max_change < needed {
        let reason = format!(
            "the heading changes by {:.1} deg at most; a steady turn is read from 180 deg on and needs {:.0} deg",
            max_change.to_degrees(),
            needed.to_degrees()
        );
        return (Measure::missing(reason.clone()), Measure::missing(reason));
    }
    let first = turned.iter().position(|&c| c >= STEADY_FROM).unwrap_or(0);
    let (x, y) = history
        .track()
        .expect("the turning circle checked the track");
    let Some(circle) = fit_circle(&x[first..], &y[first..]) else {
        let reason = "the track past 180 deg does not fit a circle".to_string();
        return (Measure::missing(reason.clone()), Measure::missing(reason));
    };
    let t = history.time();
    let duration = t[t.len() - 1] - t[first];
    let speed = match history.speed() {
        Some(s) => s[first..].iter().sum::<f64>() / s[first..].len() as f64,
        None => {
            let angle = |i: usize| (y[i] - circle.cy).atan2(x[i] - circle.cx);
            let mut swept = 0.0;
            for i in first + 1..x.len() {
                let d = angle(i) - angle(i - 1);
                swept += d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
            }
            swept.abs() * circle.radius / duration
        }
    };
    (Measure::Value(2.0 * circle.radius), Measure::Value(speed))
}

/// The rudder angle held in the turn (median of the samples after the execute) and the time
/// from the execute until the rudder first reaches it (interpolated between samples).
fn rudder_held(history: &History, exec: At, t0: f64) -> (Measure, Measure) {
    let Some(rudder) = history.rudder() else {
        let r = "the history has no rudder angle";
        return (Measure::missing(r), Measure::missing(r));
    };
    let mut held: Vec<f64> = rudder[exec.next_index()..].to_vec();
    held.sort_by(f64::total_cmp);
    let angle = held[held.len() / 2];
    let start = exec.of(rudder);
    let sign = if angle >= start { 1.0 } else { -1.0 };
    let moved: Vec<f64> = rudder.iter().map(|d| sign * (d - start)).collect();
    let reached = first_reaching(&moved, sign * (angle - start), exec)
        .map(|at| Measure::Value(at.of(history.time()) - t0))
        .unwrap_or_else(|| Measure::missing("the rudder never reaches its held angle"));
    (Measure::Value(angle), reached)
}
