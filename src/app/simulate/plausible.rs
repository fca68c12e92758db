//! The magnitude limits of a `hydroid simulate` manoeuvre beyond its sampling bounds
//! ([`super::config::limits`]): speeds a towing carriage or a vessel can have, a helm that
//! acts within the manoeuvre (docs/simulate.md, "What is checked";
//! [`crate::config::motion_limits`]).

use crate::config::{motion_limits, Problems};

/// True when every speed of `manoeuvre.speeds` is a carriage's ([`motion_limits::speed`]);
/// else a problem at each that is not.
pub(super) fn speeds(speeds: &[f64], p: &mut Problems) -> bool {
    let mut ok = true;
    for (i, u) in speeds.iter().enumerate() {
        if let Some(m) = motion_limits::speed(*u) {
            p.add(&format!("manoeuvre.speeds[{i}]"), m);
            ok = false;
        }
    }
    ok
}

/// True when the helm of a time history `duration` s long acts within it (its execute
/// time before the end); else a problem at `manoeuvre.steering.execute`.
pub(super) fn helm_within(
    law: &crate::dynamics::sim::steering::Steering,
    duration: f64,
    p: &mut Problems,
) -> bool {
    use crate::dynamics::sim::steering::Steering;
    let (Steering::Turn { execute, .. } | Steering::ZigZag { execute, .. }) = *law;
    if execute < duration {
        return true;
    }
    p.add(
        "manoeuvre.steering.execute",
        format!(
            "{} s is at or after the end of the manoeuvre ({} s, manoeuvre.duration): the helm \
             would never act; an execute time in ms, or a longer duration?",
            crate::base::numfmt::short(execute),
            crate::base::numfmt::short(duration)
        ),
    );
    false
}

/// Adds a problem at `key` when an initial surge speed `u` (m/s) is beyond a vessel's.
pub(super) fn initial_speed(key: &str, u: f64, p: &mut Problems) {
    if u.abs() > motion_limits::MAX_SPEED {
        p.add(key, motion_limits::speed(u.abs()).unwrap_or_default());
    }
}
