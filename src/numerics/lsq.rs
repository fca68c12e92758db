//! Linear least squares with column scaling and a rank test, and the covariance of the
//! solution (Golub & Van Loan 2013, section 5.3; sigma^2 (X'X)^-1 with sigma^2 = RSS / dof).

use nalgebra::{DMatrix, DVector};

/// The solution of y = X theta (no intercept) by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct Slopes {
    /// theta.
    pub theta: Vec<f64>,
    /// Covariance of theta, sigma^2 (X'X)^-1.
    pub covariance: Vec<Vec<f64>>,
    /// Residual sum of squares.
    pub rss: f64,
}

/// Solves y = X theta on unit-norm columns, with the covariance sigma^2 (X'X)^-1 from
/// `resid_dof` residual degrees of freedom. None when a column is zero or not finite, or
/// the columns are (numerically) dependent.
pub fn scaled_least_squares(
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    resid_dof: usize,
) -> Option<Slopes> {
    let (n, p) = x.shape();
    // Scale columns for the rank test.
    let norms: Vec<f64> = (0..p).map(|j| x.column(j).norm()).collect();
    if norms.iter().any(|v| *v == 0.0 || !v.is_finite()) {
        return None;
    }
    let xs = DMatrix::from_fn(n, p, |i, j| x[(i, j)] / norms[j]);
    let svd = (xs.transpose() * &xs).svd(true, true);
    let (smin, smax) = (svd.singular_values.min(), svd.singular_values.max());
    if smin.is_nan() || smin <= 1e-13 * smax {
        return None;
    }
    let inv = svd.pseudo_inverse(0.0).ok()?;
    let theta_s = &inv * (xs.transpose() * y);
    let theta = (0..p).map(|j| theta_s[j] / norms[j]).collect();
    let rss = (y - &xs * &theta_s).norm_squared();
    let s2 = rss / resid_dof as f64;
    let covariance = (0..p)
        .map(|i| {
            (0..p)
                .map(|j| s2 * inv[(i, j)] / (norms[i] * norms[j]))
                .collect()
        })
        .collect();
    Some(Slopes {
        theta,
        covariance,
        rss,
    })
}
