//! The measurement noise of a measured channel, from the data: what a real log's numbers
//! say about their own errors.
//!
//! Three things bound it from below, and the largest is used:
//!
//! 1. **High-frequency content** (sensor noise): the fourth differences of a smooth signal
//!    are ~ y'''' dt^4, those of white noise of variance s^2 have variance 70 s^2
//!    ([`crate::numerics::signal::noise_sigma`], the median form, for finely printed data; the trimmed
//!    mean-square form for a channel printed with few digits, whose median difference is 0).
//! 2. **Printed resolution**: rounding to a step d adds an error of variance d^2 / 12 to each
//!    sample (Widrow & Kollar 2008, section 4.2). It enters every sample's variance as its own
//!    step (`Record::resolution`): a heading printed with three significant digits is read to
//!    0.01 deg below 10 deg and to 1 deg above 100 deg.
//! 3. **Consistency of related channels**: a yaw rate that the heading's derivative does not
//!    follow, or velocities that the positions' derivatives do not follow, carry an error
//!    the channel's own smoothness does not show (a logger's low-pass filter, a lag, a scale
//!    error). The derivative is the local least-squares slope over +-h samples (Savitzky &
//!    Golay 1964), whose noise variance for white noise s^2 is s^2 / (dt^2 sum j^2) and is
//!    subtracted; the smallest result over a few h (the bias of a wide window grows with h)
//!    is the channel's error. It replaces the high-frequency estimate when it is more than
//!    twice as large.

use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::numerics::signal;

/// Half-widths (samples) of the local slopes the consistency check tries.
const HALF_WIDTHS: [usize; 10] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512];

/// A related channels' error replaces the high-frequency estimate beyond this factor.
const CONSISTENCY_FACTOR: f64 = 2.0;

/// Fraction of the largest fourth differences left out of the trimmed mean square.
const TRIM: f64 = 0.02;

/// E[X^2 | |X| < z] for a standard normal X with P(|X| < z) = 1 - [`TRIM`] (z = 2.326): the
/// trimmed mean square's ratio to the variance.
const TRIMMED_RATIO: f64 = 0.8733;

/// The variance, times the number of samples, that the median form's error adds to a
/// channel's mean normalised innovation: for white Gaussian noise e of variance s^2 and its
/// median-form estimate s_hat^2 from the same n samples, Var(mean(e^2) / s_hat^2) =
/// (2 + this) / n, where 2 / n is the chi-square law's share. Measured by simulation (the
/// estimate and the mean square share the samples, so they are positively correlated: 5.75
/// and 5.18 in two studies of 500 x 3000 and 400 x 2000 samples) and asserted in this
/// module's tests.
const MEDIAN_FORM_EXCESS: f64 = 5.5;

/// The same for the trimmed mean-square form (more efficient than the median; 1.49 and
/// 1.74 in the same two studies).
const TRIMMED_FORM_EXCESS: f64 = 1.6;

/// How one channel's noise was judged.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelNoise {
    /// Standard deviation of the noise besides rounding, SI.
    pub sigma: f64,
    /// Where `sigma` comes from, for the report.
    pub source: String,
    /// RMS rounding error of the printed values (step / sqrt 12), SI, when the channel is
    /// printed coarsely enough to matter.
    pub rounding: Option<f64>,
    /// Variance that the estimate's own error adds to the channel's mean normalised
    /// innovation (0 when the noise is not a statistical estimate: a floor or the rounding
    /// alone); the NIS test widens its bounds by it
    /// ([`crate::numerics::estimation::nis::mean_bounds`]).
    pub estimate_variance: f64,
}

