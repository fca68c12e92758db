//! Weighted linear least squares under linear equality and inequality constraints, solved as
//! a quadratic programme with clarabel, then polished on the active set.
//!
//! minimise ||W^1/2 (A x - y)||^2  subject to  g_i x = h_i (equalities), g_j x <= h_j
//! (inequalities). With P = A' W A and q = -A' W y this is the QP min 1/2 x'Px + q'x
//! (Goldfarb & Idnani 1983; Boyd & Vandenberghe 2004, section 4.4). clarabel (Goulart & Chen
//! 2024) takes constraints as `G x + s = h` with s in a cone: a zero cone for the equalities,
//! the non-negative orthant for the inequalities, listed in that row order.
//!
//! After the interior-point solve the active set is read from complementarity (an inequality
//! is active when its multiplier exceeds its slack) and the equality-constrained problem on
//! that set is solved exactly by the null-space method (Lawson & Hanson 1974, ch. 20;
//! Nocedal & Wright 2006, section 16.2). The covariance of the estimate is that of the
//! equality-constrained estimator: with N a basis of the null space of the active
//! constraints, Cov(x) = s^2 N (N' A'WA N)^-1 N', s^2 = RSS / (n - dim N), so constrained
//! directions carry no variance and only the free directions are counted as fitted.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Equality or inequality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// g x = h.
    Eq,
    /// g x <= h.
    Le,
}

/// One linear constraint on the parameter vector.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// Row g.
    pub g: Vec<f64>,
    /// Equality or inequality.
    pub kind: Kind,
    /// Right-hand side h.
    pub h: f64,
    /// How a user would name it, e.g. `a >= 0 (polar.drag.a_nonnegative)`.
    pub label: String,
}

/// What went wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum FitError {
    /// No parameter vector satisfies every constraint.
    Infeasible,
    /// The data do not determine the free parameters (too few distinct points).
    Underdetermined {
        /// Number of free parameters.
        free: usize,
        /// Rank of the data in the free directions.
        rank: usize,
    },
    /// The solver stopped without a solution.
    Solver(String),
}

/// The constrained least-squares estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Parameter estimate.
    pub x: Vec<f64>,
    /// Covariance of the estimate (None when there are no residual degrees of freedom).
    pub covariance: Option<Vec<Vec<f64>>>,
    /// Indices of the constraints active at the solution (every equality and the binding
    /// inequalities).
    pub active: Vec<usize>,
    /// Weighted residual sum of squares.
    pub rss: f64,
    /// Residual degrees of freedom: points with positive weight minus free parameters.
    pub dof: usize,
    /// Residuals y - A x, one per point.
    pub residuals: Vec<f64>,
    /// Weighted coefficient of determination about the weighted mean (None when y is constant).
    pub r_squared: Option<f64>,
}

