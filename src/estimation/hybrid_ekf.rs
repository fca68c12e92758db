//! Hybrid (continuous-discrete) extended Kalman filter (paper eq. 9-19; Simon 2006,
//! section 13.2.3).
//!
//! Between samples the state follows x_dot = f(x) with classical RK4. The covariance follows
//! P_dot = F P + P F^T + Q (paper eq. 15) with F = df/dx frozen at the start of each
//! sub-step; it is integrated as P <- Phi P Phi^T + Q_d, where Phi is the RK4 propagator of
//! x_dot = F x (I + hF + (hF)^2/2 + (hF)^3/6 + (hF)^4/24, the same fourth-order accuracy as
//! RK4 on P itself) and Q_d = h (Phi Q Phi^T + Q) / 2. Unlike RK4 applied to P directly, this
//! congruence keeps P positive definite when the measured states are known far better than
//! the coefficients (the RK4 truncation error of the cross terms otherwise exceeds the small
//! state variances). At a sample the update is in Joseph form
//! P = (I - K H) P (I - K H)^T + K R K^T (Simon 2006, eq. 5.19), then P is symmetrised; its variances are
//! checked at every update and its positive definiteness (Cholesky) every few updates and at
//! the end of each run.

use super::System;
use crate::linalg::{cholesky, matmul, symmetrize};
use std::fmt;

/// The filter failed: non-finite numbers, a covariance that lost positive definiteness, or a
/// state the system rejects. Carries the simulation time it happened at.
#[derive(Debug, Clone, PartialEq)]
pub struct Divergence {
    /// Time of the sample or sub-step where it happened, s.
    pub time: f64,
    /// What happened.
    pub reason: String,
}

impl fmt::Display for Divergence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the filter diverged at t = {:.4} s: {}",
            self.time, self.reason
        )
    }
}

/// The filter's state and work space. Sizes are fixed at construction; nothing allocates
/// per sample except the returned [`UpdateInfo`].
#[derive(Debug, Clone)]
pub struct HybridEkf {
    n: usize,
    nd: usize,
    /// State estimate.
    pub x: Vec<f64>,
    /// Covariance, n x n row-major, symmetric.
    pub p: Vec<f64>,
    /// Process noise spectral density, diagonal (length n), per second.
    pub q: Vec<f64>,
    /// RK4 sub-steps per sample interval.
    pub substeps: usize,
    // work space
    f: Vec<f64>,
    fp: Vec<f64>,
    dx: [Vec<f64>; 4],
    xt: Vec<f64>,
    chol: Vec<f64>,
    phi: Vec<f64>,
    phi_step: Vec<f64>,
    a_full: Vec<f64>,
    tmp: Vec<f64>,
    tmp2: Vec<f64>,
    upd: UpdateWork,
    updates_since_check: usize,
}

/// Updates between full positive-definiteness checks of P (a Cholesky factorisation; every
/// update checks the variances and finiteness).
pub const CHECK_EVERY: usize = 8;

impl HybridEkf {
    /// A filter for `system`-sized states starting at `x0` with covariance `p0`.
    pub fn new(
        n: usize,
        nd: usize,
        x0: Vec<f64>,
        p0: Vec<f64>,
        q: Vec<f64>,
        substeps: usize,
    ) -> Self {
        assert!(nd <= n && x0.len() == n && p0.len() == n * n && q.len() == n);
        let z = |len| vec![0.0; len];
        HybridEkf {
            n,
            nd,
            x: x0,
            p: p0,
            q,
            substeps: substeps.max(1),
            f: z(nd * n),
            fp: z(nd * n),
            dx: [z(nd), z(nd), z(nd), z(nd)],
            xt: z(n),
            chol: z(n * n),
            phi: z(n * n),
            phi_step: z(n * n),
            a_full: z(n * n),
            tmp: z(n * n),
            tmp2: z(n * n),
            upd: UpdateWork::default(),
            updates_since_check: 0,
        }
    }

