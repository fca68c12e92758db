//! Classical fourth-order Runge-Kutta integration in fixed sub-steps (Butcher 2008,
//! section 32), shared by the simulation (`sim`, re-simulation) and the hybrid EKF's
//! prediction (`estimation::hybrid_ekf`: the state between samples; the filter propagates the
//! covariance, paper eq. 15, itself after each step, with the Jacobian taken at the step's
//! start).
//!
//! One step of size h from (t, x) for x_dot = f(t, x):
//!
//! ```text
//! k1 = f(t, x)
//! k2 = f(t + h/2, x + h/2 k1)
//! k3 = f(t + h/2, x + h/2 k2)
//! k4 = f(t + h,   x + h k3)
//! x <- x + h/6 (k1 + 2 k2 + 2 k3 + k4)
//! ```
//!
//! The state may be augmented with constants (the filter's estimated coefficients): only its
//! first `nd` components evolve, the others are passed to f unchanged. Nothing here knows of
//! models or filters, so both `sim` and `estimation` use it without depending on each other.
//!
//! Each evaluation of f gets a [`StageTime`]: its time and the start of its step. An input
//! held between samples (a zero-order hold: u(t) = u_k for t_k <= t < t_k+1; Astrom &
//! Wittenmark, "Computer-Controlled Systems", 3rd ed. 1997, section 2.3)
//! is constant over a step, which never crosses a sample time (each interval is divided into
//! whole steps), so it is read at the step's start: the last stage, at t + h = t_k+1, sees
//! the interval's value u_k (the left limit), not the next sample's, and one step of
//! x_dot = u gives x + h u_k exactly. Reading it at the step's start, rather than just
//! before t + h, holds whatever the rounding of t + h.

/// Most RK4 steps one sample interval may take: a longer gap than `MAX_STEPS_PER_INTERVAL`
/// times the step size is not integrated but reported (it would take hours, and no filter
/// or simulation result across it would mean anything).
pub const MAX_STEPS_PER_INTERVAL: usize = 1_000_000;

/// The longest RK4 step hydroid takes unless told otherwise, s: the filter's default
/// sub-steps and the re-simulation keep every step at or below it (10 ms resolves the
/// manoeuvring time scales of the vehicles hydroid models by two orders of magnitude).
pub const DEFAULT_MAX_STEP: f64 = 0.01;

/// RK4 steps for an interval `dt` so that no step exceeds `max_step`: ceil(dt / max_step),
/// at least 1. A part per billion of slack keeps an interval equal to the step (up to
/// rounding of the time stamps) at one step. None when the interval needs more than
/// [`MAX_STEPS_PER_INTERVAL`] steps.
pub fn steps_for(dt: f64, max_step: f64) -> Option<usize> {
    let n = (dt / max_step - 1e-9).ceil().max(1.0);
    (n <= MAX_STEPS_PER_INTERVAL as f64).then_some(n as usize)
}

/// The sub-steps of the interval from `t0` to `t1` in `steps` equal steps (at least one):
/// each step's start time and size.
pub fn substeps(t0: f64, t1: f64, steps: usize) -> impl Iterator<Item = (f64, f64)> {
    let steps = steps.max(1);
    let h = (t1 - t0) / steps as f64;
    (0..steps).map(move |s| (t0 + h * s as f64, h))
}

/// When one evaluation of the right-hand side is made: the stage's time and the start of the
/// step it belongs to (module docs: a held input is read at the step's start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageTime {
    /// The stage's time, s (t, t + h/2, t + h/2, t + h for the four stages of a step at t).
    pub t: f64,
    /// The start of its step, s: the sample interval a held input is read in.
    pub step_start: f64,
}

impl StageTime {
    /// An evaluation at `t` that is the start of its step (or is at a sample, not in a step).
    pub fn at(t: f64) -> Self {
        StageTime { t, step_start: t }
    }
}

/// Classical RK4 for a state of `n` components whose first `nd` evolve (the rest are
/// constants), with its work space: sizes are fixed at construction, a step allocates
/// nothing.
#[derive(Debug, Clone)]
pub struct Rk4 {
    nd: usize,
    k: [Vec<f64>; 4],
    xt: Vec<f64>,
}

impl Rk4 {
    /// Work space for states of `n` components of which the first `nd` evolve.
    pub fn new(n: usize, nd: usize) -> Self {
        assert!(nd <= n, "the evolving states are part of the state");
        let z = || vec![0.0; nd];
        Rk4 {
            nd,
            k: [z(), z(), z(), z()],
            xt: vec![0.0; n],
        }
    }

