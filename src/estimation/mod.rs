//! State estimation, independent of ships: a continuous-discrete (hybrid) extended Kalman
//! filter, a Rauch-Tung-Striebel smoother and innovation consistency statistics.
//!
//! The filter sees a [`System`]: continuous dynamics whose first `nd` states evolve and whose
//! remaining states are constant parameters (the augmented state of paper eq. 22), with
//! discrete measurements y_k = h(x(t_k)) + v_k.

pub mod hybrid_ekf;
pub mod nis;
pub mod rts;

pub use hybrid_ekf::{Divergence, HybridEkf};

/// Continuous dynamics and a measurement map, as the filter needs them.
pub trait System {
    /// Dimension of the (augmented) state.
    fn n(&self) -> usize;

    /// Number of leading states with dynamics; states `nd..n` are constants (x_dot = 0,
    /// apart from process noise).
    fn nd(&self) -> usize;

    /// Number of measurements.
    fn m(&self) -> usize;

    /// dx (length `nd`) = f(t, x) for the dynamic states.
    fn derivative(&mut self, t: f64, x: &[f64], dx: &mut [f64]);

    /// dx as in [`System::derivative`] and its Jacobian F = df/dx (`nd x n`, row-major).
    fn jacobian(&mut self, t: f64, x: &[f64], dx: &mut [f64], f: &mut [f64]);

    /// y = h(t, x) (length `m`) and H = dh/dx (`m x n`, row-major), at time `t` (inputs
    /// may enter the measurement).
    fn observe(&mut self, t: f64, x: &[f64], y: &mut [f64], h: &mut [f64]);

    /// When every measurement is one state (H a selection of rows of the identity), the
    /// state indices; the filter then skips [`System::observe`] and updates one measurement
    /// at a time.
    fn selection(&self) -> Option<&[usize]> {
        None
    }

    /// A physical check of the state (e.g. positive effective masses); the message says what
    /// is wrong.
    fn check(&mut self, x: &[f64]) -> Result<(), String>;
}
