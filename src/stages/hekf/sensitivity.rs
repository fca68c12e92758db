//! How the HEKF estimates depend on the coefficients it holds fixed.
//!
//! The filter's covariance is conditional on the fixed coefficients being exact. They are not:
//! X_udot from a surge run, the polar coefficients, all carry uncertainty, as independent
//! directions (see [`crate::model::coefficients::Direction`]). For each direction that reaches a
//! fixed coefficient of the model, the identification is repeated with the fixed values moved
//! by plus and minus one sigma along it (one pass from the converged estimate), and the change
//! of the estimates, (beta(+) - beta(-)) / 2, is that direction's share in them: linear error
//! propagation by central differences ("consider" analysis, Bierman 1977, ch. 7). The total
//! covariance is the filter's plus the sum of these outer products. The repeated passes keep
//! no traces, so that running them side by side costs no memory per sample.
//!
//! The noise model is a choice too: the same pass with every noise variance (measurement and
//! process) at a quarter and at four times its value (the sigmas halved and doubled) says how
//! much the estimates depend on it; half the difference is the "noise model" direction of
//! the uncertainty budget, and a move beyond one sigma is worth a warning.

use super::identify::{estimates, RunData, Setup};
use crate::model::coefficients::{CoefficientSet, Direction};
use crate::model::models::Model;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// A converged identification, whose last pass the sensitivity studies repeat.
#[derive(Clone, Copy)]
pub struct Converged<'a> {
    /// The setup, with the noise as calibrated.
    pub setup: &'a Setup,
    /// The runs.
    pub runs: &'a [RunData],
    /// The estimated coefficients (SI) ...
    pub estimate: &'a [f64],
    /// ... their sigmas ...
    pub sigma: &'a [f64],
    /// ... and names.
    pub est_names: &'a [String],
}

/// The estimates' change along each upstream direction that reaches a fixed coefficient, as
/// directions with the upstream sources' labels. Directions whose repeated identification
/// fails are reported by label in the second list.
pub fn upstream<M: Model>(
    model: &M,
    at: Converged<'_>,
    known: &CoefficientSet,
) -> (Vec<Direction>, Vec<String>) {
    let Converged {
        setup,
        runs,
        estimate,
        sigma,
        est_names,
    } = at;
    let names = model.coefficient_names();
    let fixed: Vec<(usize, &str)> = names
        .iter()
        .enumerate()
        .filter(|(i, n)| !setup.est.contains(i) && !model.is_derived(n))
        .map(|(i, n)| (i, *n))
        .collect();
    let relevant: Vec<&Direction> = known
        .directions
        .iter()
        .filter(|d| fixed.iter().any(|(_, n)| d.deltas.contains_key(*n)))
        .collect();
    let base_setup = one_pass_setup(setup, estimate, sigma);
    let results: Vec<Result<Direction, String>> = relevant
        .par_iter()
        .map(|d| {
            let at = |sign: f64| {
                let mut s = base_setup.clone();
                for (i, n) in &fixed {
                    if let Some(delta) = d.deltas.get(*n) {
                        s.base[*i] += sign * delta;
                    }
                }
                estimates(model, &s, runs)
                    .ok()
                    .and_then(|mut p| p.pop().map(|p| p.values))
            };
            match (at(1.0), at(-1.0)) {
                (Some(plus), Some(minus)) => {
                    let deltas: BTreeMap<String, f64> = est_names
                        .iter()
                        .zip(plus.iter().zip(&minus))
                        .map(|(n, (p, m))| (n.clone(), 0.5 * (p - m)))
                        .collect();
                    Ok(Direction {
                        source: d.source.clone(),
                        deltas,
                    })
                }
                _ => Err(d.source.clone()),
            }
        })
        .collect();
    let mut ok = Vec::new();
    let mut failed = Vec::new();
    for r in results {
        match r {
            Ok(d) => ok.push(d),
            Err(label) => failed.push(label),
        }
    }
    (ok, failed)
}

/// One pass from the converged `estimate` with the prior later passes use (its `sigma`
/// times the repeat factor at most), the calibrated noise held, no smoother.
fn one_pass_setup(setup: &Setup, estimate: &[f64], sigma: &[f64]) -> Setup {
    let factor = setup.repeat_prior_factor.unwrap_or(f64::INFINITY);
    Setup {
        initial: estimate.to_vec(),
        prior_sigma: setup
            .prior_sigma
            .iter()
            .zip(sigma)
            .map(|(p, s)| p.min(factor * s))
            .collect(),
        passes: 1,
        smoother: false,
        adaptable: Vec::new(),
        ..setup.clone()
    }
}

/// What halving and doubling the noise model does to the estimates.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseSpread {
    /// Half the difference of the estimates with the noise doubled and halved (SI), the
    /// budget's "noise model" direction.
    pub direction: Direction,
    /// Per estimated coefficient, the largest move (halved or doubled) in units of its
    /// sigma from the data.
    pub moves: Vec<f64>,
}

/// Label of the noise-model direction in the uncertainty budget.
pub const NOISE_MODEL: &str = "noise model";

/// The estimates' dependence on the noise model: the pass from the converged estimate
/// repeated with the noise as calibrated (`setup.run_q`, the measurement noise of `runs`), at
/// a quarter and at four times every variance. None when a repeated pass fails.
pub fn noise_model<M: Model>(model: &M, converged: Converged<'_>) -> Option<NoiseSpread> {
    let (runs, sigma, est_names) = (converged.runs, converged.sigma, converged.est_names);
    let base = one_pass_setup(converged.setup, converged.estimate, sigma);
    let at: Vec<Option<Vec<f64>>> = [1.0, 0.25, 4.0]
        .par_iter()
        .map(|&scale| {
            let s = Setup {
                noise_scale: scale,
                ..base.clone()
            };
            estimates(model, &s, runs)
                .ok()
                .and_then(|mut p| p.pop().map(|p| p.values))
        })
        .collect();
    let [Some(mid), Some(half), Some(double)] = [&at[0], &at[1], &at[2]] else {
        return None;
    };
    let deltas: BTreeMap<String, f64> = est_names
        .iter()
        .zip(half.iter().zip(double))
        .map(|(n, (h, d))| (n.clone(), 0.5 * (d - h)))
        .collect();
    let moves = (0..est_names.len())
        .map(|j| {
            (half[j] - mid[j]).abs().max((double[j] - mid[j]).abs())
                / sigma[j].max(f64::MIN_POSITIVE)
        })
        .collect();
    Some(NoiseSpread {
        direction: Direction {
            source: NOISE_MODEL.to_string(),
            deltas,
        },
        moves,
    })
}
