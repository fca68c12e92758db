//! Cheap plausibility checks of a run before it is filtered, so that the common mistakes
//! (a wrong velocity frame, knots read as m/s, a heading in the wrong unit or sign, two
//! quantities mapped to one column, a constant input that does not fit the motion) are named
//! as such instead of ending as "the sway-yaw mass matrix is singular" or, worse, as
//! confident wrong coefficients.
//!
//! Kinematics need no coefficients: the positions must follow the body velocities rotated by
//! the heading (x_dot + i y_dot = (u + i v) e^(i psi), Fossen 2011, eq. 2.40 in the
//! horizontal plane), and the heading rate the yaw rate (psi_dot = (q sin phi + r cos phi) /
//! cos theta, Fossen 2011, eq. 2.41; r when roll and pitch are not given). Each relation is
//! fitted with a robust gain (medians of sample ratios, so that an outlier does not decide),
//! and when it fails, the alternatives a user may have meant are fitted too and the one
//! that holds is named.

mod inputs;

pub use inputs::{constant_inputs, Start};

use super::STAGE;
use crate::quantity::Quantity;
use crate::record::Record;
use crate::warning::Warning;

/// A finding of a check: a warning, and whether it is a clear mistake that stops the run
/// (with `hekf.checks = "error"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// What was found and what it means.
    pub warning: Warning,
    /// A clear mistake: the data contradict the configuration and an alternative fits.
    pub blocking: bool,
}

impl Finding {
    fn new(rec: &Record, blocking: bool, message: String, meaning: String) -> Self {
        Finding {
            warning: Warning::new(STAGE, message, meaning).for_run(&rec.name),
            blocking,
        }
    }
}

/// A relation holds when its robust gain is within this of 1 ...
const GAIN_TOLERANCE: f64 = 0.15;
/// ... and the median residual is below this share of the median signal.
const GOOD_FIT: f64 = 0.25;

/// Every check of a run's kinematics: duplicated columns, heading against yaw rate, positions
/// against velocities.
pub fn kinematics(rec: &Record) -> Vec<Finding> {
    let mut out = duplicates(rec);
    out.extend(heading_rate(rec));
    out.extend(track(rec));
    out
}

/// Quantities with identical values: one column mapped to several quantities.
fn duplicates(rec: &Record) -> Vec<Finding> {
    let chans: Vec<(&Quantity, &Vec<f64>)> = rec
        .channels
        .iter()
        .filter(|(q, v)| **q != Quantity::Time && v.iter().any(|x| *x != v[0]))
        .collect();
    // groups of identical channels, each named once
    let mut seen = vec![false; chans.len()];
    let mut out = Vec::new();
    for i in 0..chans.len() {
        if seen[i] {
            continue;
        }
        let group: Vec<&Quantity> = (i..chans.len())
            .filter(|&j| chans[j].1 == chans[i].1)
            .inspect(|&j| seen[j] = true)
            .map(|j| chans[j].0)
            .collect();
        // control surfaces commanded together (the helix of Mousavian et al. 2015 steps
        // rudder and stern planes to the same angle) are a manoeuvre, not a mapping mistake
        let commanded = group.iter().all(|q| is_control(**q)) && piecewise_constant(chans[i].1);
        if group.len() > 1 && !commanded {
            let names = group.iter().map(|q| q.key()).collect::<Vec<_>>().join(", ");
            out.push(Finding::new(
                rec,
                true,
                format!(
                    "{names} hold identical values in all {} rows",
                    chans[i].1.len()
                ),
                format!(
                    "one column is almost certainly mapped to several quantities; check the \
                     run's `columns` for {names}"
                ),
            ));
        }
    }
    out
}

/// Control inputs a manoeuvre may command to identical values.
fn is_control(q: Quantity) -> bool {
    matches!(
        q,
        Quantity::Rudder
            | Quantity::SternPlanes
            | Quantity::BowPlanes
            | Quantity::Rpm
            | Quantity::Thrust
    )
}

/// A series that changes in at most one sample in ten (steps, not a measured signal).
fn piecewise_constant(v: &[f64]) -> bool {
    let changes = v.windows(2).filter(|w| w[1] != w[0]).count();
    changes * 10 <= v.len()
}

