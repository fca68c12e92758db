//! `--verify`: the top candidates checked by replicas. Each replica draws the earlier runs'
//! error as a start off the current estimate by the prior covariance (as if the earlier runs
//! were repeated), simulates the candidate with the current model and adds its noise (a
//! manoeuvre also the process noise the filter assumes), and identifies again with the
//! candidate added: a captive run by the iterated Gauss-Newton (Kalman-form) update of the
//! prior with its forces (Bell & Cathey 1993), a manoeuvre by the hybrid EKF along it. The
//! achieved sigma is the spread of the replicas' estimates about the current one, which the
//! predicted sigma should match when the linearisation holds (a parametric bootstrap, Efron &
//! Tibshirani 1993, ch. 6.5).

use super::{captive, manoeuvre, Context, Plan, Settings};
use crate::base::error::{Error, Result};
use crate::model::models::Model;
use nalgebra::{DMatrix, DVector};
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Gauss-Newton iterations of a captive replica's update.
const ITERATIONS: usize = 4;

/// One verified candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verified {
    /// The candidate's name.
    pub name: String,
    /// Replicas identified.
    pub replicas: usize,
    /// Predicted sigma of each target (the plan's targets order).
    pub predicted: Vec<f64>,
    /// Achieved sigma: the replicas' RMS deviation from the current estimate.
    pub achieved: Vec<f64>,
    /// achieved / predicted.
    pub ratio: Vec<f64>,
}

/// Verifies the top `settings.verify` candidates of `plan` into its `verification`; a
/// candidate whose replicas fail (a filter diverged) joins `skipped` with the reason.
/// `progress` hears of every replica identified.
pub(crate) fn verify<M: Model>(
    ctx: &Context<M>,
    plan: &mut Plan,
    settings: &Settings,
    progress: super::VerifyProgress,
) {
    let replicas = settings.replicas.max(2);
    let count = settings.verify.min(plan.ranked.len());
    let outcomes: Vec<(String, Result<Verified>)> = plan
        .ranked
        .iter()
        .take(count)
        .enumerate()
        .map(|(k, row)| {
            let name = row.candidate.name.clone();
            let done = AtomicUsize::new(0);
            let tick = || {
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                progress(k + 1, count, n, replicas);
            };
            (
                name,
                verify_one(ctx, row, (k, replicas), settings.seed, &tick),
            )
        })
        .collect();
    for (name, outcome) in outcomes {
        match outcome {
            Ok(v) => plan.verification.push(v),
            Err(e) => plan.skipped.push(super::Skipped {
                name,
                reason: format!("verification failed: {e}"),
            }),
        }
    }
}

