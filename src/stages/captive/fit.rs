//! The fit of a model's coefficients to the forces of steady captive runs: weighted
//! nonlinear least squares by Gauss-Newton (Nocedal & Wright 2006, section 10.3) with the
//! Jacobian by automatic differentiation, each force weighted by its condition's standard
//! error when known (an averaged force history), else by its component's noise (estimated
//! from the residuals, iterated once: feasible generalised least squares), and the
//! covariance sigma^2 (J' W J)^-1 at the solution. When every value carries its own
//! standard error (averaged or harmonic force histories), the covariance is (J' W J)^-1
//! with each component's errors widened by its Birge ratio when the model misses it by
//! more than they explain beyond chance (Birge 1932; chi2 above its 95 % bound).

use super::harmonic::HarmonicMotion;
use crate::model::models::Model;
use crate::numerics::ad::{self, Scalar};
use crate::numerics::estimation::nis::variance_ratio_bound_of;
use crate::numerics::lsq::scaled_least_squares;
use nalgebra::{DMatrix, DVector};

/// One steady captive condition: the prescribed motion, the inputs and the measured forces.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    /// The model's state (velocities of the held motion; positions unused).
    pub x: Vec<f64>,
    /// The model's inputs (rudder, propeller ...).
    pub u: Vec<f64>,
    /// Measured force components, in the order of [`Model::force_quantities`].
    pub f: Vec<f64>,
    /// Their standard errors when the condition knows them (the mean of a force history);
    /// None: the fit finds each component's noise from its residuals.
    pub sigma: Option<Vec<f64>>,
    /// The run it belongs to and its file line, for messages.
    pub place: String,
    /// The motion of a harmonic (PMM) run: then `f` and `sigma` hold the Fourier parts of
    /// the forces ([`super::harmonic`]) and `x` the mean state; None for a steady condition.
    pub harmonic: Option<HarmonicMotion>,
}

impl Condition {
    /// The model's values for this condition at coefficients `c`: the steady forces, or the
    /// Fourier parts of the forces along the harmonic motion.
    pub fn predict<M: Model, T: Scalar>(&self, model: &M, c: &[T], out: &mut [T]) {
        match &self.harmonic {
            Some(motion) => super::harmonic::model_harmonics(model, motion, &self.u, c, out),
            None => {
                let x: Vec<T> = self.x.iter().map(|v| T::from(*v)).collect();
                let rest = vec![T::from(0.0); x.len()];
                model.captive_forces(&x, &rest, &self.u, c, out);
            }
        }
    }

    /// The model's values ([`Self::predict`]) at the coefficients `base` with those at `est`
    /// set to `theta`, relations applied, and their sensitivities to `theta` by automatic
    /// differentiation: (values, row-major m x p Jacobian).
    pub fn values_and_jacobian<M: Model>(
        &self,
        model: &M,
        base: &[f64],
        est: &[usize],
        theta: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        let (m, p) = (self.f.len(), theta.len());
        let mut value = vec![0.0; m];
        let mut jac = vec![0.0; m * p];
        ad::jacobian(
            theta,
            m,
            |b, out| {
                let mut cd: Vec<ad::Dual> = base.iter().map(|v| ad::constant(*v)).collect();
                for (q, &i) in est.iter().enumerate() {
                    cd[i] = b[q];
                }
                model.relations().apply(&mut cd);
                self.predict(model, &cd, out);
            },
            &mut value,
            &mut jac,
        );
        (value, jac)
    }

    /// The force component of each of its values.
    pub fn component(&self, k: usize) -> usize {
        match self.harmonic {
            Some(_) => k / super::harmonic::PER_FORCE,
            None => k,
        }
    }
}

/// The fitted coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Values of the estimated coefficients, SI.
    pub values: Vec<f64>,
    /// Their covariance.
    pub covariance: Vec<Vec<f64>>,
    /// The noise of each force component (RMS residual with the degrees of freedom).
    pub noise: Vec<f64>,
    /// Gauss-Newton iterations taken.
    pub iterations: usize,
    /// When every value has its own standard error: each component's Birge ratio
    /// sqrt(chi2 / dof) beyond its 95 % bound for the components together (else 1), by
    /// which its errors were widened; else empty.
    pub birge: Vec<f64>,
    /// Of the rows of steady tables (their noise from the residuals): each component's
    /// lack-of-fit ratio, residual variance over near-neighbour pure error
    /// ([`super::plausibility::misfit_ratios`]); above [`MISFIT_RATIO`] its errors are widened
    /// by its square root. Empty when no row is such.
    pub misfit: Vec<f64>,
}