/// Solves min ||W^1/2 (A x - y)||^2 s.t. `constraints`, with `a` given row by row and `w` the
/// relative weights (>= 0).
pub fn solve(
    a: &[Vec<f64>],
    y: &[f64],
    w: &[f64],
    constraints: &[Constraint],
) -> Result<Solution, FitError> {
    let n = a.len();
    let p = a.first().map_or(0, Vec::len);
    assert!(y.len() == n && w.len() == n, "one y and one weight per row");
    assert!(constraints.iter().all(|c| c.g.len() == p));

    // Column scaling (x = D xs) so that alpha^2, alpha and 1 columns are comparable.
    let mut scale = vec![1.0; p];
    for (j, s) in scale.iter_mut().enumerate() {
        let norm = a
            .iter()
            .zip(w)
            .map(|(r, wi)| wi * r[j] * r[j])
            .sum::<f64>()
            .sqrt();
        if norm > 0.0 {
            *s = 1.0 / norm;
        }
    }
    let sqrt_w: Vec<f64> = w.iter().map(|v| v.max(0.0).sqrt()).collect();
    let b = DMatrix::from_fn(n, p, |i, j| sqrt_w[i] * a[i][j] * scale[j]);
    let rhs = DVector::from_fn(n, |i, _| sqrt_w[i] * y[i]);
    let scaled: Vec<Constraint> = constraints
        .iter()
        .map(|c| Constraint {
            g: c.g.iter().zip(&scale).map(|(g, s)| g * s).collect(),
            ..c.clone()
        })
        .collect();

    let (xs_ipm, active) = interior_point(&b, &rhs, &scaled)?;
    let (x_eq, basis) = equality_solve(&b, &rhs, &scaled, &active)?;
    // The polished point is the exact optimum when the active set is right; keep the
    // interior-point answer in the (degenerate) case where it is not.
    let mut xs = if feasible(&x_eq, &scaled) {
        x_eq
    } else {
        xs_ipm
    };
    // No negative zeros for parameters fixed at zero.
    xs.iter_mut().filter(|v| **v == 0.0).for_each(|v| *v = 0.0);

    // Back to the original parameters.
    let x: Vec<f64> = xs.iter().zip(&scale).map(|(v, s)| v * s).collect();
    let residuals: Vec<f64> = a
        .iter()
        .zip(y)
        .map(|(row, yi)| yi - row.iter().zip(&x).map(|(r, v)| r * v).sum::<f64>())
        .collect();
    let rss: f64 = residuals.iter().zip(w).map(|(r, wi)| wi * r * r).sum();
    let used = w.iter().filter(|v| **v > 0.0).count();
    let free = basis.ncols();
    let dof = used.saturating_sub(free);
    let covariance = (dof > 0).then(|| {
        let s2 = rss / dof as f64;
        let bn = &b * &basis;
        let m = bn.transpose() * &bn;
        let m_inv = m
            .clone()
            .pseudo_inverse(1e-14 * m.norm().max(f64::MIN_POSITIVE))
            .unwrap_or_else(|_| DMatrix::zeros(free, free));
        let cov_s = &basis * m_inv * basis.transpose() * s2;
        (0..p)
            .map(|i| {
                (0..p)
                    .map(|j| cov_s[(i, j)] * scale[i] * scale[j])
                    .collect()
            })
            .collect()
    });
    let wsum: f64 = w.iter().sum();
    let r_squared = (wsum > 0.0)
        .then(|| {
            let mean = y.iter().zip(w).map(|(v, wi)| v * wi).sum::<f64>() / wsum;
            let tss: f64 = y.iter().zip(w).map(|(v, wi)| wi * (v - mean).powi(2)).sum();
            (tss > 0.0).then(|| 1.0 - rss / tss)
        })
        .flatten();
    Ok(Solution {
        x,
        covariance,
        active,
        rss,
        dof,
        residuals,
        r_squared,
    })
}

