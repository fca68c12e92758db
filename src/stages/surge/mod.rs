//! Surge acceleration stage: the added mass X_udot from a straight-line run (paper eq. 21).
//!
//! The paper's equation (m - Xud) u_dot = Xuu u|u| + X_prop is fitted in integral form,
//!
//! ```text
//! u(t) = u(t0) + 1/(m - Xud) * integral_t0^t (Xuu u|u| + X_prop) dt
//! ```
//!
//! linear in (u(t0), 1/(m - Xud)), with the measured u as the dependent variable and the
//! integral of the measured u|u| as the regressor. Differencing a noisy u amplifies its noise
//! by 1/dt and, put in the regressor, biases the slope towards zero (errors in variables,
//! e.g. Fuller, Measurement Error Models, 1987, section 1.1); the integral averages the noise
//! out instead. With `drag_from = "force"` the exported axial fluid force F = Xuu u|u| +
//! Xud u_dot gives u(t) = u(t0) + (1/Xud) integral F dt - (Xuu/Xud) integral u|u| dt, which
//! needs neither the mass nor the thrust. See docs/stages.md.

// crate::Error is large (its InputError variant); boxing it is a crate-wide choice.
#![allow(clippy::result_large_err)]

mod config;
pub mod regress;

pub use config::{DragFrom, SurgeConfig, DEFAULT_FORCE_WINDOW, DEFAULT_SPEED_BINS};

use crate::coefficients::{Coefficient, CoefficientSet, Source};
use crate::config::VehicleConfig;
use crate::error::{Error, InputError, Place, Result};
use crate::quantity::Quantity;
use crate::record::{Needs, Record};
use crate::stages::spread::{spread, Spread};
use regress::{cumulative_trapezoid, SegmentError, SegmentFit};
use serde::Serialize;
use std::ops::Range;

const STAGE: &str = "surge";

/// Fewest samples of a run inside the time window.
pub const MIN_RUN_SAMPLES: usize = 10;

/// What the stage reads from each record.
pub fn needs(config: &SurgeConfig) -> Needs<'static> {
    match config.drag_from {
        DragFrom::Coefficients => Needs {
            required: &[Quantity::Time, Quantity::U, Quantity::Thrust],
            optional: &[Quantity::Fx],
            min_rows: MIN_RUN_SAMPLES,
        },
        DragFrom::Force => Needs {
            required: &[Quantity::Time, Quantity::U, Quantity::Fx],
            optional: &[Quantity::Thrust],
            min_rows: MIN_RUN_SAMPLES,
        },
    }
}

/// Reads every run of `config` (paths relative to `base`) with what [`needs`] asks for.
pub fn load(config: &SurgeConfig, base: &std::path::Path) -> Result<Vec<Record>> {
    let needs = needs(config);
    config
        .runs
        .iter()
        .map(|spec| crate::record::load(spec, base, &needs).map_err(Error::from))
        .collect()
}

/// An estimate with its standard deviation split by cause.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// Value, SI.
    pub value: f64,
    /// Total standard deviation (statistical and from X_uu, in quadrature).
    pub sigma: Option<f64>,
    /// Standard deviation from the fit residuals alone.
    pub sigma_statistical: Option<f64>,
    /// Standard deviation carried over from the uncertainty of the X_uu used.
    pub sigma_from_xuu: Option<f64>,
}

/// The X_uu the stage used.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct XuuUsed {
    /// Value, kg/m.
    pub value: f64,
    /// Standard deviation, kg/m.
    pub sigma: Option<f64>,
    /// Where it came from.
    pub source: String,
}

/// The fit of one run or of one speed bin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartFit {
    /// X_udot, kg.
    pub xud: Estimate,
    /// X_uu fitted with it (`drag_from = "force"` only), kg/m.
    pub xuu: Option<Estimate>,
    /// Samples used.
    pub n_samples: usize,
    /// Residual standard deviation of u, m/s.
    pub residual_std: f64,
    /// Coefficient of determination of u.
    pub r_squared: Option<f64>,
}

