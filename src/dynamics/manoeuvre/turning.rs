//! The turning circle (MSC.137(76), annex, 4.2.2-4.2.4; MSC/Circ.1053, annex, 2.2.1;
//! ITTC 7.5-04-02-01, 2.2.1): advance and transfer at 90 deg change of heading, tactical
//! diameter (transfer at 180 deg), steady turning diameter and speed loss in the steady part
//! of the turn, times to 90 and 180 deg; all with the rudder held, before any pull-out.

use super::circle_fit::fit_circle;
use super::history::{first_reaching, At, History, HistoryError};
use super::measure::{Kind, Measure, Named, Side};
use super::nominal::{nominal, AngleSource, STANDARD_RUDDER_DEG};
use super::rudder::{first_hold, Hold};
use super::steady::{speeds, steady_part, Steady};
use serde::{Deserialize, Serialize};

/// Samples before the execute that give the approach speed.
const APPROACH_SAMPLES: usize = 10;

/// What the turning-circle analysis may be told instead of finding it in the data.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TurningOptions {
    /// The time of the rudder order, s; by default the last sample before the rudder moves.
    pub execute_time: Option<f64>,
    /// The test's nominal rudder angle, rad (magnitude); by default the angle held, rounded
    /// to the standard angle within reach (docs/manoeuvres.md, "Nominal angles").
    pub rudder_angle: Option<f64>,
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
    /// Rudder angle held in the turn (median of the hold), rad, in the run's sign.
    pub rudder_angle: Measure,
    /// The test's nominal rudder angle, rad (magnitude): given, or the angle held rounded to
    /// a standard angle.
    pub nominal_rudder_angle: Measure,
    /// Where the nominal rudder angle comes from (absent when it is missing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nominal_rudder_from: Option<AngleSource>,
    /// Time from the execute until the rudder reaches its angle, s.
    pub rudder_time: Measure,
    /// Time of the last sample with the rudder held, s, when it is changed before the run
    /// ends (a pull-out); absent when it is held to the end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rudder_changed_at: Option<f64>,
    /// Largest heading change reached with the rudder held, rad (positive).
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
    /// Time the steady part of the turn starts, s (it ends with the hold).
    pub steady_from: Measure,
    /// Mean yaw rate in the steady part, rad/s (positive).
    pub steady_yaw_rate: Measure,
    /// Diameter of the circle fitted to the track of the steady part, m.
    pub steady_diameter: Measure,
    /// Mean speed in the steady part, m/s.
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
            n(
                "nominal_rudder_angle",
                "rudder angle (nominal)",
                Kind::Angle,
                &self.nominal_rudder_angle,
            ),
        ]
    }

    /// Where the nominal rudder angle comes from, in words ("nominal 35 deg, given").
    pub fn nominal_text(&self) -> Option<String> {
        let (a, from) = (
            self.nominal_rudder_angle.value()?,
            self.nominal_rudder_from?,
        );
        Some(format!(
            "rudder angle {}",
            from.describe(a, "the rudder held")
        ))
    }

    /// The circle the steady turning diameter was read from: the circle fitted to the track
    /// of `history` (the history these measures were taken from) over the steady part, as
    /// (centre x, centre y, radius) in m; None when the turn has no steady part.
    pub fn steady_circle(&self, history: &History) -> Option<(f64, f64, f64)> {
        let (x, y) = history.track()?;
        let t = history.time();
        let steady_from = self.steady_from.value()?;
        let from = t.partition_point(|&s| s < steady_from);
        let to = match self.rudder_changed_at {
            Some(c) => t.partition_point(|&s| s <= c).checked_sub(1)?,
            None => t.len() - 1,
        };
        (from < to)
            .then(|| fit_circle(&x[from..=to], &y[from..=to]))
            .flatten()
            .map(|c| (c.cx, c.cy, c.radius))
    }

    /// What part of the run the measures are of, in words: "rudder held until t = 1515 s
    /// (then changed: a pull-out is not part of the turn); steady from t = 393.5 s".
    pub fn hold_text(&self) -> String {
        let held = match self.rudder_changed_at {
            Some(t) => format!(
                "rudder held until t = {} s (then changed: what follows is not part of the turn)",
                crate::base::numfmt::num(t)
            ),
            None => "rudder held to the end of the run".to_string(),
        };
        match self.steady_from {
            Measure::Value(t) => {
                format!("{held}; steady from t = {} s", crate::base::numfmt::num(t))
            }
            Measure::Missing(_) => held,
        }
    }
}

