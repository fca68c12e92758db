//! One hybrid-EKF pass of the `mmg3` ship model (KVLCC2 model, Yasukawa & Yoshimura 2015)
//! with 12 estimated hull derivatives (18 augmented states) over 10,000 samples of a 35 deg
//! turning circle at 20 Hz, smoother off.
//!
//! `cargo bench --bench ship`; numbers are recorded in docs/performance.md.

mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::mmg3::{KVLCC2, KVLCC2_RPS, KVLCC2_SPEED};
use hydroid::model::models::{Mmg3, Model};
use hydroid::stages::hekf::identify::RunData;
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

const ESTIMATED: [&str; 12] = [
    "Yv_p", "Yr_p", "Yvvv_p", "Yvvr_p", "Yvrr_p", "Yrrr_p", "Nv_p", "Nr_p", "Nvvv_p", "Nvvr_p",
    "Nvrr_p", "Nrrr_p",
];
const SAMPLES: usize = 10_000;
const DT: f64 = 0.05;

fn bench(c: &mut Criterion) {
    let m = Mmg3::build(&Mmg3::example_vehicle()).expect("the example vehicle builds");
    let truth = m.coefficient_vector(KVLCC2);
    let times: Vec<f64> = (0..SAMPLES).map(|k| k as f64 * DT).collect();
    let inputs = InputSeries::constant(&[35f64.to_radians(), KVLCC2_RPS]);
    let x0 = [KVLCC2_SPEED, 0.0, 0.0, 0.0, 0.0, 0.0];
    let xs = simulate(&m, &truth, &x0, &inputs, &times, 2).expect("the turn simulates");
    let sig = [
        2e-3,
        2e-3,
        0.05f64.to_radians(),
        5e-3,
        5e-3,
        0.05f64.to_radians(),
    ];
    let mut rng = StdRng::seed_from_u64(3);
    let mut y = Vec::with_capacity(SAMPLES * 6);
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
    let run = RunData {
        name: "kvlcc2 35 deg turn".into(),
        times,
        measured: (0..6).collect(),
        x0: y[..6].to_vec(),
        y,
        r,
        rounding: Vec::new(),
        inputs,
        p0,
        lines: Vec::new(),
    };
    let setup = common::one_pass(&m, &truth, &ESTIMATED, DT);
    let mut g = c.benchmark_group("ship");
    g.sample_size(10);
    g.throughput(Throughput::Elements(SAMPLES as u64));
    common::pass(
        &mut g,
        "mmg3 filter pass, 10000 samples, 12 estimated (18 states)",
        &m,
        &setup,
        &run,
    );
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
