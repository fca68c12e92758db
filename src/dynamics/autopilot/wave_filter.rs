//! The wave filter inside the closed loop: the hybrid EKF on the identified model's states (no
//! coefficient estimated), run online on the compass, giving the autopilot the low-frequency
//! heading psi_L and yaw rate r_L (Fossen 2011, 11.3: wave filtering by a Kalman filter on the
//! ship and wave models; the paper's eq. 20-25).
//!
//! Two choices decide how much wave motion reaches the rudder:
//! - the process noise on r_L (the paper's w_L, unmodelled yaw moments): by default the one
//!   that puts the filter's own low-frequency bandwidth a decade below the wave frequency;
//! - the start: the filter starts with its stationary covariance, so that its first gains are
//!   its steady ones rather than those of a unit covariance that let the compass, waves
//!   included, through for the first tens of seconds.

use super::closed_loop::{LoopError, Scenario};
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::InputSeries;
use crate::model::models::Model;
use crate::numerics::estimation::{Divergence, HybridEkf};

/// The process noise on r_L (rad^2/s^3) that puts the filter's low-frequency bandwidth a
/// decade below the wave frequency `w0`: the steady-state Kalman filter of a double
/// integrator (psi_L, r_L) measured with noise variance R has the natural frequency
/// (q / R)^(1/4) (Gelb 1974, Applied Optimal Estimation, ch. 4), so q = R (w0 / 10)^4.
/// Without a wave frequency, 1e-7.
pub fn default_rate_noise(compass_noise: f64, w0: Option<f64>) -> f64 {
    match w0 {
        Some(w0) => compass_noise.powi(2) * (w0 / 10.0).powi(4),
        None => 1e-7,
    }
}

/// The filter, with where it reads the heading and the yaw rate.
pub(super) struct WaveFilter {
    pub(super) ekf: HybridEkf,
    /// The coefficients estimated as appended states (none for the plain wave filter), and
    /// their scales.
    est: Vec<usize>,
    scale: Vec<f64>,
    psi_i: usize,
    r_i: usize,
    compass_i: usize,
    r_var: [f64; 1],
}

/// Samples at most spent settling the covariance, and the relative change that ends it.
const SETTLE_SAMPLES: usize = 100_000;
const SETTLED: f64 = 1e-10;

impl WaveFilter {
    /// The filter on `model` with `c`, its process noise the scenario's (every other state
    /// a small 1e-9 SI^2/s so that no covariance collapses and the filter keeps listening;
    /// r_L the scenario's `rate_noise` or [`default_rate_noise`]), settled to its stationary
    /// covariance.
    pub(super) fn new<M: Model>(
        model: &M,
        c: &[f64],
        (psi_i, r_i, compass_i): (usize, usize, usize),
        s: &Scenario,
    ) -> Result<Self, LoopError> {
        let nx = model.nx();
        let rate_noise = s
            .rate_noise
            .unwrap_or_else(|| default_rate_noise(s.compass_noise, model.wave_frequency(c)));
        let q = s
            .process_noise
            .iter()
            .enumerate()
            .map(|(i, q)| q.max(if i == r_i { rate_noise } else { 1e-9 }))
            .collect();
        let mut p0 = vec![0.0; nx * nx];
        for i in 0..nx {
            p0[i * nx + i] = 1.0;
        }
        let mut f = WaveFilter {
            ekf: HybridEkf::new(nx, nx, vec![0.0; nx], p0, q, s.dt),
            est: Vec::new(),
            scale: Vec::new(),
            psi_i,
            r_i,
            compass_i,
            r_var: [s.compass_noise.powi(2).max(1e-12)],
        };
        f.settle(model, c, s.dt)?;
        Ok(f)
    }

    /// Runs the covariance to its stationary value: predictions and updates on measurements
    /// equal to the prediction (the model is linear in its states, so the covariance does
    /// not depend on them), until no variance changes by more than [`SETTLED`] relatively.
    fn settle<M: Model>(&mut self, model: &M, c: &[f64], dt: f64) -> Result<(), LoopError> {
        let nx = model.nx();
        let diagonal = |p: &[f64]| (0..nx).map(|i| p[i * nx + i]).collect::<Vec<f64>>();
        let mut last = diagonal(&self.ekf.p);
        for k in 1..=SETTLE_SAMPLES {
            let t = k as f64 * dt;
            self.sample(model, c, (t - dt, t), 0.0, None)?;
            let predicted = model.output_values(&self.ekf.x, &[0.0], c)[self.compass_i];
            self.sample(model, c, (t, t), 0.0, Some(predicted))?;
            let now = diagonal(&self.ekf.p);
            let settled = now
                .iter()
                .zip(&last)
                .all(|(a, b)| (a - b).abs() <= SETTLED * a.abs().max(1e-300));
            last = now;
            if settled {
                break;
            }
        }
        self.ekf.x.iter_mut().for_each(|x| *x = 0.0);
        Ok(())
    }