/// Lack-of-fit ratio of a component above which the model misses the steady rows by more
/// than their noise (the ratio is near 1 for a model that fits: within 0.6 to 1.4 for white
/// noise on twelve seeds, the unit test of [`super::plausibility`]).
pub const MISFIT_RATIO: f64 = 2.0;

/// Most Gauss-Newton iterations.
const MAX_ITERATIONS: usize = 50;

/// Fits the coefficients at `est` of `base` (the full coefficient vector, fixed values set)
/// to the conditions; the model's relations are applied at every evaluation.
///
/// `signs` (one per estimated coefficient, or empty) constrain each to be >= 0 (+1), <= 0
/// (-1) or free (0): every Gauss-Newton step is then the constrained least-squares step
/// (a quadratic programme, `crate::numerics::constrained_lsq`), and a coefficient that ends on its
/// bound is held there, with no variance (the covariance is that of the others).
pub fn fit<M: Model>(
    model: &M,
    base: &[f64],
    est: &[usize],
    start: &[f64],
    signs: &[f64],
    conditions: &[Condition],
) -> Result<Fit, String> {
    let nf = model.force_quantities().len();
    let p = est.len();
    let n: usize = conditions.iter().map(|c| c.f.len()).sum();
    if n <= p {
        return Err(format!(
            "{} conditions give {n} force values for {p} coefficients: more are needed",
            conditions.len()
        ));
    }
    let problem = Problem {
        model,
        base,
        est,
        signs,
        conditions,
    };
    // first weights: each component by its measured RMS, so that N and Y count alike
    let mut scale = rms_of_components(conditions, nf);
    let mut theta = start.to_vec();
    let mut iterations = 0;
    for _ in 0..2 {
        problem.converge(&mut theta, &scale, &mut iterations)?;
        // reweight by each component's residual noise (over the conditions without their
        // own standard errors), then solve again
        problem.reweight(&theta, &mut scale);
    }
    // a coefficient that ended on its sign bound is held there: no variance
    for (t, s) in theta.iter_mut().zip(signs) {
        if *s != 0.0 && *t * s <= 0.0 {
            *t = 0.0;
        }
    }
    problem.at_solution(theta, scale, iterations)
}

/// What a fit fits: the model, the full coefficient vector `base` with the estimated ones at
/// `est`, their sign constraints, and the conditions.
struct Problem<'a, M: Model> {
    model: &'a M,
    base: &'a [f64],
    est: &'a [usize],
    signs: &'a [f64],
    conditions: &'a [Condition],
}