/// One run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunFit {
    /// The record.
    pub record: String,
    /// First and last time used, s.
    pub t_span: [f64; 2],
    /// Speed at the first and last sample used, m/s.
    pub u_span: [f64; 2],
    /// The fit of this run alone (None if it cannot be fitted alone; see `note`).
    pub fit: Option<PartFit>,
    /// Why there is no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// One speed bin (paper fig. 8: X_udot per speed band).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BinFit {
    /// Lower edge, m/s.
    pub u_min: f64,
    /// Upper edge, m/s.
    pub u_max: f64,
    /// Samples in stretches long enough to use.
    pub n_samples: usize,
    /// Stretches of runs in the bin (each with its own u(t0)).
    pub n_segments: usize,
    /// The fit (None when the bin has too little data; see `note`).
    pub fit: Option<PartFit>,
    /// Why there is no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// Residuals of one run, for plots.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunResiduals {
    /// The record.
    pub record: String,
    /// Time, s.
    pub time: Vec<f64>,
    /// Measured u, m/s.
    pub u: Vec<f64>,
    /// Fitted u, m/s.
    pub fitted: Vec<f64>,
    /// u - fitted, m/s.
    pub residual: Vec<f64>,
}

/// The momentum balance m (u - u0) = integral (F + X_prop) dt of a run that exports both the
/// axial force and the thrust (`drag_from = "force"`): a check of the export, not a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MomentumCheck {
    /// The record.
    pub record: String,
    /// RMS of m u - integral (F + X_prop) dt about its mean, N s.
    pub rms: f64,
    /// rms / (m (max u - min u)), -.
    pub relative: f64,
}

/// The fitted constants of the whole fit, with their covariance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Constants {
    /// Names: `inv_inertia` = 1/(m - Xud) (1/kg) for `coefficients`; `inv_xud` = 1/Xud
    /// (1/kg) and `xuu_over_xud` = -Xuu/Xud (1/m) for `force`.
    pub names: Vec<String>,
    /// Values.
    pub values: Vec<f64>,
    /// Covariance.
    pub covariance: Vec<Vec<f64>>,
    /// u(t0) of each run, m/s.
    pub u0: Vec<f64>,
}

/// Everything the surge stage found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurgeResult {
    /// The method in words.
    pub method: String,
    /// Where the drag term came from.
    pub drag_from: DragFrom,
    /// Vehicle mass used, kg.
    pub mass: f64,
    /// X_uu used (`coefficients`) or fitted (`force`).
    pub xuu: XuuUsed,
    /// X_udot over every run together, kg.
    pub xud: Estimate,
    /// X_uu fitted with X_udot (`force` only), kg/m.
    pub xuu_fitted: Option<Estimate>,
    /// m - X_udot, kg.
    pub inertia: Estimate,
    /// The fitted constants and their covariance.
    pub constants: Constants,
    /// Samples used.
    pub n_samples: usize,
    /// Residual standard deviation of u, m/s.
    pub residual_std: f64,
    /// Coefficient of determination of u.
    pub r_squared: Option<f64>,
    /// Lag-1 autocorrelation of the residuals of u (near 0 when the model explains the run and
    /// the rest is measurement noise; near 1 when a systematic misfit remains, and then the
    /// standard deviations are too small). Whole-integral fits only.
    pub residual_lag1: Option<f64>,
    /// Each run alone.
    pub runs: Vec<RunFit>,
    /// Each speed bin.
    pub bins: Vec<BinFit>,
    /// Spread of X_udot between the bins that have a fit (statistical sigmas: the X_uu
    /// uncertainty is common to all bins).
    pub bin_spread: Option<Spread>,
    /// Momentum balance of each run with force and thrust (`force` only).
    pub momentum: Vec<MomentumCheck>,
    /// Residuals of every run.
    pub residuals: Vec<RunResiduals>,
    /// Coefficients: Xud (and Xuu for `force`), `Source::Surge`.
    pub coefficients: Vec<Coefficient>,
    /// Things worth reading.
    pub warnings: Vec<String>,
}

impl SurgeResult {
    /// The coefficients this stage estimated.
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }
}

/// The stacked samples of every run, with the integrals the fits need.
struct Stack {
    names: Vec<String>,
    /// Row range of each run.
    runs: Vec<Range<usize>>,
    t: Vec<f64>,
    u: Vec<f64>,
    /// integral u|u| dt from the run's first sample, m^2/s.
    j: Vec<f64>,
    /// integral X_prop dt, N s (zero when the run has no thrust).
    p: Vec<f64>,
    /// integral F dt, N s (`force` only).
    g: Vec<f64>,
    has_thrust: Vec<bool>,
    /// Samples per difference window, when the fit uses windows.
    window: Option<usize>,
    /// The same in seconds.
    window_s: Option<f64>,
}

