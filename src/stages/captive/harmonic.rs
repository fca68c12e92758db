//! Harmonic captive runs (planar motion mechanism, pure sway and pure yaw; ITTC
//! 7.5-02-06-04 practice): the force histories of a prescribed oscillation reduced over whole
//! periods to their Fourier parts, the mean and the in-phase and quadrature parts of the
//! first [`HARMONICS`] harmonics.
//!
//! The model side is reduced the same way: its captive forces
//! ([`Model::captive_forces`]) along one period of the fitted motion, with the accelerations
//! of that motion, projected on the same harmonics. The fit then compares like with like for
//! any model, linear or not: a term v|v| shows in the first and third harmonics, an
//! added mass in the quadrature part of the first (v_dot leads v by 90 deg).

use super::fit::Condition;
use crate::base::numfmt::num;
use crate::base::warning::Warning;
use crate::model::models::Model;
use crate::numerics::ad::Scalar;
use crate::numerics::estimation::nis::variance_ratio_bound_of;
use crate::numerics::signal::range;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Harmonics of a force fitted and compared (the mean, then k = 1 .. HARMONICS): the third
/// carries the odd nonlinearity of v|v| and r|r|, the second that of v^2 in surge.
pub const HARMONICS: usize = 3;

/// Values per force component: the mean and a cosine and a sine part per harmonic.
pub const PER_FORCE: usize = 1 + 2 * HARMONICS;

/// Phase points per period at which the model's forces are evaluated (the discrete Fourier
/// sums are exact for harmonics below half of it).
const PHASES: usize = 64;

/// Fewest whole periods a harmonic run must hold.
pub const MIN_PERIODS: usize = 2;

/// Largest share of a state's first-harmonic amplitude that its higher harmonics and the
/// rest of the signal may hold for the motion to count as harmonic.
const HARMONIC_TOLERANCE: f64 = 0.05;

/// The whole periods of `period` s a record of `duration` s holds (a record of exactly n
/// periods, up to rounding of its time stamps, holds n).
pub fn whole_periods(duration: f64, period: f64) -> usize {
    (duration / period + 1e-6).floor() as usize
}

/// The prescribed motion of a harmonic run: each state's mean and first-harmonic cosine and
/// sine parts at frequency `omega`, phase 0 at the start of the first period used.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicMotion {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Per state: [mean, cos part, sin part] (positions and angles: zeros).
    pub states: Vec<[f64; 3]>,
}

impl HarmonicMotion {
    /// The state and its rate at phase `phase` (rad).
    fn at(&self, phase: f64) -> (Vec<f64>, Vec<f64>) {
        let (s, c) = phase.sin_cos();
        let x = self
            .states
            .iter()
            .map(|[m, a, b]| m + a * c + b * s)
            .collect();
        let dx = self
            .states
            .iter()
            .map(|[_, a, b]| self.omega * (b * c - a * s))
            .collect();
        (x, dx)
    }
}

/// The model's forces along one period of `motion`, reduced to [`PER_FORCE`] values per
/// component (mean, then cos and sin part of each harmonic), in `out`.
pub fn model_harmonics<M: Model, T: Scalar>(
    model: &M,
    motion: &HarmonicMotion,
    u: &[f64],
    c: &[T],
    out: &mut [T],
) {
    let nf = model.force_quantities().len();
    let zero = T::from(0.0);
    out.iter_mut().for_each(|o| *o = zero);
    let mut f = vec![zero; nf];
    for j in 0..PHASES {
        let phase = 2.0 * std::f64::consts::PI * j as f64 / PHASES as f64;
        let (x, dx) = motion.at(phase);
        let x: Vec<T> = x.into_iter().map(T::from).collect();
        let dx: Vec<T> = dx.into_iter().map(T::from).collect();
        model.captive_forces(&x, &dx, u, c, &mut f);
        // discrete Fourier sums: a0 = mean, a_k = 2/N sum F cos(k phase), b_k likewise
        for (i, fi) in f.iter().enumerate() {
            let row = &mut out[i * PER_FORCE..(i + 1) * PER_FORCE];
            for (k, w) in basis(phase).iter().enumerate() {
                let scale = if k == 0 { 1.0 } else { 2.0 } / PHASES as f64;
                row[k] += *fi * (w * scale);
            }
        }
    }
}