    /// State dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Replaces the dynamic states (0..nd) and their covariance block, zeroing their
    /// correlation with the parameters: the start of a new, independent run.
    pub fn restart_dynamic(&mut self, x0: &[f64], p0: &[f64]) {
        let (n, nd) = (self.n, self.nd);
        self.x[..nd].copy_from_slice(&x0[..nd]);
        for i in 0..n {
            for j in 0..n {
                if i < nd || j < nd {
                    self.p[i * n + j] = if i < nd && j < nd {
                        p0[i * nd + j]
                    } else {
                        0.0
                    };
                }
            }
        }
    }

    /// Propagates state and covariance from `t0` to `t1`. When `phi` is given it receives the
    /// state transition matrix of the interval (for the smoother).
    pub fn predict<S: System>(
        &mut self,
        sys: &mut S,
        t0: f64,
        t1: f64,
        phi: Option<&mut [f64]>,
    ) -> Result<(), Divergence> {
        let (n, nd) = (self.n, self.nd);
        let h = (t1 - t0) / self.substeps as f64;
        if phi.is_some() {
            identity(&mut self.phi, n);
        }
        for s in 0..self.substeps {
            let t = t0 + h * s as f64;
            sys.jacobian(t, &self.x, &mut self.dx[0], &mut self.f);
            // state: classical RK4 (the parameter part has zero derivative)
            let stages = [(0.5, 1usize), (0.5, 2), (1.0, 3)];
            for &(c, stage) in &stages {
                self.xt.copy_from_slice(&self.x);
                for i in 0..nd {
                    self.xt[i] += c * h * self.dx[stage - 1][i];
                }
                sys.derivative(t + c * h, &self.xt, &mut self.dx[stage]);
            }
            for i in 0..nd {
                self.x[i] += h / 6.0
                    * (self.dx[0][i] + 2.0 * self.dx[1][i] + 2.0 * self.dx[2][i] + self.dx[3][i]);
            }
            // covariance: P <- Phi P Phi^T + Q_d with Phi the RK4 propagator (module docs)
            self.propagator(h);
            self.covariance_step(h);
            if phi.is_some() {
                self.accumulate_transition();
            }
            if let Some(i) = self.x.iter().position(|v| !v.is_finite()) {
                return Err(Divergence {
                    time: t + h,
                    reason: format!("state {i} became non-finite during prediction"),
                });
            }
        }
        symmetrize(&mut self.p, n);
        if let Some(phi_out) = phi {
            phi_out.copy_from_slice(&self.phi);
        }
        if self.p.iter().any(|v| !v.is_finite()) {
            return Err(Divergence {
                time: t1,
                reason: "the covariance became non-finite during prediction".into(),
            });
        }
        sys.check(&self.x)
            .map_err(|reason| Divergence { time: t1, reason })
    }

    /// The top `nd` rows of Phi = I + hF + (hF)^2/2 + (hF)^3/6 + (hF)^4/24 into `phi_step`
    /// (`nd x n`); the bottom rows of Phi are [0 I] because the parameters are constant.
    /// With F = [F_x F_z] (rows of the dynamic states), Horner's scheme gives
    /// Phi_top = [I 0] + h S F with S = I + hF_x/2 (I + hF_x/3 (I + hF_x/4)) (nd x nd).
    fn propagator(&mut self, h: f64) {
        let (n, nd) = (self.n, self.nd);
        let s = &mut self.tmp;
        let next = &mut self.tmp2;
        // S = I + hF_x/4
        for i in 0..nd {
            for j in 0..nd {
                s[i * nd + j] = h * self.f[i * n + j] / 4.0 + if i == j { 1.0 } else { 0.0 };
            }
        }
        for k in [3.0, 2.0] {
            // S <- I + (hF_x/k) S
            for i in 0..nd {
                let row = &mut next[i * nd..(i + 1) * nd];
                row.fill(0.0);
                row[i] = 1.0;
                for l in 0..nd {
                    let a = h * self.f[i * n + l] / k;
                    if a != 0.0 {
                        for (o, sv) in row.iter_mut().zip(&s[l * nd..(l + 1) * nd]) {
                            *o += a * sv;
                        }
                    }
                }
            }
            s[..nd * nd].copy_from_slice(&next[..nd * nd]);
        }
        // Phi_top = [I 0] + h S F
        let top = &mut self.phi_step;
        matmul(&s[..nd * nd], &self.f, nd, nd, n, top);
        for v in top[..nd * n].iter_mut() {
            *v *= h;
        }
        for i in 0..nd {
            top[i * n + i] += 1.0;
        }
    }