/// The QP solve with clarabel; returns the scaled solution and the active constraints.
fn interior_point(
    b: &DMatrix<f64>,
    rhs: &DVector<f64>,
    constraints: &[Constraint],
) -> Result<(DVector<f64>, Vec<usize>), FitError> {
    let p = b.ncols();
    let btb = b.transpose() * b;
    let btr = b.transpose() * rhs;
    // P upper triangular (clarabel reads the upper triangle only; never pass the lower).
    let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..p {
        for i in 0..=j {
            if btb[(i, j)] != 0.0 {
                pi.push(i);
                pj.push(j);
                pv.push(btb[(i, j)]);
            }
        }
    }
    let pm = CscMatrix::new_from_triplets(p, p, pi, pj, pv);
    let q: Vec<f64> = btr.iter().map(|v| -v).collect();

    // Rows: equalities first (zero cone), then inequalities (non-negative cone); the cone
    // list must follow this order.
    let order: Vec<usize> = (0..constraints.len())
        .filter(|&i| constraints[i].kind == Kind::Eq)
        .chain((0..constraints.len()).filter(|&i| constraints[i].kind == Kind::Le))
        .collect();
    let n_eq = order
        .iter()
        .filter(|&&i| constraints[i].kind == Kind::Eq)
        .count();
    let n_le = order.len() - n_eq;
    let (mut gi, mut gj, mut gv) = (Vec::new(), Vec::new(), Vec::new());
    let mut h = Vec::with_capacity(order.len());
    for (row, &c) in order.iter().enumerate() {
        for (j, &g) in constraints[c].g.iter().enumerate() {
            if g != 0.0 {
                gi.push(row);
                gj.push(j);
                gv.push(g);
            }
        }
        h.push(constraints[c].h);
    }
    let gm = CscMatrix::new_from_triplets(order.len(), p, gi, gj, gv);
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    if n_eq > 0 {
        cones.push(ZeroConeT(n_eq));
    }
    if n_le > 0 {
        cones.push(NonnegativeConeT(n_le));
    }
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-12)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .max_iter(200)
        .build()
        .map_err(|e| FitError::Solver(format!("{e:?}")))?;
    let mut solver = DefaultSolver::new(&pm, &q, &gm, &h, &cones, settings)
        .map_err(|e| FitError::Solver(format!("{e:?}")))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            return Err(FitError::Infeasible)
        }
        SolverStatus::InsufficientProgress | SolverStatus::MaxIterations
            if primal_feasible(&sol.x, constraints, 1e-7) =>
        {
            // Tight tolerances can stall on an exact fit; the active-set polish finishes it.
        }
        other => return Err(FitError::Solver(format!("{other:?}"))),
    }
    let mut active = Vec::new();
    for (row, &c) in order.iter().enumerate() {
        match constraints[c].kind {
            Kind::Eq => active.push(c),
            Kind::Le if sol.z[row] > sol.s[row] => active.push(c),
            Kind::Le => {}
        }
    }
    active.sort_unstable();
    Ok((DVector::from_vec(sol.x.clone()), active))
}

fn primal_feasible(x: &[f64], constraints: &[Constraint], tol: f64) -> bool {
    constraints.iter().all(|c| {
        let gx: f64 = c.g.iter().zip(x).map(|(g, v)| g * v).sum();
        let scale = 1.0 + c.h.abs();
        match c.kind {
            Kind::Eq => (gx - c.h).abs() <= tol * scale,
            Kind::Le => gx <= c.h + tol * scale,
        }
    })
}

fn feasible(x: &DVector<f64>, constraints: &[Constraint]) -> bool {
    primal_feasible(x.as_slice(), constraints, 1e-9)
}

