//! Twin experiment on the paper's manoeuvre: simulate the spheroid with known coefficients,
//! add measurement noise, identify six coefficients with the hybrid EKF, compare.
//!
//! `cargo run --release --example twin_experiment`

use hydroid::base::progress::Silent;
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::spheroid3::BOUNDED_TRUTH;
use hydroid::model::models::{Model, Spheroid3};
use hydroid::stages::hekf::identify::{identify, RunData, Setup};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

fn main() {
    let model = Spheroid3::paper_vehicle();
    let c = model.coefficient_vector(BOUNDED_TRUTH);
    let truth_of = |n: &str| BOUNDED_TRUTH.iter().find(|(m, _)| *m == n).unwrap().1;
    let dt: f64 = std::env::args().nth(1).map_or(0.01, |s| s.parse().unwrap());
    let q_state: f64 = std::env::args().nth(2).map_or(0.0, |s| s.parse().unwrap());
    let passes: usize = std::env::args().nth(3).map_or(3, |s| s.parse().unwrap());
    let seed: u64 = std::env::args().nth(4).map_or(1, |s| s.parse().unwrap());
    let substeps: usize = std::env::args().nth(5).map_or(1, |s| s.parse().unwrap());
    let n_samples = (20.0 / dt).round() as usize + 1;
    let times: Vec<f64> = (0..n_samples).map(|i| i as f64 * dt).collect();
    let inputs = InputSeries::constant(&[22.0]);
    let xs = simulate(
        &model,
        &c,
        &[3.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        &inputs,
        &times,
        10,
    )
    .unwrap();
    let sig = [
        1e-3,
        1e-3,
        0.05f64.to_radians(),
        1e-3,
        1e-3,
        0.05f64.to_radians(),
    ];
    let mut rng = StdRng::seed_from_u64(seed);
    let mut y = Vec::new();
    for x in &xs {
        for i in 0..6 {
            y.push(x[i] + Normal::new(0.0, sig[i]).unwrap().sample(&mut rng));
        }
    }
    println!("final state {:?}", xs.last().unwrap());
    let r: Vec<f64> = sig.iter().map(|s| s * s).collect();
    let mut p0 = vec![0.0; 36];
    for i in 0..6 {
        p0[i * 6 + i] = r[i];
    }
    let run = RunData {
        name: "twin".into(),
        times: times.clone(),
        measured: (0..6).collect(),
        y: y.clone(),
        r,
        rounding: Vec::new(),
        inputs,
        x0: y[..6].to_vec(),
        p0,
        lines: Vec::new(),
    };
    let est_names = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"];
    let est: Vec<usize> = est_names
        .iter()
        .map(|n| model.coefficient_index(n).unwrap())
        .collect();
    let scale: Vec<f64> = est_names
        .iter()
        .map(|n| model.typical_magnitude(n))
        .collect();
    println!("scales {scale:?}");
    let mut base = c.clone();
    for &i in &est {
        base[i] = 0.0;
    }
    let mut q = vec![q_state; 6];
    q.extend(vec![0.0; 6]);
    let setup = Setup {
        base,
        est: est.clone(),
        scale: scale.clone(),
        initial: vec![0.0; 6],
        prior_sigma: scale.clone(),
        ranges: Vec::new(),
        prior_correlation: Vec::new(),
        held_prior: Vec::new(),
        q,
        passes,
        substeps,
        max_step: dt / substeps as f64,
        smoother: false,
        gate: 0.0,
        gate_from_pass: 1,
        repeat_prior_factor: Some(100.0),
        filter: Default::default(),
        adaptable: Vec::new(),
        run_q: Vec::new(),
        noise_scale: 1.0,
    };
    let t0 = std::time::Instant::now();
    let id = identify(&model, &setup, &[run], &mut Silent).unwrap_or_else(|e| panic!("{:?}", e));
    println!(
        "elapsed {:?} for {} samples x {} passes",
        t0.elapsed(),
        n_samples,
        passes
    );
    for (p, pe) in id.passes.iter().enumerate() {
        println!("pass {}", p + 1);
        for (j, n) in est_names.iter().enumerate() {
            let tv = truth_of(n);
            println!(
                "  {n:5} {:10.4} +- {:8.4}  truth {:8.4}  err {:7.3} %  ({:5.2} sigma)",
                pe.values[j],
                pe.sigmas[j],
                tv,
                100.0 * (pe.values[j] - tv) / tv.abs().max(1e-9),
                (pe.values[j] - tv) / pe.sigmas[j]
            );
        }
    }
    let nis = &id.traces.last().unwrap()[0].nis;
    println!("mean NIS {}", nis.iter().sum::<f64>() / nis.len() as f64);
}
