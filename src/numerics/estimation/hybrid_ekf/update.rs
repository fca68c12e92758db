//! The measurement update in Joseph form: sequential rank-one updates when the
//! measurements are a selection of states, a matrix update otherwise.

use super::{transpose, Divergence, HybridEkf, CHECK_EVERY};
use crate::numerics::estimation::System;
use crate::numerics::linalg::{cholesky, matmul, rank_two_update, symmetrize};
use crate::numerics::ode::StageTime;

impl HybridEkf {
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
        if self.kind == crate::numerics::estimation::FilterKind::Continuous {
            // the Kalman-Bucy filter uses y over the next interval (kalman_bucy.rs)
            return self.hold_measurement(sys, (t, y, r));
        }
        let n = self.n;
        let m = y.len();
        debug_assert_eq!(m, sys.m());
        let w = &mut self.upd;
        w.resize(n, m);
        self.beyond.clear();
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
        sys.observe(StageTime::at(t), &self.x, &mut w.yhat, &mut w.h);
        for k in 0..m {
            w.nu[k] = y[k] - w.yhat[k];
        }
        if selection_rows(&w.h, m, n, &mut w.sel) {
            return self.update_sequential(sys, t, r);
        }
        // H P (m x n), its transpose P H^T (n x m), S = H P H^T + R (m x m)
        w.innovation_covariance(&self.p, r, n);
        self.drop_unusable(r);
        let w = &mut self.upd;
        w.ls.copy_from_slice(&w.s);
        cholesky(&mut w.ls, m).map_err(|i| Divergence {
            time: t,
            reason: format!("innovation covariance lost positive definiteness (pivot {i})"),
        })?;
        crate::numerics::linalg::cholesky_inverse(&w.ls, m, &mut w.sinv);
        // ln det S = 2 sum ln L_kk; a dropped row (zero H, S_kk = r_k) is no measurement
        self.log_det_s = (0..m)
            .map(|k| {
                let dropped = w.h[k * n..(k + 1) * n].iter().all(|v| *v == 0.0);
                2.0 * w.ls[k * m + k].ln() - if dropped { r[k].ln() } else { 0.0 }
            })
            .sum();
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
        self.joseph(r);
        self.finish_update(sys, t, nis)
    }

    /// Drops a missing (NaN) or gated measurement from the matrix update, recomputing the
    /// innovation covariance when one was dropped.
    fn drop_unusable(&mut self, r: &[f64]) {
        let n = self.n;
        let w = &mut self.upd;
        let m = w.m;
        // A missing (NaN) or gated measurement: a zero row of H with a zero innovation is
        // exactly no measurement (S is then block diagonal with r_k for that row).
        let mut dropped = false;
        for k in 0..m {
            let missing = !w.nu[k].is_finite();
            let gated = !missing
                && self.gate > 0.0
                && w.nu[k].powi(2) > self.gate.powi(2) * w.s_diag[k]
                && note_beyond(
                    &mut self.beyond,
                    &self.ungated,
                    k,
                    w.nu[k].abs() / w.s_diag[k].sqrt(),
                );
            if missing || gated {
                w.nu[k] = 0.0;
                w.h[k * n..(k + 1) * n].fill(0.0);
                dropped = true;
            }
        }
        if dropped {
            w.innovation_covariance(&self.p, r, n);
        }
    }

    /// The covariance of the matrix update in Joseph form, from the gain K and H P in the
    /// workspace.
    fn joseph(&mut self, r: &[f64]) {
        let n = self.n;
        let w = &mut self.upd;
        let m = w.m;
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
        self.log_det_s = 0.0;
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
            if !nu.is_finite() {
                // no measurement of this quantity at this sample (NaN: an excluded outlier)
                w.nu[a] = 0.0;
                continue;
            }
            if self.gate > 0.0
                && nu * nu > self.gate * self.gate * s
                && note_beyond(&mut self.beyond, &self.ungated, a, nu.abs() / s.sqrt())
            {
                w.nu[a] = 0.0;
                continue;
            }
            nis += nu * nu / s;
            self.log_det_s += s.ln();
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
            rank_two_update(p, kvec, col, row_j);
        }
        self.finish_update(sys, t, nis)
    }

    /// Symmetrises P and checks state, covariance and the system after an update.
    pub(in crate::numerics::estimation) fn finish_update<S: System>(
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
        sys.check(&self.x).map_err(|e| Divergence {
            time: t,
            reason: e.to_string(),
        })?;
        Ok(nis)
    }

    /// The innovation y - h(x_prior) of the last update (0 for a measurement that was
    /// missing or rejected by the gate).
    pub fn innovation(&self) -> &[f64] {
        &self.upd.nu
    }

    /// The measurements whose innovation lay beyond the gate in the last update, and whether
    /// each was rejected (it was used when exempt, see [`HybridEkf::ungated`]).
    pub fn beyond_gate(&self) -> &[GateEvent] {
        &self.beyond
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

/// A measurement whose innovation lay beyond the gate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GateEvent {
    /// Index into y.
    pub measurement: usize,
    /// The innovation in standard deviations of its predicted spread.
    pub sigmas: f64,
    /// Whether it was left out (false: exempt from the gate, used).
    pub rejected: bool,
}

/// Records measurement `k` beyond the gate; true when it is to be rejected.
pub(in crate::numerics::estimation) fn note_beyond(
    events: &mut Vec<GateEvent>,
    ungated: &[bool],
    k: usize,
    sigmas: f64,
) -> bool {
    let rejected = !ungated.get(k).copied().unwrap_or(false);
    events.push(GateEvent {
        measurement: k,
        sigmas,
        rejected,
    });
    rejected
}

/// Work space of the measurement update, sized for the current number of measurements.
#[derive(Debug, Clone, Default)]
pub(in crate::numerics::estimation) struct UpdateWork {
    pub(in crate::numerics::estimation) m: usize,
    pub(in crate::numerics::estimation) yhat: Vec<f64>,
    pub(in crate::numerics::estimation) nu: Vec<f64>,
    pub(in crate::numerics::estimation) s_diag: Vec<f64>,
    pub(in crate::numerics::estimation) h: Vec<f64>,
    ht: Vec<f64>,
    hp: Vec<f64>,
    pub(in crate::numerics::estimation) pht: Vec<f64>,
    pub(in crate::numerics::estimation) s: Vec<f64>,
    pub(in crate::numerics::estimation) ls: Vec<f64>,
    sinv: Vec<f64>,
    k: Vec<f64>,
    kt: Vec<f64>,
    wm: Vec<f64>,
    pub(in crate::numerics::estimation) sel: Vec<usize>,
}

impl UpdateWork {
    /// H P, P H^T, H^T and S = H P H^T + R (with its diagonal) from H and P.
    pub(in crate::numerics::estimation) fn innovation_covariance(
        &mut self,
        p: &[f64],
        r: &[f64],
        n: usize,
    ) {
        let m = self.m;
        matmul(&self.h, p, m, n, n, &mut self.hp);
        transpose(&self.hp, m, n, &mut self.pht);
        transpose(&self.h, m, n, &mut self.ht);
        matmul(&self.hp, &self.ht, m, n, m, &mut self.s);
        for k in 0..m {
            self.s[k * m + k] += r[k];
            self.s_diag[k] = self.s[k * m + k];
        }
    }

    pub(in crate::numerics::estimation) fn resize(&mut self, n: usize, m: usize) {
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
