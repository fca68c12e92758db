//! Cheap plausibility checks of a run before it is filtered, so that the common mistakes
//! (a wrong velocity frame, knots read as m/s, a heading in the wrong unit or sign, two
//! quantities mapped to one column, the wrong column for a rate, a rudder in the wrong unit
//! or sign, rpm read as rps, positions in km or a time in minutes, u and v swapped, a
//! constant input that does not fit the motion) are named as such instead of ending as "the
//! sway-yaw mass matrix is singular", a filter divergence or, worse, confident wrong
//! coefficients.
//!
//! Kinematics need no coefficients (`rates`, `travel`): the positions must follow the body
//! velocities rotated by the heading (x_dot + i y_dot = (u + i v) e^(i psi), Fossen 2011,
//! eq. 2.40 in the horizontal plane), so the distance travelled is the speed's integral; and
//! the Euler angles' rates follow the body rates (Fossen 2011, eq. 2.41). Each relation is
//! fitted with a robust gain (medians of sample ratios, so that an outlier does not decide)
//! over windows long enough that the noise cannot dominate, and when it fails, the
//! alternatives a user may have meant are fitted too and the one that holds is named.
//!
//! The controls are judged against the model (`rudder`, `propeller`): the yaw acceleration a
//! rudder angle gives, as the run shows it and as the model at its starting coefficients
//! says, and the propeller's advance ratio.
//!
//! A finding is `blocking` when the data contradict the configuration and one unambiguous
//! alternative (a factor of 57.3, 60 or 1000, a sign) explains them; otherwise it is a
//! warning. A check that cannot judge a run (the heading does not move, the rudder is still)
//! says nothing.

mod froude;
mod inputs;
mod propeller;
mod rates;
mod rudder;
mod travel;

pub use inputs::{constant_inputs, Held, Start};

use super::STAGE;
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::model::models::Model;
use crate::stages::plausible::{file, median, median_of, named};
pub use crate::stages::plausible::{Expectation, Finding};

impl Finding {
    fn new(rec: &Record, blocking: bool, message: String, meaning: String) -> Self {
        Finding::of(STAGE, &rec.name, blocking, message, meaning)
    }
}

/// Every check of a run before it is filtered: duplicated columns, positions and time
/// against the speeds, each Euler angle against its rate, positions against the velocities
/// rotated by the heading, u and v in the approach, the rudder against the model's response
/// and the propeller's advance ratio. A time axis in the wrong unit spoils every rate, so
/// the checks built on rates are left out when one is found.
pub fn before_filter<M: Model>(model: &M, rec: &Record, expect: &Expectation) -> Vec<Finding> {
    let mut out = duplicates(rec);
    // every check indexes the channels by sample: a record whose channels differ in length
    // (made in memory, never read from a file) is not judged further
    if rec.channels.values().any(|v| v.len() != rec.rows()) {
        return out;
    }
    let speed = travel::speed(rec);
    let time_wrong = matches!(speed, Some((_, travel::Suspect::Time)));
    let speed_found = speed.is_some();
    out.extend(speed.map(|(f, _)| f));
    let mut rate_trusted = true;
    let mut heading_trusted = true;
    if !time_wrong {
        for (q, f) in rates::all(rec) {
            rate_trusted &= !(q == Quantity::R && f.blocking);
            heading_trusted &= !(q == Quantity::Yaw && f.blocking);
            out.push(f);
        }
    }
    if !speed_found && heading_trusted {
        out.extend(travel::track(rec));
    }
    out.extend(travel::sway_over_surge(rec));
    // a log at another scale than the vehicle's (a speed unit is the travel check's): the
    // propeller's advance ratio and the rudder's response are then off by the scale, not by
    // a unit of their own
    let scale = (!speed_found).then(|| froude::check(rec, expect)).flatten();
    let scaled = scale.is_some();
    out.extend(scale);
    if !time_wrong {
        let sizes = Expectation {
            sizes_known: expect.sizes_known && !scaled,
            ..expect.clone()
        };
        out.extend(rudder::check(model, rec, &sizes, rate_trusted));
    }
    if !scaled {
        out.extend(propeller::check(rec, expect));
    }
    out
}

/// Quantities with identical values: one column mapped to several quantities.
fn duplicates(rec: &Record) -> Vec<Finding> {
    crate::stages::plausible::identical_channels(rec, STAGE)
}

