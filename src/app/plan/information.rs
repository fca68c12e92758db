//! The linear-Gaussian update a planned run brings (Bayesian design of experiments;
//! Chaloner & Verdinelli 1995, section 2.1): with J the sensitivities of the run's
//! measurements to the coefficients at the current estimate and R their noise covariance, the
//! run's Fisher information is F = J' R^-1 J (Walter & Pronzato 1997, eq. 6.6) and the
//! posterior covariance P+ = (P^-1 + F)^-1, computed as (I + P F)^-1 P so that a singular
//! prior P is no obstacle. The scores of a candidate on the target coefficients T: the
//! D_s-optimal information gain 0.5 ln(det P_TT / det P+_TT) (Atkinson, Donev & Tobias 2007,
//! section 10.3) and the A-optimal share of the targets' variance removed, each target's
//! variance relative to its prior one (so that coefficients of different units count alike).

use nalgebra::DMatrix;

/// Fisher information J' R^-1 J of measurements with sensitivities `j` (m x p, rows the
/// measurements) and independent noise of standard deviations `sigma` (length m).
pub fn fisher(j: &DMatrix<f64>, sigma: &[f64]) -> DMatrix<f64> {
    let mut w = j.clone();
    for (r, s) in sigma.iter().enumerate() {
        let inv = 1.0 / s;
        w.row_mut(r).iter_mut().for_each(|v| *v *= inv);
    }
    w.transpose() * w
}

/// The posterior covariance (P^-1 + F)^-1 = (I + P F)^-1 P, symmetrised; None when I + P F
/// is singular (not for a positive semi-definite P and F).
pub fn posterior(prior: &DMatrix<f64>, info: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let p = prior.nrows();
    let a = DMatrix::identity(p, p) + prior * info;
    let post = a.lu().solve(prior)?;
    Some(0.5 * (&post + post.transpose()))
}

/// How a candidate's posterior compares with the prior on the targets `t` (indices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scores {
    /// D_s-optimal gain, nats: 0.5 ln(det P_TT / det P+_TT).
    pub d: f64,
    /// A-optimal: 1 - mean over targets of P+_ii / P_ii.
    pub a: f64,
}

/// The scores of posterior `post` against `prior` on the targets `t`.
pub fn scores(prior: &DMatrix<f64>, post: &DMatrix<f64>, t: &[usize]) -> Scores {
    let block = |m: &DMatrix<f64>| DMatrix::from_fn(t.len(), t.len(), |i, j| m[(t[i], t[j])]);
    let ln_det = |m: DMatrix<f64>| -> f64 {
        // relative to the prior's diagonal, so that units cancel and the logs stay finite
        let d: Vec<f64> = t.iter().map(|&i| prior[(i, i)].sqrt()).collect();
        let scaled = DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] / (d[i] * d[j]));
        match scaled.cholesky() {
            Some(c) => 2.0 * c.l().diagonal().iter().map(|v| v.ln()).sum::<f64>(),
            None => f64::NEG_INFINITY,
        }
    };
    let d = 0.5 * (ln_det(block(prior)) - ln_det(block(post)));
    let a =
        1.0 - t.iter().map(|&i| post[(i, i)] / prior[(i, i)]).sum::<f64>() / t.len().max(1) as f64;
    Scores { d, a }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear-in-parameters captive force model Y = Yv v + Yvd v_dot measured at points
    /// (v_k, vdot_k) with noise sigma: the Fisher information is known in closed form,
    /// F = [[sum v^2, sum v vdot], [sum v vdot, sum vdot^2]] / sigma^2, and with a diagonal
    /// prior diag(a, b) the posterior is the inverse of diag(1/a, 1/b) + F, written out here
    /// as the 2 x 2 inverse [[d, -b], [-c, a]] / det.
    #[test]
    fn fisher_information_of_a_linear_force_model_is_the_closed_form() {
        let pts = [(0.1, 0.0), (0.2, 0.3), (-0.1, 0.5), (0.0, -0.4)];
        let sigma = 0.05;
        let j = DMatrix::from_fn(4, 2, |r, c| if c == 0 { pts[r].0 } else { pts[r].1 });
        let f = fisher(&j, &[sigma; 4]);
        let svv: f64 = pts.iter().map(|p| p.0 * p.0).sum();
        let svd: f64 = pts.iter().map(|p| p.0 * p.1).sum();
        let sdd: f64 = pts.iter().map(|p| p.1 * p.1).sum();
        let s2 = sigma * sigma;
        for (got, want) in [
            (f[(0, 0)], svv / s2),
            (f[(0, 1)], svd / s2),
            (f[(1, 0)], svd / s2),
            (f[(1, 1)], sdd / s2),
        ] {
            assert!(
                (got - want).abs() < 1e-9 * want.abs().max(1.0),
                "{got} {want}"
            );
        }
        let (pa, pb) = (4.0, 0.25);
        let prior = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![pa, pb]));
        let post = posterior(&prior, &f).unwrap();
        let (a, b, c, d) = (1.0 / pa + svv / s2, svd / s2, svd / s2, 1.0 / pb + sdd / s2);
        let det = a * d - b * c;
        for (got, want) in [
            (post[(0, 0)], d / det),
            (post[(0, 1)], -b / det),
            (post[(1, 1)], a / det),
        ] {
            assert!(
                (got - want).abs() < 1e-12 + 1e-9 * want.abs(),
                "{got} {want}"
            );
        }
        // D score of the first coefficient alone: 0.5 ln(prior var / posterior var)
        let s = scores(&prior, &post, &[0]);
        assert!((s.d - 0.5 * (pa / (d / det)).ln()).abs() < 1e-9);
        assert!((s.a - (1.0 - (d / det) / pa)).abs() < 1e-12);
    }

    #[test]
    fn a_singular_prior_is_no_obstacle() {
        let prior = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let f = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]);
        let post = posterior(&prior, &f).unwrap();
        // measuring the first of two perfectly correlated coefficients with unit
        // information halves both variances
        assert!((post[(0, 0)] - 0.5).abs() < 1e-12 && (post[(1, 1)] - 0.5).abs() < 1e-12);
    }
}
