//! The samples of every run stacked, the regressions on them and X_udot (X_uu) from a fit.

use super::regress::{self, cumulative_trapezoid, SegmentError, SegmentFit};
use super::{DragFrom, Estimate, PartFit, SurgeConfig, DEFAULT_FORCE_WINDOW, MIN_RUN_SAMPLES};
use crate::base::error::{Error, InputError, Place, Result};
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::numerics::hac;
use std::ops::Range;

/// The stacked samples of every run, with the integrals the fits need.
pub(super) struct Stack {
    pub(super) names: Vec<String>,
    /// Row range of each run.
    pub(super) runs: Vec<Range<usize>>,
    pub(super) t: Vec<f64>,
    pub(super) u: Vec<f64>,
    /// integral u|u| dt from the run's first sample, m^2/s.
    pub(super) j: Vec<f64>,
    /// integral X_prop dt, N s (zero when the run has no thrust).
    pub(super) p: Vec<f64>,
    /// integral F dt, N s (`force` only).
    pub(super) g: Vec<f64>,
    pub(super) has_thrust: Vec<bool>,
    /// Samples per difference window, when the fit uses windows.
    pub(super) window: Option<usize>,
    /// The same in seconds.
    pub(super) window_s: Option<f64>,
}

/// The length of the difference windows the fit uses, s (None: the whole integral).
pub(super) fn window_seconds(config: &SurgeConfig) -> Option<f64> {
    match (config.window, config.drag_from) {
        (Some(w), _) => Some(w),
        (None, DragFrom::Force) => Some(DEFAULT_FORCE_WINDOW),
        (None, DragFrom::Coefficients) => None,
    }
}

/// Reads every record into the stack, checking what the mode needs.
pub(super) fn stack(config: &SurgeConfig, records: &[Record]) -> Result<Stack> {
    let mut s = Stack {
        names: Vec::new(),
        runs: Vec::new(),
        t: Vec::new(),
        u: Vec::new(),
        j: Vec::new(),
        p: Vec::new(),
        g: Vec::new(),
        has_thrust: Vec::new(),
        window: None,
        window_s: None,
    };
    for rec in records {
        let err = |m: String| -> Error {
            InputError::new(
                Place::file(&rec.source),
                format!("surge run '{}': {m}", rec.name),
            )
            .into()
        };
        let t = rec.time().ok_or_else(|| err("no time column".into()))?;
        let u = rec
            .channel(Quantity::U)
            .ok_or_else(|| err("no u column (surge velocity)".into()))?;
        let lo = config.t_start.unwrap_or(f64::NEG_INFINITY);
        let hi = config.t_end.unwrap_or(f64::INFINITY);
        let rows: Vec<usize> = (0..rec.rows())
            .filter(|&i| t[i] >= lo && t[i] <= hi)
            .collect();
        if rows.len() < MIN_RUN_SAMPLES {
            return Err(err(format!(
                "only {} samples between t_start and t_end (at least {MIN_RUN_SAMPLES} needed)",
                rows.len()
            )));
        }
        let tt: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
        let uu: Vec<f64> = rows.iter().map(|&i| u[i]).collect();
        let has_thrust = rec.has(Quantity::Thrust);
        let thrust: Vec<f64> = rows
            .iter()
            .map(|&i| rec.value_at(Quantity::Thrust, i).unwrap_or(0.0))
            .collect();
        match config.drag_from {
            DragFrom::Coefficients if !has_thrust => {
                return Err(err(
                    "drag_from = \"coefficients\" needs the thrust X_prop: a `thrust` column \
                     or `constants = { thrust = \"22 N\" }`"
                        .into(),
                ))
            }
            DragFrom::Force if rec.channel(Quantity::Fx).is_none() => {
                return Err(err(
                    "drag_from = \"force\" needs the exported axial fluid force as an `fx` \
                     column"
                        .into(),
                ))
            }
            _ => {}
        }
        let uabs: Vec<f64> = uu.iter().map(|v| v * v.abs()).collect();
        let start = s.t.len();
        s.j.extend(cumulative_trapezoid(&tt, &uabs));
        s.p.extend(cumulative_trapezoid(&tt, &thrust));
        match rec.channel(Quantity::Fx) {
            Some(f) => {
                let ff: Vec<f64> = rows.iter().map(|&i| f[i]).collect();
                s.g.extend(cumulative_trapezoid(&tt, &ff));
            }
            None => s.g.extend(std::iter::repeat_n(0.0, rows.len())),
        }
        s.t.extend(tt);
        s.u.extend(uu);
        s.runs.push(start..s.t.len());
        s.names.push(rec.name.clone());
        s.has_thrust.push(has_thrust);
    }
    if let Some(w) = window_seconds(config) {
        let mut steps: Vec<f64> = s
            .runs
            .iter()
            .flat_map(|r| (r.start + 1..r.end).map(|i| s.t[i] - s.t[i - 1]))
            .collect();
        steps.sort_by(|a, b| a.partial_cmp(b).expect("finite times"));
        let dt = steps[steps.len() / 2];
        s.window = Some(((w / dt).round() as usize + 1).max(2));
        s.window_s = Some(w);
    }
    Ok(s)
}

