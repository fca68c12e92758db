//! One hybrid-EKF pass over 2000 samples of the paper's manoeuvre with 6 estimated
//! coefficients (12 augmented states), without and with the RTS smoother, and the model
//! Jacobian alone.
//!
//! `cargo bench --bench hekf`; numbers are recorded in docs/performance.md.

mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hydroid::dynamics::model_system::ModelSystem;
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::spheroid3::BOUNDED_TRUTH;
use hydroid::model::models::{Model, Spheroid3};
use hydroid::numerics::estimation::System;
use hydroid::numerics::ode::StageTime;
use hydroid::stages::hekf::identify::{RunData, Setup};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::hint::black_box;

const ESTIMATED: [&str; 6] = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"];

fn run_data(m: &Spheroid3, c: &[f64]) -> RunData {
    let times: Vec<f64> = (0..2000).map(|k| k as f64 * 0.01).collect();
    let inputs = InputSeries::constant(&[22.0]);
    let xs = simulate(m, c, &[3.0, 1.0, 0.0, 0.0, 0.0, 0.0], &inputs, &times, 4).unwrap();
    let sig = [
        1e-3,
        1e-3,
        0.05f64.to_radians(),
        1e-3,
        1e-3,
        0.05f64.to_radians(),
    ];
    let mut rng = StdRng::seed_from_u64(1);
    let mut y = Vec::new();
    for x in &xs {
        for i in 0..6 {
            y.push(x[i] + Normal::new(0.0, sig[i]).unwrap().sample(&mut rng));
        }
    }
    let r: Vec<f64> = sig.iter().map(|s| s * s).collect();
    let mut p0 = vec![0.0; 36];
    for i in 0..6 {
        p0[i * 6 + i] = r[i];
    }
    RunData {
        name: "bench".into(),
        times,
        measured: (0..6).collect(),
        x0: y[..6].to_vec(),
        y,
        r,
        rounding: Vec::new(),
        inputs,
        p0,
        lines: Vec::new(),
    }
}

fn bench(c: &mut Criterion) {
    let m = Spheroid3::paper_vehicle();
    let truth = m.coefficient_vector(BOUNDED_TRUTH);
    let run = run_data(&m, &truth);
    let setup = common::one_pass(&m, &truth, &ESTIMATED, 0.01);
    let (base, est, scale) = (setup.base.clone(), setup.est.clone(), setup.scale.clone());
    let mut g = c.benchmark_group("hekf");
    g.throughput(Throughput::Elements(run.times.len() as u64));
    common::pass(
        &mut g,
        "filter pass, 2000 samples, 12 states",
        &m,
        &setup,
        &run,
    );
    let smoothed = Setup {
        smoother: true,
        ..setup.clone()
    };
    common::pass(
        &mut g,
        "filter pass and smoother, 2000 samples, 12 states",
        &m,
        &smoothed,
        &run,
    );
    g.finish();
    let inputs = InputSeries::constant(&[22.0]);
    let measured: Vec<usize> = (0..6).collect();
    let mut sys = ModelSystem::new(&m, base, &est, &scale, &inputs, &measured);
    let x = [
        3.0, 1.0, -0.2, 1.0, 2.0, 0.4, -0.9, 0.0, -0.06, 0.5, -0.2, 0.02,
    ];
    let mut dx = [0.0; 6];
    let mut f = [0.0; 72];
    c.bench_function("augmented Jacobian (AD), 6 x 12", |b| {
        b.iter(|| sys.jacobian(StageTime::at(0.0), black_box(&x), &mut dx, &mut f))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
