//! The continuous-time extended Kalman filter ([`FilterKind::Continuous`]): the Kalman-Bucy
//! form of Simon 2006, "Optimal State Estimation", section 13.3, as the
//! NPS AUV paper uses it (Mousavian, Koofigar & Ekramian 2015):
//!
//! ```text
//! xhat_dot = f(xhat, u) + K (y - h(xhat)),   K = P H^T R_c^-1
//! P_dot    = F P + P F^T - P H^T R_c^-1 H P + Q
//! ```
//!
//! with F = df/dx and H = dh/dx at xhat (automatic differentiation, as for the other forms).
//!
//! Measurements: the sample y_k is held (zero-order) over the interval [t_k, t_k+1) that
//! follows it, and state and covariance are integrated together by classical RK4 (Butcher
//! 2008, section 32; F and H re-evaluated at every stage) in steps no longer than
//! [`HybridEkf::max_step`] and no longer than half the Riccati term's time scale,
//! min_a R_c,a / (H P H^T)_aa, which is short while a measured quantity is still uncertain
//! (P0 of 1 against R_c of 1e-7: the first steps are a few microseconds).
//!
//! Measurement noise: the configured (or estimated) noise is a per-sample variance R_d. A
//! sample held over an interval of length dt stands for a white noise of spectral density
//!
//! ```text
//! R_c = R_d dt
//! ```
//!
//! (a white noise of density R_c averaged over dt has variance R_c / dt), so that each
//! sample carries the information 1 / R_d of one discrete measurement, whatever the
//! interval. A missing measurement (NaN) or one rejected by the innovation gate is not held.
//!
//! At each sample the filter reports the innovation y_k - h(xhat(t_k)) with its variance
//! S = H P H^T + R_d and the normalised innovation squared, as the other forms do, but it
//! makes no jump: the sample enters through the integration over the next interval. P is
//! symmetrised after every step and checked (finite, positive variances, Cholesky) at every
//! sample like the hybrid filter's; failures are [`Divergence`]s with their time.
//!
//! Smoothing: the RTS smoother of [`crate::numerics::estimation::rts`] needs a prior and a posterior
//! per sample and the transition between them; the Kalman-Bucy filter has neither, so
//! [`HybridEkf::predict`] refuses to give a transition matrix and the stage does not smooth.

use super::hybrid_ekf::{note_beyond, Divergence, HybridEkf};
use super::{FilterKind, System};
use crate::numerics::linalg::{cholesky, cholesky_solve, matmul, symmetrize};
use crate::numerics::ode::{StageTime, MAX_STEPS_PER_INTERVAL};

/// The held measurement and the work space of the Kalman-Bucy filter (and the Euler step's
/// derivative).
#[derive(Debug, Clone, Default)]
pub struct Work {
    /// f(x), for the discrete filter's Euler step and the stages here.
    pub(super) dx: Vec<f64>,
    /// The held measurement (NaN: none for this quantity).
    y: Vec<f64>,
    /// Its per-sample variance R_d.
    r: Vec<f64>,
    /// Spectral densities R_c over the current interval.
    rc: Vec<f64>,
    /// The measured states, when every measurement is one state.
    sel: Option<Vec<usize>>,
    yhat: Vec<f64>,
    h: Vec<f64>,
    f: Vec<f64>,
    fp: Vec<f64>,
    col: Vec<f64>,
    xs: Vec<f64>,
    ps: Vec<f64>,
    kx: Vec<f64>,
    kp: Vec<f64>,
    nu: Vec<f64>,
}

/// Fraction of the Riccati time scale one RK4 step may take.
const RICCATI_STEP: f64 = 0.5;

impl Work {
    fn size(&mut self, n: usize, nd: usize, m: usize) {
        // lengths in the order of the vectors below
        let lengths = [
            nd,
            m,
            m,
            m * n,
            nd * n,
            nd * n,
            n,
            n,
            n * n,
            4 * n,
            4 * n * n,
            m,
        ];
        let vectors = [
            &mut self.dx,
            &mut self.rc,
            &mut self.yhat,
            &mut self.h,
            &mut self.f,
            &mut self.fp,
            &mut self.col,
            &mut self.xs,
            &mut self.ps,
            &mut self.kx,
            &mut self.kp,
            &mut self.nu,
        ];
        for (v, len) in vectors.into_iter().zip(lengths) {
            v.resize(len, 0.0);
        }
    }

