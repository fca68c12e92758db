//! Rauch-Tung-Striebel fixed-interval smoother over a filter pass (Simon 2006, section 9.4.2):
//! G_k = P_k|k Phi_k^T P_k+1|k^-1, x_k|N = x_k|k + G_k (x_k+1|N - x_k+1|k),
//! P_k|N = P_k|k + G_k (P_k+1|N - P_k+1|k) G_k^T.

use crate::linalg::{cholesky, cholesky_solve, matmul, matmul_bt, symmetrize};

/// What the filter keeps for the smoother, one entry per sample.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    /// State dimension.
    pub n: usize,
    /// Time of each sample.
    pub t: Vec<f64>,
    /// Prior (predicted) state at each sample (K x n).
    pub x_prior: Vec<f64>,
    /// Prior covariance at each sample (K x n x n).
    pub p_prior: Vec<f64>,
    /// Posterior (updated) state (K x n).
    pub x_post: Vec<f64>,
    /// Posterior covariance (K x n x n).
    pub p_post: Vec<f64>,
    /// Transition matrix from the previous sample to this one (K x n x n; entry 0 unused).
    pub phi: Vec<f64>,
}

impl Trace {
    /// An empty trace for n states.
    pub fn new(n: usize) -> Self {
        Trace {
            n,
            ..Default::default()
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Smoothed states (K x n) and covariances (K x n x n). Fails (with the sample index) if
    /// a predicted covariance is not positive definite.
    pub fn smooth(&self) -> Result<(Vec<f64>, Vec<f64>), usize> {
        let n = self.n;
        let kk = self.len();
        let nn = n * n;
        let mut xs = self.x_post.clone();
        let mut ps = self.p_post.clone();
        let mut l = vec![0.0; nn];
        let mut b = vec![0.0; nn];
        let mut g = vec![0.0; nn];
        let mut d = vec![0.0; nn];
        let mut tmp = vec![0.0; nn];
        let mut col = vec![0.0; n];
        for k in (0..kk.saturating_sub(1)).rev() {
            // G^T = P_prior(k+1)^-1 Phi(k+1) P_post(k)
            l.copy_from_slice(&self.p_prior[(k + 1) * nn..(k + 2) * nn]);
            cholesky(&mut l, n).map_err(|_| k + 1)?;
            matmul(
                &self.phi[(k + 1) * nn..(k + 2) * nn],
                &self.p_post[k * nn..(k + 1) * nn],
                n,
                n,
                n,
                &mut b,
            );
            for j in 0..n {
                for i in 0..n {
                    col[i] = b[i * n + j];
                }
                cholesky_solve(&l, n, &mut col);
                for i in 0..n {
                    g[j * n + i] = col[i]; // G = (G^T)^T
                }
            }
            // state
            for i in 0..n {
                let mut s = 0.0;
                for j in 0..n {
                    s += g[i * n + j] * (xs[(k + 1) * n + j] - self.x_prior[(k + 1) * n + j]);
                }
                xs[k * n + i] += s;
            }
            // covariance
            for i in 0..nn {
                d[i] = ps[(k + 1) * nn + i] - self.p_prior[(k + 1) * nn + i];
            }
            matmul(&g, &d, n, n, n, &mut tmp);
            matmul_bt(&tmp, &g, n, n, n, &mut d);
            let pk = &mut ps[k * nn..(k + 1) * nn];
            for (p, dv) in pk.iter_mut().zip(&d) {
                *p += dv;
            }
            symmetrize(pk, n);
        }
        Ok((xs, ps))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_a_random_walk_pulls_the_past_towards_later_data() {
        // scalar random walk, Phi = 1, q = 1, r = 1: measurements 0 then 10
        let mut tr = Trace::new(1);
        let (mut x, mut p) = (0.0, 1.0);
        let ys = [0.0, 10.0];
        for (k, y) in ys.iter().enumerate() {
            if k > 0 {
                p += 1.0;
            }
            tr.t.push(k as f64);
            tr.x_prior.push(x);
            tr.p_prior.push(p);
            tr.phi.push(1.0);
            let kg = p / (p + 1.0);
            x += kg * (y - x);
            p *= 1.0 - kg;
            tr.x_post.push(x);
            tr.p_post.push(p);
        }
        let (xs, ps) = tr.smooth().unwrap();
        // filtered x0 = 0 (p 0.5); prior x1 = 0 (p 1.5); posterior x1 = 6 (p 0.6)
        // G0 = 0.5/1.5 = 1/3; xs0 = 0 + (6 - 0)/3 = 2; ps0 = 0.5 + (0.6 - 1.5)/9 = 0.4
        assert!((xs[0] - 2.0).abs() < 1e-12);
        assert!((ps[0] - 0.4).abs() < 1e-12);
        assert!((xs[1] - 6.0).abs() < 1e-12);
    }
}