/// Samples per window of the integral checks: increments over a few samples average the
/// measurement noise out of the comparison.
const WINDOW: usize = 5;

/// Fewest windows a check fits its gain over (longer windows are tried while at least this
/// many fit in the run).
const MIN_WINDOWS: usize = 40;

/// Non-overlapping windows (first, last sample) of `len` regular intervals (each within 1 %
/// of the median interval).
fn windows(times: &[f64], len: usize) -> Vec<(usize, usize)> {
    let Some(dt) = crate::sampling::median_interval(times) else {
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

/// The increment of `y` over a window and the integral of `rate(k)` over it (trapezoid):
/// y(t1) - y(t0) = integral of y_dot dt.
fn increment(
    times: &[f64],
    (a, b): (usize, usize),
    y: &[f64],
    rate: impl Fn(usize) -> f64,
) -> (f64, f64) {
    let integral = (a..b)
        .map(|k| 0.5 * (rate(k) + rate(k + 1)) * (times[k + 1] - times[k]))
        .sum();
    (y[b] - y[a], integral)
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
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

/// Words for a gain that is a common unit factor.
fn unit_factor(gain: f64) -> Option<&'static str> {
    const KNOT: f64 = 1852.0 / 3600.0;
    const FOOT: f64 = 0.3048;
    const KMH: f64 = 1.0 / 3.6;
    let known: [(f64, &str); 8] = [
        (KNOT, "the velocities look like knots read as m/s"),
        (1.0 / KNOT, "the velocities look like m/s read as knots"),
        (
            FOOT,
            "the velocities look like ft/s read as m/s, or the positions like feet",
        ),
        (1.0 / FOOT, "the positions look like feet read as metres"),
        (KMH, "the velocities look like km/h read as m/s"),
        (
            std::f64::consts::PI / 180.0,
            "the rate looks like deg/s read as rad/s",
        ),
        (
            180.0 / std::f64::consts::PI,
            "the angle looks like degrees read as radians (or the rate like rad/s read as deg/s)",
        ),
        (
            1000.0,
            "one of the two looks like millimetres or kilometres",
        ),
    ];
    known
        .iter()
        .find(|(f, _)| (gain / f - 1.0).abs() < 0.03)
        .map(|(_, s)| *s)
}

/// The heading rate against the yaw rate.
fn heading_rate(rec: &Record) -> Option<Finding> {
    let times = rec.time()?;
    let psi = rec.channel(Quantity::Yaw)?;
    let r = rec.channel(Quantity::R)?;
    // psi_dot = (q sin phi + r cos phi) / cos theta (Fossen 2011, eq. 2.41)
    let euler = |k: usize| -> f64 {
        match (
            rec.channel(Quantity::Roll),
            rec.channel(Quantity::Pitch),
            rec.channel(Quantity::Q),
        ) {
            (Some(phi), Some(theta), Some(q)) => {
                (q[k] * phi[k].sin() + r[k] * phi[k].cos()) / theta[k].cos()
            }
            _ => r[k],
        }
    };
    type Pairs = Vec<(f64, f64)>;
    let fit = |wins: &[(usize, usize)]| {
        let (measured, predicted): (Pairs, Pairs) = wins
            .iter()
            .map(|&w| {
                let (m, p) = increment(times, w, psi, euler);
                ((m, 0.0), (p, 0.0))
            })
            .unzip();
        complex_gain(&measured, &predicted)
    };
    // A slow turn changes the heading less in a few samples than the heading's noise: the
    // windows grow (doubling) until the relation holds or too few windows are left, and
    // the longest (least noisy) fit is reported.
    let mut len = WINDOW;
    let mut wins = windows(times, len);
    let mut last = fit(&wins)?;
    loop {
        let ((g, _), rel) = last;
        if (g - 1.0).abs() < GAIN_TOLERANCE && rel < GOOD_FIT {
            return None;
        }
        len *= 2;
        let longer = windows(times, len);
        if longer.len() < MIN_WINDOWS {
            break;
        }
        match fit(&longer) {
            Some(f) => (last, wins) = (f, longer),
            None => break,
        }
    }
    let ((g, _), rel) = last;
    // A heading that moves no more than its noise over the longest windows (a vertical
    // manoeuvre) says nothing about the yaw rate: no finding. An increment of two noisy
    // samples has sigma sqrt(2) s; 4 s is beyond it for nine windows in ten.
    let noise = crate::signal::noise_sigma(psi).unwrap_or(0.0);
    let mut moves: Vec<f64> = wins.iter().map(|&(a, b)| (psi[b] - psi[a]).abs()).collect();
    if median(&mut moves).is_none_or(|m| m < 4.0 * noise) {
        return None;
    }
    let fits = rel < GOOD_FIT;
    let seen = format!(
        "the heading changes {} times as fast as the yaw rate r says (median relative \
         residual {:.0} %)",
        sig(g),
        100.0 * rel
    );
    let (blocking, meaning) = if fits && (g + 1.0).abs() < GAIN_TOLERANCE {
        (
            true,
            "heading and yaw rate follow opposite sign conventions (e.g. a compass heading \
             clockwise from north with r positive to port): flip one of them with `scale = -1` \
             in its column entry"
                .to_string(),
        )
    } else if let Some(words) = fits.then(|| unit_factor(g.abs())).flatten() {
        (
            true,
            format!(
                "{words}: give the column's unit explicitly, e.g. `unit = \"deg\"` or \
                 `unit = \"deg/s\"` in its column entry"
            ),
        )
    } else {
        (
            false,
            "heading and yaw rate disagree; the filter will trust whichever has the smaller \
             noise, and the coefficients absorb the rest: check both columns' units, signs and \
             which columns they are"
                .to_string(),
        )
    };
    Some(Finding::new(rec, blocking, seen, meaning))
}

/// The positions against the velocities rotated by the heading.
fn track(rec: &Record) -> Option<Finding> {
    let times = rec.time()?;
    let (x, y) = (rec.channel(Quantity::X)?, rec.channel(Quantity::Y)?);
    let psi = rec.channel(Quantity::Yaw)?;
    let (u, v) = (rec.channel(Quantity::U)?, rec.channel(Quantity::V)?);
    let wins = windows(times, WINDOW);
    let measured: Vec<(f64, f64)> = wins
        .iter()
        .map(|&(a, b)| (x[b] - x[a], y[b] - y[a]))
        .collect();
    let rotate = |k: usize, sway: f64, heading: f64| -> (f64, f64) {
        let (s, c) = (heading * psi[k]).sin_cos();
        let (a, b) = (u[k], sway * v[k]);
        (a * c - b * s, a * s + b * c)
    };
    // x(t1) - x(t0) + i (y(t1) - y(t0)) = integral of the predicted earth velocity
    let fit = |predict: &dyn Fn(usize) -> (f64, f64)| {
        let p: Vec<(f64, f64)> = wins
            .iter()
            .map(|&w| {
                let re = increment(times, w, x, |k| predict(k).0).1;
                let im = increment(times, w, y, |k| predict(k).1).1;
                (re, im)
            })
            .collect();
        complex_gain(&measured, &p)
    };
    let holds = |(g, rel): ((f64, f64), f64)| {
        (g.0 - 1.0).abs() < GAIN_TOLERANCE && g.1.abs() < GAIN_TOLERANCE && rel < GOOD_FIT
    };
    let configured = fit(&|k| rotate(k, 1.0, 1.0))?;
    if holds(configured) {
        return None;
    }
    let ((gr, gi), rel) = configured;
    let gain = gr.hypot(gi);
    let angle = gi.atan2(gr).to_degrees();
    let seen = format!(
        "the positions do not move as u and v rotated by the heading say: they move {} times \
         as far, turned by {:.0} deg (median relative residual {:.0} %)",
        sig(gain),
        angle,
        100.0 * rel
    );
    let clear = |meaning: String| Some(Finding::new(rec, true, seen.clone(), meaning));
    // a mix-up that explains the data exactly comes first
    type Predict<'a> = Box<dyn Fn(usize) -> (f64, f64) + 'a>;
    let alternatives: [(Predict, &str); 3] = [
        (
            Box::new(|k| (u[k], v[k])),
            "the velocity columns hold earth-frame velocities (dx/dt, dy/dt), not body \
             velocities: set `velocity_frame = \"earth\"` for this run",
        ),
        (
            Box::new(|k| rotate(k, 1.0, -1.0)),
            "the heading has the opposite sign convention to the positions (e.g. clockwise \
             while x-y is counter-clockwise): flip it with `scale = -1` in its column entry",
        ),
        (
            Box::new(|k| rotate(k, -1.0, 1.0)),
            "the sway velocity has the opposite sign convention (positive to port): flip it \
             with `scale = -1` in its column entry",
        ),
    ];
    for (predict, words) in &alternatives {
        if fit(predict.as_ref()).is_some_and(holds) {
            return clear(words.to_string());
        }
    }
    if rel < GOOD_FIT {
        // the relation holds up to a factor or a turn
        if let Some(words) = unit_factor(gain).filter(|_| angle.abs() < 10.0) {
            return clear(format!(
                "{words}: give the columns' units explicitly, e.g. `u = {{ column = \"...\", \
                 unit = \"kn\" }}`"
            ));
        }
        if angle.abs() >= 10.0 && (gain - 1.0).abs() < GAIN_TOLERANCE {
            return clear(format!(
                "the heading seems offset by {angle:.0} deg from the x axis of the positions \
                 (e.g. a compass heading from north with positions east-north): check which \
                 axis the heading is measured from"
            ));
        }
    }
    Some(Finding::new(
        rec,
        false,
        seen,
        "positions, heading and velocities disagree and no simple mix-up explains it; the \
         filter will fit a compromise and the coefficients absorb the rest: check the units, \
         signs and frames of x, y, yaw, u and v"
            .to_string(),
    ))
}

fn sig(v: f64) -> String {
    crate::numfmt::num(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    use std::collections::BTreeMap;

    /// A slow steady turn (the NPS AUV helix: 1 deg/s) sampled at 100 Hz with a heading
    /// noise of 0.05 deg and a yaw-rate noise of 0.1 deg/s; `rate_scale` mislabels the rate.
    fn slow_turn(rate_scale: f64) -> Record {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let psi_noise = Normal::new(0.0, 0.05f64.to_radians()).unwrap();
        let r_noise = Normal::new(0.0, 0.1f64.to_radians()).unwrap();
        let k = 6000;
        let rate = -1.0f64.to_radians();
        let mut channels = BTreeMap::new();
        let t: Vec<f64> = (0..k).map(|i| i as f64 * 0.01).collect();
        let psi = t
            .iter()
            .map(|t| rate * t + psi_noise.sample(&mut rng))
            .collect();
        let r = t
            .iter()
            .map(|_| rate_scale * (rate + r_noise.sample(&mut rng)))
            .collect();
        channels.insert(Quantity::Time, t);
        channels.insert(Quantity::Yaw, psi);
        channels.insert(Quantity::R, r);
        Record::from_channels("slow turn", "turn.csv", channels)
    }

    #[test]
    fn a_slow_noisy_turn_is_not_taken_for_a_heading_mistake() {
        // over 5 samples the heading moves 0.05 deg, its noise as much: the windows must grow
        assert_eq!(heading_rate(&slow_turn(1.0)), None);
    }

    #[test]
    fn a_heading_that_does_not_move_beyond_its_noise_is_not_judged() {
        // a vertical zig-zag: the heading holds, r is noise
        let mut still = slow_turn(1.0);
        let n = still.channels[&Quantity::Yaw].len();
        let psi: Vec<f64> = (0..n).map(|k| 1e-3 * ((k * 7919) % 13) as f64).collect();
        still.channels.insert(Quantity::Yaw, psi);
        let r: Vec<f64> = (0..n)
            .map(|k| 2e-3 * ((k * 104729) % 11) as f64 - 0.01)
            .collect();
        still.channels.insert(Quantity::R, r);
        assert_eq!(heading_rate(&still), None);
    }

    #[test]
    fn a_rate_in_degrees_read_as_radians_is_still_named_in_a_slow_turn() {
        // a rate in deg/s read as rad/s: 57 times too large
        let f = heading_rate(&slow_turn(180.0 / std::f64::consts::PI)).expect("a finding");
        assert!(f.blocking, "{f:?}");
        assert!(
            f.warning.meaning.contains("deg/s read as rad/s"),
            "{:?}",
            f.warning
        );
    }
}