    /// P <- Phi P Phi^T + h (Phi Q Phi^T + Q) / 2, using the block structure of Phi.
    fn covariance_step(&mut self, h: f64) {
        let (n, nd) = (self.n, self.nd);
        let top = &self.phi_step[..nd * n];
        // M = Phi_top P (nd x n)
        let m = &mut self.fp;
        matmul(top, &self.p, nd, n, n, m);
        // new P_xx = M Phi_top^T; new P_xz = M[:, nd..]; P_zz unchanged
        let top_t = &mut self.tmp2;
        transpose(top, nd, n, top_t);
        let pxx = &mut self.tmp;
        matmul(m, top_t, nd, n, nd, pxx);
        for i in 0..nd {
            for j in 0..n {
                let v = if j < nd {
                    pxx[i * nd + j]
                } else {
                    m[i * n + j]
                };
                self.p[i * n + j] = v;
                if j >= nd {
                    self.p[j * n + i] = v;
                }
            }
        }
        if self.q.iter().any(|&q| q != 0.0) {
            // Q_d = h (Phi Q Phi^T + Q) / 2 with Q diagonal and Phi = [[top], [0 I]]:
            // (Phi Q Phi^T)_ij = sum_k top_ik q_k top_jk for i, j < nd; top_ij q_j for i < nd
            // <= j; q_i on the diagonal below.
            let q = &self.q;
            let half_h = 0.5 * h;
            for i in 0..nd {
                let ti = &top[i * n..(i + 1) * n];
                for j in i..nd {
                    let tj = &top[j * n..(j + 1) * n];
                    let v: f64 = ti
                        .iter()
                        .zip(tj)
                        .zip(q)
                        .map(|((a, b), qk)| a * qk * b)
                        .sum();
                    let qd = half_h * (v + if i == j { q[i] } else { 0.0 });
                    self.p[i * n + j] += qd;
                    if j != i {
                        self.p[j * n + i] += qd;
                    }
                }
                for j in nd..n {
                    let qd = half_h * ti[j] * q[j];
                    self.p[i * n + j] += qd;
                    self.p[j * n + i] += qd;
                }
            }
            for i in nd..n {
                self.p[i * n + i] += h * q[i];
            }
        }
    }

    /// Accumulates the full transition matrix of the sample interval: Phi <- Phi_step Phi.
    fn accumulate_transition(&mut self) {
        let (n, nd) = (self.n, self.nd);
        let full = &mut self.a_full;
        full.fill(0.0);
        full[..nd * n].copy_from_slice(&self.phi_step[..nd * n]);
        for i in nd..n {
            full[i * n + i] = 1.0;
        }
        matmul(full, &self.phi, n, n, n, &mut self.tmp);
        self.phi.copy_from_slice(&self.tmp);
    }

