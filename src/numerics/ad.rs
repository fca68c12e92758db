//! Forward-mode automatic differentiation (num-dual) for the vehicle models.
//!
//! Models are written once, generic over [`Scalar`]; with `f64` they simulate, with
//! `DualSVec64<CHUNK>` they give exact Jacobians. Jacobians are taken in chunks of
//! [`CHUNK`] directions, so one dual type serves any number of states and coefficients
//! (the chunked forward mode of ForwardDiff.jl) and nothing is allocated per evaluation.

use num_dual::{DualNum, DualSVec64, DualStruct};

/// A number a model can be evaluated with: `f64`, or a dual number carrying derivatives.
pub trait Scalar: DualNum<Primitive = f64> + Copy + Send + Sync {
    /// The real part.
    fn value(&self) -> f64;
}

impl<T: DualNum<Primitive = f64> + Copy + Send + Sync + DualStruct<Real = f64>> Scalar for T {
    fn value(&self) -> f64 {
        self.re()
    }
}

/// Number of derivative directions carried per evaluation (6 measured fastest for the
/// 12-state spheroid filter: two passes of 6 beat one of 12 or passes of 8 and 4).
pub const CHUNK: usize = 6;

/// The dual number used for Jacobians.
pub type Dual = DualSVec64<CHUNK>;

/// A dual number with value `re` and derivative `seed` in direction `k` of the chunk.
pub fn seeded(re: f64, k: usize, seed: f64) -> Dual {
    let mut eps = nalgebra::SVector::<f64, CHUNK>::zeros();
    eps[k] = seed;
    Dual::new(re, num_dual::Derivative::some(eps))
}

/// A dual number with no derivative.
pub fn constant(re: f64) -> Dual {
    Dual::from_re(re)
}

/// Derivative of `d` in direction `k` of the chunk.
pub fn derivative(d: &Dual, k: usize) -> f64 {
    d.eps.0.as_ref().map_or(0.0, |e| e[k])
}

/// Jacobian of `f: R^n -> R^m` at `x` by chunked forward-mode AD.
///
/// `f` receives the dual input and writes `m` dual outputs. The result is row-major `m x n`
/// in `jac`, and `value` receives f(x).
pub fn jacobian<F>(x: &[f64], m: usize, mut f: F, value: &mut [f64], jac: &mut [f64])
where
    F: FnMut(&[Dual], &mut [Dual]),
{
    let n = x.len();
    assert_eq!(jac.len(), m * n);
    assert_eq!(value.len(), m);
    let mut xd: Vec<Dual> = x.iter().map(|&v| constant(v)).collect();
    let mut out = vec![constant(0.0); m];
    let mut start = 0;
    loop {
        let end = (start + CHUNK).min(n);
        for (i, xi) in xd.iter_mut().enumerate() {
            *xi = if (start..end).contains(&i) {
                seeded(x[i], i - start, 1.0)
            } else {
                constant(x[i])
            };
        }
        f(&xd, &mut out);
        for (r, o) in out.iter().enumerate() {
            value[r] = o.re;
            for c in start..end {
                jac[r * n + c] = derivative(o, c - start);
            }
        }
        if end >= n {
            break;
        }
        start = end;
    }
}

/// Jacobian by central finite differences, to check the AD one.
pub fn jacobian_fd<F>(x: &[f64], m: usize, mut f: F, jac: &mut [f64])
where
    F: FnMut(&[f64], &mut [f64]),
{
    let n = x.len();
    let mut xp = x.to_vec();
    let mut fp = vec![0.0; m];
    let mut fm = vec![0.0; m];
    for c in 0..n {
        let h = 1e-6 * x[c].abs().max(1.0);
        xp[c] = x[c] + h;
        f(&xp, &mut fp);
        xp[c] = x[c] - h;
        f(&xp, &mut fm);
        xp[c] = x[c];
        for r in 0..m {
            jac[r * n + c] = (fp[r] - fm[r]) / (2.0 * h);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g<T: Scalar>(x: &[T], y: &mut [T]) {
        // more inputs than one chunk, to exercise chunking
        let s: T = x.iter().copied().sum();
        y[0] = x[0] * x[1].sin() + s;
        y[1] = x[9] * x[9].abs() - x[3].cos() * x[8];
    }

    #[test]
    fn chunked_ad_matches_finite_differences() {
        let x: Vec<f64> = (0..10).map(|i| 0.3 * i as f64 - 1.1).collect();
        let mut val = [0.0; 2];
        let mut ja = vec![0.0; 20];
        jacobian(&x, 2, g, &mut val, &mut ja);
        let mut jf = vec![0.0; 20];
        jacobian_fd(&x, 2, g, &mut jf);
        for (a, b) in ja.iter().zip(&jf) {
            assert!((a - b).abs() < 1e-7, "{a} vs {b}");
        }
        let mut y = [0.0; 2];
        g(&x, &mut y);
        assert_eq!(val, y);
    }
}
