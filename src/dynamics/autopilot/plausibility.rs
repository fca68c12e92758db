//! Whether a closed loop is one a working autopilot gives: a recorded disturbance the rudder
//! can hold, and after the run a heading held (its error RMS far below a turn's) with the
//! rudder not hard over most of the time. A loop that spins (a plant whose rudder works the
//! other way, a propeller speed in rpm read as rev/s) gives heading errors of thousands of
//! degrees RMS: it is said, with the likely causes, rather than reported as a result.

use super::closed_loop::{LoopError, Scenario};
use super::seas::{DisturbanceKind, Seas};
use super::AutopilotResult;
use crate::base::warning::Warning;

/// Heading error RMS beyond which a loop holds no course, rad (45 deg): a working loop's is a
/// few degrees in waves, and a course change under the reference model adds little.
pub const LOST_HEADING: f64 = std::f64::consts::FRAC_PI_4;

/// Share of the samples with the rudder at its limit beyond which the loop is saturated.
pub const HARD_OVER_SHARE: f64 = 0.5;

/// Refuses a recorded rudder disturbance (or a yaw moment as the rudder angle it is worth on
/// the plant, `per_rudder` its yaw acceleration per rudder angle, 1/s^2) whose RMS is beyond
/// the rudder limit or whose peak is beyond 90 deg: no rudder holds it, so the loop would
/// only say that the file's unit or the yaw inertia is wrong.
pub fn disturbance_within_rudder(
    seas: &Seas,
    per_rudder: f64,
    s: &Scenario,
) -> Result<(), LoopError> {
    let Seas::Recorded(r) = seas else {
        return Ok(());
    };
    let (rms, peak) = r.rms_and_peak(s.duration);
    let (scale, what) = match r.kind {
        DisturbanceKind::WaveYaw => return Ok(()),
        DisturbanceKind::Rudder => (
            1.0,
            "the recorded rudder-equivalent disturbance".to_string(),
        ),
        DisturbanceKind::YawMoment => {
            let inertia = r.yaw_inertia.unwrap_or(f64::NAN);
            (
                1.0 / (inertia * per_rudder),
                format!(
                    "the recorded yaw moment (RMS {:.4e} N m, peak {:.4e} N m, on a yaw inertia \
                     of {inertia:.4e} kg m^2 and the plant's {:.4e} 1/s^2 of yaw acceleration \
                     per rudder radian)",
                    rms, peak, per_rudder
                ),
            )
        }
    };
    let (rms, peak) = ((rms * scale).abs(), (peak * scale).abs());
    let limit = s.limits.angle;
    if rms.is_finite() && rms <= limit && peak <= std::f64::consts::FRAC_PI_2 {
        return Ok(());
    }
    Err(LoopError::Disturbance(format!(
        "{what} is worth a rudder of {:.1} deg RMS and {:.1} deg at its peak: beyond the \
         rudder limit of {:.1} deg (autopilot.rudder_limit), no rudder holds it; check the \
         file's unit (a header unit such as `[deg]` or `[kN m]` is converted; without one a \
         rudder angle is read in autopilot.disturbance_unit and a moment in N m) and \
         autopilot.yaw_inertia",
        rms.to_degrees(),
        peak.to_degrees(),
        limit.to_degrees()
    )))
}

/// Warnings on the feeds whose loop does not hold a course: a heading error RMS beyond
/// [`LOST_HEADING`], or the rudder at its `limit` (rad) for more than [`HARD_OVER_SHARE`]
/// of the run. `causes` says what to check about the plant.
pub fn closed_loop_warnings(r: &AutopilotResult, limit: f64, causes: &str) -> Vec<Warning> {
    let mut lost = Vec::new();
    for l in &r.feeds {
        let hard_over = l.rudder.iter().filter(|d| d.abs() >= 0.999 * limit).count() as f64
            / l.rudder.len().max(1) as f64;
        if l.heading_error_rms > LOST_HEADING || hard_over > HARD_OVER_SHARE {
            lost.push(format!(
                "fed the {}, heading error RMS {:.1} deg with the rudder hard over ({} deg) \
                 {:.0} % of the time",
                l.feed.describe(),
                l.heading_error_rms.to_degrees(),
                crate::base::numfmt::fixed_trimmed(limit.to_degrees(), 1),
                100.0 * hard_over
            ));
        }
    }
    if lost.is_empty() {
        return Vec::new();
    }
    vec![Warning::new(
        "autopilot",
        format!(
            "the closed loop holds no course ({}): a working loop keeps the heading error RMS \
             within a few degrees and the rudder off its stops; {}",
            lost.join("; "),
            r.plant.line()
        ),
        format!("these statistics describe a loop that does not work, not the autopilot: {causes}"),
    )]
}
