//! Checks of a fit that are not fits: the momentum balance of a force export, whether the
//! residuals are white, whether X_udot is the same in every speed bin and physical.

use super::estimate::Stack;
use super::{Estimate, MomentumCheck, RunResiduals, STAGE};
use crate::base::warning::Warning;
use crate::stages::spread::Spread;

/// The warning when X_udot differs between the speed bins by more than their standard errors
/// explain (chi-squared test at 1 %).
pub(super) fn bin_spread_warning(s: &Spread) -> Option<Warning> {
    s.p_value.is_some_and(|p| p < 0.01).then(|| {
        Warning::new(
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
        )
    })
}

/// The warning when X_udot is positive (an added mass makes the body harder to accelerate).
pub(super) fn positive_xud_warning(xud: &Estimate) -> Option<Warning> {
    (xud.value > 0.0).then(|| {
        Warning::new(
            STAGE,
            format!(
                "Xud = {:.4} kg is positive: an added mass makes the body harder to \
                 accelerate (Xud < 0)",
                xud.value
            ),
            "the surge fit is not physical: check the thrust, Xuu and the sign conventions \
             before using Xud or anything the HEKF identifies with it",
        )
    })
}

/// The warning when the residuals of u are strongly autocorrelated (lag-1 correlation
/// above 0.5), with the factor by which that widened Xud's statistical sigma.
pub(super) fn autocorrelation_warning(r1: f64, factor: Option<f64>) -> Option<Warning> {
    (r1 > 0.5).then(|| {
        let widened = match factor {
            Some(f) => format!(
                "; Xud's statistical sigma is widened {}x for it (Newey-West long-run variance)",
                crate::base::numfmt::num(f)
            ),
            None => String::new(),
        };
        Warning::new(
            STAGE,
            format!(
                "the residuals of u are strongly autocorrelated (lag-1 correlation {r1:.2}){widened}"
            ),
            "a systematic misfit remains (a drag law other than Xuu u|u|, a thrust that is not \
             the force the run felt, a held Xuu that is off) or the noise is coloured: the \
             sigma from white residuals would understate the error of Xud",
        )
    })
}

/// The momentum balance m (u - u0) = integral (F + X_prop) dt of every run with an axial force
/// and a thrust (Newton's second law along x); more than 5 % off gives a warning.
pub(super) fn momentum(
    stack: &Stack,
    mass: f64,
    warnings: &mut Vec<Warning>,
) -> Vec<MomentumCheck> {
    let mut momentum = Vec::new();
    {
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
            let (lo, hi) = crate::numerics::signal::range(stack.u[r.clone()].iter().copied());
            let relative = rms / (mass * (hi - lo)).max(f64::MIN_POSITIVE);
            if relative > 0.05 {
                warnings.push(
                    Warning::new(
                        super::STAGE,
                        format!(
                            "the exported force and thrust do not account for the motion \
                             (momentum balance off by {} the momentum change)",
                            crate::base::numfmt::proportion(relative)
                        ),
                        "Xuu and Xud fitted from this force export are not reliable: check \
                         vehicle.mass, the thrust and the sign of fx",
                    )
                    .for_run(&stack.names[k]),
                );
            }
            momentum.push(MomentumCheck {
                record: stack.names[k].clone(),
                rms,
                relative,
            });
        }
    }

    momentum
}

/// Lag-1 autocorrelation of the residuals, pooled over runs.
pub(super) fn lag1(runs: &[RunResiduals]) -> Option<f64> {
    crate::numerics::hac::lag1(runs.iter().map(|r| r.residual.as_slice()))
}
