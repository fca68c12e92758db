//! The discrete-time extended Kalman filter ([`FilterKind::Discrete`]): the prediction of
//! Simon 2006, "Optimal State Estimation", section 13.1, with the model
//! discretised by explicit Euler as the Nomoto wave-filter paper writes it (Dinh, Hoang &
//! Pham 2016, eq. 20-25):
//!
//! ```text
//! x_k+1 = x_k + Delta f(x_k, u_k)                 (paper eq. 20-24)
//! Phi_k = I + Delta F_k,   F_k = df/dx (x_k)       (Simon 2006, section 13.1)
//! P_k+1 = Phi_k P_k Phi_k^T + Q_d,   Q_d = Q Delta
//! ```
//!
//! then the Joseph-form update shared with the hybrid filter
//! ([`HybridEkf::update`](crate::numerics::estimation::HybridEkf::update)).
//!
//! Process noise: `Q` is the same spectral density (SI^2 per second) the hybrid filter takes;
//! a white noise of density Q integrated over Delta has covariance Q Delta, the first-order
//! (Euler) form of the hybrid filter's Q_d = integral Phi Q Phi^T. A per-step covariance
//! Q_step as the paper writes it (x2(k+1) = x2 + w, var(w) = Q_step) is the density
//! Q_step / Delta.
//!
//! Steps: an interval is crossed in ceil(Delta / max_step) equal Euler steps (the same
//! sub-steps as the hybrid filter; with `hekf.substeps = 1` a regular interval is one step,
//! the paper's form, and a gap is crossed in steps no longer than the regular interval).
//! Explicit Euler is stable only while h |lambda| stays below 2 for the eigenvalues lambda
//! of F_x (the dynamic block of F); the filter bounds the largest by the row-sum norm
//! ||F_x||_inf and refuses a step with h ||F_x||_inf > [`EULER_LIMIT`] with a
//! [`Divergence`] naming the time and the number of sub-steps that would do.

use super::hybrid_ekf::{congruence_blocks, Divergence, HybridEkf};
use super::{FilterKind, System};
use crate::numerics::linalg::matmul;
use crate::numerics::ode::StageTime;

/// Largest h ||F_x||_inf an Euler step may take: explicit Euler on x_dot = lambda x is stable
/// for |1 + h lambda| <= 1, which for a real negative lambda is h |lambda| <= 2, and
/// ||F_x||_inf bounds every |lambda|.
pub const EULER_LIMIT: f64 = 2.0;

