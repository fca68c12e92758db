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
mod result;

pub use config::{DragFrom, SurgeConfig, DEFAULT_FORCE_WINDOW, DEFAULT_SPEED_BINS};
pub use naive::naive_xud;
pub use result::{
    BinFit, Constants, Estimate, MomentumCheck, PartFit, RunFit, RunResiduals, SurgeResult, XuuUsed,
};

use crate::coefficients::{Coefficient, CoefficientSet, Source};
use crate::config::VehicleConfig;
use crate::error::{Error, Result};
use crate::quantity::Quantity;
use crate::record::{Needs, Record};
use crate::warning::Warning;
use estimate::{part, solve, stack};
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

    let (bins, bin_spread) = bins::speed_bins(config, &stack, mode, mass, xuu, &fit_all);
    if let Some(s) = &bin_spread {
        if s.p_value.is_some_and(|p| p < 0.01) {
            warnings.push(Warning::new(
                STAGE,
                format!(
                    "Xud differs between speed bins by more than their standard errors explain \
                     (range {:.4} kg, chi2 = {:.1} on {} dof): the model (m - Xud) u_dot = \
                     Xuu u|u| + X_prop with one Xuu does not hold over the whole speed range",
                    s.range,
                    s.chi2.unwrap_or(f64::NAN),
                    s.dof
                ),
                "Xud absorbs the misfit of the drag term; its sigma from the fit alone is too \
                 small. When Xuu comes from the polar, its uncertainty is carried into Xud's \
                 sigma (see the uncertainty budget); a bias of Xuu of the order of its sigma \
                 is the usual cause",
            ));
        }
    }
    let momentum = match mode {
        DragFrom::Force => checks::momentum(&stack, mass, &mut warnings),
        DragFrom::Coefficients => Vec::new(),
    };

    if whole.xud.value > 0.0 {
        warnings.push(Warning::new(
            STAGE,
            format!(
                "Xud = {:.4} kg is positive: an added mass makes the body harder to \
                 accelerate (Xud < 0)",
                whole.xud.value
            ),
            "the surge fit is not physical: check the thrust, Xuu and the sign conventions \
             before using Xud or anything the HEKF identifies with it",
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
    let residual_lag1 = stack
        .window
        .map_or_else(|| checks::lag1(&residuals), |_| None);
    if let Some(r1) = residual_lag1 {
        if r1 > 0.5 {
            warnings.push(Warning::new(
                STAGE,
                format!(
                    "the residuals of u are strongly autocorrelated (lag-1 correlation {r1:.2})"
                ),
                "a systematic misfit remains, so the standard deviations of the fit understate \
                 the error of Xud",
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
        coefficients,
        warnings,
    })
}

fn list_names(names: &[String], r: Range<usize>) -> String {
    names[r]
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}