/// Runs the surge stage on records already read. `known` supplies X_uu (with its sigma) for
/// `drag_from = "coefficients"`.
pub fn run(
    config: &SurgeConfig,
    vehicle: &VehicleConfig,
    known: &CoefficientSet,
    records: &[Record],
) -> Result<SurgeResult> {
    if records.is_empty() {
        return Err(Error::numerical(STAGE, "no surge run to fit"));
    }
    let mass = vehicle.mass;
    let mode = config.drag_from;
    let stack = stack(config, records)?;
    let all: Vec<Range<usize>> = stack.runs.clone();
    let mut warnings = Vec::new();

    let xuu_known = match mode {
        DragFrom::Coefficients => {
            let c = known.get("Xuu").ok_or_else(|| {
                Error::numerical(
                    STAGE,
                    "Xuu is not known: run the polar stage, give coefficients.Xuu, or set \
                     surge.drag_from = \"force\" to fit it from the exported axial force",
                )
            })?;
            if c.value >= 0.0 {
                warnings.push(format!(
                    "Xuu = {} kg/m is not negative: drag should oppose the motion",
                    c.value
                ));
            }
            Some((
                c.value,
                c.sigma,
                format!(
                    "{} ({})",
                    c.source,
                    c.note.clone().unwrap_or_else(|| "known".into())
                ),
            ))
        }
        DragFrom::Force => None,
    };
    let xuu = xuu_known.as_ref().map(|k| (k.0, k.1));

    let fit_all = solve(&stack, mode, xuu, &all).map_err(|e| {
        Error::numerical(
            STAGE,
            format!("{} ({})", e, list_names(&stack.names, 0..stack.names.len())),
        )
    })?;
    let whole = part(&stack, mode, mass, xuu, &all, &fit_all).map_err(|m| {
        Error::numerical(
            STAGE,
            format!("{m} ({})", list_names(&stack.names, 0..stack.names.len())),
        )
    })?;

    // Each run alone, when there are several.
    let mut runs = Vec::new();
    for (k, r) in stack.runs.iter().enumerate() {
        let (fit, note) = if stack.runs.len() == 1 {
            (Some(whole.clone()), None)
        } else {
            let seg = std::slice::from_ref(r);
            match solve(&stack, mode, xuu, seg)
                .map_err(|e| e.to_string())
                .and_then(|f| part(&stack, mode, mass, xuu, seg, &f))
            {
                Ok(p) => (Some(p), None),
                Err(m) => (None, Some(m)),
            }
        };
        runs.push(RunFit {
            record: stack.names[k].clone(),
            t_span: [stack.t[r.start], stack.t[r.end - 1]],
            u_span: [stack.u[r.start], stack.u[r.end - 1]],
            fit,
            note,
        });
    }

    // Speed bins, assigned by the fitted (noise-free) speed so that the noise in u does not
    // decide which samples a bin keeps.
    let smooth: Vec<f64> = fit_all.fitted.concat();
    let edges = match &config.speed_bin_edges {
        Some(e) => e.clone(),
        None => {
            let n = config.speed_bins.unwrap_or(DEFAULT_SPEED_BINS).max(1);
            let lo = smooth.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = smooth.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (0..=n)
                .map(|i| lo + (hi - lo) * i as f64 / n as f64)
                .collect()
        }
    };
    let mut bins = Vec::new();
    for (b, w) in edges.windows(2).enumerate() {
        let last = b + 2 == edges.len();
        let inside = |v: f64| v >= w[0] && (v < w[1] || (last && v <= w[1]));
        let mut segs = Vec::new();
        for r in &stack.runs {
            let mut start = None;
            for i in r.clone() {
                match (inside(smooth[i]), start) {
                    (true, None) => start = Some(i),
                    (false, Some(s)) => {
                        segs.push(s..i);
                        start = None;
                    }
                    _ => {}
                }
            }
            if let Some(s) = start {
                segs.push(s..r.end);
            }
        }
        segs.retain(|s| s.len() >= config.min_bin_samples);
        let n_samples = segs.iter().map(|s| s.len()).sum();
        let (fit, note) = if segs.is_empty() {
            (
                None,
                Some(format!(
                    "no stretch of {} or more samples in this speed range",
                    config.min_bin_samples
                )),
            )
        } else {
            match solve(&stack, mode, xuu, &segs)
                .map_err(|e| e.to_string())
                .and_then(|f| part(&stack, mode, mass, xuu, &segs, &f))
            {
                Ok(p) => (Some(p), None),
                Err(m) => (None, Some(m)),
            }
        };
        bins.push(BinFit {
            u_min: w[0],
            u_max: w[1],
            n_samples,
            n_segments: segs.len(),
            fit,
            note,
        });
    }
    let bin_estimates: Vec<(f64, Option<f64>)> = bins
        .iter()
        .filter_map(|b| b.fit.as_ref())
        .map(|f| (f.xud.value, f.xud.sigma_statistical))
        .collect();
    let bin_spread = spread("Xud", "kg", &bin_estimates);
    if let Some(s) = &bin_spread {
        if s.p_value.is_some_and(|p| p < 0.01) {
            warnings.push(format!(
                "Xud differs between speed bins by more than their standard errors explain \
                 (range {:.4} kg, chi2 = {:.1} on {} dof): the model (m - Xud) u_dot = Xuu u|u| \
                 + X_prop with one Xuu does not hold over the whole speed range",
                s.range,
                s.chi2.unwrap_or(f64::NAN),
                s.dof
            ));
        }
    }

    // Momentum balance of runs that export force and thrust.
    let mut momentum = Vec::new();
    if mode == DragFrom::Force {
        for (k, r) in stack.runs.iter().enumerate() {
            if !stack.has_thrust[k] {
                continue;
            }
            // m (u - u0) = integral (F + X_prop) dt (Newton's second law along x)
            let d: Vec<f64> = r
                .clone()
                .map(|i| mass * stack.u[i] - stack.g[i] - stack.p[i])
                .collect();
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let rms = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
            let (lo, hi) = stack.u[r.clone()]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(*v), b.max(*v))
                });
            let relative = rms / (mass * (hi - lo)).max(f64::MIN_POSITIVE);
            if relative > 0.05 {
                warnings.push(format!(
                    "{}: the exported force and thrust do not account for the motion (momentum \
                     balance off by {:.0} %): check vehicle.mass, the thrust and the sign of fx",
                    stack.names[k],
                    100.0 * relative
                ));
            }
            momentum.push(MomentumCheck {
                record: stack.names[k].clone(),
                rms,
                relative,
            });
        }
    }

    if whole.xud.value > 0.0 {
        warnings.push(format!(
            "Xud = {:.4} kg is positive: an added mass makes the body harder to accelerate \
             (Xud < 0); check the thrust, Xuu and the sign conventions",
            whole.xud.value
        ));
    }

    let residuals: Vec<RunResiduals> = stack
        .runs
        .iter()
        .zip(&fit_all.fitted)
        .enumerate()
        .map(|(k, (r, f))| RunResiduals {
            record: stack.names[k].clone(),
            time: stack.t[r.clone()].to_vec(),
            u: stack.u[r.clone()].to_vec(),
            fitted: f.clone(),
            residual: stack.u[r.clone()]
                .iter()
                .zip(f)
                .map(|(a, b)| a - b)
                .collect(),
        })
        .collect();

    // With windows the level residuals carry the integrated force noise (a random walk) by
    // design, so their autocorrelation says nothing about the fit.
    let residual_lag1 = stack.window.map_or_else(|| lag1(&residuals), |_| None);
    if let Some(r1) = residual_lag1 {
        if r1 > 0.5 {
            warnings.push(format!(
                "the residuals of u are strongly autocorrelated (lag-1 correlation {r1:.2}): a \
                 systematic misfit remains and the standard deviations understate the error"
            ));
        }
    }
    let inertia = Estimate {
        value: mass - whole.xud.value,
        ..whole.xud
    };
    let (names, xuu_used) = match mode {
        DragFrom::Coefficients => {
            let (v, s, src) = xuu_known.expect("coefficients mode");
            (
                vec!["inv_inertia".to_string()],
                XuuUsed {
                    value: v,
                    sigma: s,
                    source: src,
                },
            )
        }
        DragFrom::Force => {
            let x = whole.xuu.expect("force mode fits Xuu");
            (
                vec!["inv_xud".to_string(), "xuu_over_xud".to_string()],
                XuuUsed {
                    value: x.value,
                    sigma: x.sigma,
                    source: "fitted with Xud from the exported axial force".into(),
                },
            )
        }
    };
    let n_runs = stack.runs.len();
    let form = match (stack.window, stack.window_s) {
        (Some(n), Some(w)) => {
            format!("; fitted on differences over non-overlapping {w} s windows ({n} samples)")
        }
        _ => "; fitted on the whole integral, sigma by the delta method with the noise of u in \
              both u and the integral"
            .to_string(),
    };
    let method = match mode {
        DragFrom::Coefficients => format!(
            "paper eq. 21 in integral form: u(t) = u(t0) + 1/(m - Xud) integral (Xuu u|u| + \
             X_prop) dt, least squares over {n_runs} run(s) with u(t0) free per run; m = {mass} \
             kg, Xuu = {} kg/m{form}",
            xuu_used.value
        ),
        DragFrom::Force => format!(
            "axial force F = Xuu u|u| + Xud u_dot in integral form: u(t) = u(t0) + (1/Xud) \
             integral F dt - (Xuu/Xud) integral u|u| dt, least squares over {n_runs} run(s) with \
             u(t0) free per run{form}"
        ),
    };
    let mut coefficients =
        vec![
            Coefficient::new("Xud", whole.xud.value, whole.xud.sigma, Source::Surge).with_note(
                format!(
                    "paper eq. 21, integral form over {n_runs} run(s), {} samples",
                    fit_all.n
                ),
            ),
        ];
    if let Some(x) = whole.xuu {
        coefficients.push(
            Coefficient::new("Xuu", x.value, x.sigma, Source::Surge)
                .with_note("fitted with Xud from the axial force of the surge run(s)"),
        );
    }
    Ok(SurgeResult {
        method,
        drag_from: mode,
        mass,
        xuu: xuu_used,
        xud: whole.xud,
        xuu_fitted: whole.xuu,
        inertia,
        constants: Constants {
            names,
            values: fit_all.theta.clone(),
            covariance: fit_all.covariance.clone(),
            u0: fit_all.intercepts.clone(),
        },
        n_samples: fit_all.n,
        residual_std: whole.residual_std,
        r_squared: whole.r_squared,
        residual_lag1,
        runs,
        bins,
        bin_spread,
        momentum,
        residuals,
        coefficients,
        warnings,
    })
}