/// The regression on `segments`, with X_uu (value) for `coefficients`; in the whole-integral
/// form its kappa variance from the noise's sensitivities, widened for autocorrelated
/// residuals.
pub(super) fn solve(
    s: &Stack,
    mode: DragFrom,
    xuu: Option<(f64, Option<f64>)>,
    segments: &[Range<usize>],
) -> std::result::Result<SegmentFit, FitFailure> {
    let r = match mode {
        DragFrom::Coefficients => {
            let x = xuu.expect("coefficients mode has Xuu").0;
            let i = integrand(s, x);
            levels_or_windows(s, &[&i], segments).map(|mut f| {
                if s.window.is_none() {
                    let s2 = f.rss / f.dof as f64;
                    let g = kappa_sensitivities(s, x, f.theta[0], segments, &i);
                    let white = s2 * g.iter().map(|v| v * v).sum::<f64>();
                    let long_run = long_run_variance(s, segments, &f, &g);
                    f.covariance[0][0] = white.max(long_run.unwrap_or(0.0));
                    f.misfit_factor = long_run
                        .filter(|v| *v > white && white > 0.0)
                        .map(|v| (v / white).sqrt());
                }
                f
            })
        }
        DragFrom::Force => levels_or_windows(s, &[&s.g, &s.j], segments),
    };
    r.map_err(|e| FitFailure(e, mode))
}

/// integral (Xuu u|u| + X_prop) dt with X_uu = `xuu` (paper eq. 21 integrated from t0).
fn integrand(s: &Stack, xuu: f64) -> Vec<f64> {
    s.j.iter().zip(&s.p).map(|(j, p)| xuu * j + p).collect()
}

/// kappa = 1/(m - Xud) of the fit with X_uu = `xuu`, without its variance (the central
/// difference of the sensitivity to X_uu needs the value only).
fn kappa_with(s: &Stack, xuu: f64, segments: &[Range<usize>]) -> Option<f64> {
    levels_or_windows(s, &[&integrand(s, xuu)], segments)
        .ok()
        .map(|f| f.theta[0])
}