    /// Appends the coefficients at `est` of the model to the settled filter's state (the
    /// online estimation of the adaptive autopilot; Dinh, Hoang & Pham 2016, eq. 20-22: K,
    /// 1/T and the rudder bias as states of a random walk), starting at `values` with the
    /// standard deviations `sigma` and the random-walk intensities `q` (SI^2/s); each scaled
    /// by its starting magnitude so that the filter works on numbers near one.
    pub(super) fn augment(&mut self, est: Vec<usize>, values: &[f64], sigma: &[f64], q: &[f64]) {
        let nd = self.ekf.x.len();
        let n = nd + est.len();
        let scale: Vec<f64> = values
            .iter()
            .map(|v| if v.abs() > 1e-12 { v.abs() } else { 1.0 })
            .collect();
        let mut x = self.ekf.x.clone();
        x.extend(values.iter().zip(&scale).map(|(v, s)| v / s));
        let mut p = vec![0.0; n * n];
        for i in 0..nd {
            for j in 0..nd {
                p[i * n + j] = self.ekf.p[i * nd + j];
            }
        }
        let mut qs = self.ekf.q.clone();
        for (k, s) in scale.iter().enumerate() {
            p[(nd + k) * n + nd + k] = (sigma[k] / s).powi(2);
            qs.push(q[k] / (s * s));
        }
        let dt = self.ekf.max_step;
        self.ekf = HybridEkf::new(n, nd, x, p, qs, dt);
        self.est = est;
        self.scale = scale;
    }

    /// The estimated coefficients (SI) and their covariance (row-major), in the order
    /// appended.
    pub(super) fn estimates(&self) -> (Vec<f64>, Vec<f64>) {
        let (n, nd, ne) = (
            self.ekf.x.len(),
            self.ekf.x.len() - self.est.len(),
            self.est.len(),
        );
        let values = (0..ne)
            .map(|i| self.ekf.x[nd + i] * self.scale[i])
            .collect();
        let mut cov = vec![0.0; ne * ne];
        for i in 0..ne {
            for j in 0..ne {
                cov[i * ne + j] = self.ekf.p[(nd + i) * n + nd + j] * self.scale[i] * self.scale[j];
            }
        }
        (values, cov)
    }

    /// Starts the estimate on the first compass reading (the ship on its course, no wave yaw
    /// known yet).
    fn start(&mut self, compass: f64) {
        self.ekf.x[self.psi_i] = compass;
    }

    /// The prediction from `t0` to `t1` with the rudder held at `delta`, then (with a
    /// compass reading at `t1`) the update.
    fn sample<M: Model>(
        &mut self,
        model: &M,
        c: &[f64],
        (t0, t1): (f64, f64),
        delta: f64,
        compass: Option<f64>,
    ) -> Result<(), LoopError> {
        let inputs = InputSeries::constant(&[delta]);
        let measured = [self.compass_i];
        let mut sys = ModelSystem::new(
            model,
            c.to_vec(),
            &self.est,
            &self.scale,
            &inputs,
            &measured,
        );
        let diverged = |d: Divergence| LoopError::FilterDiverged(d.reason);
        if t1 > t0 {
            self.ekf.predict(&mut sys, t0, t1, None).map_err(diverged)?;
        }
        if let Some(z) = compass {
            self.ekf
                .update(&mut sys, t1, &[z], &self.r_var)
                .map_err(diverged)?;
        }
        Ok(())
    }

    /// Sample `k` at `t`: the filter started on the first compass reading, then
    /// [`Self::step`]; returns psi_L and r_L.
    pub(super) fn read<M: Model>(
        &mut self,
        (k, t, dt): (usize, f64, f64),
        model: &M,
        c: &[f64],
        delta: f64,
        compass: f64,
    ) -> Result<(f64, f64), LoopError> {
        if k == 0 {
            self.start(compass);
        }
        self.step(model, c, t, dt, delta, compass)
    }

    /// One sample: the prediction over the interval ending at `t` with the rudder held at
    /// `delta` (none at the first sample), the update on `compass`; returns psi_L and r_L.
    pub(super) fn step<M: Model>(
        &mut self,
        model: &M,
        c: &[f64],
        t: f64,
        dt: f64,
        delta: f64,
        compass: f64,
    ) -> Result<(f64, f64), LoopError> {
        self.sample(model, c, ((t - dt).max(0.0), t), delta, Some(compass))?;
        Ok((self.ekf.x[self.psi_i], self.ekf.x[self.r_i]))
    }
}