impl<M: Model> Problem<'_, M> {
    /// Weighted residuals and their Jacobian at `theta` ([`residuals`]).
    fn residuals(&self, theta: &[f64], scale: &[f64]) -> (DVector<f64>, DMatrix<f64>) {
        residuals(
            self.model,
            self.base,
            self.est,
            theta,
            self.conditions,
            scale,
        )
    }

    /// Gauss-Newton steps from `theta` at fixed weights until converged, counting them in
    /// `iterations` (at most [`MAX_ITERATIONS`] over all calls).
    fn converge(
        &self,
        theta: &mut [f64],
        scale: &[f64],
        iterations: &mut usize,
    ) -> Result<(), String> {
        let n: usize = self.conditions.iter().map(|c| c.f.len()).sum();
        let dof = n - self.est.len();
        while *iterations < MAX_ITERATIONS {
            *iterations += 1;
            let (r, j) = self.residuals(theta, scale);
            let (step, rss_after) = gauss_newton_step(&j, &r, theta, self.signs, dof)?;
            let mut largest: f64 = 0.0;
            for (t, d) in theta.iter_mut().zip(&step) {
                largest = largest.max(d.abs() / t.abs().max(1e-12));
                *t += d;
            }
            // converged: the step is negligible, or it cannot lower the residual further
            // (the rounding floor of a fit to noise-free forces)
            let rss = r.norm_squared();
            if largest < 1e-10 || rss - rss_after <= 1e-12 * rss {
                return Ok(());
            }
        }
        Err(format!(
            "the fit did not converge in {MAX_ITERATIONS} Gauss-Newton iterations"
        ))
    }

    /// Each component's weight `scale` set to its residual noise at `theta` over the
    /// conditions without their own standard errors (unchanged when there are none).
    fn reweight(&self, theta: &[f64], scale: &mut [f64]) {
        let (r, _) = self.residuals(theta, scale);
        let mut offset = 0;
        let mut own = Vec::new();
        for c in self.conditions {
            if c.sigma.is_none() {
                own.push(offset);
            }
            offset += c.f.len();
        }
        if own.is_empty() {
            return;
        }
        let nf = scale.len();
        let dof = (own.len() as f64 - self.est.len() as f64 / nf as f64).max(1.0);
        for (i, s) in scale.iter_mut().enumerate() {
            let rss: f64 = own.iter().map(|&k| (r[k + i] * *s).powi(2)).sum();
            *s = (rss / dof).sqrt().max(1e-12 * *s);
        }
    }

    /// The fit at its solution `theta` (a coefficient on its sign bound at 0): the
    /// covariance of the coefficients off their bounds, from the values' own standard
    /// errors widened by each component's Birge ratio when every value has them, else from
    /// the pooled residuals ([`pooled_covariance`]).
    fn at_solution(
        &self,
        theta: Vec<f64>,
        scale: Vec<f64>,
        iterations: usize,
    ) -> Result<Fit, String> {
        let p = self.est.len();
        let free: Vec<usize> = (0..p)
            .filter(|&q| {
                self.signs
                    .get(q)
                    .is_none_or(|s| *s == 0.0 || theta[q] != 0.0)
            })
            .collect();
        let (mut r, j_all) = self.residuals(&theta, &scale);
        let mut j = DMatrix::from_fn(j_all.nrows(), free.len(), |i, c| j_all[(i, free[c])]);
        if free.is_empty() {
            return Ok(Fit {
                values: theta,
                covariance: vec![vec![0.0; p]; p],
                noise: scale,
                iterations,
                birge: Vec::new(),
                misfit: Vec::new(),
            });
        }
        let singular = || "the covariance of the fit is singular".to_string();
        let (covariance, factor, birge, misfit) =
            if self.conditions.iter().all(|c| c.sigma.is_some()) {
                let (covariance, factor, birge) =
                    birge_covariance(self.conditions, scale.len(), &mut r, &mut j)
                        .ok_or_else(singular)?;
                (covariance, factor, birge, Vec::new())
            } else {
                let (covariance, factor, misfit) =
                    pooled_covariance(self.conditions, &scale, &mut r, &mut j)
                        .ok_or_else(singular)?;
                (covariance, factor, Vec::new(), misfit)
            };
        Ok(Fit {
            values: theta,
            covariance: embed(&covariance, factor, &free, p),
            noise: scale,
            iterations,
            birge,
            misfit,
        })
    }
}

/// Each force component's RMS over the conditions' values (the first weights).
fn rms_of_components(conditions: &[Condition], nf: usize) -> Vec<f64> {
    let mut scale = vec![0.0; nf];
    let mut count = vec![0usize; nf];
    for c in conditions {
        for (k, v) in c.f.iter().enumerate() {
            scale[c.component(k)] += v * v;
            count[c.component(k)] += 1;
        }
    }
    for (s, n) in scale.iter_mut().zip(&count) {
        *s = (*s / (*n).max(1) as f64).sqrt().max(f64::MIN_POSITIVE);
    }
    scale
}

/// The covariance `cov` of the free coefficients (at the indices `free` of `p`) times
/// `factor` in the full p x p matrix, 0 for the coefficients held on their bounds.
fn embed(cov: &[Vec<f64>], factor: f64, free: &[usize], p: usize) -> Vec<Vec<f64>> {
    let mut full = vec![vec![0.0; p]; p];
    for (a, &qa) in free.iter().enumerate() {
        for (b, &qb) in free.iter().enumerate() {
            full[qa][qb] = cov[a][b] * factor;
        }
    }
    full
}

