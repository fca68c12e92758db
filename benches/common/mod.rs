//! What the filter benchmarks share: the setup of one pass that estimates a model's
//! coefficients from zero, every other coefficient at its true value.

use hydroid::models::Model;
use hydroid::stages::hekf::identify::Setup;

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
    }
}