/// The noise of channel `q` of `rec` (its values `y`, outliers already cleaned), from the
/// data alone: see the module documentation.
/// `bias` is the constant already taken off the channel (a rate sensor's bias, [`rate_bias`]).
pub fn estimate(rec: &Record, q: Quantity, y: &[f64], bias: f64) -> Option<ChannelNoise> {
    let rounding_var = rec.resolution.get(&q).map(|r| mean_square(r) / 12.0);
    let mut excess = match rounding_var {
        Some(_) => TRIMMED_FORM_EXCESS,
        None => MEDIAN_FORM_EXCESS,
    };
    let hf = match rounding_var {
        // few printed digits: the median fourth difference is often exactly 0
        Some(rv) => trimmed_sigma(y).map(|s| (s * s - rv).max(0.0).sqrt()),
        None => signal::noise_sigma(y),
    }?;
    let floor = signal::noise_floor(y);
    // a statistical estimate (not a floor): its error widens the NIS test
    // (the trimmed form estimates the whole variance, rounding included, so its error is a
    // share of the whole; a consistency check's error only of its own part)
    let mut estimated = (hf >= floor).then_some(1.0);
    let mut out = ChannelNoise {
        sigma: hf.max(floor),
        source: match (hf >= floor, rounding_var) {
            (true, _) => "estimated from the data".to_string(),
            (false, Some(_)) => "the printed digits' rounding (no noise beyond it)".to_string(),
            (false, None) => "floor (the data look noise-free)".to_string(),
        },
        rounding: rounding_var.map(f64::sqrt),
        estimate_variance: 0.0,
    };
    if let Some((cons, with)) = consistency(rec, q, bias) {
        let seen = (out.sigma.powi(2) + rounding_var.unwrap_or(0.0)).sqrt();
        if cons > CONSISTENCY_FACTOR * seen {
            out.sigma = cons;
            out.source = format!("from the consistency of {q} with {with}");
            // a derivative's residual is no more certain than the median form (conservative)
            excess = excess.max(MEDIAN_FORM_EXCESS);
            let var = cons * cons;
            estimated = Some(var / (var + rounding_var.unwrap_or(0.0)).max(f64::MIN_POSITIVE));
        }
    }
    if let Some(share) = estimated {
        out.estimate_variance = excess / y.len().max(1) as f64 * share * share;
    }
    Some(out)
}

/// An interval longer than this many median sampling intervals is a gap in the time axis.
const GAP: f64 = 3.0;