/// The Fourier basis at a phase: 1, cos(phase), sin(phase), cos(2 phase) ...
fn basis(phase: f64) -> [f64; PER_FORCE] {
    let mut b = [0.0; PER_FORCE];
    b[0] = 1.0;
    for k in 1..=HARMONICS {
        let (s, c) = (k as f64 * phase).sin_cos();
        b[2 * k - 1] = c;
        b[2 * k] = s;
    }
    b
}

/// What a harmonic run was reduced over, for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Periods {
    /// Frequency of the motion, Hz.
    pub frequency: f64,
    /// Whole periods used.
    pub periods: usize,
    /// Start of the periods used, s.
    pub from: f64,
    /// End of the periods used, s.
    pub to: f64,
    /// Time at the end of the run not used (less than a period), s.
    pub unused_end: f64,
    /// The oscillating states and their first-harmonic amplitudes (SI): `v 0.2`.
    pub oscillating: Vec<(String, f64)>,
}

/// One sample of a history: its time and the steady condition read from its row.
pub struct Sample<'a> {
    /// Time, s.
    pub t: f64,
    /// The row as a condition (state, inputs, forces).
    pub row: &'a Condition,
}

/// Why a harmonic run's history cannot be reduced to Fourier parts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReduceError {
    /// No velocity state moves.
    #[error("no state oscillates")]
    NoOscillation,
    /// The leading state does not cross its mean often enough to give a period.
    #[error(
        "{state} does not cross its mean often enough to find the period of the motion: a \
         harmonic run needs at least {MIN_PERIODS} whole periods after the transient"
    )]
    NoPeriod {
        /// The state's name.
        state: String,
    },
    /// Fewer than [`MIN_PERIODS`] whole periods after the transient.
    #[error(
        "the motion has a period of {} s and the run holds {} of them from t = {} s: at \
         least {MIN_PERIODS} whole periods are needed (incomplete periods are not used)",
        num(*.period),
        num(*.held),
        num(*.from)
    )]
    TooFewPeriods {
        /// The period, s.
        period: f64,
        /// The periods the run holds (a fraction).
        held: f64,
        /// Where the used samples start, s.
        from: f64,
    },
    /// The samples do not resolve the period (the Fourier fit is singular).
    #[error("the samples do not resolve the motion's period")]
    Unresolved,
    /// An oscillating state is not one sine.
    #[error(
        "the motion is not harmonic: {state} has a first harmonic of amplitude {} at {} Hz \
         but its higher harmonics and the rest hold {} (more than {} % of it); a \
         harmonic (PMM) run is reduced only when its prescribed motion is one sine",
        num(*.first),
        num(*.frequency),
        num(*.rest),
        100.0 * HARMONIC_TOLERANCE
    )]
    NotHarmonic {
        /// The state's name.
        state: String,
        /// Its first harmonic's amplitude, SI.
        first: f64,
        /// The motion's frequency, Hz.
        frequency: f64,
        /// The amplitude of the higher harmonics and the rest, SI.
        rest: f64,
    },
}

/// Reduces the history of a harmonic run (samples from the end of its transient on) to one
/// condition of Fourier parts. `oscillating` are the indices of the velocity states that
/// move; `names` names every state.
pub fn reduce(
    run: &str,
    samples: &[Sample],
    oscillating: &[usize],
    names: &[&str],
    forces: &[&str],
) -> Result<(Condition, Periods, Option<Warning>), ReduceError> {
    let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let omega = motion_frequency(samples, &t, oscillating, names)?;
    let period = 2.0 * std::f64::consts::PI / omega;
    let t0 = t[0];
    let dt = median_step(&t);
    let whole = whole_periods(t[t.len() - 1] - t0 + dt, period);
    if whole < MIN_PERIODS {
        return Err(ReduceError::TooFewPeriods {
            period,
            held: (t[t.len() - 1] - t0 + dt) / period,
            from: t0,
        });
    }
    let end = t0 + whole as f64 * period;
    let used: Vec<usize> = (0..t.len()).filter(|&k| t[k] < end - 0.5 * dt).collect();
    let phases: Vec<f64> = used.iter().map(|&k| omega * (t[k] - t0)).collect();
    let (states, amplitudes) = motion_parts(samples, &used, &phases, oscillating, names, omega)?;
    let (values, sigma, changing) = force_parts(samples, &used, &phases, whole, forces)?;
    let nu = samples[0].row.u.len();
    let u = (0..nu)
        .map(|j| used.iter().map(|&k| samples[k].row.u[j]).sum::<f64>() / used.len() as f64)
        .collect();
    let from = t[used[0]];
    let warning = (!changing.is_empty()).then(|| {
        Warning::new(
            super::STAGE,
            format!(
                "the force harmonics change from the first to the second half of the {whole} \
                 periods: {}",
                changing.join(", ")
            ),
            "the run may still carry its start-up transient: the Fourier parts and their \
             standard errors are biased; start later (captive.average_after) or run more \
             periods",
        )
        .for_run(run)
    });
    let x = states.iter().map(|s| s[0]).collect();
    Ok((
        Condition {
            x,
            u,
            f: values,
            sigma: Some(sigma),
            place: format!("{run}, {whole} periods from t = {} s", num(from)),
            harmonic: Some(HarmonicMotion { omega, states }),
        },
        Periods {
            frequency: omega / (2.0 * std::f64::consts::PI),
            periods: whole,
            from,
            to: end,
            unused_end: (t[t.len() - 1] + dt - end).max(0.0),
            oscillating: amplitudes,
        },
        warning,
    ))
}

