//! Cumulative integrals and least squares with one free intercept per segment (a
//! fixed-effects regression: each stretch of a run keeps its own u(t0)).

use crate::numerics::lsq::Slopes;
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// Cumulative trapezoidal integral of `f` over `t`, starting at 0.
pub fn cumulative_trapezoid(t: &[f64], f: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(t.len());
    let mut acc = 0.0;
    for i in 0..t.len() {
        if i > 0 {
            acc += 0.5 * (f[i] + f[i - 1]) * (t[i] - t[i - 1]);
        }
        out.push(acc);
    }
    out
}

/// Least squares y = c_s + sum_j theta_j x_j with an intercept c_s per segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentFit {
    /// Slopes theta.
    pub theta: Vec<f64>,
    /// Covariance of theta, sigma^2 (X'X)^-1 on the within-segment centred regressors.
    pub covariance: Vec<Vec<f64>>,
    /// Intercepts c_s, one per segment.
    pub intercepts: Vec<f64>,
    /// Residual sum of squares.
    pub rss: f64,
    /// Residual degrees of freedom: samples - segments - slopes.
    pub dof: usize,
    /// Samples used.
    pub n: usize,
    /// Fitted values on each segment, in segment order.
    pub fitted: Vec<Vec<f64>>,
    /// Coefficient of determination about the segment means.
    pub r_squared: Option<f64>,
    /// The factor by which autocorrelated residuals widened the standard deviation of the
    /// slope (set by the stage that computes it; None when the residuals look white).
    pub misfit_factor: Option<f64>,
}

/// Why a segment fit failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SegmentError {
    /// Fewer samples than parameters plus one.
    TooFew,
    /// A regressor does not vary within the segments (e.g. no acceleration), or two move
    /// together.
    Singular,
}

fn scaled_least_squares(
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    resid_dof: usize,
) -> Result<Slopes, SegmentError> {
    crate::numerics::lsq::scaled_least_squares(x, y, resid_dof).ok_or(SegmentError::Singular)
}

/// Fits y = c_s + X theta over `segments` (index ranges into `y` and each of `x`).
pub fn fit(y: &[f64], x: &[&[f64]], segments: &[Range<usize>]) -> Result<SegmentFit, SegmentError> {
    let p = x.len();
    let n: usize = segments.iter().map(|s| s.len()).sum();
    let s_count = segments.len();
    if n <= s_count + p {
        return Err(SegmentError::TooFew);
    }
    // Within-segment centring removes the intercepts (Frisch-Waugh-Lovell).
    let mut xc = DMatrix::zeros(n, p);
    let mut yc = DVector::zeros(n);
    let mut means = Vec::with_capacity(s_count);
    let mut row = 0;
    for seg in segments {
        let len = seg.len() as f64;
        let my = y[seg.clone()].iter().sum::<f64>() / len;
        let mx: Vec<f64> = x
            .iter()
            .map(|c| c[seg.clone()].iter().sum::<f64>() / len)
            .collect();
        for i in seg.clone() {
            yc[row] = y[i] - my;
            for j in 0..p {
                xc[(row, j)] = x[j][i] - mx[j];
            }
            row += 1;
        }
        means.push((my, mx));
    }
    let dof = n - s_count - p;
    let Slopes {
        theta,
        covariance,
        rss,
    } = scaled_least_squares(&xc, &yc, dof)?;
    let tss = yc.norm_squared();
    let mut intercepts = Vec::with_capacity(s_count);
    let mut fitted = Vec::with_capacity(s_count);
    for (seg, (my, mx)) in segments.iter().zip(&means) {
        let c = my - mx.iter().zip(&theta).map(|(m, t)| m * t).sum::<f64>();
        intercepts.push(c);
        fitted.push(
            seg.clone()
                .map(|i| c + (0..p).map(|j| theta[j] * x[j][i]).sum::<f64>())
                .collect(),
        );
    }
    Ok(SegmentFit {
        theta,
        covariance,
        intercepts,
        rss,
        dof,
        n,
        fitted,
        r_squared: (tss > 0.0).then(|| 1.0 - rss / tss),
        misfit_factor: None,
    })
}

