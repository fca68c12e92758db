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

mod bins;
mod checks;
use crate::config::surge as config;
mod estimate;
mod naive;
pub mod regress;
pub mod replica;
mod result;

pub use config::{DragFrom, SurgeConfig, DEFAULT_FORCE_WINDOW, DEFAULT_SPEED_BINS};
pub use naive::naive_xud;
pub use result::{
    BinFit, Constants, Estimate, MomentumCheck, PartFit, RunFit, RunResiduals, SurgeResult, XuuUsed,
};

use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::VehicleConfig;
use crate::io::record::{Needs, Record};
use crate::model::coefficients::{Coefficient, CoefficientSet, Source};
use estimate::{part, solve, stack, Stack};
use regress::SegmentFit;
use std::ops::Range;

pub(crate) const STAGE: &str = "surge";

/// Fewest samples of a run inside the time window.
pub const MIN_RUN_SAMPLES: usize = 10;

/// The coefficients this stage estimates: Xud, and Xuu when it fits the drag too.
pub fn provides(config: &SurgeConfig) -> &'static [&'static str] {
    provides_with(config.drag_from)
}

/// The coefficients the stage estimates with its drag taken from `drag_from`.
pub fn provides_with(drag_from: DragFrom) -> &'static [&'static str] {
    match drag_from {
        DragFrom::Coefficients => &["Xud"],
        DragFrom::Force => &["Xud", "Xuu"],
    }
}

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
    let mut warnings = Vec::new();
    let xuu_known = match mode {
        DragFrom::Coefficients => Some(known_xuu(known, &mut warnings)?),
        DragFrom::Force => None,
    };
    let xuu = xuu_known.as_ref().map(|k| (k.value, k.sigma));
    let (fit_all, whole) = fit_together(&stack, mode, mass, xuu)?;
    let runs = fit_each_run(&stack, mode, mass, xuu, &whole);
    let (bins, bin_spread) = bins::speed_bins(config, &stack, mode, mass, xuu, &fit_all);
    warnings.extend(bin_spread.as_ref().and_then(checks::bin_spread_warning));
    let momentum = match mode {
        DragFrom::Force => checks::momentum(&stack, mass, &mut warnings),
        DragFrom::Coefficients => Vec::new(),
    };
    warnings.extend(checks::positive_xud_warning(&whole.xud));
    let residuals = run_residuals(&stack, &fit_all);
    // With windows the level residuals carry the integrated force noise (a random walk) by
    // design, so their autocorrelation says nothing about the fit.
    let residual_lag1 = stack
        .window
        .map_or_else(|| checks::lag1(&residuals), |_| None);
    warnings.extend(
        residual_lag1.and_then(|r| checks::autocorrelation_warning(r, whole.xud.misfit_factor)),
    );
    let inertia = Estimate {
        value: mass - whole.xud.value,
        ..whole.xud
    };
    let (names, xuu_used) = constants_and_xuu(xuu_known, &whole);
    Ok(SurgeResult {
        method: method(mode, &stack, mass, xuu_used.value),
        drag_from: mode,
        mass,
        xuu: xuu_used,
        xud: whole.xud,
        xuu_fitted: whole.xuu,
        covariance_xud_xuu: whole.covariance_xud_xuu,
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
        coefficients: coefficients(&whole, fit_all.n, stack.runs.len()),
        warnings,
    })
}

/// The checks of the stage that need its runs but no fit, for `hydroid check` and `hydroid
/// run` before any stage runs (the fit makes them again): X_uu will be known when the drag
/// comes from the coefficients (`xuu_available`: the polar stage or `[coefficients]` gives
/// it), and every run has enough samples between `t_start` and `t_end` (and windows). The
/// first problem, if any (of the runs only when some were read).
pub fn preflight(config: &SurgeConfig, records: &[Record], xuu_available: bool) -> Option<Error> {
    if config.drag_from == DragFrom::Coefficients && !xuu_available {
        return Some(xuu_unknown());
    }
    if records.is_empty() {
        // no run given is the configuration's problem; none read, the inputs'
        return None;
    }
    stack(config, records).err()
}

/// Xuu is needed and nothing gives it.
fn xuu_unknown() -> Error {
    Error::numerical(
        STAGE,
        "Xuu is not known: run the polar stage, give coefficients.Xuu, or set \
         surge.drag_from = \"force\" to fit it from the exported axial force",
    )
}