/// The covariance of a fit whose every value has its own standard error: (J' W J)^-1 as
/// the scaled covariance and its factor, each component's errors widened by its own Birge
/// ratio sqrt(chi2 / dof) when beyond chance (a component the model misses, e.g. through a biased
/// fixed coefficient, then widens only what it determines), and the Birge ratios. None when
/// J' W J is singular.
fn birge_covariance(
    conditions: &[Condition],
    nf: usize,
    r: &mut DVector<f64>,
    j: &mut DMatrix<f64>,
) -> Option<(Vec<Vec<f64>>, f64, Vec<f64>)> {
    let (n, pf) = j.shape();
    let birge = component_birge(conditions, r, nf, pf, n);
    let mut row = 0;
    for c in conditions {
        for k in 0..c.f.len() {
            let f = birge[c.component(k)];
            r[row] /= f;
            for q in 0..pf {
                j[(row, q)] /= f;
            }
            row += 1;
        }
    }
    let last = scaled_least_squares(j, r, n - pf)?;
    let s2 = last.rss / (n - pf) as f64;
    Some((last.covariance, 1.0 / s2.max(f64::MIN_POSITIVE), birge))
}

/// The covariance of a fit whose noise comes from its residuals: s^2 (J' W J)^-1 as the
/// scaled covariance and its factor, with the rows of a component that shows a lack of fit
/// down-weighted ([`widen_by_misfit`]; the unwidened s^2 kept), and the misfit ratios. None
/// when J' W J is singular.
fn pooled_covariance(
    conditions: &[Condition],
    scale: &[f64],
    r: &mut DVector<f64>,
    j: &mut DMatrix<f64>,
) -> Option<(Vec<Vec<f64>>, f64, Vec<f64>)> {
    let (n, p) = j.shape();
    let last = scaled_least_squares(j, r, n - p)?;
    let misfit = widen_by_misfit(conditions, scale, p, r, j);
    if !misfit.iter().any(|f| *f > MISFIT_RATIO) {
        return Some((last.covariance, 1.0, misfit));
    }
    let widened = scaled_least_squares(j, r, n - p)?;
    let factor = last.rss / widened.rss.max(f64::MIN_POSITIVE);
    Some((widened.covariance, factor, misfit))
}

/// The lack-of-fit ratio of each component over the rows without their own standard
/// errors ([`super::plausibility::misfit_ratios`]), and those rows' weighted residuals and
/// Jacobian divided by its square root where it exceeds [`MISFIT_RATIO`]: a misfit that
/// varies smoothly over the conditions makes their errors correlated, and the sigmas from
/// the pooled residuals alone too small (the sigmas grow with the misfit, as the HEKF's
/// grow with its innovations' NIS).
fn widen_by_misfit(
    conditions: &[Condition],
    scale: &[f64],
    p: usize,
    r: &mut DVector<f64>,
    j: &mut DMatrix<f64>,
) -> Vec<f64> {
    let mut rows = Vec::new();
    let mut pooled = Vec::new();
    let mut residuals = Vec::new();
    let mut offset = 0;
    for c in conditions {
        if c.sigma.is_none() && c.harmonic.is_none() {
            pooled.push(c);
            rows.push(offset);
            residuals.push((0..c.f.len()).map(|k| r[offset + k] * scale[k]).collect());
        }
        offset += c.f.len();
    }
    if pooled.is_empty() {
        return Vec::new();
    }
    let n: usize = conditions.iter().map(|c| c.f.len()).sum();
    let ratios = super::plausibility::misfit_ratios(&pooled, &residuals, 1.0 - p as f64 / n as f64);
    for &row in &rows {
        for (k, f) in ratios.iter().enumerate() {
            if *f > MISFIT_RATIO {
                let w = f.sqrt();
                r[row + k] /= w;
                for q in 0..j.ncols() {
                    j[(row + k, q)] /= w;
                }
            }
        }
    }
    ratios
}

