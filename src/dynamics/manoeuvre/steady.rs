//! The steady part of a turn: the samples with the rudder held at which the rate of turn and
//! the speed have settled to their final values. ITTC 7.5-04-02-01, 2.2.1 reads the steady
//! turning diameter and speed once the rate of turn has become constant with the rudder
//! held (MSC.137(76), annex, 4.2.2: the turning circle with the rudder held); the pull-out
//! after it (rudder back to zero) is another manoeuvre (ITTC 7.5-04-02-01, 2.2.6).
//!
//! Defined from the data: over the hold (from the rudder reaching its angle to the last
//! sample before it is changed, or the run's end) the mean yaw rate and speed are taken over
//! windows of [`WINDOW_ARC`] of heading change; their final values are those of the last
//! window. The steady part starts at the centre of the first window after which every
//! window's yaw rate is within [`YAW_RATE_SHARE`] and speed within [`SPEED_SHARE`] of the
//! final values, and ends with the hold. It must span [`STEADY_ARC_MIN`].

use super::history::History;

/// Heading change a window spans, rad (45 deg): long enough that a heading printed to
/// 1 deg (three significant digits past 100 deg) moves the window's yaw rate by 2 % at most.
pub const WINDOW_ARC: f64 = std::f64::consts::FRAC_PI_4;

/// Largest departure of a window's yaw rate from the final one in a steady turn (5 %).
pub const YAW_RATE_SHARE: f64 = 0.05;

/// Largest departure of a window's speed from the final one in a steady turn (10 %): wider
/// than the yaw rate's because a basin's drift and the last of the speed decay move the
/// speed over ground by several per cent over a turn (MARIN KVLCC2 35 deg turns: 2.8 to
/// 3.1 m/s with the yaw rate within 2 %).
pub const SPEED_SHARE: f64 = 0.1;

/// Heading change the steady part must span for a diameter to be fitted, rad (90 deg).
pub const STEADY_ARC_MIN: f64 = std::f64::consts::FRAC_PI_2;

/// The steady part of a turn: samples `from..=to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Steady {
    /// First sample.
    pub from: usize,
    /// Last sample (the end of the hold).
    pub to: usize,
}

/// The steady part of the hold `a..=b` of `history`, whose heading change towards the turn
/// is `turned` (rad); the reason when there is none.
pub(super) fn steady_part(
    history: &History,
    turned: &[f64],
    a: usize,
    b: usize,
) -> Result<Steady, String> {
    let t = history.time();
    let held = turned[b] - turned[a];
    if held < WINDOW_ARC + STEADY_ARC_MIN {
        return Err(format!(
            "the heading changes by {:.1} deg with the rudder held at its angle; a steady turn \
             is read over {:.0} deg windows and needs {:.0} deg",
            held.to_degrees(),
            WINDOW_ARC.to_degrees(),
            (WINDOW_ARC + STEADY_ARC_MIN).to_degrees()
        ));
    }
    let speed = speeds(history);
    let at = |time: f64| history.at_time(time).of(turned);
    // the last window: the last WINDOW_ARC of heading change of the hold
    let last = (a..b).rev().find(|&i| turned[i] <= turned[b] - WINDOW_ARC);
    let start = last.map_or(t[a], |i| {
        let f = (turned[b] - WINDOW_ARC - turned[i]) / (turned[i + 1] - turned[i]);
        t[i] + f * (t[i + 1] - t[i])
    });
    let w = t[b] - start;
    let (rate_final, speed_final) = (WINDOW_ARC / w, mean_between(t, &speed, start, t[b]));
    let mut from = None;
    for i in a..=b {
        let (lo, hi) = (t[i] - 0.5 * w, t[i] + 0.5 * w);
        if lo < t[a] || hi > t[b] {
            continue;
        }
        let rate = (at(hi) - at(lo)) / w;
        let u = mean_between(t, &speed, lo, hi);
        let steady = (rate - rate_final).abs() <= YAW_RATE_SHARE * rate_final
            && (u - speed_final).abs() <= SPEED_SHARE * speed_final;
        match (steady, from) {
            (true, None) => from = Some(i),
            (false, _) => from = None,
            _ => {}
        }
    }
    let from = from.unwrap_or(b);
    let arc = turned[b] - turned[from];
    if arc < STEADY_ARC_MIN {
        return Err(format!(
            "the turn is steady (yaw rate within {:.0} % and speed within {:.0} % of their \
             values over the last {:.0} deg with the rudder held) over {:.1} deg of heading \
             change only; the steady turning diameter needs {:.0} deg",
            100.0 * YAW_RATE_SHARE,
            100.0 * SPEED_SHARE,
            WINDOW_ARC.to_degrees(),
            arc.to_degrees(),
            STEADY_ARC_MIN.to_degrees()
        ));
    }
    Ok(Steady { from, to: b })
}

/// The speed at each sample: from u and v when the history has them, else from the track
/// (the chord to the next sample over its time; the last sample repeats the one before).
pub(super) fn speeds(history: &History) -> Vec<f64> {
    if let Some(s) = history.speed() {
        return s;
    }
    let t = history.time();
    let Some((x, y)) = history.track() else {
        return vec![0.0; t.len()];
    };
    let mut s: Vec<f64> = (1..t.len())
        .map(|i| (x[i] - x[i - 1]).hypot(y[i] - y[i - 1]) / (t[i] - t[i - 1]))
        .collect();
    s.push(s[s.len() - 1]);
    s
}

/// The mean of `v` over the samples whose time lies in `[lo, hi]` (the nearest sample when
/// none does).
fn mean_between(t: &[f64], v: &[f64], lo: f64, hi: f64) -> f64 {
    let first = t.partition_point(|&s| s < lo);
    let end = t.partition_point(|&s| s <= hi);
    if end > first {
        v[first..end].iter().sum::<f64>() / (end - first) as f64
    } else {
        v[first.min(v.len() - 1)]
    }
}
