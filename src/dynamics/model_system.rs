//! A vehicle model with unknown coefficients appended to its state (paper eq. 22), as the
//! filter's [`System`]: x* = [x, z] with z_j = beta_j / s_j (coefficients scaled to order one
//! so that a 0.5 and a 25 are equally well conditioned), measurements a subset of the model's
//! outputs: of its states when it declares no measurement function (then the filter updates
//! one state at a time), else of y = h(x, u, c) with H from automatic differentiation.

use crate::dynamics::sim::InputSeries;
use crate::model::models::Model;
use crate::numerics::ad::{self, Dual, CHUNK};
use crate::numerics::estimation::System;
use crate::numerics::ode::StageTime;

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
    /// Indices of the measured outputs (states when the model declares no outputs).
    measured: &'a [usize],
    // work space
    u: Vec<f64>,
    c: Vec<f64>,
    /// The scaled coefficients `c` was completed for (NaN: not yet).
    c_for: Vec<f64>,
    xd: Vec<Dual>,
    cd: Vec<Dual>,
    outd: Vec<Dual>,
    yd: Vec<Dual>,
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
        // the completed base: the coefficients as they are when nothing is estimated (the
        // cache below is keyed on the estimated part of the state, empty then)
        let mut c = base.clone();
        model.relations().apply(&mut c);
        ModelSystem {
            model,
            base,
            est,
            scale,
            inputs,
            measured,
            u: vec![0.0; inputs.len()],
            c,
            c_for: vec![f64::NAN; est.len()],
            xd: vec![ad::constant(0.0); nx],
            cd: vec![ad::constant(0.0); nc],
            outd: vec![ad::constant(0.0); nx],
            yd: vec![ad::constant(0.0); model.outputs().len()],
        }
    }

    /// Chunked forward-mode AD over the augmented state (see crate::numerics::ad): for each chunk of
    /// the Jacobian's columns `start..end`, seeds the duals and calls `eval`.
    fn for_each_chunk(&mut self, x: &[f64], mut eval: impl FnMut(&mut Self, usize, usize)) {
        let n = self.n();
        let mut start = 0;
        while start < n {
            let end = (start + CHUNK).min(n);
            self.seed_chunk(x, start, end);
            eval(self, start, end);
            start = end;
        }
    }

    /// Seeds the dual states and coefficients for the derivatives along augmented states
    /// `start..end` (one chunk of the Jacobian's columns).
    fn seed_chunk(&mut self, x: &[f64], start: usize, end: usize) {
        let nx = self.model.nx();
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

    fn derivative(&mut self, at: StageTime, x: &[f64], dx: &mut [f64]) {
        let nx = self.model.nx();
        self.inputs.in_step(at, &mut self.u);
        self.coefficients(x);
        self.model.derivatives(&x[..nx], &self.u, &self.c, dx);
    }

    fn jacobian(&mut self, at: StageTime, x: &[f64], dx: &mut [f64], f: &mut [f64]) {
        let n = self.n();
        self.inputs.in_step(at, &mut self.u);
        self.for_each_chunk(x, |s, start, end| {
            s.model.derivatives(&s.xd, &s.u, &s.cd, &mut s.outd);
            for (r, o) in s.outd.iter().enumerate() {
                dx[r] = o.re;
                for col in start..end {
                    f[r * n + col] = ad::derivative(o, col - start);
                }
            }
        });
    }

    fn observe(&mut self, at: StageTime, x: &[f64], y: &mut [f64], h: &mut [f64]) {
        let n = self.n();
        h.fill(0.0);
        if self.model.outputs().is_empty() {
            for (k, &i) in self.measured.iter().enumerate() {
                y[k] = x[i];
                h[k * n + i] = 1.0;
            }
            return;
        }
        // y = h(x, u, c) and its Jacobian by chunked forward-mode AD, as the dynamics'
        self.inputs.in_step(at, &mut self.u);
        self.for_each_chunk(x, |s, start, end| {
            s.model.measure(&s.xd, &s.u, &s.cd, &mut s.yd);
            for (k, &o) in s.measured.iter().enumerate() {
                let out = &s.yd[o];
                y[k] = out.re;
                for col in start..end {
                    h[k * n + col] = ad::derivative(out, col - start);
                }
            }
        });
    }

    fn selection(&self) -> Option<&[usize]> {
        self.model.outputs().is_empty().then_some(self.measured)
    }

    fn check(&mut self, x: &[f64]) -> Result<(), crate::model::models::Unphysical> {
        let nx = self.model.nx();
        self.coefficients(x);
        self.model.check(&x[..nx], &self.c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::quantity::Quantity;
    use crate::model::coefficients::{CompiledRelations, Relation};
    use crate::model::models::{
        CoefDef, Example, InputDef, OutputDef, Spheroid3, StateDef, Vehicle, VehicleProblem,
    };
    use crate::numerics::ad::Scalar;

    /// A surge model whose log reads the speed with a calibration error that grows with the
    /// distance run (y = u (1 + k x)) and whose position is measured: a measurement that is
    /// not a selection of states.
    struct LoggedSurge(CompiledRelations);

    impl Model for LoggedSurge {
        const NAME: &'static str = "logged_surge";
        const DESCRIPTION: &'static str = "test model";
        const COEFFICIENTS: &'static [CoefDef] = &[
            CoefDef::prime("Xuu", "kg/m", "drag"),
            CoefDef::prime("k", "1/m", "log calibration drift"),
        ];
        const INPUTS: &'static [InputDef] = &[];
        const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[];

        fn build(_: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
            Ok(LoggedSurge(CompiledRelations::compile(&[], &[])))
        }
        fn states(&self) -> &'static [StateDef] {
            &[
                StateDef {
                    name: "u",
                    quantity: Quantity::U,
                },
                StateDef {
                    name: "x",
                    quantity: Quantity::X,
                },
            ]
        }
        fn outputs(&self) -> &'static [OutputDef] {
            &[
                OutputDef {
                    name: "log",
                    quantity: Quantity::U,
                },
                OutputDef {
                    name: "x",
                    quantity: Quantity::X,
                },
            ]
        }
        fn measure<T: Scalar>(&self, x: &[T], _u: &[f64], c: &[T], y: &mut [T]) {
            y[0] = x[0] * (c[1] * x[1] + 1.0);
            y[1] = x[1];
        }
        fn relations(&self) -> &CompiledRelations {
            &self.0
        }
        fn compared(&self) -> &'static [Quantity] {
            &[Quantity::U]
        }
        fn typical_magnitude(&self, _: &str) -> f64 {
            1.0
        }
        fn derivatives<T: Scalar>(&self, x: &[T], _u: &[f64], c: &[T], dx: &mut [T]) {
            dx[0] = c[0] * x[0] * x[0].abs() / 50.0;
            dx[1] = x[0];
        }
        fn check(&self, _: &[f64], _: &[f64]) -> Result<(), crate::model::models::Unphysical> {
            Ok(())
        }
        fn example_vehicle() -> Vehicle {
            Vehicle::paper_spheroid()
        }
        fn example(&self) -> Example {
            Example {
                coefficients: &[("Xuu", -1.3), ("k", 0.01)],
                state: vec![2.0, 0.0],
                inputs: vec![],
                estimated: &["Xuu", "k"],
                duration: 10.0,
            }
        }
    }

    /// The filter's prediction reads a held input as the simulation does: x_dot = T / m
    /// (surge1 without drag or added mass) with T held at its samples gains exactly h T_k / m
    /// over the interval from t_k, in each form of the filter, in one step or four (it used
    /// to gain (5 T_k + T_k+1) h / (6 m) in one RK4 step).
    #[test]
    fn every_filter_form_holds_a_held_input_over_its_interval() {
        use crate::dynamics::sim::inputs::Input;
        use crate::model::models::Surge1;
        use crate::numerics::estimation::{FilterKind, HybridEkf};
        let m = Surge1::build(&Vehicle::paper_spheroid()).unwrap();
        let base = m.coefficient_vector(&[("Xud", 0.0), ("Xuu", 0.0)]);
        let inputs = InputSeries {
            t: vec![0.0, 0.5, 1.0],
            inputs: vec![Input::Held(vec![1.0, 7.0, -2.0])],
        };
        for kind in [
            FilterKind::Hybrid,
            FilterKind::Discrete,
            FilterKind::Continuous,
        ] {
            for max_step in [0.5, 0.125] {
                let mut sys = ModelSystem::new(&m, base.clone(), &[], &[], &inputs, &[0]);
                let p0 = vec![1e-4, 0.0, 0.0, 1e-4];
                let mut f = HybridEkf::new(2, 2, vec![0.25, 0.0], p0, vec![0.0; 2], max_step);
                f.kind = kind;
                for (k, gain) in [1.0, 7.0].iter().enumerate() {
                    let (t0, u0) = (0.5 * k as f64, f.x[0]);
                    f.predict(&mut sys, t0, t0 + 0.5, None).unwrap();
                    let want = u0 + 0.5 * gain / m.mass;
                    assert!(
                        (f.x[0] - want).abs() < 1e-14,
                        "{kind}, steps of {max_step} s, interval {k}: {} for {want}",
                        f.x[0]
                    );
                }
            }
        }
    }

    #[test]
    fn a_measurement_function_gives_its_values_and_ad_jacobian() {
        let m = LoggedSurge::build(&Vehicle::paper_spheroid()).unwrap();
        let inputs = InputSeries::constant(&[]);
        let (est, scale, measured) = ([0, 1], [1.3, 0.01], [0, 1]);
        let mut sys = ModelSystem::new(&m, vec![0.0; 2], &est, &scale, &inputs, &measured);
        assert!(sys.selection().is_none(), "not a selection of states");
        let x = [2.0, 15.0, -1.0, 1.0];
        let (mut y, mut h) = ([0.0; 2], [0.0; 8]);
        sys.observe(StageTime::at(0.0), &x, &mut y, &mut h);
        // y0 = u (1 + k x) with k = z1 * 0.01 = 0.01
        assert!((y[0] - 2.0 * 1.15).abs() < 1e-12 && y[1] == 15.0);
        let mut hf = [0.0; 8];
        let mut scratch = [0.0; 8];
        ad::jacobian_fd(
            &x,
            2,
            |xs, out| sys.observe(StageTime::at(0.0), xs, out, &mut scratch),
            &mut hf,
        );
        for (a, b) in h.iter().zip(&hf) {
            assert!((a - b).abs() < 1e-8, "{h:?} vs {hf:?}");
        }
        // dy0/dz1 = u x * 0.01
        assert!((h[3] - 0.3).abs() < 1e-12);
    }

    #[test]
    fn the_filter_identifies_through_a_measurement_function() {
        use crate::numerics::estimation::HybridEkf;
        let m = LoggedSurge::build(&Vehicle::paper_spheroid()).unwrap();
        let truth = m.coefficient_vector(m.example().coefficients);
        let inputs = InputSeries::constant(&[]);
        let times: Vec<f64> = (0..2001).map(|k| k as f64 * 0.005).collect();
        let xs =
            crate::dynamics::sim::simulate(&m, &truth, &[2.0, 0.0], &inputs, &times, 1).unwrap();
        let (est, scale, measured) = ([0, 1], [1.3, 0.01], [0, 1]);
        let mut sys = ModelSystem::new(&m, vec![0.0; 2], &est, &scale, &inputs, &measured);
        let x0 = vec![2.0, 0.0, 0.0, 0.0];
        let mut p0 = vec![0.0; 16];
        for (i, v) in [1e-6, 1e-6, 1.0, 1.0].iter().enumerate() {
            p0[i * 4 + i] = *v;
        }
        let mut f = HybridEkf::new(4, 2, x0, p0, vec![0.0; 4], 0.005);
        for (k, x) in xs.iter().enumerate() {
            if k > 0 {
                f.predict(&mut sys, times[k - 1], times[k], None).unwrap();
            }
            let y = m.output_values(x, &[], &truth);
            f.update(&mut sys, times[k], &y, &[1e-8, 1e-8]).unwrap();
        }
        assert!(
            (f.x[2] * 1.3 - -1.3).abs() < 1e-3 * 1.3,
            "Xuu {}",
            f.x[2] * 1.3
        );
        assert!((f.x[3] * 0.01 - 0.01).abs() < 1e-4, "k {}", f.x[3] * 0.01);
    }

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
        sys.jacobian(StageTime::at(0.0), &x, &mut dx, &mut fa);
        let mut ff = vec![0.0; 6 * n];
        ad::jacobian_fd(
            &x,
            6,
            |xs, out| sys.derivative(StageTime::at(0.0), xs, out),
            &mut ff,
        );
        for (i, (a, b)) in fa.iter().zip(&ff).enumerate() {
            assert!(
                (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                "entry {i}: {a} vs {b}"
            );
        }
        // the estimated Yvd moves Xvr and Nuva inside the dynamics: du_dot/dz(Yvd) != 0
        assert!(fa[6].abs() > 1e-6);
    }

    /// With no coefficient estimated (an online wave filter), the filter's prediction is the
    /// model's own motion: the coefficients are the base, not zeros (a cache keyed on the
    /// estimated part of the state, empty then, once left them at zero).
    #[test]
    fn with_nothing_estimated_the_prediction_is_the_models_motion() {
        use crate::dynamics::sim::{simulate, InputSeries};
        use crate::model::models::nomoto_wave::{NomotoWave, FRIGATE_9MS};
        use crate::numerics::estimation::hybrid_ekf::HybridEkf;
        let m = NomotoWave::build(&NomotoWave::example_vehicle()).unwrap();
        let c = m.coefficient_vector(FRIGATE_9MS);
        let mut x = vec![0.0, 0.0, 0.01, 0.0];
        let mut ekf = HybridEkf::new(4, 4, x.clone(), vec![0.0; 16], vec![0.0; 4], 0.1);
        for k in 1..=100 {
            let t = k as f64 * 0.1;
            let held = InputSeries::constant(&[(t * 0.1).sin() * 0.3]);
            x = simulate(&m, &c, &x, &held, &[t - 0.1, t], 1).unwrap()[1].clone();
            let mut sys = ModelSystem::new(&m, c.clone(), &[], &[], &held, &[0]);
            ekf.predict(&mut sys, t - 0.1, t, None).unwrap();
        }
        for (a, b) in x.iter().zip(&ekf.x) {
            assert!((a - b).abs() < 1e-9, "{x:?} against {:?}", ekf.x);
        }
    }
}
