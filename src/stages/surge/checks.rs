//! Checks of a fit that are not fits: the momentum balance of a force export, and whether
//! the residuals are white.

use super::estimate::Stack;
use super::{MomentumCheck, RunResiduals};
use crate::warning::Warning;

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
            let (lo, hi) = stack.u[r.clone()]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(*v), b.max(*v))
                });
            let relative = rms / (mass * (hi - lo)).max(f64::MIN_POSITIVE);
            if relative > 0.05 {
                warnings.push(
                    Warning::new(
                        super::STAGE,
                        format!(
                            "the exported force and thrust do not account for the motion \
                             (momentum balance off by {} the momentum change)",
                            crate::numfmt::proportion(relative)
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
    let (mut num, mut den) = (0.0, 0.0);
    for r in runs {
        let e = &r.residual;
        num += e.windows(2).map(|w| w[0] * w[1]).sum::<f64>();
        den += e.iter().map(|v| v * v).sum::<f64>();
    }
    (den > 0.0).then(|| num / den)
}
