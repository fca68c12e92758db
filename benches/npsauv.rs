//! One hybrid-EKF pass of the `npsauv` model (NPS AUV II, Healey & Lienard 1993) estimating
//! the 17 coefficients of Mousavian et al. (2015) over 10,000 samples of the paper's helix
//! (rudder and stern planes at 10 deg, 500 rpm) at 100 Hz, nine states measured (u, v, w,
//! p, q, r, phi, theta, psi), smoother off. hydroid's model also carries x, y, z, so the
//! filter has 12 + 17 = 29 augmented states (the paper's has 26, without the positions).
//!
//! `cargo bench --bench npsauv`; numbers are recorded in docs/performance.md.

mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::npsauv::{PAPER_17, PUBLISHED};
use hydroid::model::models::{Model, NpsAuv};
use hydroid::stages::hekf::identify::RunData;
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

const SAMPLES: usize = 10_000;
const DT: f64 = 0.01;
/// The measured states: velocities, rates and Euler angles.
const MEASURED: [usize; 9] = [0, 1, 2, 3, 4, 5, 9, 10, 11];

fn bench(c: &mut Criterion) {
    let m = NpsAuv::build(&NpsAuv::example_vehicle()).expect("the example vehicle builds");
    let ex = m.example();
    let truth = m.coefficient_vector(PUBLISHED);
    let times: Vec<f64> = (0..SAMPLES).map(|k| k as f64 * DT).collect();
    let inputs = InputSeries::constant(&ex.inputs);
    let xs = simulate(&m, &truth, &ex.state, &inputs, &times, 1).expect("the helix simulates");
    // sensor noise: velocities 0.01 m/s, rates 0.1 deg/s, angles 0.05 deg
    let sig = [
        0.01,
        0.01,
        0.01,
        0.1f64.to_radians(),
        0.1f64.to_radians(),
        0.1f64.to_radians(),
        0.05f64.to_radians(),
        0.05f64.to_radians(),
        0.05f64.to_radians(),
    ];
    let mut rng = StdRng::seed_from_u64(12);
    let mut y = Vec::with_capacity(SAMPLES * MEASURED.len());
    for x in &xs {
        for (k, &i) in MEASURED.iter().enumerate() {
            y.push(x[i] + Normal::new(0.0, sig[k]).unwrap().sample(&mut rng));
        }
    }
    let nd = m.nx();
    let r: Vec<f64> = sig.iter().map(|s| s * s).collect();
    let mut p0 = vec![0.0; nd * nd];
    for i in 0..nd {
        p0[i * nd + i] = 1e-4;
    }
    let run = RunData {
        name: "npsauv helix".into(),
        times,
        measured: MEASURED.to_vec(),
        x0: ex.state.clone(),
        y,
        r,
        rounding: Vec::new(),
        inputs,
        p0,
        lines: Vec::new(),
    };
    let setup = common::one_pass(&m, &truth, PAPER_17, DT);
    let mut g = c.benchmark_group("npsauv");
    g.sample_size(10);
    g.throughput(Throughput::Elements(SAMPLES as u64));
    common::pass(
        &mut g,
        "npsauv filter pass, 10000 samples, 17 estimated (29 states)",
        &m,
        &setup,
        &run,
    );
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