/// The approach: the leading samples before the manoeuvre, while the heading stays within
/// 5 deg and the rudder within 2 deg of their starting values (the median of the first five
/// samples); the whole run when it has neither. None when shorter than 10 samples.
fn approach(rec: &Record) -> Option<std::ops::Range<usize>> {
    let n = rec.rows();
    let departs = |q: Quantity, limit_deg: f64| -> usize {
        let Some(v) = rec.channel(q) else {
            return n;
        };
        let Some(start) = median_of(v.iter().take(5).copied()) else {
            return n;
        };
        let limit = limit_deg.to_radians();
        v.iter()
            .position(|x| (x - start).abs() > limit)
            .unwrap_or(v.len())
    };
    let end = departs(Quantity::Yaw, 5.0)
        .min(departs(Quantity::Rudder, 2.0))
        .min(n);
    (end >= 10).then_some(0..end)
}

/// Samples per window of the integral checks: increments over a few samples average the
/// measurement noise out of the comparison.
const WINDOW: usize = 5;

/// Fewest windows a check fits its gain over (longer windows are tried while at least this
/// many fit in the run).
const MIN_WINDOWS: usize = 40;

/// A relation holds when its robust gain is within this of 1 ...
const GAIN_TOLERANCE: f64 = 0.15;
/// ... and the median residual is below this share of the median signal.
const GOOD_FIT: f64 = 0.25;

/// Non-overlapping windows (first, last sample) of `len` regular intervals (each within 1 %
/// of the median interval).
fn windows(times: &[f64], len: usize) -> Vec<(usize, usize)> {
    let Some(dt) = crate::numerics::sampling::median_interval(times) else {
        return Vec::new();
    };
    let regular = |k: usize| (times[k + 1] - times[k] - dt).abs() < 0.01 * dt;
    let mut out = Vec::new();
    let mut k = 0;
    while k + len < times.len() {
        match (k..k + len).find(|&j| !regular(j)) {
            Some(j) => k = j + 1,
            None => {
                out.push((k, k + len));
                k += len;
            }
        }
    }
    out
}

/// The window lengths (samples) a check tries, shortest first: 5 samples, doubled while at
/// least [`MIN_WINDOWS`] windows fit in the run. A relation that fails over short windows
/// because the signal moves less than its noise (or its printed resolution) holds over the
/// longer ones; one that fails over every length is a mistake.
fn window_lengths(times: &[f64]) -> Vec<usize> {
    let mut out = vec![WINDOW];
    let mut len = WINDOW;
    loop {
        len *= 2;
        if windows(times, len).len() < MIN_WINDOWS {
            return out;
        }
        out.push(len);
    }
}

/// The increment of `y` over a window and the integral of `rate(k)` over it (trapezoid):
/// y(t1) - y(t0) = integral of y_dot dt.
fn increment(
    times: &[f64],
    (a, b): (usize, usize),
    y: &[f64],
    rate: impl Fn(usize) -> f64,
) -> (f64, f64) {
    (y[b] - y[a], integral(times, (a, b), rate))
}

/// The integral of `rate(k)` over a window (trapezoid).
fn integral(times: &[f64], (a, b): (usize, usize), rate: impl Fn(usize) -> f64) -> f64 {
    (a..b)
        .map(|k| 0.5 * (rate(k) + rate(k + 1)) * (times[k + 1] - times[k]))
        .sum()
}

/// A robust complex gain g with measured = g * predicted, and the median relative residual,
/// from samples where the prediction is large (above a fifth of its 95th percentile).
fn complex_gain(measured: &[(f64, f64)], predicted: &[(f64, f64)]) -> Option<((f64, f64), f64)> {
    let mut mag: Vec<f64> = predicted.iter().map(|p| p.0.hypot(p.1)).collect();
    if mag.is_empty() {
        return None;
    }
    let idx95 = (0.95 * (mag.len() - 1) as f64) as usize;
    let p95 = *mag.select_nth_unstable_by(idx95, f64::total_cmp).1;
    if p95.is_nan() || p95 <= 0.0 {
        return None;
    }
    let used: Vec<usize> = (0..predicted.len())
        .filter(|&k| predicted[k].0.hypot(predicted[k].1) > 0.2 * p95)
        .collect();
    if used.len() < 10 {
        return None;
    }
    // g_k = m_k / p_k (complex division)
    let (mut re, mut im): (Vec<f64>, Vec<f64>) = used
        .iter()
        .map(|&k| {
            let (a, b) = measured[k];
            let (c, d) = predicted[k];
            let den = c * c + d * d;
            ((a * c + b * d) / den, (b * c - a * d) / den)
        })
        .unzip();
    let g = (median(&mut re)?, median(&mut im)?);
    let mut res: Vec<f64> = used
        .iter()
        .map(|&k| {
            let (c, d) = predicted[k];
            let (pr, pi) = (g.0 * c - g.1 * d, g.0 * d + g.1 * c);
            (measured[k].0 - pr).hypot(measured[k].1 - pi)
        })
        .collect();
    let mut size: Vec<f64> = used
        .iter()
        .map(|&k| measured[k].0.hypot(measured[k].1))
        .collect();
    let rel = median(&mut res)? / median(&mut size)?.max(f64::MIN_POSITIVE);
    Some((g, rel))
}