/// One Gauss-Newton step for the weighted residuals `r` with Jacobian `j`: the least-squares
/// step, or with sign constraints the constrained one (theta + step keeps each sign), and
/// the residual sum of squares the linearised problem expects after it.
fn gauss_newton_step(
    j: &DMatrix<f64>,
    r: &DVector<f64>,
    theta: &[f64],
    signs: &[f64],
    dof: usize,
) -> Result<(Vec<f64>, f64), String> {
    let dependent = || {
        "the conditions do not separate the estimated coefficients (their force columns are \
         dependent): add conditions that move them differently"
            .to_string()
    };
    if signs.iter().all(|s| *s == 0.0) {
        let step = scaled_least_squares(j, r, dof).ok_or_else(dependent)?;
        return Ok((step.theta, step.rss));
    }
    use crate::numerics::constrained_lsq::{solve, Constraint, FitError, Kind};
    let p = theta.len();
    let rows: Vec<Vec<f64>> = (0..j.nrows())
        .map(|i| (0..p).map(|q| j[(i, q)]).collect())
        .collect();
    let y: Vec<f64> = r.iter().copied().collect();
    // sign s of theta_q + step_q >= 0: -s step_q <= s theta_q
    let constraints: Vec<Constraint> = signs
        .iter()
        .enumerate()
        .filter(|(_, s)| **s != 0.0)
        .map(|(q, s)| {
            let mut g = vec![0.0; p];
            g[q] = -s;
            Constraint {
                g,
                kind: Kind::Le,
                h: s * theta[q],
                label: format!("sign of coefficient {q}"),
            }
        })
        .collect();
    match solve(&rows, &y, &vec![1.0; y.len()], &constraints) {
        Ok(sol) => Ok((sol.x, sol.rss)),
        Err(FitError::Underdetermined { .. }) => Err(dependent()),
        Err(e) => Err(format!("the constrained step failed: {e:?}")),
    }
}

/// Each force component's Birge ratio sqrt(chi2 / dof) over its weighted residuals when chi2
/// lies beyond its one-sided 95 % bound (Sidak-corrected for the components tested
/// together), else 1 (the degrees of freedom shared out by the
/// component's share of the values).
fn component_birge(
    conditions: &[Condition],
    r: &DVector<f64>,
    nf: usize,
    p: usize,
    n: usize,
) -> Vec<f64> {
    let mut chi2 = vec![0.0; nf];
    let mut count = vec![0usize; nf];
    let mut row = 0;
    for c in conditions {
        for k in 0..c.f.len() {
            chi2[c.component(k)] += r[row] * r[row];
            count[c.component(k)] += 1;
            row += 1;
        }
    }
    (0..nf)
        .map(|i| {
            let dof = (count[i] as f64 * (1.0 - p as f64 / n as f64)).max(1.0);
            // a lack of fit only beyond chance (the one-sided 95 % chi-square bound, for the
            // components tested together): the ratio floored at 1 alone widens half the fits
            // of a right model
            let ratio = chi2[i] / dof;
            if ratio > variance_ratio_bound_of(dof, nf) {
                ratio.sqrt()
            } else {
                1.0
            }
        })
        .collect()
}

/// Weighted residuals (measured - model) / scale and their Jacobian with respect to the
/// estimated coefficients, row per condition and value.
fn residuals<M: Model>(
    model: &M,
    base: &[f64],
    est: &[usize],
    theta: &[f64],
    conditions: &[Condition],
    scale: &[f64],
) -> (DVector<f64>, DMatrix<f64>) {
    let p = est.len();
    let n: usize = conditions.iter().map(|c| c.f.len()).sum();
    let mut r = DVector::zeros(n);
    let mut j = DMatrix::zeros(n, p);
    let mut row0 = 0;
    for c in conditions {
        let m = c.f.len();
        let (value, jac) = c.values_and_jacobian(model, base, est, theta);
        for k in 0..m {
            let s = scale[c.component(k)];
            let w = c.sigma.as_ref().map_or(s, |sig| sig[k].max(1e-12 * s));
            r[row0 + k] = (c.f[k] - value[k]) / w;
            for q in 0..p {
                j[(row0 + k, q)] = jac[k * p + q] / w;
            }
        }
        row0 += m;
    }
    (r, j)
}
