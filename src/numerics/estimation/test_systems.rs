//! Small linear systems for the filters' unit tests.

use super::System;
use crate::numerics::ode::StageTime;

/// x_dot = A x for the first `nd` states (A is nd x nd, row-major), constant parameters
/// after them; y = x_0.
pub struct Linear {
    /// A, nd x nd row-major.
    pub a: Vec<f64>,
    /// Dynamic states.
    pub nd: usize,
    /// All states.
    pub n: usize,
}

impl System for Linear {
    fn n(&self) -> usize {
        self.n
    }
    fn nd(&self) -> usize {
        self.nd
    }
    fn m(&self) -> usize {
        1
    }
    fn derivative(&mut self, _at: StageTime, x: &[f64], dx: &mut [f64]) {
        for (i, d) in dx.iter_mut().enumerate() {
            *d = (0..self.nd).map(|j| self.a[i * self.nd + j] * x[j]).sum();
        }
    }
    fn jacobian(&mut self, at: StageTime, x: &[f64], dx: &mut [f64], f: &mut [f64]) {
        self.derivative(at, x, dx);
        f.fill(0.0);
        for i in 0..self.nd {
            for j in 0..self.nd {
                f[i * self.n + j] = self.a[i * self.nd + j];
            }
        }
    }
    fn observe(&mut self, _at: StageTime, x: &[f64], y: &mut [f64], h: &mut [f64]) {
        y[0] = x[0];
        h.fill(0.0);
        h[0] = 1.0;
    }
    fn check(&mut self, _x: &[f64]) -> Result<(), crate::base::error::Unphysical> {
        Ok(())
    }
}