/// The X_uu the fit takes from the known coefficients (`drag_from = "coefficients"`), with a
/// warning when it is not negative.
fn known_xuu(known: &CoefficientSet, warnings: &mut Vec<Warning>) -> Result<XuuUsed> {
    let c = known.get("Xuu").ok_or_else(xuu_unknown)?;
    if c.value >= 0.0 {
        warnings.push(Warning::new(
            STAGE,
            format!(
                "Xuu = {} kg/m is not negative: drag should oppose the motion",
                c.value
            ),
            "Xud is fitted against a drag that pushes the body forward, so it absorbs \
             the error; check the polar stage or coefficients.Xuu",
        ));
    }
    Ok(XuuUsed {
        value: c.value,
        sigma: c.sigma,
        source: format!(
            "{} ({})",
            c.source,
            c.note.clone().unwrap_or_else(|| "known".into())
        ),
    })
}

/// The fit of every run together: the regression and X_udot (X_uu) from it.
fn fit_together(
    stack: &Stack,
    mode: DragFrom,
    mass: f64,
    xuu: Option<(f64, Option<f64>)>,
) -> Result<(SegmentFit, PartFit)> {
    let every_run = || list_names(&stack.names, 0..stack.names.len());
    let fit = solve(stack, mode, xuu, &stack.runs)
        .map_err(|e| Error::numerical(STAGE, format!("{e} ({})", every_run())))?;
    let whole = part(stack, mode, mass, xuu, &stack.runs, &fit)
        .map_err(|m| Error::numerical(STAGE, format!("{m} ({})", every_run())))?;
    Ok((fit, whole))
}

/// Each run fitted alone, when there are several (the fit of all is the one run's fit when
/// there is one); a run that cannot be fitted alone says why.
fn fit_each_run(
    stack: &Stack,
    mode: DragFrom,
    mass: f64,
    xuu: Option<(f64, Option<f64>)>,
    whole: &PartFit,
) -> Vec<RunFit> {
    let mut runs = Vec::new();
    for (k, r) in stack.runs.iter().enumerate() {
        let (fit, note) = if stack.runs.len() == 1 {
            (Some(whole.clone()), None)
        } else {
            let seg = std::slice::from_ref(r);
            match solve(stack, mode, xuu, seg)
                .map_err(|e| e.to_string())
                .and_then(|f| part(stack, mode, mass, xuu, seg, &f))
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
    runs
}

/// The measured and fitted u of each run and their difference.
fn run_residuals(stack: &Stack, fit: &SegmentFit) -> Vec<RunResiduals> {
    stack
        .runs
        .iter()
        .zip(&fit.fitted)
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
        .collect()
}

/// The names of the fitted constants and the X_uu used: the known one
/// (`drag_from = "coefficients"`), or the one fitted with X_udot (`force`).
fn constants_and_xuu(xuu_known: Option<XuuUsed>, whole: &PartFit) -> (Vec<String>, XuuUsed) {
    match xuu_known {
        Some(k) => (vec!["inv_inertia".to_string()], k),
        None => {
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
    }
}

/// The method in words, for the report.
fn method(mode: DragFrom, stack: &Stack, mass: f64, xuu: f64) -> String {
    let n_runs = stack.runs.len();
    let form = match (stack.window, stack.window_s) {
        (Some(n), Some(w)) => {
            format!("; fitted on differences over non-overlapping {w} s windows ({n} samples)")
        }
        _ => "; fitted on the whole integral, sigma by the delta method with the noise of u in \
              both u and the integral"
            .to_string(),
    };
    match mode {
        DragFrom::Coefficients => format!(
            "paper eq. 21 in integral form: u(t) = u(t0) + 1/(m - Xud) integral (Xuu u|u| + \
             X_prop) dt, least squares over {n_runs} run(s) with u(t0) free per run; m = {mass} \
             kg, Xuu = {xuu} kg/m{form}"
        ),
        DragFrom::Force => format!(
            "axial force F = Xuu u|u| + Xud u_dot in integral form: u(t) = u(t0) + (1/Xud) \
             integral F dt - (Xuu/Xud) integral u|u| dt, least squares over {n_runs} run(s) with \
             u(t0) free per run{form}"
        ),
    }
}

/// The coefficients the stage gives: Xud, and Xuu when fitted with it.
fn coefficients(whole: &PartFit, n_samples: usize, n_runs: usize) -> Vec<Coefficient> {
    let mut coefficients =
        vec![
            Coefficient::new("Xud", whole.xud.value, whole.xud.sigma, Source::Surge).with_note(
                format!("paper eq. 21, integral form over {n_runs} run(s), {n_samples} samples"),
            ),
        ];
    if let Some(x) = whole.xuu {
        coefficients.push(
            Coefficient::new("Xuu", x.value, x.sigma, Source::Surge)
                .with_note("fitted with Xud from the axial force of the surge run(s)"),
        );
    }
    coefficients
}

fn list_names(names: &[String], r: Range<usize>) -> String {
    names[r]
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}