/// Pearson's correlation of two equally long series (None when either does not vary).
fn correlation(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len().min(b.len());
    if n < 3 {
        return None;
    }
    let mean = |v: &[f64]| v[..n].iter().sum::<f64>() / n as f64;
    let (ma, mb) = (mean(a), mean(b));
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (x, y) = (a[k] - ma, b[k] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    let r = sab / (saa * sbb).sqrt();
    r.is_finite().then_some(r)
}

/// A unit mistake a gain may reveal: the factor and what it means, with the fix.
struct Factor {
    gain: f64,
    words: &'static str,
}

/// Positions travelled per the speeds' distance: what a factor means.
const TRAVEL_FACTORS: &[Factor] = &[
    Factor {
        gain: 1852.0 / 3600.0,
        words: "the velocities look like knots read as m/s: give their unit, e.g. \
                `u = { column = \"...\", unit = \"kn\" }` (and v)",
    },
    Factor {
        gain: 3600.0 / 1852.0,
        words: "the velocities look like m/s read as knots: give `unit = \"m/s\"` in the u \
                and v column entries",
    },
    Factor {
        gain: 0.3048,
        words: "the velocities look like ft/s read as m/s, or the positions like feet: give \
                `unit = \"ft/s\"` in the u and v column entries, or `unit = \"ft\"` in x and y",
    },
    Factor {
        gain: 1.0 / 0.3048,
        words: "the positions look like feet read as metres: give `unit = \"ft\"` in the x and \
                y column entries",
    },
    Factor {
        gain: 1.0 / 3.6,
        words: "the velocities look like km/h read as m/s: give `unit = \"km/h\"` in the u \
                and v column entries",
    },
    // the words of the two factors of 1000 depend on the unit read (`travel::thousand`)
    Factor {
        gain: 1e-3,
        words: "the positions look 1000 times too small for the speeds",
    },
    Factor {
        gain: 1e3,
        words: "the positions look 1000 times too large for the speeds",
    },
    Factor {
        gain: 60.0,
        words: "the time looks like minutes read as seconds: give `time = { column = \"...\", \
                unit = \"min\" }`",
    },
    Factor {
        gain: 1.0 / 60.0,
        words: "the time looks like seconds read as minutes: give `unit = \"s\"` in the time \
                column entry",
    },
];

/// An angle's change per its rate's integral: what a factor means.
const RATE_FACTORS: &[Factor] = &[
    Factor {
        gain: std::f64::consts::PI / 180.0,
        words: "the rate looks like deg/s read as rad/s: give the column's unit explicitly, \
                e.g. `unit = \"deg/s\"` in its column entry",
    },
    Factor {
        gain: 180.0 / std::f64::consts::PI,
        words: "the angle looks like degrees read as radians (or the rate like rad/s read as \
                deg/s): give the column's unit explicitly, e.g. `unit = \"deg\"` or \
                `unit = \"deg/s\"` in its column entry",
    },
    Factor {
        gain: 60.0,
        words: "the time looks like minutes read as seconds (or the rate like a rate per \
                minute): give `time = { column = \"...\", unit = \"min\" }`",
    },
    Factor {
        gain: 1.0 / 60.0,
        words: "the time looks like seconds read as minutes: give `unit = \"s\"` in the time \
                column entry",
    },
];

/// The factor of `table` within 3 % of `gain`.
fn factor(gain: f64, table: &'static [Factor]) -> Option<&'static Factor> {
    table.iter().find(|f| (gain / f.gain - 1.0).abs() < 0.03)
}

fn sig(v: f64) -> String {
    crate::base::numfmt::num(v)
}

#[cfg(test)]
mod tests;
