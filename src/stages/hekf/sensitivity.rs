//! How the HEKF estimates depend on the coefficients it holds fixed.
//!
//! The filter's covariance is conditional on the fixed coefficients being exact. They are not:
//! X_udot from a surge run, the polar coefficients, all carry uncertainty, as independent
//! directions (see [`crate::coefficients::Direction`]). For each direction that reaches a
//! fixed coefficient of the model, the identification is repeated with the fixed values moved
//! by plus and minus one sigma along it (one pass from the converged estimate), and the change
//! of the estimates, (beta(+) - beta(-)) / 2, is that direction's share in them: linear error
//! propagation by central differences ("consider" analysis, Bierman 1977, ch. 7). The total
//! covariance is the filter's plus the sum of these outer products. The repeated passes keep
//! no traces, so that running them side by side costs no memory per sample.

use super::identify::{estimates, RunData, Setup};
use crate::coefficients::{CoefficientSet, Direction};
use crate::models::Model;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// The estimates' change along each upstream direction that reaches a fixed coefficient, as
/// directions with the upstream sources' labels. Directions whose repeated identification
/// fails are reported by label in the second list.
pub fn upstream<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    estimate: &[f64],
    sigma: &[f64],
    est_names: &[String],
    known: &CoefficientSet,
) -> (Vec<Direction>, Vec<String>) {
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
    // one pass from the converged estimate, with the prior later passes use
    let factor = setup.repeat_prior_factor.unwrap_or(f64::INFINITY);
    let base_setup = Setup {
        initial: estimate.to_vec(),
        prior_sigma: setup
            .prior_sigma
            .iter()
            .zip(sigma)
            .map(|(p, s)| p.min(factor * s))
            .collect(),
        passes: 1,
        smoother: false,
        ..setup.clone()
    };
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
