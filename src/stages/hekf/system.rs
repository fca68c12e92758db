//! A vehicle model with unknown coefficients appended to its state (paper eq. 22), as the
//! filter's [`System`]: x* = [x, z] with z_j = beta_j / s_j (coefficients scaled to order one
//! so that a 0.5 and a 25 are equally well conditioned), measurements a subset of the states.

use crate::ad::{self, Dual, CHUNK};
use crate::estimation::System;
use crate::models::Model;
use crate::sim::InputSeries;

/// The augmented system of one run.
pub struct ModelSystem<'a, M: Model> {
    model: &'a M,
    /// Full coefficient vector with the fixed values (free ones overwritten from the state).
    base: Vec<f64>,
    /// Indices of the estimated coefficients in the model's coefficient vector.
    est: &'a [usize],
    /// Scale of each estimated coefficient.
    scale: &'a [f64],
    inputs: &'a InputSeries,
    /// Indices of the measured states.
    measured: &'a [usize],
    // work space
    u: Vec<f64>,
    c: Vec<f64>,
    /// The scaled coefficients `c` was completed for (NaN: not yet).
    c_for: Vec<f64>,
    xd: Vec<Dual>,
    cd: Vec<Dual>,
    outd: Vec<Dual>,
}

impl<'a, M: Model> ModelSystem<'a, M> {
    /// The system for `model` with fixed coefficients `base` (full vector), estimated
    /// coefficients at `est` scaled by `scale`, inputs and measured state indices.
    pub fn new(
        model: &'a M,
        base: Vec<f64>,
        est: &'a [usize],
        scale: &'a [f64],
        inputs: &'a InputSeries,
        measured: &'a [usize],
    ) -> Self {
        let nx = model.nx();
        let nc = base.len();
        ModelSystem {
            model,
            base,
            est,
            scale,
            inputs,
            measured,
            u: vec![0.0; inputs.len()],
            c: vec![0.0; nc],
            c_for: vec![f64::NAN; est.len()],
            xd: vec![ad::constant(0.0); nx],
            cd: vec![ad::constant(0.0); nc],
            outd: vec![ad::constant(0.0); nx],
        }
    }

    /// The completed coefficient vector for augmented state `x` (recomputed only when the
    /// coefficient part of `x` changed: it is constant between measurement updates).
    pub fn coefficients(&mut self, x: &[f64]) -> &[f64] {
        let nx = self.model.nx();
        if x[nx..] == self.c_for[..] {
            return &self.c;
        }
        self.c_for.copy_from_slice(&x[nx..]);
        self.c.copy_from_slice(&self.base);
        for (j, &i) in self.est.iter().enumerate() {
            self.c[i] = x[nx + j] * self.scale[j];
        }
        self.model.relations().apply(&mut self.c);
        &self.c
    }
}

impl<M: Model> System for ModelSystem<'_, M> {
    fn n(&self) -> usize {
        self.model.nx() + self.est.len()
    }

    fn nd(&self) -> usize {
        self.model.nx()
    }

    fn m(&self) -> usize {
        self.measured.len()
    }

    fn derivative(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        let nx = self.model.nx();
        self.inputs.at(t, &mut self.u);
        self.coefficients(x);
        self.model.derivatives(&x[..nx], &self.u, &self.c, dx);
    }

    fn jacobian(&mut self, t: f64, x: &[f64], dx: &mut [f64], f: &mut [f64]) {
        let nx = self.model.nx();
        let n = self.n();
        self.inputs.at(t, &mut self.u);
        // chunked forward-mode AD over the augmented state (see crate::ad)
        let mut start = 0;
        while start < n {
            let end = (start + CHUNK).min(n);
            let seed = |i: usize, v: f64, d: f64| {
                if (start..end).contains(&i) {
                    ad::seeded(v, i - start, d)
                } else {
                    ad::constant(v)
                }
            };
            for i in 0..nx {
                self.xd[i] = seed(i, x[i], 1.0);
            }
            for (c, &b) in self.cd.iter_mut().zip(&self.base) {
                *c = ad::constant(b);
            }
            for (j, &i) in self.est.iter().enumerate() {
                // d beta / d z = scale
                self.cd[i] = seed(nx + j, x[nx + j] * self.scale[j], self.scale[j]);
            }
            self.model.relations().apply(&mut self.cd);
            self.model
                .derivatives(&self.xd, &self.u, &self.cd, &mut self.outd);
            for (r, o) in self.outd.iter().enumerate() {
                dx[r] = o.re;
                for col in start..end {
                    f[r * n + col] = ad::derivative(o, col - start);
                }
            }
            start = end;
        }
    }

    fn observe(&mut self, x: &[f64], y: &mut [f64], h: &mut [f64]) {
        let n = self.n();
        h.fill(0.0);
        for (k, &i) in self.measured.iter().enumerate() {
            y[k] = x[i];
            h[k * n + i] = 1.0;
        }
    }

    fn selection(&self) -> Option<&[usize]> {
        Some(self.measured)
    }

    fn check(&mut self, x: &[f64]) -> Result<(), String> {
        let nx = self.model.nx();
        self.coefficients(x);
        self.model.check(&x[..nx], &self.c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Spheroid3;

    #[test]
    fn augmented_jacobian_matches_finite_differences() {
        let m = Spheroid3::paper_vehicle();
        let names = m.coefficient_names();
        let mut base = vec![0.0; names.len()];
        for (n, v) in [
            ("Xud", -1.16),
            ("Xuu", -1.33),
            ("Yuvl", -16.3),
            ("Nuvl", 13.4),
        ] {
            base[m.coefficient_index(n).unwrap()] = v;
        }
        let est: Vec<usize> = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"]
            .iter()
            .map(|n| m.coefficient_index(n).unwrap())
            .collect();
        let scale = [25.0, 6.0, 1.5, 19.0, 28.0, 23.0];
        let inputs = InputSeries::constant(&[22.0]);
        let measured = [0, 1, 2, 3, 4, 5];
        let mut sys = ModelSystem::new(&m, base, &est, &scale, &inputs, &measured);
        let x = [
            3.0, 1.0, -0.3, 2.0, 1.0, 0.5, -0.9, 0.1, -0.8, 0.4, -0.2, 0.03,
        ];
        let n = 12;
        let mut dx = vec![0.0; 6];
        let mut fa = vec![0.0; 6 * n];
        sys.jacobian(0.0, &x, &mut dx, &mut fa);
        let mut ff = vec![0.0; 6 * n];
        ad::jacobian_fd(&x, 6, |xs, out| sys.derivative(0.0, xs, out), &mut ff);
        for (i, (a, b)) in fa.iter().zip(&ff).enumerate() {
            assert!(
                (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                "entry {i}: {a} vs {b}"
            );
        }
        // the estimated Yvd moves Xvr and Nuva inside the dynamics: du_dot/dz(Yvd) != 0
        assert!(fa[6].abs() > 1e-6);
    }
}