    /// The predicted measurement at x into `yhat` (and H into `h` unless a selection).
    fn observe<S: System>(&mut self, sys: &mut S, at: StageTime, x: &[f64]) {
        match &self.sel {
            Some(sel) => {
                for (y, &j) in self.yhat.iter_mut().zip(sel) {
                    *y = x[j];
                }
            }
            None => sys.observe(at, x, &mut self.yhat, &mut self.h),
        }
    }

    /// col = P H_a^T for measurement a.
    fn gain_column(&mut self, p: &[f64], a: usize, n: usize) {
        match &self.sel {
            Some(sel) => self.col.copy_from_slice(&p[sel[a] * n..(sel[a] + 1) * n]),
            None => {
                let ha = &self.h[a * n..(a + 1) * n];
                for (i, c) in self.col.iter_mut().enumerate() {
                    *c = p[i * n..(i + 1) * n]
                        .iter()
                        .zip(ha)
                        .map(|(a, b)| a * b)
                        .sum();
                }
            }
        }
    }

    /// The Riccati term's rate max_a (H P H^T)_aa / R_c,a over the held measurements (1/s).
    fn riccati_rate<S: System>(&mut self, sys: &mut S, t: f64, x: &[f64], p: &[f64]) -> f64 {
        let (n, m) = (x.len(), self.rc.len());
        if m == 0 {
            return 0.0;
        }
        self.observe(sys, StageTime::at(t), x);
        let mut rate: f64 = 0.0;
        for a in 0..m {
            if !self.y[a].is_finite() {
                continue;
            }
            self.gain_column(p, a, n);
            let hph = match &self.sel {
                Some(sel) => self.col[sel[a]],
                None => self
                    .col
                    .iter()
                    .zip(&self.h[a * n..])
                    .map(|(c, h)| c * h)
                    .sum::<f64>(),
            };
            rate = rate.max(hph / self.rc[a]);
        }
        rate
    }

    /// The right-hand side of the Kalman-Bucy equations (module docs) at (t, x, P): x_dot
    /// (length n) into `out_x`, P_dot (n x n) into `out_p`.
    #[allow(clippy::too_many_arguments)]
    fn rates<S: System>(
        &mut self,
        sys: &mut S,
        t: StageTime,
        x: &[f64],
        p: &[f64],
        q: &[f64],
        nd: usize,
        out_x: &mut [f64],
        out_p: &mut [f64],
    ) {
        let n = x.len();
        // f(xhat) and F (Simon 2006, section 13.3)
        sys.jacobian(t, x, &mut self.dx, &mut self.f);
        out_x[..nd].copy_from_slice(&self.dx);
        out_x[nd..].fill(0.0);
        // F P + P F^T + Q (Simon 2006, section 13.3), F zero below its nd rows
        matmul(&self.f, p, nd, n, n, &mut self.fp);
        for i in 0..n {
            for j in 0..n {
                let mut v = if i < nd { self.fp[i * n + j] } else { 0.0 };
                if j < nd {
                    v += self.fp[j * n + i];
                }
                out_p[i * n + j] = v;
            }
            out_p[i * n + i] += q[i];
        }
        // + K (y - h(xhat)) and - P H^T R_c^-1 H P, one measurement at a time (R_c diagonal)
        if self.rc.is_empty() {
            return;
        }
        self.observe(sys, t, x);
        for a in 0..self.rc.len() {
            let nu = self.y[a] - self.yhat[a];
            if !nu.is_finite() {
                continue;
            }
            self.gain_column(p, a, n);
            let inv = 1.0 / self.rc[a];
            for (i, ci) in self.col.iter().enumerate() {
                out_x[i] += ci * inv * nu;
                let row = &mut out_p[i * n..(i + 1) * n];
                let cii = ci * inv;
                for (o, cj) in row.iter_mut().zip(&self.col) {
                    *o -= cii * cj;
                }
            }
        }
    }
}

impl HybridEkf {
    /// The Kalman-Bucy prediction over [t0, t1] with the held measurement (module docs).
    pub(super) fn predict_kalman_bucy<S: System>(
        &mut self,
        sys: &mut S,
        (t0, t1): (f64, f64),
    ) -> Result<(), Divergence> {
        debug_assert_eq!(self.kind, FilterKind::Continuous);
        let (n, nd) = (self.n, self.nd);
        let m = self.kb.y.len();
        let mut w = std::mem::take(&mut self.kb);
        w.size(n, nd, m);
        // R_c = R_d dt over this interval
        let dt = t1 - t0;
        for (rc, r) in w.rc.iter_mut().zip(&w.r) {
            *rc = r * dt;
        }
        let result = self.integrate(sys, &mut w, t0, t1);
        self.kb = w;
        result?;
        self.finish_prediction(sys, t1)
    }

