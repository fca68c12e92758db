//! What the filter benchmarks share: the setup of one pass that estimates a model's
//! coefficients from zero, every other coefficient at its true value, and its measurement.

use criterion::measurement::WallTime;
use criterion::BenchmarkGroup;
use hydroid::base::progress::Silent;
use hydroid::model::models::Model;
use hydroid::stages::hekf::identify::{identify, RunData, Setup};
use std::hint::black_box;

/// One filter pass estimating `estimated` from zero (prior sigma: the typical magnitude),
/// the rest of `truth` known, a small process noise on the motion states, no smoother, no
/// gate, RK4 steps of at most `max_step`.
pub fn one_pass<M: Model>(m: &M, truth: &[f64], estimated: &[&str], max_step: f64) -> Setup {
    let est: Vec<usize> = estimated
        .iter()
        .map(|n| m.coefficient_index(n).expect("a coefficient of the model"))
        .collect();
    let scale: Vec<f64> = estimated.iter().map(|n| m.typical_magnitude(n)).collect();
    let mut base = truth.to_vec();
    for &i in &est {
        base[i] = 0.0;
    }
    let mut q = vec![1e-10; m.nx()];
    q.extend(vec![0.0; est.len()]);
    Setup {
        base,
        initial: vec![0.0; est.len()],
        est,
        prior_sigma: scale.clone(),
        ranges: Vec::new(),
        prior_correlation: Vec::new(),
        held_prior: Vec::new(),
        scale,
        q,
        passes: 1,
        substeps: 1,
        max_step,
        smoother: false,
        gate: 0.0,
        gate_from_pass: 1,
        repeat_prior_factor: Some(100.0),
        filter: Default::default(),
        adaptable: Vec::new(),
        run_q: Vec::new(),
        noise_scale: 1.0,
    }
}

/// Measures `identify` of `m` with `setup` over the one run `run` as `label` in group `g`.
pub fn pass<M: Model>(
    g: &mut BenchmarkGroup<WallTime>,
    label: &str,
    m: &M,
    setup: &Setup,
    run: &RunData,
) {
    g.bench_function(label, |b| {
        b.iter(|| identify(black_box(m), setup, std::slice::from_ref(run), &mut Silent).unwrap())
    });
}