/// A constant bias of the yaw rate against the heading it should integrate to (a rate gyro's
/// bias, or a heading that drifts), when the data show one: the least-squares fit of
/// psi_k - psi_0 - int_0^t_k r dt = c - b t_k (trapezoidal integral) over the run, taken when
/// the heading it accumulates over the run, |b| T, exceeds five times the scatter about the
/// fit (rounding and noise) and five times the rate's own rounding over the run. Planar runs
/// only (no roll or pitch channel). Returns the bias (rad/s, to subtract from r) and the
/// heading it accumulates over the run (rad).
pub fn rate_bias(rec: &Record) -> Option<(f64, f64)> {
    if rec.channel(Quantity::Roll).is_some() || rec.channel(Quantity::Pitch).is_some() {
        return None;
    }
    let (t, psi, r) = (
        rec.time()?,
        rec.channel(Quantity::Yaw)?,
        rec.channel(Quantity::R)?,
    );
    let n = t.len();
    if n < 20 {
        return None;
    }
    // d_k = psi_k - psi_0 - int r, fitted by c - b t_k; across a gap in the time axis the
    // trapezoid cannot integrate r, and d is carried over unchanged
    let step = crate::numerics::sampling::median_interval(t)?;
    let mut integral = 0.0;
    let mut d = Vec::with_capacity(n);
    for k in 0..n {
        if k > 0 {
            let h = t[k] - t[k - 1];
            integral += if h > GAP * step {
                psi[k] - psi[k - 1]
            } else {
                0.5 * (r[k] + r[k - 1]) * h
            };
        }
        d.push(psi[k] - psi[0] - integral);
    }
    let tm = t.iter().sum::<f64>() / n as f64;
    let dm = d.iter().sum::<f64>() / n as f64;
    let stt: f64 = t.iter().map(|v| (v - tm).powi(2)).sum();
    let std: f64 = t.iter().zip(&d).map(|(a, b)| (a - tm) * (b - dm)).sum();
    if stt.is_nan() || stt <= 0.0 {
        return None;
    }
    let slope = std / stt;
    let scatter = (d
        .iter()
        .zip(t)
        .map(|(v, tk)| (v - dm - slope * (tk - tm)).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt();
    let span = t[n - 1] - t[0];
    let drift = slope.abs() * span;
    let rate_rounding = rec
        .resolution
        .get(&Quantity::R)
        .map_or(0.0, |res| mean_square(res).sqrt() / 12f64.sqrt());
    (drift > 5.0 * scatter && slope.abs() > 5.0 * rate_rounding).then_some((-slope, drift))
}

/// Values beyond this many times the median magnitude are outlying (a 1e308 cell, its print
/// step 1e292) and left out of a mean square.
const STEP_OUTLIER: f64 = 100.0;

/// The mean of the squares of `v` (print steps, errors), outlying and non-finite values
/// left out.
fn mean_square(v: &[f64]) -> f64 {
    let mut sorted: Vec<f64> = v
        .iter()
        .map(|x| x.abs())
        .filter(|x| x.is_finite())
        .collect();
    if sorted.is_empty() {
        return 0.0;
    }
    sorted.sort_by(f64::total_cmp);
    let limit = STEP_OUTLIER * sorted[sorted.len() / 2];
    let kept: Vec<f64> = sorted.into_iter().filter(|x| *x <= limit).collect();
    kept.iter().map(|x| x * x).sum::<f64>() / kept.len().max(1) as f64
}

/// White-noise standard deviation from the trimmed mean square of the fourth differences
/// (the largest [`TRIM`] left out, the rest scaled by [`TRIMMED_RATIO`]).
fn trimmed_sigma(y: &[f64]) -> Option<f64> {
    if y.len() < 5 {
        return None;
    }
    let mut d: Vec<f64> = y
        .windows(5)
        .map(|w| (w[4] - 4.0 * w[3] + 6.0 * w[2] - 4.0 * w[1] + w[0]).powi(2))
        .collect();
    d.sort_by(f64::total_cmp);
    let keep = ((1.0 - TRIM) * d.len() as f64).ceil().max(1.0) as usize;
    let ms = d[..keep.min(d.len())].iter().sum::<f64>() / keep as f64;
    Some((ms / (70.0 * TRIMMED_RATIO)).sqrt())
}

/// The error of channel `q` that a related channel shows, and that channel's name: the yaw
/// rate against the heading's rate, body velocities against the positions' rates; planar
/// runs only (no roll or pitch channel).
fn consistency(rec: &Record, q: Quantity, bias: f64) -> Option<(f64, String)> {
    // planar kinematics only: with roll or pitch, psi_dot = (q sin phi + r cos phi) / cos
    // theta and the track has a vertical part (Fossen 2011, section 2.2.1)
    if rec.channel(Quantity::Roll).is_some() || rec.channel(Quantity::Pitch).is_some() {
        return None;
    }
    let t = rec.time()?;
    // the regular interval: a gap does not move the median
    let dt = crate::numerics::sampling::median_interval(t).filter(|d| *d > 0.0)?;
    match q {
        Quantity::R => {
            let psi = rec.channel(Quantity::Yaw)?;
            let r = rec.channel(Quantity::R)?;
            let var = noise_var(rec, Quantity::Yaw, psi);
            let e = |h: usize, k: usize| r[k] - bias - slope(psi, k, h, dt);
            Some((best(t, dt, var, &e)?, "the heading's rate".to_string()))
        }
        Quantity::U | Quantity::V => {
            let (x, y) = (rec.channel(Quantity::X)?, rec.channel(Quantity::Y)?);
            let (u, v) = (rec.channel(Quantity::U)?, rec.channel(Quantity::V)?);
            let psi = rec.channel(Quantity::Yaw)?;
            let var = 0.5 * (noise_var(rec, Quantity::X, x) + noise_var(rec, Quantity::Y, y));
            // earth velocity from u, v and the heading against the positions' slopes; the
            // two components' errors are pooled (the same speed error turns with the ship)
            let e = |h: usize, k: usize| {
                let (s, c) = psi[k].sin_cos();
                let ex = c * u[k] - s * v[k] - slope(x, k, h, dt);
                let ey = s * u[k] + c * v[k] - slope(y, k, h, dt);
                ((ex * ex + ey * ey) / 2.0).sqrt()
            };
            Some((
                best(t, dt, var, &e)?,
                "the track's rate (x, y and the heading)".to_string(),
            ))
        }
        _ => None,
    }
}

/// The white-noise variance of a related channel: its high-frequency noise plus its mean
/// rounding variance.
fn noise_var(rec: &Record, q: Quantity, y: &[f64]) -> f64 {
    let rounding = rec
        .resolution
        .get(&q)
        .map_or(0.0, |r| mean_square(r) / 12.0);
    let hf = if rounding > 0.0 {
        trimmed_sigma(y).map_or(0.0, |s| (s * s - rounding).max(0.0))
    } else {
        signal::noise_sigma(y).map_or(0.0, |s| s * s)
    };
    hf + rounding
}

/// Least-squares slope of `y` over samples k-h..k+h (interval dt), shifted inwards at the
/// ends.
fn slope(y: &[f64], k: usize, h: usize, dt: f64) -> f64 {
    let n = y.len();
    let c = k.clamp(h, n - 1 - h);
    let mut num = 0.0;
    for j in 1..=h {
        num += j as f64 * (y[c + j] - y[c - j]);
    }
    num / (dt * sum_j2(h))
}

/// Sum of j^2 over j = -h..h.
fn sum_j2(h: usize) -> f64 {
    let h = h as f64;
    h * (h + 1.0) * (2.0 * h + 1.0) / 3.0
}

/// The smallest error over the half-widths: the mean square of `e(h, k)` over the samples
/// whose window crosses no gap in the time axis `t`, less the variance the related channel's
/// noise gives the slope (`var` / (dt^2 sum j^2)).
fn best(t: &[f64], dt: f64, var: f64, e: &dyn Fn(usize, usize) -> f64) -> Option<f64> {
    let n = t.len();
    // gaps[k]: the gaps among the first k intervals
    let mut gaps = vec![0usize; n];
    for k in 1..n {
        gaps[k] = gaps[k - 1] + usize::from(t[k] - t[k - 1] > GAP * dt);
    }
    HALF_WIDTHS
        .iter()
        .filter(|&&h| n > 4 * h + 4)
        .filter_map(|&h| {
            let errors: Vec<f64> = (0..n)
                .filter(|&k| {
                    let c = k.clamp(h, n - 1 - h);
                    gaps[c + h] == gaps[c - h]
                })
                .map(|k| e(h, k))
                .collect();
            // an outlying cell of a related channel (left out of the filter, not of these
            // channels) is left out here too, as an outlying print step is
            let used = errors.len();
            (used * 2 >= n).then(|| (mean_square(&errors) - var / (dt * dt * sum_j2(h))).max(0.0))
        })
        .min_by(f64::total_cmp)
        .map(f64::sqrt)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};
    use std::collections::BTreeMap;

    /// A steady-ish turn: heading and yaw rate, `n` samples every `dt`.
    fn turn(n: usize, dt: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
        let r: Vec<f64> = t.iter().map(|t| 0.05 + 0.02 * (0.3 * t).sin()).collect();
        let psi: Vec<f64> = t
            .iter()
            .map(|t| 0.05 * t - 0.02 / 0.3 * ((0.3 * t).cos() - 1.0))
            .collect();
        (t, psi, r)
    }

    fn record(t: Vec<f64>, psi: Vec<f64>, r: Vec<f64>) -> Record {
        let mut ch = BTreeMap::new();
        ch.insert(Quantity::Time, t);
        ch.insert(Quantity::Yaw, psi);
        ch.insert(Quantity::R, r);
        Record::from_channels("turn", "turn.csv", ch)
    }

    #[test]
    fn a_smooth_yaw_rate_that_the_heading_does_not_follow_gets_the_disagreement() {
        let (t, psi, r) = turn(4000, 0.05);
        let mut rng = StdRng::seed_from_u64(3);
        let n = Normal::new(0.0, 1e-5).unwrap();
        let psi: Vec<f64> = psi.iter().map(|p| p + n.sample(&mut rng)).collect();
        // the logged rate lags the true one by 0.5 s (a logger's filter): smooth, but wrong
        let lagged: Vec<f64> = t
            .iter()
            .map(|t| 0.05 + 0.02 * (0.3 * (t - 0.5)).sin())
            .collect();
        let truth_error = {
            let d: Vec<f64> = lagged.iter().zip(&r).map(|(a, b)| a - b).collect();
            mean_square(&d).sqrt()
        };
        let rec = record(t, psi, lagged.clone());
        let got = estimate(&rec, Quantity::R, &lagged, 0.0).unwrap();
        assert!(got.source.contains("consistency"), "{got:?}");
        assert!(
            (got.sigma / truth_error - 1.0).abs() < 0.1,
            "{} against {truth_error}",
            got.sigma
        );
    }

    #[test]
    fn consistent_channels_keep_their_own_noise() {
        let (t, psi, r) = turn(4000, 0.05);
        let mut rng = StdRng::seed_from_u64(4);
        let (np, nr) = (
            Normal::new(0.0, 1e-3).unwrap(),
            Normal::new(0.0, 2e-3).unwrap(),
        );
        let psi: Vec<f64> = psi.iter().map(|p| p + np.sample(&mut rng)).collect();
        let r: Vec<f64> = r.iter().map(|v| v + nr.sample(&mut rng)).collect();
        let rec = record(t, psi, r.clone());
        let got = estimate(&rec, Quantity::R, &r, 0.0).unwrap();
        assert_eq!(got.source, "estimated from the data");
        assert!((got.sigma / 2e-3 - 1.0).abs() < 0.1, "{got:?}");
    }

    #[test]
    fn a_channel_printed_with_three_digits_is_never_called_noise_free() {
        let (t, psi, _) = turn(4000, 0.05);
        let deg: Vec<f64> = psi
            .iter()
            .map(|p| format!("{:.2e}", p.to_degrees()).parse::<f64>().unwrap())
            .collect();
        let printed: Vec<f64> = deg.iter().map(|d| d.to_radians()).collect();
        let mut rec = record(t, printed.clone(), vec![0.0; 4000]);
        let res = crate::numerics::printed::coarse_resolutions(&deg).expect("coarse");
        rec.resolution
            .insert(Quantity::Yaw, res.iter().map(|r| r.to_radians()).collect());
        let got = estimate(&rec, Quantity::Yaw, &printed, 0.0).unwrap();
        let rounding = got.rounding.expect("rounding");
        // 3 digits of up to 600 deg: steps of 0.001 to 1 deg, mostly 1 deg (above 100 deg)
        assert!(rounding > 0.5f64.to_radians() / 12f64.sqrt(), "{got:?}");
        assert!(rounding < 1f64.to_radians() / 12f64.sqrt(), "{got:?}");
        assert!(got.sigma < 0.1 * rounding, "{got:?}");
    }

    /// White N(0, 1) noise of `n` samples.
    fn white(rng: &mut StdRng, n: usize) -> Vec<f64> {
        let g = Normal::new(0.0, 1.0).unwrap();
        (0..n).map(|_| g.sample(rng)).collect()
    }

    #[test]
    fn the_estimates_error_in_the_normalised_innovation_is_the_constant_the_test_allows() {
        // n Var(mean(e^2) / s_hat^2) - 2 over 400 runs of 2000 samples, for each form
        let (n, runs) = (2000, 400);
        let mut rng = StdRng::seed_from_u64(11);
        type Form = fn(&[f64]) -> Option<f64>;
        let forms: [(Form, f64); 2] = [
            (signal::noise_sigma, MEDIAN_FORM_EXCESS),
            (trimmed_sigma, TRIMMED_FORM_EXCESS),
        ];
        for (form, excess) in forms {
            let ratios: Vec<f64> = (0..runs)
                .map(|_| {
                    let e = white(&mut rng, n);
                    mean_square(&e) / form(&e).unwrap().powi(2)
                })
                .collect();
            let mean = ratios.iter().sum::<f64>() / runs as f64;
            let var = ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (runs - 1) as f64;
            let measured = n as f64 * var - 2.0;
            eprintln!("excess measured {measured}, constant {excess}");
            assert!((mean - 1.0).abs() < 0.01, "mean ratio {mean}");
            // the variance of a variance from 400 runs is known to about +-7 %
            assert!(
                ((2.0 + measured) / (2.0 + excess) - 1.0).abs() < 0.2,
                "measured excess {measured} against {excess}"
            );
        }
    }

    #[test]
    fn an_estimated_noise_does_not_raise_false_nis_alarms() {
        // three channels of white noise whose sigmas are estimated from the same samples:
        // the NIS of the true innovations against the estimated noise, 200 runs; the
        // chi-square bounds alone flag about a third of them, the widened ones about 5 %
        let (n, runs) = (3000, 200);
        let mut rng = StdRng::seed_from_u64(12);
        let (mut widened, mut plain) = (0, 0);
        for _ in 0..runs {
            let t: Vec<f64> = (0..n).map(|k| 0.1 * k as f64).collect();
            let mut ch = BTreeMap::new();
            ch.insert(Quantity::Time, t);
            let qs = [Quantity::U, Quantity::V, Quantity::R];
            for (i, q) in qs.iter().enumerate() {
                ch.insert(
                    *q,
                    white(&mut rng, n)
                        .iter()
                        .map(|e| e * 0.01 * (i + 1) as f64)
                        .collect(),
                );
            }
            let rec = Record::from_channels("white", "white.csv", ch);
            let mut nis = vec![0.0; n];
            let mut extra = 0.0;
            for q in qs {
                let y = rec.channel(q).unwrap();
                let got = estimate(&rec, q, y, 0.0).unwrap();
                assert_eq!(got.source, "estimated from the data");
                extra += got.estimate_variance;
                for (k, v) in y.iter().enumerate() {
                    nis[k] += v * v / (got.sigma * got.sigma);
                }
            }
            let nis_summary = |x| crate::numerics::estimation::nis::summarize(&nis, 3, x);
            widened += usize::from(!nis_summary(extra).unwrap().consistent);
            plain += usize::from(!nis_summary(0.0).unwrap().consistent);
        }
        // docs/hekf.md, "Innovation consistency": "flag 54 of 200 runs ... Widened, 6 of the
        // 200 runs are flagged"
        assert_eq!((plain, widened), (54, 6), "of {runs} runs");
    }
}