/// The row-sum norm ||F_x||_inf of the dynamic block (first `nd` columns) of F (nd x n).
pub fn dynamic_row_sum_norm(f: &[f64], nd: usize, n: usize) -> f64 {
    (0..nd)
        .map(|i| f[i * n..i * n + nd].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

impl HybridEkf {
    /// One explicit Euler step of length `h` from `t` (module docs): x <- x + h f(x),
    /// P <- Phi P Phi^T + Q h with Phi = I + h F, leaving Phi's top rows in `phi_step`.
    pub(super) fn euler_step<S: System>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
    ) -> Result<(), Divergence> {
        debug_assert_eq!(self.kind, FilterKind::Discrete);
        let (n, nd) = (self.n, self.nd);
        let mut dx = std::mem::take(&mut self.kb.dx);
        dx.resize(nd, 0.0);
        // f(x_k) and F_k = df/dx at x_k (Simon 2006, section 13.1)
        sys.jacobian(StageTime::at(t), &self.x, &mut dx, &mut self.f);
        let norm = dynamic_row_sum_norm(&self.f, nd, n);
        let stable = h * norm <= EULER_LIMIT;
        if !stable {
            self.kb.dx = dx;
            return Err(Divergence {
                time: t,
                reason: format!(
                    "an explicit Euler step of {h} s is unstable here (step x ||F||_inf = \
                     {:.3}, above {EULER_LIMIT}): the discrete filter needs steps of at most \
                     {:.3e} s; raise hekf.substeps by a factor of {} or use filter = \"hybrid\"",
                    h * norm,
                    EULER_LIMIT / norm,
                    (h * norm / EULER_LIMIT).ceil()
                ),
            });
        }
        // x_k+1 = x_k + h f(x_k) (paper eq. 20-24); the parameters are constant
        for (x, d) in self.x[..nd].iter_mut().zip(&dx) {
            *x += h * d;
        }
        self.kb.dx = dx;
        // Phi_top = [I 0] + h F (the bottom rows are [0 I])
        let top = &mut self.phi_step;
        for (o, v) in top[..nd * n].iter_mut().zip(&self.f) {
            *o = h * v;
        }
        for i in 0..nd {
            top[i * n + i] += 1.0;
        }
        // P <- Phi P Phi^T + Q h (Simon 2006, section 13.1, with Q_d = Q h)
        matmul(&self.phi_step[..nd * n], &self.p, nd, n, n, &mut self.fp);
        congruence_blocks(&mut self.p, &self.fp, &self.phi_step[..nd * n], nd, n);
        for (i, q) in self.q.iter().enumerate() {
            self.p[i * n + i] += h * q;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::numerics::estimation::test_systems::Linear;

    fn mul(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
        let mut o = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                o[i * n + j] = (0..n).map(|k| a[i * n + k] * b[k * n + j]).sum();
            }
        }
        o
    }

    fn transposed(a: &[f64], n: usize) -> Vec<f64> {
        let mut o = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                o[j * n + i] = a[i * n + j];
            }
        }
        o
    }

    #[test]
    fn the_prediction_is_one_euler_step_and_its_covariance() {
        let a = [-0.3, 1.2, -0.7, -0.1];
        let mut sys = Linear {
            a: a.to_vec(),
            nd: 2,
            n: 3,
        };
        let x0 = vec![0.4, -1.3, 2.0];
        let p0 = vec![0.5, 0.1, 0.05, 0.1, 0.8, -0.02, 0.05, -0.02, 0.3];
        let q = vec![1e-3, 2e-3, 5e-4];
        let dt = 0.25;
        // max_step no shorter than the interval: one Euler step, the paper's form
        let mut f = HybridEkf::new(3, 2, x0.clone(), p0.clone(), q.clone(), dt);
        f.kind = FilterKind::Discrete;
        let mut phi = vec![0.0; 9];
        f.predict(&mut sys, 1.0, 1.0 + dt, Some(&mut phi)).unwrap();
        // x + Delta A x
        let want_x = [
            x0[0] + dt * (a[0] * x0[0] + a[1] * x0[1]),
            x0[1] + dt * (a[2] * x0[0] + a[3] * x0[1]),
            x0[2],
        ];
        for (g, w) in f.x.iter().zip(want_x) {
            assert!((g - w).abs() <= 1e-15 * w.abs().max(1.0), "{g} {w}");
        }
        // (I + Delta A) P (I + Delta A)^T + Q Delta
        let big_phi = [
            1.0 + dt * a[0],
            dt * a[1],
            0.0,
            dt * a[2],
            1.0 + dt * a[3],
            0.0,
            0.0,
            0.0,
            1.0,
        ];
        let mut want_p = mul(&mul(&big_phi, &p0, 3), &transposed(&big_phi, 3), 3);
        for i in 0..3 {
            want_p[i * 3 + i] += q[i] * dt;
        }
        for (g, w) in f.p.iter().zip(&want_p) {
            assert!((g - w).abs() <= 1e-14, "P {g} against {w}");
        }
        // the smoother's transition matrix is Phi
        for (g, w) in phi.iter().zip(big_phi) {
            assert!((g - w).abs() <= 1e-15, "Phi {g} against {w}");
        }
        assert_eq!(f.p[1], f.p[3], "symmetric");
    }

    #[test]
    fn an_unstable_euler_step_is_refused_with_its_time() {
        let mut sys = Linear {
            a: vec![-30.0, 0.0, 0.0, -1.0],
            nd: 2,
            n: 3,
        };
        let mut f = HybridEkf::new(3, 2, vec![1.0; 3], vec![0.0; 9], vec![0.0; 3], 0.1);
        f.kind = FilterKind::Discrete;
        let e = f.predict(&mut sys, 2.0, 2.1, None).unwrap_err();
        assert_eq!(e.time, 2.0);
        assert!(
            e.reason.contains("Euler step") && e.reason.contains("substeps"),
            "{e}"
        );
        // in sub-steps short enough (max_step 0.05: 30 x 0.05 = 1.5) it goes through
        f.max_step = 0.05;
        f.predict(&mut sys, 2.0, 2.1, None).unwrap();
        assert!(
            (f.x[0] - (1.0f64 - 1.5).powi(2)).abs() < 1e-12,
            "{}",
            f.x[0]
        );
    }
}