/// Least squares with the `active` constraints as equalities (null-space method). Returns the
/// solution and a basis of the free directions.
fn equality_solve(
    b: &DMatrix<f64>,
    rhs: &DVector<f64>,
    constraints: &[Constraint],
    active: &[usize],
) -> Result<(DVector<f64>, DMatrix<f64>), FitError> {
    let p = b.ncols();
    let (x_p, basis) = if active.is_empty() {
        (DVector::zeros(p), DMatrix::identity(p, p))
    } else {
        let g = DMatrix::from_fn(active.len(), p, |i, j| constraints[active[i]].g[j]);
        let h = DVector::from_fn(active.len(), |i, _| constraints[active[i]].h);
        let gtg = g.transpose() * &g;
        let eig = SymmetricEigen::new(gtg);
        let top = eig.eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let null: Vec<usize> = (0..p)
            .filter(|&k| eig.eigenvalues[k].abs() <= 1e-12 * top.max(1.0))
            .collect();
        let basis = DMatrix::from_fn(p, null.len(), |i, k| eig.eigenvectors[(i, null[k])]);
        let pinv = g
            .clone()
            .pseudo_inverse(1e-12 * top.sqrt().max(1.0))
            .map_err(|e| FitError::Solver(e.to_string()))?;
        (pinv * h, basis)
    };
    let free = basis.ncols();
    if free == 0 {
        return Ok((x_p, basis));
    }
    let bn = b * &basis;
    let r = rhs - b * &x_p;
    let svd = bn.clone().svd(true, true);
    let smax = svd.singular_values.iter().fold(0.0f64, |m, v| m.max(*v));
    let tol = 1e-10 * smax.max(f64::MIN_POSITIVE);
    let rank = svd.singular_values.iter().filter(|s| **s > tol).count();
    if rank < free {
        return Err(FitError::Underdetermined { free, rank });
    }
    let z = svd
        .solve(&r, tol)
        .map_err(|e| FitError::Solver(e.to_string()))?;
    Ok((x_p + &basis * z, basis))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_data() -> (Vec<Vec<f64>>, Vec<f64>) {
        // y = 2 + 3 x, exactly.
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        (
            xs.iter().map(|x| vec![1.0, *x]).collect(),
            xs.iter().map(|x| 2.0 + 3.0 * x).collect(),
        )
    }

    fn c(g: &[f64], kind: Kind, h: f64) -> Constraint {
        Constraint {
            g: g.to_vec(),
            kind,
            h,
            label: String::new(),
        }
    }

    #[test]
    fn unconstrained_fit_is_ordinary_least_squares() {
        let (a, y) = line_data();
        let s = solve(&a, &y, &[1.0; 5], &[]).unwrap();
        assert!((s.x[0] - 2.0).abs() < 1e-12 && (s.x[1] - 3.0).abs() < 1e-12);
        assert!(s.active.is_empty());
        assert!(s.rss < 1e-20);
    }

    #[test]
    fn binding_inequality_gives_the_constrained_optimum() {
        // y = 2 + 3x with the intercept forced <= 1: the optimum has intercept exactly 1 and
        // the slope of the regression of (y - 1) on x through the origin: sum x(y-1)/sum x^2.
        let (a, y) = line_data();
        let s = solve(&a, &y, &[1.0; 5], &[c(&[1.0, 0.0], Kind::Le, 1.0)]).unwrap();
        let sxy: f64 = (0..5).map(|i| i as f64 * (y[i] - 1.0)).sum();
        let sxx: f64 = (0..5).map(|i| (i * i) as f64).sum();
        assert_eq!(s.active, vec![0]);
        assert!((s.x[0] - 1.0).abs() < 1e-12, "{:?}", s.x);
        assert!((s.x[1] - sxy / sxx).abs() < 1e-12, "{:?}", s.x);
        // The fixed direction has no variance; the slope's is s^2 / sum x^2 with n - 1 dof.
        let cov = s.covariance.unwrap();
        assert!(cov[0][0].abs() < 1e-20 && cov[0][1].abs() < 1e-20);
        assert_eq!(s.dof, 4);
        assert!((cov[1][1] - s.rss / 4.0 / sxx).abs() < 1e-12 * cov[1][1]);
    }

    #[test]
    fn slack_inequality_is_not_active() {
        let (a, y) = line_data();
        let s = solve(&a, &y, &[1.0; 5], &[c(&[-1.0, 0.0], Kind::Le, 0.0)]).unwrap();
        assert!(s.active.is_empty());
        assert!((s.x[0] - 2.0).abs() < 1e-10);
    }

    #[test]
    fn contradictory_constraints_are_infeasible() {
        let (a, y) = line_data();
        let cons = [
            c(&[1.0, 1.0], Kind::Le, -1.0),
            c(&[-1.0, 0.0], Kind::Le, 0.0),
            c(&[0.0, -1.0], Kind::Le, 0.0),
        ];
        assert_eq!(solve(&a, &y, &[1.0; 5], &cons), Err(FitError::Infeasible));
    }

    #[test]
    fn too_few_points_are_underdetermined() {
        let a = vec![vec![1.0, 1.0, 1.0]];
        let e = solve(&a, &[1.0], &[1.0], &[]).unwrap_err();
        assert_eq!(e, FitError::Underdetermined { free: 3, rank: 1 });
    }

    #[test]
    fn weights_shift_the_fit_towards_heavy_points() {
        // Two inconsistent observations of a constant: the weighted mean is the answer.
        let a = vec![vec![1.0], vec![1.0]];
        let s = solve(&a, &[0.0, 1.0], &[1.0, 3.0], &[]).unwrap();
        assert!((s.x[0] - 0.75).abs() < 1e-12);
    }
}