/// Lag-1 autocorrelation of the residuals, pooled over runs.
fn lag1(runs: &[RunResiduals]) -> Option<f64> {
    let (mut num, mut den) = (0.0, 0.0);
    for r in runs {
        let e = &r.residual;
        num += e.windows(2).map(|w| w[0] * w[1]).sum::<f64>();
        den += e.iter().map(|v| v * v).sum::<f64>();
    }
    (den > 0.0).then(|| num / den)
}

fn list_names(names: &[String], r: Range<usize>) -> String {
    names[r]
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads every record into the stack, checking what the mode needs.
fn stack(config: &SurgeConfig, records: &[Record]) -> Result<Stack> {
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
    let window = match (config.window, config.drag_from) {
        (Some(w), _) => Some(w),
        (None, DragFrom::Force) => Some(DEFAULT_FORCE_WINDOW),
        (None, DragFrom::Coefficients) => None,
    };
    if let Some(w) = window {
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

/// The regression on `segments`, with X_uu (value) for `coefficients`.
fn solve(
    s: &Stack,
    mode: DragFrom,
    xuu: Option<(f64, Option<f64>)>,
    segments: &[Range<usize>],
) -> std::result::Result<SegmentFit, FitFailure> {
    let r = match mode {
        DragFrom::Coefficients => {
            let x = xuu.expect("coefficients mode has Xuu").0;
            // integral (Xuu u|u| + X_prop) dt (paper eq. 21 integrated from t0)
            let i: Vec<f64> = s.j.iter().zip(&s.p).map(|(j, p)| x * j + p).collect();
            levels_or_windows(s, &[&i], segments).map(|mut f| {
                if s.window.is_none() {
                    let s2 = f.rss / f.dof as f64;
                    f.covariance[0][0] = kappa_variance(s, x, f.theta[0], segments, &i, s2);
                }
                f
            })
        }
        DragFrom::Force => levels_or_windows(s, &[&s.g, &s.j], segments),
    };
    r.map_err(|e| FitFailure(e, mode))
}

/// First-order variance of kappa = 1/(m - Xud) in the whole-integral fit when the white
/// noise n_j of the measured u enters both the dependent variable and, through u|u| in the
/// integrand, the regressor I (errors in variables; the delta method). With centred sums,
/// kappa = S_Iu / S_II, so d kappa / d n_j = (I_cj - kappa b_j A_j) / S_II, where
/// b_j = d(Xuu u|u|)/du = 2 Xuu |u_j| and A_j = sum_k I_ck dI_k/df_j with the trapezoid
/// weights dI_k/df_j = (dt_j [j > s] + dt_j+1 [k > j]) / 2 for k >= j; contributions that are
/// the same for every k of a segment cancel in the centring. Var = sigma_u^2 sum_j g_j^2.
fn kappa_variance(
    s: &Stack,
    xuu: f64,
    kappa: f64,
    segments: &[Range<usize>],
    i: &[f64],
    sigma2: f64,
) -> f64 {
    let mut s_ii = 0.0;
    let mut centred = Vec::with_capacity(segments.len());
    for seg in segments {
        let m = i[seg.clone()].iter().sum::<f64>() / seg.len() as f64;
        let c: Vec<f64> = i[seg.clone()].iter().map(|v| v - m).collect();
        s_ii += c.iter().map(|v| v * v).sum::<f64>();
        centred.push(c);
    }
    let mut sum_g2 = 0.0;
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
            let g = (ic[k] - kappa * b * a) / s_ii;
            sum_g2 += g * g;
        }
    }
    sigma2 * sum_g2
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
struct FitFailure(SegmentError, DragFrom);

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
fn part(
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
            let sigma_xuu = match xuu_sigma {
                Some(sx) => {
                    let h = 1e-6 * xuu_value.abs().max(1e-6);
                    let at = |x: f64| {
                        solve(s, mode, Some((x, None)), segments)
                            .ok()
                            .map(|f| mass - 1.0 / f.theta[0])
                    };
                    match (at(xuu_value + h), at(xuu_value - h)) {
                        (Some(a), Some(b)) => Some(((a - b) / (2.0 * h)).abs() * sx),
                        _ => None,
                    }
                }
                None => None,
            };
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
                },
                xuu: None,
                n_samples: fit.n,
                residual_std,
                r_squared: fit.r_squared,
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
                },
                xuu: Some(Estimate {
                    value: xuu_fit,
                    sigma: Some(su),
                    sigma_statistical: Some(su),
                    sigma_from_xuu: None,
                }),
                n_samples: fit.n,
                residual_std,
                r_squared: fit.r_squared,
            })
        }
    }
}