/// The `replicas` replicas of the `k`-th candidate (`row`) identified, and their spread;
/// `tick` after each.
fn verify_one<M: Model>(
    ctx: &Context<M>,
    row: &super::Row,
    (k, replicas): (usize, usize),
    seed: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<Verified> {
    let seed = seed.wrapping_add((k * replicas) as u64);
    let estimates: Vec<Vec<f64>> = (0..replicas)
        .into_par_iter()
        .map(|r| {
            let e = replica(ctx, &row.candidate, seed.wrapping_add(r as u64));
            tick();
            e
        })
        .collect::<Result<_>>()?;
    let current = ctx.prior.values();
    let achieved: Vec<f64> = ctx
        .targets
        .iter()
        .map(|&i| {
            let ss: f64 = estimates.iter().map(|e| (e[i] - current[i]).powi(2)).sum();
            (ss / replicas as f64).sqrt()
        })
        .collect();
    Ok(Verified {
        name: row.candidate.name.clone(),
        replicas,
        ratio: achieved
            .iter()
            .zip(&row.sigma_after)
            .map(|(a, p)| a / p)
            .collect(),
        predicted: row.sigma_after.clone(),
        achieved,
    })
}

/// A draw from N(0, cov) by the symmetric square root (the covariance may be singular).
fn draw(cov: &DMatrix<f64>, rng: &mut StdRng) -> DVector<f64> {
    let eig = cov.clone().symmetric_eigen();
    let z = DVector::from_fn(cov.nrows(), |_, _| -> f64 { StandardNormal.sample(rng) });
    let scaled = DVector::from_fn(cov.nrows(), |i, _| {
        eig.eigenvalues[i].max(0.0).sqrt() * z[i]
    });
    &eig.eigenvectors * scaled
}

/// One replica identified: the parameters' estimate.
fn replica<M: Model>(ctx: &Context<M>, c: &super::Candidate, seed: u64) -> Result<Vec<f64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let truth = ctx.prior.values();
    let start: Vec<f64> = (DVector::from_vec(truth.clone()) + draw(&ctx.prior.cov, &mut rng))
        .iter()
        .copied()
        .collect();
    if c.kind.is_captive() {
        let cond = captive::condition(ctx.model, &ctx.prior, &ctx.op, c, ctx.scale)?;
        let sigma = cond.sigma.clone().unwrap_or_default();
        let y: Vec<f64> = cond
            .f
            .iter()
            .zip(&sigma)
            .map(|(f, s)| f + s * normal(&mut rng))
            .collect();
        return captive_update(ctx, &cond, &start, &y, &sigma);
    }
    let q = ctx.op.q.clone();
    let mut forcing = |x: &mut [f64], dt: f64| {
        for (xi, qi) in x.iter_mut().zip(&q) {
            *xi += (qi * dt).sqrt() * normal(&mut rng);
        }
    };
    let run = manoeuvre::simulate_run(ctx.model, &ctx.prior, &ctx.op, c, &mut forcing)?;
    let mut rng = StdRng::seed_from_u64(seed ^ 0x9e37_79b9_7f4a_7c15);
    let ys: Vec<Vec<f64>> = manoeuvre::outputs(ctx.model, &ctx.prior, &run)
        .into_iter()
        .map(|y| {
            y.iter()
                .zip(&run.sigma)
                .map(|(v, s)| v + s * normal(&mut rng))
                .collect()
        })
        .collect();
    manoeuvre::filter(ctx.model, &ctx.prior, &ctx.op, &run, &start, &ys).map(|(t, _)| t)
}

/// The iterated update of the prior (mean `start`, the prior covariance) with a captive
/// run's values `y`: theta <- start + K (y - h(theta) - J (start - theta)),
/// K = P J' (J P J' + R)^-1, J at theta (Bell & Cathey 1993, eq. 8).
fn captive_update<M: Model>(
    ctx: &Context<M>,
    cond: &crate::stages::captive::fit::Condition,
    start: &[f64],
    y: &[f64],
    sigma: &[f64],
) -> Result<Vec<f64>> {
    let p0 = DVector::from_column_slice(start);
    let mut theta = p0.clone();
    let r = DMatrix::from_diagonal(&DVector::from_iterator(
        sigma.len(),
        sigma.iter().map(|s| s * s),
    ));
    for _ in 0..ITERATIONS {
        let (h, mut j) =
            captive::values_and_jacobian(ctx.model, &ctx.prior, cond, theta.as_slice());
        captive::drop_unused(&mut j, &ctx.unused);
        let pjt = &ctx.prior.cov * j.transpose();
        let s = &j * &pjt + &r;
        let innovation = DVector::from_column_slice(y) - DVector::from_vec(h) - &j * (&p0 - &theta);
        let step = s.lu().solve(&innovation).ok_or_else(|| {
            Error::numerical("plan", format!("verify '{}': singular update", cond.place))
        })?;
        theta = &p0 + pjt * step;
    }
    Ok(theta.iter().copied().collect())
}

/// A standard normal draw.
fn normal(rng: &mut StdRng) -> f64 {
    StandardNormal.sample(rng)
}
