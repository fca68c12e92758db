//! The run's speed-length ratio against the model's: a Froude number U / sqrt(g L) far from
//! the one the model is made for (its example's, [`crate::stages::plausible::model_froude`])
//! is a log at another scale than the vehicle's: a full-scale test read for the model-scale
//! vehicle gives sqrt(lambda) times the Froude number, the reverse 1 / sqrt(lambda) (equal
//! Froude numbers at both scales, ITTC 7.5-02-06-01; `froude` of a run, src/io/froude.rs).
//! The propeller's advance ratio J = U (1 - w) / (n D) is Froude-invariant, so a log at the
//! wrong scale with the vehicle's propeller diameter shows J lambda times too large (too
//! small): when J divided (multiplied) by the lambda the speeds give is a working one, the
//! scale is clear. A log's own consistency (positions against speeds, angles against rates)
//! holds at either scale, so no other check sees it; the advance ratio's check alone would
//! call a full-scale log "rev/s read as rpm" (J 45.7 times too large for the KVLCC2 model
//! is near 60).

use super::{file, median_of, sig, Expectation, Finding};
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::stages::plausible::{G, WORKING_ADVANCE};

/// A Froude number this many times the model's (or its inverse) is another scale (lambda
/// above 9: model scales run from about 1:15 to 1:60) ...
const FAR: f64 = 3.0;
/// ... and this many times is one without the propeller's confirmation (lambda above 25;
/// a slow run needs the propeller's confirmation: AUVs and starts from rest are slow).
const CLEAR: f64 = 5.0;

/// The scale check: None when the run's Froude number is within [`FAR`] of the model's.
pub(super) fn check(rec: &Record, expect: &Expectation) -> Option<Finding> {
    let model = expect.froude_model?;
    let (speed, used) = approach_speed(rec)?;
    let fr = speed / (G * expect.length).sqrt();
    let ratio = fr / model;
    if (1.0 / FAR..=FAR).contains(&ratio) {
        return None;
    }
    let full = ratio > 1.0;
    let lambda = if full {
        ratio * ratio
    } else {
        1.0 / (ratio * ratio)
    };
    // J of a log at the wrong scale: lambda times the working one (a full-scale log) or
    // 1 / lambda of it
    let advance = advance(rec, expect, &used);
    let scaled = advance.map(|j| if full { j / lambda } else { j * lambda });
    let inside = |j: f64| (WORKING_ADVANCE.0..=WORKING_ADVANCE.1).contains(&j);
    // clear when the propeller confirms it, or when the speed alone is far off; a slow run
    // without the propeller's confirmation is no finding (an AUV's or a start from rest)
    let confirmed = scaled.is_some_and(inside) && advance.is_some_and(|j| !inside(j));
    if !full && !confirmed {
        return None;
    }
    let clear = confirmed || ratio >= CLEAR;
    let j_words = advance
        .map(|j| {
            format!(
                "; the propeller's advance ratio J = U (1 - w) / (n D) is {} with D = {} m ({} at \
                 that scale; a working propeller: {} to {})",
                sig(j),
                sig(expect.propeller_diameter.unwrap_or(0.0)),
                sig(scaled.unwrap_or(j)),
                WORKING_ADVANCE.0,
                WORKING_ADVANCE.1
            )
        })
        .unwrap_or_default();
    let seen = format!(
        "in {}, the speed U = {} m/s (the approach's) gives a Froude number U / sqrt(g L) of \
         {} for L = {} m, {} times that of the model's example ({}){j_words}",
        file(rec),
        sig(speed),
        sig(fr),
        sig(expect.length),
        sig(ratio),
        sig(model)
    );
    // the propeller speed off by 60 at the vehicle's scale too: a second mistake
    let propeller = scaled
        .and_then(crate::stages::plausible::propeller_unit)
        .filter(|(clear, _)| *clear)
        .map(|(_, words)| format!("; at that scale {words}"))
        .unwrap_or_default();
    let meaning = if full {
        format!(
            "the log looks like a full-scale test read for the model-scale vehicle: give the \
             run's Froude scaling, `froude = {{ lambda = {}, to = \"model\" }}` with lambda = \
             L_ship / L_model (about {} from the speeds: the ship's length over \
             vehicle.length), which brings its speeds, times, rates and propeller speed to the \
             model's scale (not the propeller's unit: a factor of 60 would leave the speeds at \
             full scale; a run Froude-scaled already has a lambda about {} times too small){propeller}",
            round_lambda(lambda),
            round_lambda(lambda),
            round_lambda(lambda)
        )
    } else {
        format!(
            "the log looks like a model test read for the full-scale vehicle: give the run's \
             Froude scaling, `froude = {{ lambda = {}, to = \"full\" }}` with lambda = L_ship / \
             L_model (about {} from the speeds), or describe the model in [vehicle]{propeller}",
            round_lambda(lambda),
            round_lambda(lambda)
        )
    };
    Some(Finding::new(rec, clear, seen, meaning))
}

/// A scale ratio rounded for a message: to 2 significant digits.
fn round_lambda(lambda: f64) -> String {
    let digits = 10f64.powf(lambda.log10().floor() - 1.0);
    let rounded = (lambda / digits).round() * digits;
    if rounded >= 10.0 {
        format!("{rounded:.0}")
    } else {
        format!("{rounded:.1}")
    }
}

/// The approach speed (the median over the run's approach, before the heading or the rudder
/// moves: the model's example speed is an approach speed, and a turn slows the vehicle
/// down; the run's 95th percentile without an approach) and the samples at speed (at least
/// half the 95th percentile: not a start from rest) for the advance ratio; None without u
/// or with fewer than 10 samples.
fn approach_speed(rec: &Record) -> Option<(f64, Vec<usize>)> {
    let n = rec.rows();
    let u = rec.channel(Quantity::U).filter(|u| u.len() == n)?;
    let v = rec.channel(Quantity::V).filter(|v| v.len() == n);
    let speed = |k: usize| u[k].hypot(v.map_or(0.0, |v| v[k]));
    let mut all: Vec<f64> = (0..n).map(speed).filter(|s| s.is_finite()).collect();
    if all.len() < 10 {
        return None;
    }
    let idx95 = (0.95 * (all.len() - 1) as f64) as usize;
    let fast = *all.select_nth_unstable_by(idx95, f64::total_cmp).1;
    if fast <= 0.0 {
        return None;
    }
    let used: Vec<usize> = (0..n).filter(|&k| speed(k) >= 0.5 * fast).collect();
    let approach = super::approach(rec)
        .and_then(|range| median_of(range.map(speed)))
        .unwrap_or(fast);
    Some((approach, used))
}

/// The median advance ratio over the samples `used` with the propeller turning ahead.
fn advance(rec: &Record, expect: &Expectation, used: &[usize]) -> Option<f64> {
    let d = expect.propeller_diameter?;
    let u = rec.channel(Quantity::U)?;
    let v = rec.channel(Quantity::V);
    median_of(used.iter().filter_map(|&k| {
        let n = rec.value_at(Quantity::Rpm, k).filter(|n| *n > 0.0)?;
        let speed = u[k].hypot(v.map_or(0.0, |v| v[k]));
        Some(speed * (1.0 - expect.wake) / (n * d))
    }))
}

#[cfg(test)]
mod tests {
    use super::round_lambda;

    #[test]
    fn lambda_is_rounded_to_two_digits() {
        assert_eq!(round_lambda(52.37), "52");
        assert_eq!(round_lambda(9.64), "9.6");
        assert_eq!(round_lambda(123.0), "120");
    }
}