/// First-order sensitivities g_j = d kappa / d n_j of kappa = 1/(m - Xud) in the
/// whole-integral fit to the noise n_j of the measured u, which enters both the dependent
/// variable and, through u|u| in the integrand, the regressor I (errors in variables; the
/// delta method). With centred sums, kappa = S_Iu / S_II, so g_j = (I_cj - kappa b_j A_j) /
/// S_II, where b_j = d(Xuu u|u|)/du = 2 Xuu |u_j| and A_j = sum_k I_ck dI_k/df_j with the
/// trapezoid weights dI_k/df_j = (dt_j [j > s] + dt_j+1 [k > j]) / 2 for k >= j;
/// contributions that are the same for every k of a segment cancel in the centring. For white
/// noise of variance sigma_u^2, Var kappa = sigma_u^2 sum_j g_j^2. In stack order.
fn kappa_sensitivities(
    s: &Stack,
    xuu: f64,
    kappa: f64,
    segments: &[Range<usize>],
    i: &[f64],
) -> Vec<f64> {
    let mut s_ii = 0.0;
    let mut centred = Vec::with_capacity(segments.len());
    for seg in segments {
        let m = i[seg.clone()].iter().sum::<f64>() / seg.len() as f64;
        let c: Vec<f64> = i[seg.clone()].iter().map(|v| v - m).collect();
        s_ii += c.iter().map(|v| v * v).sum::<f64>();
        centred.push(c);
    }
    let mut g = vec![0.0; s.u.len()];
    for (seg, ic) in segments.iter().zip(&centred) {
        let n = seg.len();
        // suffix[k] = sum_{q >= k} ic[q]
        let mut suffix = vec![0.0; n + 1];
        for k in (0..n).rev() {
            suffix[k] = suffix[k + 1] + ic[k];
        }
        for k in 0..n {
            let j = seg.start + k;
            let dt_here = if k > 0 { s.t[j] - s.t[j - 1] } else { 0.0 };
            let dt_next = if k + 1 < n { s.t[j + 1] - s.t[j] } else { 0.0 };
            let a = 0.5 * dt_here * suffix[k] + 0.5 * dt_next * suffix[k + 1];
            let b = 2.0 * xuu * s.u[j].abs();
            g[j] = (ic[k] - kappa * b * a) / s_ii;
        }
    }
    g
}

/// Lag-1 autocorrelation of the residuals above which they are taken as correlated: three
/// standard errors 1/sqrt(n) of a white sequence's (Box & Jenkins 1976, section 6.2.2).
const CORRELATED_SE: f64 = 3.0;

/// The variance of kappa when the residuals of u are autocorrelated (a misfit the model
/// leaves, or coloured noise): the prewhitened Newey-West long-run form of sum_j g_j e_j
/// ([`crate::numerics::hac::prewhitened`]). None when the residuals' lag-1 correlation is within
/// [`CORRELATED_SE`] standard errors of white.
fn long_run_variance(
    s: &Stack,
    segments: &[Range<usize>],
    fit: &SegmentFit,
    g: &[f64],
) -> Option<f64> {
    let mut e = vec![0.0; s.u.len()];
    for (seg, f) in segments.iter().zip(&fit.fitted) {
        for (j, fj) in seg.clone().zip(f) {
            e[j] = s.u[j] - fj;
        }
    }
    let rho = hac::lag1(hac::pieces(&e, segments))?;
    if rho <= CORRELATED_SE / (fit.n as f64).sqrt() {
        return None;
    }
    Some(hac::prewhitened(g, &e, segments))
}

fn levels_or_windows(
    s: &Stack,
    x: &[&[f64]],
    segments: &[Range<usize>],
) -> std::result::Result<SegmentFit, SegmentError> {
    match s.window {
        Some(len) => regress::fit_windows(&s.u, x, segments, len),
        None => regress::fit(&s.u, x, segments),
    }
}

#[derive(Debug)]
pub(super) struct FitFailure(SegmentError, DragFrom);

impl std::fmt::Display for FitFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (&self.0, self.1) {
            (SegmentError::TooFew, _) => f.write_str("too few samples to fit"),
            (SegmentError::Singular, DragFrom::Coefficients) => f.write_str(
                "the forces do not change over the samples (no acceleration to identify \
                 X_udot from)",
            ),
            (SegmentError::Singular, DragFrom::Force) => f.write_str(
                "integral F dt and integral u|u| dt move together over the samples: an \
                 accelerating run is needed to separate X_udot from X_uu",
            ),
        }
    }
}