    /// Measurement update with measurement `y` and diagonal measurement noise variance `r`.
    /// Returns the normalised innovation squared; the innovation and its variance are then
    /// available from [`HybridEkf::innovation`] and [`HybridEkf::innovation_variance`].
    pub fn update<S: System>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        r: &[f64],
    ) -> Result<f64, Divergence> {
        let n = self.n;
        let m = y.len();
        debug_assert_eq!(m, sys.m());
        let w = &mut self.upd;
        w.resize(n, m);
        // H is usually a selection of states: then the update is done one measurement at a
        // time (exact for a linear h with diagonal R), each a rank-one Joseph update.
        if let Some(sel) = sys.selection() {
            for k in 0..m {
                w.sel[k] = sel[k];
                w.yhat[k] = self.x[sel[k]];
                w.nu[k] = y[k] - w.yhat[k];
            }
            return self.update_sequential(sys, t, r);
        }
        sys.observe(&self.x, &mut w.yhat, &mut w.h);
        for k in 0..m {
            w.nu[k] = y[k] - w.yhat[k];
        }
        if selection_rows(&w.h, m, n, &mut w.sel) {
            return self.update_sequential(sys, t, r);
        }
        // H P (m x n), its transpose P H^T (n x m), S = H P H^T + R (m x m)
        matmul(&w.h, &self.p, m, n, n, &mut w.hp);
        transpose(&w.hp, m, n, &mut w.pht);
        transpose(&w.h, m, n, &mut w.ht);
        matmul(&w.hp, &w.ht, m, n, m, &mut w.s);
        for k in 0..m {
            w.s[k * m + k] += r[k];
            w.s_diag[k] = w.s[k * m + k];
        }
        w.ls.copy_from_slice(&w.s);
        cholesky(&mut w.ls, m).map_err(|i| Divergence {
            time: t,
            reason: format!("innovation covariance lost positive definiteness (pivot {i})"),
        })?;
        crate::linalg::cholesky_inverse(&w.ls, m, &mut w.sinv);
        // K = P H^T S^-1 (n x m) and its transpose
        matmul(&w.pht, &w.sinv, n, m, m, &mut w.k);
        transpose(&w.k, n, m, &mut w.kt);
        let mut nis = 0.0;
        for k in 0..m {
            let mut sn = 0.0;
            for l in 0..m {
                sn += w.sinv[k * m + l] * w.nu[l];
            }
            nis += w.nu[k] * sn;
        }
        for i in 0..n {
            let mut dx = 0.0;
            for k in 0..m {
                dx += w.k[i * m + k] * w.nu[k];
            }
            self.x[i] += dx;
        }
        // Joseph form: P = B P B^T + K R K^T with B = I - K H.
        // B P = P - K (H P)
        let bp = &mut self.tmp;
        matmul(&w.k, &w.hp, n, m, n, bp);
        for (b, p) in bp.iter_mut().zip(&self.p) {
            *b = p - *b;
        }
        // P_new = BP - (BP H^T) K^T + K R K^T = BP + (K R - BP H^T) K^T
        matmul(bp, &w.ht, n, n, m, &mut w.wm);
        for i in 0..n {
            for k in 0..m {
                w.wm[i * m + k] = w.k[i * m + k] * r[k] - w.wm[i * m + k];
            }
        }
        matmul(&w.wm, &w.kt, n, m, n, &mut self.tmp2);
        for i in 0..n * n {
            self.p[i] = self.tmp[i] + self.tmp2[i];
        }
        self.finish_update(sys, t, nis)
    }

    /// Sequential scalar updates for a selection H: for each measured state j,
    /// k = P e_j / s with s = P_jj + r_j, then Joseph form with B = I - k e_j^T:
    /// P1 = B P = P - k P_j, P = P1 B^T + r k k^T = P1 - (P1 e_j) k^T + r k k^T.
    /// The NIS of the vector innovation is the sum of the scalar ones.
    fn update_sequential<S: System>(
        &mut self,
        sys: &mut S,
        t: f64,
        r: &[f64],
    ) -> Result<f64, Divergence> {
        let n = self.n;
        let w = &mut self.upd;
        let m = w.m;
        let p = &mut self.p;
        let kvec = &mut w.k[..n];
        let col = &mut w.wm[..n];
        let row_j = &mut w.ht[..n];
        for a in 0..m {
            let j = w.sel[a];
            w.s_diag[a] = p[j * n + j] + r[a];
        }
        let mut nis = 0.0;
        for a in 0..m {
            let j = w.sel[a];
            let s = p[j * n + j] + r[a];
            if !(s > 0.0 && s.is_finite()) {
                return Err(Divergence {
                    time: t,
                    reason: format!(
                        "innovation variance of measurement {a} is not positive ({s:e})"
                    ),
                });
            }
            // innovation against the current (partly updated) state
            let nu = w.nu[a] - (self.x[j] - w.yhat[a]);
            nis += nu * nu / s;
            // p = P e_j (= row j, P symmetric), k = p / s
            row_j.copy_from_slice(&p[j * n..(j + 1) * n]);
            let pjj = row_j[j];
            for ((k, x), pi) in kvec.iter_mut().zip(self.x.iter_mut()).zip(row_j.iter()) {
                *k = pi / s;
                *x += *k * nu;
            }
            // Joseph form with B = I - k e_j^T: P1 = B P = P - k p^T, whose column j is
            // p - k p_jj; P = P1 B^T + r k k^T = P1 - (P1 e_j) k^T + r k k^T. Fused:
            // P_il += -k_i p_l + (r k_i - (p_i - k_i p_jj)) k_l.
            for ((c, k), pi) in col.iter_mut().zip(kvec.iter()).zip(row_j.iter()) {
                *c = r[a] * k - (pi - k * pjj);
            }
            for ((prow, ki), ci) in p.chunks_exact_mut(n).zip(kvec.iter()).zip(col.iter()) {
                for ((pv, pl), kl) in prow.iter_mut().zip(row_j.iter()).zip(kvec.iter()) {
                    *pv += ci * kl - ki * pl;
                }
            }
        }
        self.finish_update(sys, t, nis)
    }

    /// Symmetrises P and checks state, covariance and the system after an update.
    fn finish_update<S: System>(
        &mut self,
        sys: &mut S,
        t: f64,
        nis: f64,
    ) -> Result<f64, Divergence> {
        symmetrize(&mut self.p, self.n);
        if let Some(i) = self.x.iter().position(|v| !v.is_finite()) {
            return Err(Divergence {
                time: t,
                reason: format!("state {i} became non-finite in the update"),
            });
        }
        self.updates_since_check += 1;
        let diag_ok = (0..self.n).all(|i| self.p[i * self.n + i] > 0.0);
        if !diag_ok || self.updates_since_check >= CHECK_EVERY {
            self.check_covariance(t)?;
        }
        sys.check(&self.x)
            .map_err(|reason| Divergence { time: t, reason })?;
        Ok(nis)
    }

    /// The innovation y - h(x_prior) of the last update.
    pub fn innovation(&self) -> &[f64] {
        &self.upd.nu
    }

    /// The diagonal of the innovation covariance S = H P H^T + R of the last update.
    pub fn innovation_variance(&self) -> &[f64] {
        &self.upd.s_diag
    }

    /// Fails when P is not finite or not positive definite (a Cholesky factorisation). The
    /// filter does this after every `CHECK_EVERY`-th update and whenever a variance is not
    /// positive; call it at the end of a run to check the last samples too.
    pub fn check_covariance(&mut self, t: f64) -> Result<(), Divergence> {
        self.updates_since_check = 0;
        self.chol.copy_from_slice(&self.p);
        cholesky(&mut self.chol, self.n).map_err(|i| Divergence {
            time: t,
            reason: format!("the covariance lost positive definiteness (state {i})"),
        })
    }
}