    fn integrate<S: System>(
        &mut self,
        sys: &mut S,
        w: &mut Work,
        t0: f64,
        t1: f64,
    ) -> Result<(), Divergence> {
        let (n, nd) = (self.n, self.nd);
        let nn = n * n;
        let h_max = (t1 - t0) / self.steps(t0, t1)? as f64;
        let mut t = t0;
        let mut count = 0;
        while t < t1 {
            count += 1;
            if count > MAX_STEPS_PER_INTERVAL {
                return Err(Divergence {
                    time: t,
                    reason: format!(
                        "the Riccati equation needs more than {MAX_STEPS_PER_INTERVAL} steps \
                         between t = {t0} s and {t1} s (a measured quantity far more \
                         uncertain than its noise)"
                    ),
                });
            }
            let rate = w.riccati_rate(sys, t, &self.x, &self.p);
            let mut h = h_max;
            if rate > 0.0 {
                h = h.min(RICCATI_STEP / rate);
            }
            let rest = t1 - t;
            if h >= rest * (1.0 - 1e-9) {
                h = rest;
            }
            // classical RK4 on (x, P) (Butcher 2008, section 32)
            let (mut kx, mut kp) = (std::mem::take(&mut w.kx), std::mem::take(&mut w.kp));
            for s in 0..4 {
                let (c, prev) = match s {
                    0 => (0.0, 0),
                    3 => (h, 2),
                    _ => (0.5 * h, s - 1),
                };
                w.xs.copy_from_slice(&self.x);
                w.ps.copy_from_slice(&self.p);
                if s > 0 {
                    for (v, k) in w.xs.iter_mut().zip(&kx[prev * n..(prev + 1) * n]) {
                        *v += c * k;
                    }
                    for (v, k) in w.ps.iter_mut().zip(&kp[prev * nn..(prev + 1) * nn]) {
                        *v += c * k;
                    }
                }
                let (xs, ps) = (std::mem::take(&mut w.xs), std::mem::take(&mut w.ps));
                // held inputs at the step's start, also in the last stage (ode::StageTime)
                w.rates(
                    sys,
                    StageTime {
                        t: t + c,
                        step_start: t,
                    },
                    &xs,
                    &ps,
                    &self.q,
                    nd,
                    &mut kx[s * n..(s + 1) * n],
                    &mut kp[s * nn..(s + 1) * nn],
                );
                (w.xs, w.ps) = (xs, ps);
            }
            let sixth = h / 6.0;
            for i in 0..n {
                self.x[i] +=
                    sixth * (kx[i] + 2.0 * kx[n + i] + 2.0 * kx[2 * n + i] + kx[3 * n + i]);
            }
            for i in 0..nn {
                self.p[i] +=
                    sixth * (kp[i] + 2.0 * kp[nn + i] + 2.0 * kp[2 * nn + i] + kp[3 * nn + i]);
            }
            (w.kx, w.kp) = (kx, kp);
            symmetrize(&mut self.p, n);
            t = if h == rest { t1 } else { t + h };
            if let Some(i) = self.x.iter().position(|v| !v.is_finite()) {
                return Err(Divergence {
                    time: t,
                    reason: format!("state {i} became non-finite during prediction"),
                });
            }
            let not_positive = |v: f64| v.is_nan() || v <= 0.0;
            if let Some(i) = (0..n).find(|&i| not_positive(self.p[i * n + i])) {
                return Err(Divergence {
                    time: t,
                    reason: format!(
                        "the variance of state {i} became {:e} in the Riccati equation",
                        self.p[i * n + i]
                    ),
                });
            }
        }
        Ok(())
    }

