//! Each Euler angle against its body rate: the heading against the yaw rate r, and where the
//! run has them, the roll against p and the pitch against q. The zyx Euler angles change as
//! (Fossen 2011, eq. 2.41)
//!
//! ```text
//! phi_dot   = p + (q sin phi + r cos phi) tan theta
//! theta_dot = q cos phi - r sin phi
//! psi_dot   = (q sin phi + r cos phi) / cos theta
//! ```
//!
//! (an angle or rate the run does not have counts as zero), so the increment of an angle
//! over a window is the integral of that expression. A column whose integral follows the
//! angle up to a factor is a unit or sign mistake; one whose integral does not follow the
//! angle at all, while the angle moves well beyond its noise, is not that rate.

use super::{
    complex_gain, correlation, factor, file, increment, median, named, sig, window_lengths,
    windows, Finding, GAIN_TOLERANCE, GOOD_FIT, RATE_FACTORS,
};
use crate::base::quantity::Quantity;
use crate::io::record::Record;

/// An angle and the body rate that drives it.
struct Pair {
    angle: Quantity,
    rate: Quantity,
    /// The angle in words.
    angle_words: &'static str,
    /// The rate in words.
    rate_words: &'static str,
}

const PAIRS: [Pair; 3] = [
    Pair {
        angle: Quantity::Yaw,
        rate: Quantity::R,
        angle_words: "heading",
        rate_words: "yaw rate",
    },
    Pair {
        angle: Quantity::Roll,
        rate: Quantity::P,
        angle_words: "roll angle",
        rate_words: "roll rate",
    },
    Pair {
        angle: Quantity::Pitch,
        rate: Quantity::Q,
        angle_words: "pitch angle",
        rate_words: "pitch rate",
    },
];

/// Every angle-rate pair the run has, each finding with the quantity it blames (the rate,
/// or the heading when the track says the heading column is the wrong one).
pub(super) fn all(rec: &Record) -> Vec<(Quantity, Finding)> {
    PAIRS.iter().filter_map(|p| pair(rec, p)).collect()
}

/// The Euler-angle rate of `angle` at sample `k` from the body rates (eq. 2.41 above).
fn euler_rate(rec: &Record, angle: Quantity, k: usize) -> f64 {
    let at = |q: Quantity| rec.channel(q).map_or(0.0, |v| v[k]);
    let (phi, theta) = (at(Quantity::Roll), at(Quantity::Pitch));
    let (p, q, r) = (at(Quantity::P), at(Quantity::Q), at(Quantity::R));
    match angle {
        Quantity::Roll => p + (q * phi.sin() + r * phi.cos()) * theta.tan(),
        Quantity::Pitch => q * phi.cos() - r * phi.sin(),
        _ => (q * phi.sin() + r * phi.cos()) / theta.cos(),
    }
}

/// The fit of one window length: the robust gain, its median relative residual, the
/// correlation of the increments with the integrals, and the windows used.
struct Fit {
    gain: f64,
    rel: f64,
    rho: f64,
    windows: Vec<(usize, usize)>,
    len: usize,
}

fn fit(rec: &Record, times: &[f64], p: &Pair, len: usize) -> Option<Fit> {
    let angle = rec.channel(p.angle)?;
    let wins = windows(times, len);
    let (measured, predicted): (Vec<f64>, Vec<f64>) = wins
        .iter()
        .map(|&w| increment(times, w, angle, |k| euler_rate(rec, p.angle, k)))
        .unzip();
    let pairs = |v: &[f64]| v.iter().map(|x| (*x, 0.0)).collect::<Vec<_>>();
    let ((gain, _), rel) = complex_gain(&pairs(&measured), &pairs(&predicted))?;
    let rho = correlation(&measured, &predicted).unwrap_or(0.0);
    Some(Fit {
        gain,
        rel,
        rho,
        windows: wins,
        len,
    })
}

/// One angle against its rate. A slow motion changes the angle less in a few samples than
/// its noise: the windows grow (doubling) until the relation holds or too few windows are
/// left, and the longest (least noisy) fit is judged.
fn pair(rec: &Record, p: &Pair) -> Option<(Quantity, Finding)> {
    let times = rec.time()?;
    let angle = rec.channel(p.angle)?;
    rec.channel(p.rate)?;
    let mut last = None;
    for len in window_lengths(times) {
        let Some(f) = fit(rec, times, p, len) else {
            break;
        };
        if (f.gain - 1.0).abs() < GAIN_TOLERANCE && f.rel < GOOD_FIT {
            return None;
        }
        last = Some(f);
    }
    let f = last?;
    // An angle that moves no more than its noise over the longest windows (a heading in a
    // vertical manoeuvre) says nothing about its rate: no finding. An increment of two
    // noisy samples has sigma sqrt(2) s; 4 s is beyond it for nine windows in ten, 10 s
    // makes the noise's share of the increments' spread below 2 %, so that a correlation
    // below 0.9 is the column's, not the noise's.
    let noise = crate::numerics::signal::noise_sigma(angle).unwrap_or(0.0);
    let mut moves: Vec<f64> = f
        .windows
        .iter()
        .map(|&(a, b)| (angle[b] - angle[a]).abs())
        .collect();
    let moved = median(&mut moves)?;
    if moved < 4.0 * noise {
        return None;
    }
    Some(judge(rec, p, &f, moved >= 10.0 * noise))
}