/// The angular frequency of the motion (rad/s), from the state that swings most relative
/// to its RMS.
fn motion_frequency(
    samples: &[Sample],
    t: &[f64],
    oscillating: &[usize],
    names: &[&str],
) -> Result<f64, ReduceError> {
    // the largest relative swing: a rate and a velocity compared by their RMS
    let swing = |i: usize| {
        let (lo, hi) = range(samples.iter().map(|s| s.row.x[i]));
        (hi - lo) / rms(samples.iter().map(|s| s.row.x[i])).max(1e-300)
    };
    let (lead, _) = oscillating
        .iter()
        .map(|&i| (i, swing(i)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or(ReduceError::NoOscillation)?;
    let lead_series: Vec<f64> = samples.iter().map(|s| s.row.x[lead]).collect();
    frequency(t, &lead_series).ok_or_else(|| ReduceError::NoPeriod {
        state: names[lead].to_string(),
    })
}

/// The motion's parts per state: mean and first harmonic of each oscillating state (refused
/// when it is not one sine), the mean of the rest; and the oscillating states' amplitudes.
#[allow(clippy::type_complexity)]
fn motion_parts(
    samples: &[Sample],
    used: &[usize],
    phases: &[f64],
    oscillating: &[usize],
    names: &[&str],
    omega: f64,
) -> Result<(Vec<[f64; 3]>, Vec<(String, f64)>), ReduceError> {
    // the motion: mean and first harmonic of every oscillating state, the mean of the rest
    let nx = samples[0].row.x.len();
    let mut states = vec![[0.0; 3]; nx];
    let mut amplitudes = Vec::new();
    for (i, state) in states.iter_mut().enumerate() {
        let y: Vec<f64> = used.iter().map(|&k| samples[k].row.x[i]).collect();
        if !oscillating.contains(&i) {
            state[0] = y.iter().sum::<f64>() / y.len() as f64;
            continue;
        }
        let f = fourier(phases, &y).ok_or(ReduceError::Unresolved)?;
        let first = f.values[1].hypot(f.values[2]);
        let higher: f64 = (2..=HARMONICS)
            .map(|k| f.values[2 * k - 1].powi(2) + f.values[2 * k].powi(2))
            .sum::<f64>()
            .sqrt();
        let rest = (2.0 * f.rss / y.len() as f64).sqrt();
        if higher.hypot(rest) > HARMONIC_TOLERANCE * first {
            return Err(ReduceError::NotHarmonic {
                state: names[i].to_string(),
                first,
                frequency: omega / (2.0 * std::f64::consts::PI),
                rest: higher.hypot(rest),
            });
        }
        *state = [f.values[0], f.values[1], f.values[2]];
        amplitudes.push((names[i].to_string(), first));
    }
    Ok((states, amplitudes))
}

/// The forces' Fourier parts and their standard errors (widened to the spread of the
/// periods' own parts), and the forces whose parts change from the first to the second half
/// of the periods.
#[allow(clippy::type_complexity)]
fn force_parts(
    samples: &[Sample],
    used: &[usize],
    phases: &[f64],
    whole: usize,
    forces: &[&str],
) -> Result<(Vec<f64>, Vec<f64>, Vec<String>), ReduceError> {
    // the forces: mean and harmonics with their standard errors
    let nf = samples[0].row.f.len();
    let mut values = Vec::with_capacity(nf * PER_FORCE);
    let mut sigma = Vec::with_capacity(nf * PER_FORCE);
    let mut changing = Vec::new();
    let half = used.len() / 2;
    for i in 0..nf {
        let y: Vec<f64> = used.iter().map(|&k| samples[k].row.f[i]).collect();
        let f = fourier(phases, &y).ok_or(ReduceError::Unresolved)?;
        let mut se = f.standard_errors();
        if whole >= 3 {
            // the spread of the periods' own parts, when it says more than white noise: its
            // variance above the white one's beyond the one-sided 95 % bound of a variance
            // with (periods - 1) degrees of freedom, for the record's values tested together
            // (the larger of two estimates of one variance would widen every record of white
            // noise; each value at 95 % alone, most records)
            let (spread, periods) = period_spread(phases, &y, whole);
            let bound = variance_ratio_bound_of(periods.saturating_sub(1) as f64, nf * PER_FORCE);
            for (s, p) in se.iter_mut().zip(spread) {
                if p * p > bound * *s * *s {
                    *s = p;
                }
            }
        }
        // the first and the second half of the periods (at least MIN_PERIODS = 2 of them)
        // must agree: no transient left
        let split = (whole / 2) as f64 * 2.0 * std::f64::consts::PI;
        let cut = phases.iter().position(|p| *p >= split).unwrap_or(half);
        if let (Some(a), Some(b)) = (
            fourier(&phases[..cut], &y[..cut]),
            fourier(&phases[cut..], &y[cut..]),
        ) {
            let (sa, sb) = (a.standard_errors(), b.standard_errors());
            // beyond the noise, and beyond rounding (a noise-free history)
            let floor = 1e-9 * rms(y.iter().copied());
            for k in 0..3 {
                let d = (a.values[k] - b.values[k]).abs();
                if d > 4.0 * sa[k].hypot(sb[k]) && d > floor {
                    changing.push(format!(
                        "{} ({}: {}, then {})",
                        forces.get(i).copied().unwrap_or("a force"),
                        part_name(k),
                        num(a.values[k]),
                        num(b.values[k])
                    ));
                    break;
                }
            }
        }
        values.extend_from_slice(&f.values);
        sigma.extend(se);
    }
    Ok((values, sigma, changing))
}

/// The name of the k-th Fourier value of a force.
fn part_name(k: usize) -> String {
    match k {
        0 => "mean".into(),
        k if k % 2 == 1 => format!("cos part of harmonic {}", k.div_ceil(2)),
        k => format!("sin part of harmonic {}", k / 2),
    }
}

/// A least-squares Fourier fit: values in [`basis`] order, the residual sum of squares and
/// (X'X)^-1's diagonal.
struct Fourier {
    values: Vec<f64>,
    rss: f64,
    inverse_diagonal: Vec<f64>,
    dof: usize,
}

impl Fourier {
    /// Standard errors under white noise: sigma^2 (X'X)^-1 with sigma^2 = RSS / dof.
    fn standard_errors(&self) -> Vec<f64> {
        let s2 = self.rss / self.dof.max(1) as f64;
        self.inverse_diagonal
            .iter()
            .map(|d| (s2 * d).max(0.0).sqrt())
            .collect()
    }
}

/// Fits mean and harmonics to samples at `phases` by least squares (Nocedal & Wright 2006,
/// section 10.2); None when the phases do not resolve them.
fn fourier(phases: &[f64], y: &[f64]) -> Option<Fourier> {
    let n = phases.len();
    if n <= PER_FORCE {
        return None;
    }
    let x = DMatrix::from_fn(n, PER_FORCE, |r, c| basis(phases[r])[c]);
    let xtx = x.transpose() * &x;
    let inv = xtx.try_inverse()?;
    let yv = DVector::from_column_slice(y);
    let beta = &inv * (x.transpose() * &yv);
    let rss = (yv - &x * &beta).norm_squared();
    Some(Fourier {
        values: beta.iter().copied().collect(),
        rss,
        inverse_diagonal: (0..PER_FORCE).map(|k| inv[(k, k)]).collect(),
        dof: n - PER_FORCE,
    })
}

/// The standard error of each Fourier value from the spread of the periods' own values:
/// sd / sqrt(periods), and how many periods gave them.
fn period_spread(phases: &[f64], y: &[f64], periods: usize) -> (Vec<f64>, usize) {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut per = Vec::new();
    for p in 0..periods {
        let idx: Vec<usize> = (0..phases.len())
            .filter(|&k| phases[k] >= p as f64 * two_pi && phases[k] < (p + 1) as f64 * two_pi)
            .collect();
        let ph: Vec<f64> = idx.iter().map(|&k| phases[k]).collect();
        let yy: Vec<f64> = idx.iter().map(|&k| y[k]).collect();
        if let Some(f) = fourier(&ph, &yy) {
            per.push(f.values);
        }
    }
    let n = per.len();
    if n < 3 {
        return (vec![0.0; PER_FORCE], n);
    }
    let spread = (0..PER_FORCE)
        .map(|k| {
            let m = per.iter().map(|v| v[k]).sum::<f64>() / n as f64;
            let var = per.iter().map(|v| (v[k] - m).powi(2)).sum::<f64>() / (n - 1) as f64;
            (var / n as f64).sqrt()
        })
        .collect();
    (spread, n)
}

/// The angular frequency of a periodic signal: the period from its upward crossings of the
/// mean (with a hysteresis of a third of its half-range, so noise does not count), refined by
/// the best first-harmonic fit within 3 % of it (golden-section search). None with fewer
/// than two crossings.
fn frequency(t: &[f64], y: &[f64]) -> Option<f64> {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let (lo, hi) = range(y.iter().copied());
    let h = (hi - lo) / 6.0;
    let mut below = y[0] < mean - h;
    let mut ups = Vec::new();
    for k in 1..y.len() {
        if y[k] < mean - h {
            below = true;
        } else if below && y[k] > mean + h {
            below = false;
            // the crossing of the mean itself: the last sample pair around it
            let mut j = k;
            while j > 0 && y[j - 1] >= mean {
                j -= 1;
            }
            let (t1, t2, y1, y2) = if j > 0 {
                (t[j - 1], t[j], y[j - 1], y[j])
            } else {
                (t[0], t[0], y[0], y[0])
            };
            let frac = if y2 != y1 {
                (mean - y1) / (y2 - y1)
            } else {
                0.0
            };
            ups.push(t1 + frac * (t2 - t1));
        }
    }
    if ups.len() < 2 {
        return None;
    }
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let omega0 = 2.0 * std::f64::consts::PI / period;
    let misfit = |w: f64| -> f64 {
        // residual of mean + first harmonic at w
        let n = t.len();
        let x = DMatrix::from_fn(n, 3, |r, c| match c {
            0 => 1.0,
            1 => (w * (t[r] - t[0])).cos(),
            _ => (w * (t[r] - t[0])).sin(),
        });
        let yv = DVector::from_column_slice(y);
        match (x.transpose() * &x).try_inverse() {
            Some(inv) => {
                let beta = inv * (x.transpose() * &yv);
                (yv - &x * beta).norm_squared()
            }
            None => f64::INFINITY,
        }
    };
    let (mut a, mut b) = (0.97 * omega0, 1.03 * omega0);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (misfit(c), misfit(d));
    for _ in 0..60 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = misfit(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = misfit(d);
        }
    }
    Some(0.5 * (a + b))
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (s / n.max(1) as f64).sqrt()
}

fn median_step(t: &[f64]) -> f64 {
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(t: &[f64], f: f64, a: f64) -> Vec<f64> {
        t.iter()
            .map(|t| a * (2.0 * std::f64::consts::PI * f * t).sin())
            .collect()
    }

    #[test]
    fn the_frequency_of_a_sampled_sine_is_found() {
        let t: Vec<f64> = (0..2000).map(|k| k as f64 * 0.01).collect();
        let y = sine(&t, 0.37, 2.0);
        let w = frequency(&t, &y).unwrap();
        assert!(
            (w / (2.0 * std::f64::consts::PI) - 0.37).abs() < 1e-6,
            "{w}"
        );
    }

    #[test]
    fn fourier_parts_of_a_known_signal() {
        let phases: Vec<f64> = (0..400).map(|k| k as f64 * 0.05).collect();
        let y: Vec<f64> = phases
            .iter()
            .map(|p| 1.0 + 2.0 * p.cos() - 0.5 * p.sin() + 0.25 * (3.0 * p).sin())
            .collect();
        let f = fourier(&phases, &y).unwrap();
        let want = [1.0, 2.0, -0.5, 0.0, 0.0, 0.0, 0.25];
        for (a, b) in f.values.iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "{:?}", f.values);
        }
    }
}