/// Diagnostic only, and biased: X_udot from regressing the force Xuu u|u| + X_prop on a
/// central-difference u_dot through the origin, (m - Xud) = sum(F u_dot) / sum(u_dot^2).
/// Noise in u becomes noise of size sqrt(2) sigma_u / (2 dt) in u_dot, which shrinks the
/// fitted slope (regression dilution; Fuller 1987, section 1.1); since X_udot is the small
/// difference m - slope, a few per cent of dilution flips its sign. Kept to show why the
/// stage uses the integral form; `force[i]` is the total force at sample i.
pub fn naive_xud(time: &[f64], u: &[f64], force: &[f64], mass: f64) -> Result<f64> {
    let n = time.len();
    if n < 3 || u.len() != n || force.len() != n {
        return Err(Error::numerical(
            STAGE,
            "naive_xud needs time, u and force of equal length (at least 3 samples)",
        ));
    }
    let (mut sfu, mut suu) = (0.0, 0.0);
    for i in 1..n - 1 {
        // central difference u_dot = (u[i+1] - u[i-1]) / (t[i+1] - t[i-1])
        let ud = (u[i + 1] - u[i - 1]) / (time[i + 1] - time[i - 1]);
        sfu += force[i] * ud;
        suu += ud * ud;
    }
    if suu == 0.0 {
        return Err(Error::numerical(STAGE, "naive_xud: u does not change"));
    }
    Ok(mass - sfu / suu)
}