/// What a failed relation means, with the quantity it blames.
fn judge(rec: &Record, p: &Pair, f: &Fit, clear_motion: bool) -> (Quantity, Finding) {
    let dt = rec
        .time()
        .and_then(crate::numerics::sampling::median_interval)
        .unwrap_or(0.0);
    let seen = format!(
        "in {}, the {} {} changes {} times as fast as the {} {} says (over {} windows of {} s: \
         correlation {:.2}, median relative residual {:.0} %)",
        file(rec),
        p.angle_words,
        named(rec, p.angle),
        sig(f.gain),
        p.rate_words,
        named(rec, p.rate),
        f.windows.len(),
        sig(f.len as f64 * dt),
        f.rho,
        100.0 * f.rel
    );
    let fits = f.rel < GOOD_FIT;
    let mut blamed = p.rate;
    let (blocking, meaning) = if fits && (f.gain + 1.0).abs() < GAIN_TOLERANCE {
        (
            true,
            format!(
                "{} and {} follow opposite sign conventions (e.g. a compass heading clockwise \
                 from north with r positive to port): flip one of them with `scale = -1` in \
                 its column entry",
                p.angle_words, p.rate_words
            ),
        )
    } else if let Some(fac) = fits.then(|| factor(f.gain.abs(), RATE_FACTORS)).flatten() {
        (true, fac.words.to_string())
    } else if f.rho.abs() < 0.9 && clear_motion {
        match (p.angle == Quantity::Yaw)
            .then(|| wrong_heading(rec))
            .flatten()
        {
            Some(words) => {
                blamed = Quantity::Yaw;
                (true, words)
            }
            None => (true, not_the_rate(rec, p)),
        }
    } else {
        (
            false,
            format!(
                "{} and {} disagree; the filter will trust whichever has the smaller noise, \
                 and the coefficients absorb the rest: check both columns' units, signs and \
                 which columns they are",
                p.angle_words, p.rate_words
            ),
        )
    };
    (blamed, Finding::new(rec, blocking, seen, meaning))
}

/// When the heading column disagrees with the yaw rate, the track tells which is wrong: the
/// positions move as the body velocities rotated by the heading (Fossen 2011, eq. 2.40), so
/// the heading that makes them do so is the right one. The meaning blaming the heading
/// column when the yaw rate's integral (from the column's first value, the rotation left
/// free) turns the velocities into the track and the column does not; None otherwise (or
/// without positions and velocities).
fn wrong_heading(rec: &Record) -> Option<String> {
    let times = rec.time()?;
    let yaw = rec.channel(Quantity::Yaw)?;
    let mut integral = vec![yaw[0]; yaw.len()];
    for k in 1..yaw.len() {
        let rate =
            0.5 * (euler_rate(rec, Quantity::Yaw, k - 1) + euler_rate(rec, Quantity::Yaw, k));
        integral[k] = integral[k - 1] + rate * (times[k] - times[k - 1]);
    }
    let holds = |(g, rel): (f64, f64)| (g - 1.0).abs() < GAIN_TOLERANCE && rel < GOOD_FIT;
    let by_rate = super::travel::heading_fit(rec, &integral)?;
    let by_column = super::travel::heading_fit(rec, yaw);
    if !holds(by_rate) || by_column.is_some_and(holds) {
        return None;
    }
    Some(format!(
        "the column mapped to yaw is not the heading: the positions move as u and v rotated by \
         the integral of r (median relative residual {:.0} %), not as rotated by the yaw \
         column{}. Map yaw to the column that holds the heading (r is consistent with the \
         track)",
        100.0 * by_rate.1,
        by_column
            .map(|(_, rel)| format!(" ({:.0} %)", 100.0 * rel))
            .unwrap_or_default()
    ))
}

/// The meaning of a rate column whose integral does not follow its angle: not that rate,
/// with the angle it resembles, if any (a roll angle follows the turn in a zig-zag).
fn not_the_rate(rec: &Record, p: &Pair) -> String {
    let column = rec.channel(p.rate).unwrap_or_default();
    let resembles: Vec<String> = PAIRS
        .iter()
        .filter_map(|o| {
            let rho = correlation(column, rec.channel(o.angle)?)?;
            (rho.abs() > 0.8).then(|| format!("the {} (correlation {rho:.2})", o.angle_words))
        })
        .collect();
    let like = if resembles.is_empty() {
        String::new()
    } else {
        format!(
            "; it moves like {}, as an angle does, not a rate",
            resembles.join(" and ")
        )
    };
    format!(
        "the column mapped to {rate} is not the {words}: its integral does not follow the \
         {angle}{like}. Map {rate} to the column that holds the {words} (a log's column list \
         can call another quantity `{rate}`; the {words}'s integral is the {angle}), or leave \
         {rate} unmapped and the filter estimates it from the {angle}",
        rate = p.rate.key(),
        words = p.rate_words,
        angle = p.angle_words,
    )
}