/// Work space of the measurement update, sized for the current number of measurements.
#[derive(Debug, Clone, Default)]
struct UpdateWork {
    m: usize,
    yhat: Vec<f64>,
    nu: Vec<f64>,
    s_diag: Vec<f64>,
    h: Vec<f64>,
    ht: Vec<f64>,
    hp: Vec<f64>,
    pht: Vec<f64>,
    s: Vec<f64>,
    ls: Vec<f64>,
    sinv: Vec<f64>,
    k: Vec<f64>,
    kt: Vec<f64>,
    wm: Vec<f64>,
    sel: Vec<usize>,
}

impl UpdateWork {
    fn resize(&mut self, n: usize, m: usize) {
        if self.m == m && self.h.len() == m * n {
            return;
        }
        self.m = m;
        for (v, len) in [
            (&mut self.yhat, m),
            (&mut self.nu, m),
            (&mut self.s_diag, m),
            (&mut self.h, m * n),
            (&mut self.ht, m * n),
            (&mut self.hp, m * n),
            (&mut self.pht, m * n),
            (&mut self.s, m * m),
            (&mut self.ls, m * m),
            (&mut self.sinv, m * m),
            (&mut self.k, m * n),
            (&mut self.kt, m * n),
            (&mut self.wm, m * n),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
        self.sel.clear();
        self.sel.resize(m, 0);
    }
}

/// True when every row of H (m x n) is a unit vector; `sel` receives the selected columns.
fn selection_rows(h: &[f64], m: usize, n: usize, sel: &mut [usize]) -> bool {
    for k in 0..m {
        let row = &h[k * n..(k + 1) * n];
        let mut one = None;
        for (j, &v) in row.iter().enumerate() {
            if v == 1.0 && one.is_none() {
                one = Some(j);
            } else if v != 0.0 {
                return false;
            }
        }
        match one {
            Some(j) => sel[k] = j,
            None => return false,
        }
    }
    true
}

fn identity(a: &mut [f64], n: usize) {
    a.fill(0.0);
    for i in 0..n {
        a[i * n + i] = 1.0;
    }
}

fn transpose(a: &[f64], r: usize, c: usize, out: &mut [f64]) {
    for i in 0..r {
        for j in 0..c {
            out[j * r + i] = a[i * c + j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x_dot = -a x with unknown a appended; y = x.
    struct Decay {
        calls: usize,
    }

    impl System for Decay {
        fn n(&self) -> usize {
            2
        }
        fn nd(&self) -> usize {
            1
        }
        fn m(&self) -> usize {
            1
        }
        fn derivative(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) {
            self.calls += 1;
            dx[0] = -x[1] * x[0];
        }
        fn jacobian(&mut self, t: f64, x: &[f64], dx: &mut [f64], f: &mut [f64]) {
            self.derivative(t, x, dx);
            f[0] = -x[1];
            f[1] = -x[0];
        }
        fn observe(&mut self, x: &[f64], y: &mut [f64], h: &mut [f64]) {
            y[0] = x[0];
            h[0] = 1.0;
            h[1] = 0.0;
        }
        fn check(&mut self, _x: &[f64]) -> Result<(), String> {
            Ok(())
        }
    }

    #[test]
    fn linear_prediction_matches_the_exact_solution() {
        // a known (P_aa = 0): x(t) = x0 exp(-a t), P_xx(t) = P0 exp(-2 a t)
        let mut sys = Decay { calls: 0 };
        let mut f = HybridEkf::new(
            2,
            1,
            vec![2.0, 0.7],
            vec![0.5, 0.0, 0.0, 1e-12],
            vec![0.0; 2],
            20,
        );
        f.predict(&mut sys, 0.0, 1.0, None).unwrap();
        assert!((f.x[0] - 2.0 * (-0.7f64).exp()).abs() < 1e-6);
        assert!((f.p[0] - 0.5 * (-1.4f64).exp()).abs() < 1e-6);
    }

    #[test]
    fn identifies_a_decay_rate() {
        let a_true: f64 = 0.8;
        let mut sys = Decay { calls: 0 };
        let mut f = HybridEkf::new(
            2,
            1,
            vec![1.0, 0.0],
            vec![1e-6, 0.0, 0.0, 1.0],
            vec![0.0; 2],
            1,
        );
        let dt = 0.01;
        let mut t = 0.0;
        f.update(&mut sys, 0.0, &[1.0], &[1e-8]).unwrap();
        for k in 1..300 {
            let t1 = k as f64 * dt;
            f.predict(&mut sys, t, t1, None).unwrap();
            let y = (-a_true * t1).exp();
            f.update(&mut sys, t1, &[y], &[1e-8]).unwrap();
            t = t1;
        }
        assert!((f.x[1] - a_true).abs() < 1e-3, "a = {}", f.x[1]);
        // Joseph form keeps P symmetric positive definite
        assert_eq!(f.p[1], f.p[2]);
        assert!(f.p[3] > 0.0);
    }

    #[test]
    fn a_bad_measurement_noise_is_reported_with_its_time() {
        let mut sys = Decay { calls: 0 };
        let mut f = HybridEkf::new(2, 1, vec![1.0, 0.5], vec![0.0; 4], vec![0.0; 2], 1);
        let e = f.update(&mut sys, 1.25, &[1.0], &[-1.0]).unwrap_err();
        assert_eq!(e.time, 1.25);
        assert!(e.to_string().contains("t = 1.2500"), "{e}");
    }
}