    /// At a sample of the continuous filter: the innovation y - h(xhat) with its variance
    /// S = H P H^T + R_d and the NIS for the statistics, the innovation gate, and y held for
    /// the next interval (module docs). Returns the NIS.
    pub(super) fn hold_measurement<S: System>(
        &mut self,
        sys: &mut S,
        (t, y, r): (f64, &[f64], &[f64]),
    ) -> Result<f64, Divergence> {
        let (n, nd, m) = (self.n, self.nd, y.len());
        self.beyond.clear();
        let mut kb = std::mem::take(&mut self.kb);
        match sys.selection() {
            Some(sel) => {
                let v = kb.sel.get_or_insert_with(Vec::new);
                v.clear();
                v.extend_from_slice(sel);
            }
            None => kb.sel = None,
        }
        kb.y.clear();
        kb.y.extend_from_slice(y);
        kb.r.clear();
        kb.r.extend_from_slice(r);
        kb.size(n, nd, m);
        kb.observe(sys, StageTime::at(t), &self.x);
        let w = &mut self.upd;
        w.resize(n, m);
        match &kb.sel {
            Some(sel) => {
                w.h.fill(0.0);
                for (a, &j) in sel.iter().enumerate() {
                    w.h[a * n + j] = 1.0;
                }
            }
            None => w.h.copy_from_slice(&kb.h),
        }
        w.innovation_covariance(&self.p, r, n);
        for a in 0..m {
            let nu = y[a] - kb.yhat[a];
            let keep = nu.is_finite()
                && !(self.gate > 0.0
                    && nu * nu > self.gate * self.gate * w.s_diag[a]
                    && note_beyond(
                        &mut self.beyond,
                        &self.ungated,
                        a,
                        nu.abs() / w.s_diag[a].sqrt(),
                    ));
            w.nu[a] = if keep { nu } else { 0.0 };
            if !keep {
                // not held: no measurement of this quantity over the next interval; its row
                // of S made the identity so that the NIS leaves it out
                kb.y[a] = f64::NAN;
                for b in 0..m {
                    w.s[a * m + b] = 0.0;
                    w.s[b * m + a] = 0.0;
                }
                w.s[a * m + a] = 1.0;
            }
        }
        // NIS = nu^T S^-1 nu
        w.ls.copy_from_slice(&w.s);
        let chol = cholesky(&mut w.ls, m);
        kb.nu.copy_from_slice(&w.nu);
        let nis = match chol {
            Ok(()) => {
                cholesky_solve(&w.ls, m, &mut kb.nu);
                w.nu.iter().zip(&kb.nu).map(|(a, b)| a * b).sum::<f64>()
            }
            Err(i) => {
                self.kb = kb;
                return Err(Divergence {
                    time: t,
                    reason: format!("innovation covariance lost positive definiteness (pivot {i})"),
                });
            }
        };
        self.kb = kb;
        self.finish_update(sys, t, nis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::numerics::estimation::test_systems::Linear;

    /// x_dot = a x + w, y = x + v.
    fn scalar(a: f64) -> Linear {
        Linear {
            a: vec![a],
            nd: 1,
            n: 1,
        }
    }

    #[test]
    fn the_covariance_converges_to_the_steady_state_riccati_solution() {
        // 0 = 2 a P - P^2 / R_c + q  =>  P = R_c (a + sqrt(a^2 + q / R_c))
        let (a, q, r_d, dt): (f64, f64, f64, f64) = (-0.5, 0.2, 0.01, 0.1);
        let r_c = r_d * dt;
        let want = r_c * (a + (a * a + q / r_c).sqrt());
        let mut sys = scalar(a);
        let mut f = HybridEkf::new(1, 1, vec![0.0], vec![1.0], vec![q], dt);
        f.kind = FilterKind::Continuous;
        let mut t = 0.0;
        for k in 0..200 {
            f.update(&mut sys, t, &[0.0], &[r_d]).unwrap();
            let t1 = (k + 1) as f64 * dt;
            f.predict(&mut sys, t, t1, None).unwrap();
            t = t1;
        }
        assert!(
            ((f.p[0] - want) / want).abs() < 1e-9,
            "P = {}, steady state {want}",
            f.p[0]
        );
        // no transition matrix for the smoother
        let mut phi = [0.0];
        assert!(f.predict(&mut sys, t, t + dt, Some(&mut phi)).is_err());
    }

    #[test]
    fn a_measurement_beyond_the_gate_is_not_held() {
        let mut sys = scalar(0.0);
        let mut f = HybridEkf::new(1, 1, vec![0.0], vec![1e-4], vec![0.0], 0.1);
        f.kind = FilterKind::Continuous;
        f.gate = 5.0;
        f.ungated = vec![false];
        f.update(&mut sys, 0.0, &[1.0], &[1e-4]).unwrap();
        assert_eq!(f.beyond_gate().len(), 1);
        f.predict(&mut sys, 0.0, 0.1, None).unwrap();
        assert_eq!(f.x[0], 0.0, "the rejected sample moved the state");
        f.update(&mut sys, 0.1, &[0.01], &[1e-4]).unwrap();
        f.predict(&mut sys, 0.1, 0.2, None).unwrap();
        assert!(f.x[0] > 0.0 && f.x[0] < 0.01, "{}", f.x[0]);
    }
}
