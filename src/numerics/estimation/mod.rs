//! State estimation, independent of ships: an extended Kalman filter in three forms
//! ([`FilterKind`]: continuous-discrete (hybrid), discrete-time with explicit Euler
//! ([`discrete_ekf`]), continuous-time Kalman-Bucy ([`kalman_bucy`])), a Rauch-Tung-Striebel
//! smoother and innovation consistency statistics. The three share one filter type
//! ([`HybridEkf`]), its work space and its Joseph-form measurement update; only the
//! propagation between samples differs.
//!
//! The filter sees a [`System`]: continuous dynamics whose first `nd` states evolve and whose
//! remaining states are constant parameters (the augmented state of paper eq. 22), with
//! discrete measurements y_k = h(x(t_k)) + v_k.

pub mod discrete_ekf;
pub mod hybrid_ekf;
pub mod kalman_bucy;
pub mod nis;
pub mod rts;
#[cfg(test)]
mod test_systems;

pub use hybrid_ekf::{Divergence, HybridEkf};

use crate::numerics::ode::StageTime;

/// Which form of the extended Kalman filter runs (`hekf.filter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterKind {
    /// Continuous-discrete: RK4 prediction between samples, Joseph update at each sample
    /// (paper eq. 9-19; Simon 2006, section 13.2.3). The default.
    #[default]
    Hybrid,
    /// Discrete-time: one explicit Euler step x + Delta f(x) per sample interval (or per
    /// sub-step), Phi = I + Delta F, Q_d = Q Delta, Joseph update (Simon 2006, section 13.1;
    /// the Nomoto wave-filter paper, eq. 20-25). See [`discrete_ekf`].
    Discrete,
    /// Continuous-time Kalman-Bucy: state and Riccati equation integrated together with the
    /// measurement held between samples (Simon 2006, section 13.3; the NPS AUV paper). No
    /// smoother. See [`kalman_bucy`].
    Continuous,
}

impl FilterKind {
    /// The configuration's name of the filter.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Hybrid => "hybrid",
            FilterKind::Discrete => "discrete",
            FilterKind::Continuous => "continuous",
        }
    }

    /// True for the default (`hybrid`).
    pub fn is_default(&self) -> bool {
        *self == FilterKind::default()
    }
}

impl std::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Continuous dynamics and a measurement map, as the filter needs them.
pub trait System {
    /// Dimension of the (augmented) state.
    fn n(&self) -> usize;

    /// Number of leading states with dynamics; states `nd..n` are constants (x_dot = 0,
    /// apart from process noise).
    fn nd(&self) -> usize;

    /// Number of measurements.
    fn m(&self) -> usize;

    /// dx (length `nd`) = f(t, x) for the dynamic states, at `at.t` in the integration step
    /// that starts at `at.step_start` (an input held between samples is read there:
    /// [`crate::numerics::ode::StageTime`]; `StageTime::at(t)` at a sample).
    fn derivative(&mut self, at: StageTime, x: &[f64], dx: &mut [f64]);

    /// dx as in [`System::derivative`] and its Jacobian F = df/dx (`nd x n`, row-major).
    fn jacobian(&mut self, at: StageTime, x: &[f64], dx: &mut [f64], f: &mut [f64]);

    /// y = h(t, x) (length `m`) and H = dh/dx (`m x n`, row-major), at `at` as in
    /// [`System::derivative`] (inputs may enter the measurement).
    fn observe(&mut self, at: StageTime, x: &[f64], y: &mut [f64], h: &mut [f64]);

    /// When every measurement is one state (H a selection of rows of the identity), the
    /// state indices; the filter then skips [`System::observe`] and updates one measurement
    /// at a time.
    fn selection(&self) -> Option<&[usize]> {
        None
    }

    /// A physical check of the state (e.g. positive effective masses); the message says what
    /// is wrong.
    fn check(&mut self, x: &[f64]) -> Result<(), crate::base::error::Unphysical>;
}