/// X_udot (and X_uu) from a fit, with standard deviations.
pub(super) fn part(
    s: &Stack,
    mode: DragFrom,
    mass: f64,
    xuu: Option<(f64, Option<f64>)>,
    segments: &[Range<usize>],
    fit: &SegmentFit,
) -> std::result::Result<PartFit, String> {
    let residual_std = (fit.rss / fit.dof.max(1) as f64).sqrt();
    match mode {
        DragFrom::Coefficients => {
            let (xuu_value, xuu_sigma) = xuu.expect("coefficients mode has Xuu");
            let kappa = fit.theta[0];
            if kappa.is_nan() || kappa <= 0.0 {
                return Err(format!(
                    "the fitted 1/(m - Xud) = {kappa:.4e} 1/kg is not positive: the run does not \
                     accelerate the way Xuu u|u| + X_prop says (check the thrust sign and Xuu)"
                ));
            }
            // Xud = m - 1/kappa; d Xud / d kappa = 1/kappa^2 (paper eq. 21)
            let xud = mass - 1.0 / kappa;
            let sigma_stat = fit.covariance[0][0].max(0.0).sqrt() / (kappa * kappa);
            // Sensitivity to Xuu by a central difference of the whole fit.
            let sensitivity = {
                let h = 1e-6 * xuu_value.abs().max(1e-6);
                let at = |x: f64| kappa_with(s, x, segments).map(|k| mass - 1.0 / k);
                match (at(xuu_value + h), at(xuu_value - h)) {
                    (Some(a), Some(b)) => Some((a - b) / (2.0 * h)),
                    _ => None,
                }
            };
            let sigma_xuu = xuu_sigma.and_then(|sx| sensitivity.map(|k| k.abs() * sx));
            let total = match sigma_xuu {
                Some(sx) => (sigma_stat.powi(2) + sx.powi(2)).sqrt(),
                None => sigma_stat,
            };
            Ok(PartFit {
                xud: Estimate {
                    value: xud,
                    sigma: Some(total),
                    sigma_statistical: Some(sigma_stat),
                    sigma_from_xuu: sigma_xuu,
                    sensitivity_to_xuu: sensitivity,
                    misfit_factor: fit.misfit_factor,
                },
                xuu: None,
                n_samples: fit.n,
                residual_std,
                r_squared: fit.r_squared,
                covariance_xud_xuu: None,
            })
        }
        DragFrom::Force => {
            let (t1, t2) = (fit.theta[0], fit.theta[1]);
            if t1 == 0.0 || !t1.is_finite() {
                return Err("the fitted 1/Xud is zero: no added-mass effect in the force".into());
            }
            // Xud = 1/t1, Xuu = -t2/t1; Jacobians for the delta method.
            let xud = 1.0 / t1;
            let xuu_fit = -t2 / t1;
            let c = &fit.covariance;
            let jx = [-1.0 / (t1 * t1), 0.0];
            let ju = [t2 / (t1 * t1), -1.0 / t1];
            let quad = |a: &[f64; 2], b: &[f64; 2]| {
                let mut v = 0.0;
                for i in 0..2 {
                    for k in 0..2 {
                        v += a[i] * c[i][k] * b[k];
                    }
                }
                v
            };
            let sx = quad(&jx, &jx).max(0.0).sqrt();
            let su = quad(&ju, &ju).max(0.0).sqrt();
            Ok(PartFit {
                xud: Estimate {
                    value: xud,
                    sigma: Some(sx),
                    sigma_statistical: Some(sx),
                    sigma_from_xuu: None,
                    sensitivity_to_xuu: None,
                    misfit_factor: None,
                },
                xuu: Some(Estimate {
                    value: xuu_fit,
                    sigma: Some(su),
                    sigma_statistical: Some(su),
                    sigma_from_xuu: None,
                    sensitivity_to_xuu: None,
                    misfit_factor: None,
                }),
                n_samples: fit.n,
                residual_std,
                r_squared: fit.r_squared,
                covariance_xud_xuu: Some(quad(&jx, &ju)),
            })
        }
    }
}