/// Least squares on differences over non-overlapping windows: for each window [i, k] of
/// `len` samples inside a segment, y_k - y_i = sum_j theta_j (x_j,k - x_j,i), without
/// intercept. Windows share no sample, so noise that the integrals accumulate (a random walk)
/// stays independent between windows and the usual standard errors hold. The intercepts and
/// fitted values are then set per segment from theta.
pub fn fit_windows(
    y: &[f64],
    x: &[&[f64]],
    segments: &[Range<usize>],
    len: usize,
) -> Result<SegmentFit, SegmentError> {
    let p = x.len();
    let len = len.max(2);
    let mut pairs = Vec::new();
    for seg in segments {
        let mut start = seg.start;
        while start + len <= seg.end {
            pairs.push((start, start + len - 1));
            start += len;
        }
    }
    let m = pairs.len();
    if m <= p {
        return Err(SegmentError::TooFew);
    }
    let dx = DMatrix::from_fn(m, p, |w, j| x[j][pairs[w].1] - x[j][pairs[w].0]);
    let dy = DVector::from_fn(m, |w, _| y[pairs[w].1] - y[pairs[w].0]);
    let dof = m - p;
    let Slopes {
        theta,
        covariance,
        rss,
    } = scaled_least_squares(&dx, &dy, dof)?;
    let (mut intercepts, mut fitted) = (Vec::new(), Vec::new());
    let (mut res2, mut tot2, mut n) = (0.0, 0.0, 0);
    for seg in segments {
        let xt = |i: usize| (0..p).map(|j| theta[j] * x[j][i]).sum::<f64>();
        let len = seg.len() as f64;
        let c = seg.clone().map(|i| y[i] - xt(i)).sum::<f64>() / len;
        let my = y[seg.clone()].iter().sum::<f64>() / len;
        let f: Vec<f64> = seg.clone().map(|i| c + xt(i)).collect();
        for (i, fi) in seg.clone().zip(&f) {
            res2 += (y[i] - fi).powi(2);
            tot2 += (y[i] - my).powi(2);
        }
        n += seg.len();
        intercepts.push(c);
        fitted.push(f);
    }
    Ok(SegmentFit {
        theta,
        covariance,
        intercepts,
        rss,
        dof,
        n,
        fitted,
        r_squared: (tot2 > 0.0).then(|| 1.0 - res2 / tot2),
        misfit_factor: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_integrates_a_line_exactly() {
        let t = [0.0, 0.5, 1.5, 2.0];
        let f: Vec<f64> = t.iter().map(|v| 2.0 * v + 1.0).collect();
        let i = cumulative_trapezoid(&t, &f);
        for (ti, ii) in t.iter().zip(&i) {
            assert!((ii - (ti * ti + ti)).abs() < 1e-14);
        }
    }

    #[test]
    fn segments_keep_their_own_intercepts() {
        // Two segments of y = c_s + 2 x with c = 1 and c = 5.
        let x: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| if i < 5 { 1.0 } else { 5.0 } + 2.0 * v)
            .collect();
        let f = fit(&y, &[&x], &[0..5, 5..10]).unwrap();
        assert!((f.theta[0] - 2.0).abs() < 1e-12);
        assert!((f.intercepts[0] - 1.0).abs() < 1e-12 && (f.intercepts[1] - 5.0).abs() < 1e-12);
        assert_eq!(f.dof, 7);
        // One shared intercept cannot fit the jump: the slope changes.
        let g = fit(&y, &[&x], std::slice::from_ref(&(0..10))).unwrap();
        assert!((g.theta[0] - 2.0).abs() > 0.1);
    }

    #[test]
    fn constant_regressor_is_singular() {
        let y = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(
            fit(&y, &[&[1.0; 4]], std::slice::from_ref(&(0..4))),
            Err(SegmentError::Singular)
        );
    }

    #[test]
    fn windows_match_the_levels_fit_on_exact_data() {
        let x: Vec<f64> = (0..100)
            .map(|i| (i as f64 * 0.1).sin() + i as f64 * 0.05)
            .collect();
        let y: Vec<f64> = x.iter().map(|v| 3.0 + 0.7 * v).collect();
        let f = fit_windows(&y, &[&x], std::slice::from_ref(&(0..100)), 10).unwrap();
        assert!((f.theta[0] - 0.7).abs() < 1e-12);
        assert!((f.intercepts[0] - 3.0).abs() < 1e-12);
        assert_eq!(f.dof, 9);
    }
}
