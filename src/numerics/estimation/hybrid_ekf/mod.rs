//! Hybrid (continuous-discrete) extended Kalman filter (paper eq. 9-19; Simon 2006,
//! section 13.2.3).
//!
//! Between samples the state follows x_dot = f(x) with classical RK4 ([`crate::numerics::ode::Rk4`],
//! the stepper the simulation uses; Butcher 2008, section 32), in steps no longer than
//! [`HybridEkf::max_step`] ([`crate::numerics::ode::steps_for`]). The covariance follows
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
//!
//! The same type runs the two other forms of the filter ([`HybridEkf::kind`]): the
//! discrete-time EKF with explicit Euler ([`crate::numerics::estimation::discrete_ekf`]) and the
//! continuous-time Kalman-Bucy filter ([`crate::numerics::estimation::kalman_bucy`]); they share the
//! work space, the checks and the measurement update here.

use super::{FilterKind, System};
use crate::numerics::linalg::{dot, dot3, matmul, symmetrize};
use crate::numerics::ode::{self, Rk4};
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
/// per sample.
#[derive(Debug, Clone)]
pub struct HybridEkf {
    pub(super) n: usize,
    pub(super) nd: usize,
    /// Which form of the filter runs (default [`FilterKind::Hybrid`]).
    pub kind: FilterKind,
    /// State estimate.
    pub x: Vec<f64>,
    /// Covariance, n x n row-major, symmetric.
    pub p: Vec<f64>,
    /// Process noise spectral density, diagonal (length n), per second.
    pub q: Vec<f64>,
    /// Longest RK4 step, s: each sample interval is integrated in ceil(dt / max_step) equal
    /// steps, so a gap in the data is crossed in steps no longer than the regular ones.
    pub max_step: f64,
    /// Innovation gate in standard deviations (0: none): a measurement whose innovation
    /// exceeds `gate` times the square root of its predicted variance is not used
    /// (Bar-Shalom, Li & Kirubarajan 2001, section 2.4.3, validation gate).
    pub gate: f64,
    /// Measurements (indices into y) exempt from the gate: beyond it they are used, and
    /// only reported in [`HybridEkf::beyond_gate`].
    pub ungated: Vec<bool>,
    pub(super) beyond: Vec<GateEvent>,
    /// ln det S of the last update's innovation covariance over the measurements it used
    /// (with the NIS, the sample's term of the innovations' -2 log-likelihood; 0 for the
    /// continuous filter).
    pub log_det_s: f64,
    // work space
    pub(super) f: Vec<f64>,
    pub(super) fp: Vec<f64>,
    rk4: Rk4,
    chol: Vec<f64>,
    pub(super) phi: Vec<f64>,
    pub(super) phi_step: Vec<f64>,
    a_full: Vec<f64>,
    tmp: Vec<f64>,
    tmp2: Vec<f64>,
    pub(super) upd: UpdateWork,
    updates_since_check: usize,
    /// The Kalman-Bucy filter's held measurement and work space (empty for the others).
    pub(super) kb: crate::numerics::estimation::kalman_bucy::Work,
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
        max_step: f64,
    ) -> Self {
        assert!(nd <= n && x0.len() == n && p0.len() == n * n && q.len() == n);
        let z = |len| vec![0.0; len];
        HybridEkf {
            n,
            nd,
            kind: FilterKind::Hybrid,
            x: x0,
            p: p0,
            q,
            max_step,
            gate: 0.0,
            ungated: Vec::new(),
            beyond: Vec::new(),
            f: z(nd * n),
            fp: z(nd * n),
            rk4: Rk4::new(n, nd),
            chol: z(n * n),
            phi: z(n * n),
            phi_step: z(n * n),
            a_full: z(n * n),
            tmp: z(n * n),
            tmp2: z(n * n),
            upd: UpdateWork::default(),
            updates_since_check: 0,
            log_det_s: 0.0,
            kb: Default::default(),
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

    /// Propagates state and covariance from `t0` to `t1` by the filter's form
    /// ([`HybridEkf::kind`]). When `phi` is given it receives the state transition matrix of
    /// the interval (for the smoother; the continuous filter has none and fails).
    pub fn predict<S: System>(
        &mut self,
        sys: &mut S,
        t0: f64,
        t1: f64,
        phi: Option<&mut [f64]>,
    ) -> Result<(), Divergence> {
        match self.kind {
            FilterKind::Hybrid => self.propagate(sys, t0, t1, phi, |f, sys, t, h| {
                // state: classical RK4 of the dynamic states (the parameters have zero
                // derivative); F = df/dx at the step's start, for the covariance below
                let jac = &mut f.f;
                f.rk4.step(t, h, &mut f.x, |at, x, dx, at_start| {
                    if at_start {
                        sys.jacobian(at, x, dx, jac);
                    } else {
                        sys.derivative(at, x, dx);
                    }
                });
                // covariance: P <- Phi P Phi^T + Q_d with Phi the RK4 propagator (module docs)
                f.propagator(h);
                f.covariance_step(h);
                Ok(())
            }),
            FilterKind::Discrete => self.propagate(sys, t0, t1, phi, Self::euler_step),
            FilterKind::Continuous if phi.is_some() => Err(Divergence {
                time: t0,
                reason: "the continuous (Kalman-Bucy) filter has no transition matrix between \
                         samples: the RTS smoother cannot run on it"
                    .into(),
            }),
            FilterKind::Continuous => self.predict_kalman_bucy(sys, (t0, t1)),
        }
    }

    /// The steps of no more than [`HybridEkf::max_step`] from `t0` to `t1`, or the error
    /// naming an interval that would need too many.
    pub(super) fn steps(&self, t0: f64, t1: f64) -> Result<usize, Divergence> {
        ode::steps_for(t1 - t0, self.max_step).ok_or_else(|| Divergence {
            time: t0,
            reason: format!(
                "the interval from t = {t0} s to {t1} s would need more than {} steps of \
                 {} s",
                ode::MAX_STEPS_PER_INTERVAL,
                self.max_step
            ),
        })
    }

    /// The prediction in equal sub-steps of at most `max_step`: `step(self, sys, t, h)`
    /// advances x and P over one sub-step and leaves its transition matrix's top rows in
    /// `phi_step`, which are accumulated into the interval's when `phi` is wanted; the state
    /// is checked after each sub-step, the covariance and the system at the end.
    pub(super) fn propagate<S: System>(
        &mut self,
        sys: &mut S,
        t0: f64,
        t1: f64,
        phi: Option<&mut [f64]>,
        mut step: impl FnMut(&mut Self, &mut S, f64, f64) -> Result<(), Divergence>,
    ) -> Result<(), Divergence> {
        let steps = self.steps(t0, t1)?;
        if phi.is_some() {
            identity(&mut self.phi, self.n);
        }
        for (t, h) in ode::substeps(t0, t1, steps) {
            step(self, sys, t, h)?;
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
        if let Some(phi_out) = phi {
            phi_out.copy_from_slice(&self.phi);
        }
        self.finish_prediction(sys, t1)
    }

    /// The end of every prediction: P symmetrised and checked finite, the state checked by
    /// the system.
    pub(super) fn finish_prediction<S: System>(
        &mut self,
        sys: &mut S,
        t1: f64,
    ) -> Result<(), Divergence> {
        symmetrize(&mut self.p, self.n);
        if self.p.iter().any(|v| !v.is_finite()) {
            return Err(Divergence {
                time: t1,
                reason: "the covariance became non-finite during prediction".into(),
            });
        }
        sys.check(&self.x).map_err(|e| Divergence {
            time: t1,
            reason: e.to_string(),
        })
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
        congruence_blocks(&mut self.p, m, top, nd, n);
        trapezoidal_noise(&mut self.p, top, &self.q, nd, h);
    }

    /// Accumulates the full transition matrix of the sample interval: Phi <- Phi_step Phi.
    pub(super) fn accumulate_transition(&mut self) {
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
}

/// P <- Phi P Phi^T once M = Phi_top P is known (Phi = [[top], [0 I]]): new
/// P_xx = M Phi_top^T (symmetric: upper triangle, mirrored), new P_xz = M[:, nd..], P_zz
/// unchanged.
pub(super) fn congruence_blocks(p: &mut [f64], m: &[f64], top: &[f64], nd: usize, n: usize) {
    crate::numerics::linalg::dispatch!(congruence_blocks_impl(p, m, top, nd, n))
}

#[inline(always)]
fn congruence_blocks_impl(p: &mut [f64], m: &[f64], top: &[f64], nd: usize, n: usize) {
    for i in 0..nd {
        let mi = &m[i * n..(i + 1) * n];
        for j in i..nd {
            let v = dot(mi, &top[j * n..(j + 1) * n]);
            p[i * n + j] = v;
            p[j * n + i] = v;
        }
        for j in nd..n {
            p[i * n + j] = mi[j];
            p[j * n + i] = mi[j];
        }
    }
}

/// P += Q_d = h (Phi Q Phi^T + Q) / 2 with Q diagonal, where (Phi Q Phi^T)_ij =
/// sum_k top_ik q_k top_jk for i, j < nd, top_ij q_j for i < nd <= j, and q_i on the
/// diagonal below.
fn trapezoidal_noise(p: &mut [f64], top: &[f64], q: &[f64], nd: usize, h: f64) {
    crate::numerics::linalg::dispatch!(trapezoidal_noise_impl(p, top, q, nd, h))
}

#[inline(always)]
fn trapezoidal_noise_impl(p: &mut [f64], top: &[f64], q: &[f64], nd: usize, h: f64) {
    let n = q.len();
    if q.iter().all(|&v| v == 0.0) {
        return;
    }
    let half_h = 0.5 * h;
    for i in 0..nd {
        let ti = &top[i * n..(i + 1) * n];
        for j in i..nd {
            let v = dot3(ti, q, &top[j * n..(j + 1) * n]);
            let qd = half_h * (v + if i == j { q[i] } else { 0.0 });
            p[i * n + j] += qd;
            if j != i {
                p[j * n + i] += qd;
            }
        }
        for j in nd..n {
            let qd = half_h * ti[j] * q[j];
            p[i * n + j] += qd;
            p[j * n + i] += qd;
        }
    }
    for i in nd..n {
        p[i * n + i] += h * q[i];
    }
}

pub(super) fn identity(a: &mut [f64], n: usize) {
    a.fill(0.0);
    for i in 0..n {
        a[i * n + i] = 1.0;
    }
}

pub(super) fn transpose(a: &[f64], r: usize, c: usize, out: &mut [f64]) {
    for i in 0..r {
        for j in 0..c {
            out[j * r + i] = a[i * c + j];
        }
    }
}

mod update;

pub use update::GateEvent;
pub(super) use update::{note_beyond, UpdateWork};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::linalg::simd_check;
    use crate::numerics::ode::StageTime;

    /// y = x_0 + x_1 of two constant states: an H that is not a selection (the matrix update).
    struct Sum;

    impl System for Sum {
        fn n(&self) -> usize {
            2
        }
        fn nd(&self) -> usize {
            2
        }
        fn m(&self) -> usize {
            1
        }
        fn derivative(&mut self, _at: StageTime, _x: &[f64], dx: &mut [f64]) {
            dx.fill(0.0);
        }
        fn jacobian(&mut self, _at: StageTime, _x: &[f64], dx: &mut [f64], f: &mut [f64]) {
            dx.fill(0.0);
            f.fill(0.0);
        }
        fn observe(&mut self, _at: StageTime, x: &[f64], y: &mut [f64], h: &mut [f64]) {
            y[0] = x[0] + x[1];
            h.copy_from_slice(&[1.0, 1.0]);
        }
        fn check(&mut self, _x: &[f64]) -> Result<(), crate::base::error::Unphysical> {
            Ok(())
        }
    }

    /// ln det S of an update is that of H P H^T + R, by the matrix update and by the
    /// sequential one (a selection H), and the NIS is the innovation's square over S.
    #[test]
    fn the_update_gives_ln_det_s_with_the_nis() {
        let p0 = vec![0.5, 0.1, 0.1, 0.2];
        let mut f = HybridEkf::new(2, 2, vec![0.0, 0.0], p0.clone(), vec![0.0; 2], 0.1);
        let nis = f.update(&mut Sum, 0.0, &[0.3], &[0.05]).unwrap();
        let s = 0.5 + 0.2 + 2.0 * 0.1 + 0.05;
        assert!((f.log_det_s - f64::ln(s)).abs() < 1e-12, "{}", f.log_det_s);
        assert!((nis - 0.09 / s).abs() < 1e-12, "{nis}");
        let mut sys = crate::numerics::estimation::test_systems::Linear {
            a: vec![0.0],
            nd: 1,
            n: 2,
        };
        let mut f = HybridEkf::new(2, 1, vec![0.0, 0.0], p0, vec![0.0; 2], 0.1);
        f.update(&mut sys, 0.0, &[0.3], &[0.05]).unwrap();
        assert!(
            (f.log_det_s - f64::ln(0.55)).abs() < 1e-12,
            "{}",
            f.log_det_s
        );
    }

    /// Numbers of dynamic states tried with `n` states in all: one, about half, all.
    fn dynamic_sizes(n: usize) -> Vec<usize> {
        let mut nd = vec![1, n.div_ceil(2), n];
        nd.dedup();
        nd
    }

    /// congruence_blocks through the dispatch (AVX2 where the processor has it) against its
    /// baseline copy, bit for bit, for every state count of `simd_check::SIZES`.
    #[test]
    fn congruence_blocks_avx2_and_baseline_copies_agree_to_the_bit() {
        if !simd_check::avx2_path_differs("congruence_blocks") {
            return;
        }
        let mut rng = simd_check::rng(3);
        for &n in &simd_check::SIZES {
            for nd in dynamic_sizes(n) {
                let (m, top) = (
                    simd_check::values(&mut rng, nd * n),
                    simd_check::values(&mut rng, nd * n),
                );
                let p = simd_check::values(&mut rng, n * n);
                let (mut p1, mut p2) = (p.clone(), p);
                congruence_blocks(&mut p1, &m, &top, nd, n);
                congruence_blocks_impl(&mut p2, &m, &top, nd, n);
                simd_check::assert_same_bits(&p1, &p2, &format!("n = {n}, nd = {nd}"));
            }
        }
    }

    /// trapezoidal_noise through the dispatch against its baseline copy, bit for bit: Q with
    /// every entry positive, with the coefficients' entries zero (as the filters have it),
    /// and all zero (the early return).
    #[test]
    fn trapezoidal_noise_avx2_and_baseline_copies_agree_to_the_bit() {
        if !simd_check::avx2_path_differs("trapezoidal_noise") {
            return;
        }
        let mut rng = simd_check::rng(4);
        for &n in &simd_check::SIZES {
            for nd in dynamic_sizes(n) {
                let top = simd_check::values(&mut rng, nd * n);
                let p = simd_check::values(&mut rng, n * n);
                let full: Vec<f64> = simd_check::values(&mut rng, n)
                    .iter()
                    .map(|v| v.abs())
                    .collect();
                let mut states_only = full.clone();
                states_only[nd..].fill(0.0);
                for (label, q) in [
                    ("full", full),
                    ("states", states_only),
                    ("zero", vec![0.0; n]),
                ] {
                    let (mut p1, mut p2) = (p.clone(), p.clone());
                    trapezoidal_noise(&mut p1, &top, &q, nd, 0.0123);
                    trapezoidal_noise_impl(&mut p2, &top, &q, nd, 0.0123);
                    let case = format!("n = {n}, nd = {nd}, Q {label}");
                    simd_check::assert_same_bits(&p1, &p2, &case);
                }
            }
        }
    }

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
        fn derivative(&mut self, _at: StageTime, x: &[f64], dx: &mut [f64]) {
            self.calls += 1;
            dx[0] = -x[1] * x[0];
        }
        fn jacobian(&mut self, at: StageTime, x: &[f64], dx: &mut [f64], f: &mut [f64]) {
            self.derivative(at, x, dx);
            f[0] = -x[1];
            f[1] = -x[0];
        }
        fn observe(&mut self, _at: StageTime, x: &[f64], y: &mut [f64], h: &mut [f64]) {
            y[0] = x[0];
            h[0] = 1.0;
            h[1] = 0.0;
        }
        fn check(&mut self, _x: &[f64]) -> Result<(), crate::base::error::Unphysical> {
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
            0.05,
        );
        f.predict(&mut sys, 0.0, 1.0, None).unwrap();
        assert!((f.x[0] - 2.0 * (-0.7f64).exp()).abs() < 1e-6);
        assert!((f.p[0] - 0.5 * (-1.4f64).exp()).abs() < 1e-6);
    }

    #[test]
    fn a_gap_is_crossed_in_steps_no_longer_than_the_regular_ones() {
        // samples every 10 ms, then a 3 s gap: integrated in 300 steps of 10 ms, not one
        let mut sys = Decay { calls: 0 };
        let mut f = HybridEkf::new(
            2,
            1,
            vec![2.0, 0.7],
            vec![0.5, 0.0, 0.0, 1e-12],
            vec![0.0; 2],
            0.01,
        );
        f.predict(&mut sys, 1.0, 4.0, None).unwrap();
        assert_eq!(sys.calls, 4 * 300, "RK4 calls");
        assert!(
            (f.x[0] - 2.0 * (-0.7f64 * 3.0).exp()).abs() < 1e-9,
            "{}",
            f.x[0]
        );
        assert!((f.p[0] - 0.5 * (-1.4f64 * 3.0).exp()).abs() < 1e-9);
        // an absurd gap is an error naming it, not hours of integration
        let e = f.predict(&mut sys, 4.0, 1e9, None).unwrap_err();
        assert!(e.reason.contains("would need more than"), "{e}");
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
            0.01,
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
        let mut f = HybridEkf::new(2, 1, vec![1.0, 0.5], vec![0.0; 4], vec![0.0; 2], 1.0);
        let e = f.update(&mut sys, 1.25, &[1.0], &[-1.0]).unwrap_err();
        assert_eq!(e.time, 1.25);
        assert!(e.to_string().contains("t = 1.2500"), "{e}");
    }
}