/// The turning circle of `history`, which must have the track. Measures the run does not
/// reach with the rudder held are [`Measure::Missing`] with the reason.
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
    let hold = history.rudder().map(|r| first_hold(r, exec));
    let end = hold.map_or(time.len() - 1, |h| h.last(time.len()));
    let after = exec.next_index().min(end);
    let change: Vec<f64> = history.heading().iter().map(|p| p - psi0).collect();
    let peak = (after..=end)
        .max_by(|&a, &b| change[a].abs().total_cmp(&change[b].abs()))
        .unwrap_or(after);
    let side = Side::of(change[peak]);
    let s = side.sign();
    let turned: Vec<f64> = change.iter().map(|c| s * c).collect();
    let max_heading_change = turned[peak].max(0.0);
    let changed = hold.and_then(|h| h.released).map(|i| time[i]);

    // Advance along the original course, transfer across it towards the turn.
    let (cos0, sin0) = (psi0.cos(), psi0.sin());
    let along = |at: At| (at.of(x) - x0) * cos0 + (at.of(y) - y0) * sin0;
    let across = |at: At| s * (-(at.of(x) - x0) * sin0 + (at.of(y) - y0) * cos0);
    let held_to = match changed {
        Some(t) => format!(" with the rudder held (it is changed at t = {t:.1} s)"),
        None => " after the execute".to_string(),
    };
    let reach = |deg: f64| {
        first_reaching(&turned[..=end], deg.to_radians(), exec).ok_or_else(|| {
            format!(
                "the heading changes by {:.1} deg at most{held_to}; this needs {deg} deg",
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
    let steady = steady_turn(history, &turned, hold.map_or(after, |h| h.reached), end);
    let speed_ratio = match (&steady.speed, &approach_speed) {
        (Measure::Value(s), Measure::Value(a)) if *a > 0.0 => Measure::Value(s / a),
        (Measure::Missing(r), _) | (_, Measure::Missing(r)) => Measure::missing(r.clone()),
        _ => Measure::missing("the approach speed is zero"),
    };
    let (rudder_angle, rudder_time) = rudder_held(history, hold.as_ref(), exec, t0);
    let (nominal_rudder_angle, nominal_rudder_from) =
        match (options.rudder_angle, rudder_angle.value()) {
            (None, None) => (rudder_angle.clone(), None),
            (given, held) => {
                let (a, from) = nominal(given, held.unwrap_or(0.0), &STANDARD_RUDDER_DEG);
                (Measure::Value(a), Some(from))
            }
        };
    Ok(TurningCircle {
        side,
        execute_time: t0,
        approach_heading: psi0,
        approach_speed,
        rudder_angle,
        nominal_rudder_angle,
        nominal_rudder_from,
        rudder_time,
        rudder_changed_at: changed,
        max_heading_change,
        advance: measure(&at90, &along),
        transfer: measure(&at90, &across),
        time_to_90: measure(&at90, &since),
        tactical_diameter: measure(&at180, &across),
        time_to_180: measure(&at180, &since),
        steady_from: steady.from,
        steady_yaw_rate: steady.yaw_rate,
        steady_diameter: steady.diameter,
        steady_speed: steady.speed,
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

/// The steady turn's measures: when it starts, its yaw rate, diameter and speed.
struct SteadyTurn {
    from: Measure,
    yaw_rate: Measure,
    diameter: Measure,
    speed: Measure,
}

/// The steady turn in the hold `a..=b` ([`steady_part`]): the diameter of the circle fitted
/// to its track (Kåsa), the mean yaw rate, and the speed as the mean of u, v or, without
/// them, the arc swept about the fitted centre by its time.
fn steady_turn(history: &History, turned: &[f64], a: usize, b: usize) -> SteadyTurn {
    let missing = |reason: String| SteadyTurn {
        from: Measure::missing(reason.clone()),
        yaw_rate: Measure::missing(reason.clone()),
        diameter: Measure::missing(reason.clone()),
        speed: Measure::missing(reason),
    };
    let Steady { from, to } = match steady_part(history, turned, a, b) {
        Ok(s) => s,
        Err(reason) => return missing(reason),
    };
    let Some((x, y)) = history.track() else {
        return missing("the history has no track".to_string());
    };
    let Some(circle) = fit_circle(&x[from..=to], &y[from..=to]) else {
        return missing("the track of the steady turn does not fit a circle".to_string());
    };
    let t = history.time();
    let duration = t[to] - t[from];
    let speed = match history.speed() {
        Some(_) => {
            let s = speeds(history);
            s[from..=to].iter().sum::<f64>() / (to - from + 1) as f64
        }
        None => {
            let angle = |i: usize| (y[i] - circle.cy).atan2(x[i] - circle.cx);
            let mut swept = 0.0;
            for i in from + 1..=to {
                let d = angle(i) - angle(i - 1);
                swept += d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
            }
            swept.abs() * circle.radius / duration
        }
    };
    SteadyTurn {
        from: Measure::Value(t[from]),
        yaw_rate: Measure::Value((turned[to] - turned[from]) / duration),
        diameter: Measure::Value(2.0 * circle.radius),
        speed: Measure::Value(speed),
    }
}

/// The rudder angle held in the turn (median of the hold) and the time from the execute
/// until the rudder first reaches it (interpolated between samples).
fn rudder_held(history: &History, hold: Option<&Hold>, exec: At, t0: f64) -> (Measure, Measure) {
    let (Some(rudder), Some(hold)) = (history.rudder(), hold) else {
        let r = "the history has no rudder angle";
        return (Measure::missing(r), Measure::missing(r));
    };
    let angle = hold.angle;
    let start = exec.of(rudder);
    let sign = if angle >= start { 1.0 } else { -1.0 };
    let moved: Vec<f64> = rudder.iter().map(|d| sign * (d - start)).collect();
    let reached = first_reaching(&moved, sign * (angle - start), exec)
        .map(|at| Measure::Value(at.of(history.time()) - t0))
        .unwrap_or_else(|| Measure::missing("the rudder never reaches its held angle"));
    (Measure::Value(angle), reached)
}