    /// One step of size `h` from time `t`: `x[..nd]` advances, `x[nd..]` stays.
    ///
    /// `f(at, x, dx, at_start)` writes the derivative of the evolving states at (at.t, x)
    /// into `dx` (length nd); `at.step_start` is `t` for all four stages. `at_start` is true
    /// for the first of the four evaluations, at the step's start state, where a caller may
    /// also take its Jacobian.
    #[inline]
    pub fn step<F>(&mut self, t: f64, h: f64, x: &mut [f64], mut f: F)
    where
        F: FnMut(StageTime, &[f64], &mut [f64], bool),
    {
        let at = |t_stage: f64| StageTime {
            t: t_stage,
            step_start: t,
        };
        let nd = self.nd;
        debug_assert_eq!(x.len(), self.xt.len());
        let [k1, k2, k3, k4] = &mut self.k;
        f(at(t), x, k1, true);
        if nd < x.len() {
            self.xt[nd..].copy_from_slice(&x[nd..]);
        }
        // k2, k3, k4 at x + c h k_prev, c = 1/2, 1/2, 1
        stage_state(&mut self.xt[..nd], &x[..nd], 0.5 * h, k1);
        f(at(t + 0.5 * h), &self.xt, k2, false);
        stage_state(&mut self.xt[..nd], &x[..nd], 0.5 * h, k2);
        f(at(t + 0.5 * h), &self.xt, k3, false);
        stage_state(&mut self.xt[..nd], &x[..nd], h, k3);
        f(at(t + h), &self.xt, k4, false);
        for ((((xi, a), b), c), d) in x[..nd].iter_mut().zip(&*k1).zip(&*k2).zip(&*k3).zip(&*k4) {
            *xi += h / 6.0 * (a + 2.0 * b + 2.0 * c + d);
        }
    }
}

/// The state at which a stage evaluates the derivative: xt = x + ch k.
#[inline(always)]
fn stage_state(xt: &mut [f64], x: &[f64], ch: f64, k: &[f64]) {
    for ((o, xi), ki) in xt.iter_mut().zip(x).zip(k) {
        *o = xi + ch * ki;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_keep_every_step_at_or_below_the_longest() {
        assert_eq!(steps_for(0.01, 0.01), Some(1));
        assert_eq!(steps_for(0.01 * (1.0 + 1e-12), 0.01), Some(1), "rounding");
        assert_eq!(steps_for(0.0101, 0.01), Some(2));
        assert_eq!(steps_for(3.0, 0.01), Some(300));
        assert_eq!(steps_for(0.0, 0.01), Some(1));
        assert_eq!(steps_for(1e9, 0.01), None);
    }

    #[test]
    fn substeps_cover_the_interval_in_equal_steps() {
        let s: Vec<(f64, f64)> = substeps(1.0, 2.0, 4).collect();
        assert_eq!(
            s,
            vec![(1.0, 0.25), (1.25, 0.25), (1.5, 0.25), (1.75, 0.25)]
        );
        assert_eq!(substeps(0.0, 1.0, 0).count(), 1);
    }

    #[test]
    fn one_step_is_fourth_order_and_leaves_the_constants() {
        // x_dot = a x (a the constant second component): one step gives the Taylor series of
        // exp(a h) to h^4 exactly, and evaluates f at t, t + h/2 (twice) and t + h
        let (a, h) = (-0.7, 0.3);
        let mut x = [2.0, a];
        let mut rk = Rk4::new(2, 1);
        let mut calls = Vec::new();
        rk.step(1.0, h, &mut x, |at, x, dx, at_start| {
            assert_eq!(x[1], a);
            assert_eq!(at.step_start, 1.0, "every stage knows its step's start");
            calls.push((at.t, at_start));
            dx[0] = x[1] * x[0];
        });
        let ah: f64 = a * h;
        let taylor = 1.0 + ah + ah.powi(2) / 2.0 + ah.powi(3) / 6.0 + ah.powi(4) / 24.0;
        assert!((x[0] - 2.0 * taylor).abs() < 1e-15, "{}", x[0]);
        assert_eq!(x[1], a);
        assert_eq!(
            calls,
            vec![
                (1.0, true),
                (1.0 + 0.5 * h, false),
                (1.0 + 0.5 * h, false),
                (1.0 + h, false)
            ]
        );
    }
}
