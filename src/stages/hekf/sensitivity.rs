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

use super::identify::{estimates, last_estimate, RunData, Setup};
use crate::model::coefficients::{CoefficientSet, Direction};
use crate::model::models::Model;
use crate::numerics::estimation::nis::variance_ratio_bound_of;
use nalgebra::DMatrix;
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
pub(super) fn one_pass_setup(setup: &Setup, estimate: &[f64], sigma: &[f64]) -> Setup {
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
    /// Whether the direction stays within what a right noise model moves the estimates by
    /// chance ([`chance_variances`]): then it is already in the statistical sigma and is
    /// not added to the budget. Its largest ratio, move over the chance standard deviation.
    pub within_chance: Option<f64>,
}

/// Label of the noise-model direction in the uncertainty budget.
pub const NOISE_MODEL: &str = "noise model";

/// The estimates' dependence on the noise model: the pass from the converged estimate
/// repeated with the noise as calibrated (`setup.run_q`, the measurement noise of `runs`), at
/// a quarter and at four times every variance. None when a repeated pass fails.
pub fn noise_model<M: Model>(model: &M, converged: Converged<'_>) -> Option<NoiseSpread> {
    let (runs, sigma, est_names) = (converged.runs, converged.sigma, converged.est_names);
    let base = one_pass_setup(converged.setup, converged.estimate, sigma);
    let at: Vec<Option<(Vec<f64>, Vec<f64>)>> = [1.0, 0.25, 4.0]
        .par_iter()
        .map(|&scale| {
            let s = Setup {
                noise_scale: scale,
                ..base.clone()
            };
            last_estimate(model, &s, runs)
                .ok()
                .map(|(p, cov)| (p.values, cov))
        })
        .collect();
    let [Some((mid, posterior)), Some((half, _)), Some((double, _))] = [&at[0], &at[1], &at[2]]
    else {
        return None;
    };
    let nb = est_names.len();
    let prior = base.prior_covariance(&vec![1.0; nb]);
    let chance = chance_variances(
        &DMatrix::from_row_slice(nb, nb, &prior),
        &DMatrix::from_row_slice(nb, nb, posterior),
    );
    // a move beyond chance in any coefficient (the one-sided 95 % bound of one chi-square
    // degree of freedom, for the coefficients tested together)
    let bound = variance_ratio_bound_of(1.0, nb);
    let within_chance = chance.and_then(|v| {
        let worst = (0..nb)
            .map(|j| 0.5 * (double[j] - half[j]).abs() / v[j].sqrt())
            .fold(0.0, f64::max);
        (worst * worst <= bound).then_some(worst)
    });
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
        within_chance,
    })
}

/// The covariance of the noise-model direction that a RIGHT noise model gives by chance,
/// per coefficient (its diagonal, SI): the passes from the estimate with the noise variances
/// at 1/4 and 4 weigh the same data against the same prior differently, so their estimates
/// differ by chance, and that difference is part of the statistical sigma already.
///
/// Linear-Gaussian reading (prior information A about the estimate, data information B with
/// every noise variance scaled by s, posterior covariance C = (A + B)^-1): the pass with
/// scale s moves the estimate by (A + B/s)^-1 (B/s) (x_d - x) where x_d is the data's own
/// estimate, and u = B (x_d - x) has covariance H = A (A + B)^-1 B = A - A C A (its prior
/// and data parts independent). Half the difference of s = 1/4 and s = 4 is K u with
/// K = (4 (A + 4B)^-1 - (A + B/4)^-1 / 4) / 2, of covariance K H K'. Computed in units of
/// each coefficient's posterior sigma. None when a matrix is not invertible.
pub fn chance_variances(prior: &DMatrix<f64>, posterior: &DMatrix<f64>) -> Option<Vec<f64>> {
    let n = posterior.nrows();
    let d: Vec<f64> = (0..n).map(|i| posterior[(i, i)].sqrt()).collect();
    if d.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
        return None;
    }
    let unit = |m: &DMatrix<f64>| DMatrix::from_fn(n, n, |i, j| m[(i, j)] / (d[i] * d[j]));
    let c = unit(posterior);
    let a = unit(prior).cholesky()?.inverse();
    let c_inv = c.clone().cholesky()?.inverse();
    // A + 4B = 4 C^-1 - 3A and A + B/4 = C^-1/4 + 3A/4, with B = C^-1 - A
    let m4 = (&c_inv * 4.0 - &a * 3.0).try_inverse()?;
    let m14 = (&c_inv * 0.25 + &a * 0.75).try_inverse()?;
    let k = (m4 * 4.0 - m14 * 0.25) * 0.5;
    let h = &a - &a * &c * &a;
    let e = &k * h * k.transpose();
    let v: Vec<f64> = (0..n).map(|i| e[(i, i)].max(0.0) * d[i] * d[i]).collect();
    v.iter().all(|x| x.is_finite()).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, StandardNormal};

    /// A draw of N(0, cov) through the Cholesky factor.
    fn draw(rng: &mut StdRng, cov: &DMatrix<f64>) -> nalgebra::DVector<f64> {
        let l = cov.clone().cholesky().unwrap().l();
        let z = nalgebra::DVector::from_fn(cov.nrows(), |_, _| StandardNormal.sample(&mut *rng));
        l * z
    }

    /// The chance covariance against a Monte Carlo of the linear-Gaussian problem it reads,
    /// written from the equations: a correlated prior m, data x_d of information B, the
    /// estimate x = (A + B)^-1 (A m + B x_d), and a pass with every noise variance scaled by
    /// s started from x: (A + B/s)^-1 (A x + B/s x_d).
    #[test]
    fn chance_variances_match_a_monte_carlo() {
        let prior = DMatrix::from_row_slice(2, 2, &[4.0, 1.8, 1.8, 1.0]);
        let data_info = DMatrix::from_row_slice(2, 2, &[0.5, -0.2, -0.2, 3.0]);
        let a = prior.clone().try_inverse().unwrap();
        let posterior = (&a + &data_info).try_inverse().unwrap();
        let data_cov = data_info.clone().try_inverse().unwrap();
        let chance = chance_variances(&prior, &posterior).unwrap();
        let mut rng = StdRng::seed_from_u64(11);
        let n = 40_000;
        let mut sum = [0.0; 2];
        for _ in 0..n {
            let m = draw(&mut rng, &prior);
            let xd = draw(&mut rng, &data_cov);
            let x = &posterior * (&a * &m + &data_info * &xd);
            let pass = |s: f64| {
                (&a + &data_info / s).try_inverse().unwrap() * (&a * &x + &data_info / s * &xd)
            };
            let half = (pass(4.0) - pass(0.25)) * 0.5;
            for (k, t) in sum.iter_mut().enumerate() {
                *t += half[k] * half[k];
            }
        }
        for k in 0..2 {
            let mc = sum[k] / n as f64;
            // 40,000 draws: the variance within 1.5 % (its standard error 0.7 %)
            assert!(
                (mc / chance[k] - 1.0).abs() < 0.015,
                "coefficient {k}: Monte Carlo {mc}, formula {}",
                chance[k]
            );
        }
        // no prior information: a noise scale changes nothing by chance
        let flat = DMatrix::from_row_slice(2, 2, &[1e12, 0.0, 0.0, 1e12]);
        let only_data = data_cov.clone();
        let v = chance_variances(&flat, &only_data).unwrap();
        assert!(v
            .iter()
            .zip([data_cov[(0, 0)], data_cov[(1, 1)]])
            .all(|(v, c)| *v < 1e-9 * c));
    }
}
