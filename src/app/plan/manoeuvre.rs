//! A candidate manoeuvre (turning circle, zig-zag, vertical zig-zag, helix, free run) as the HEKF would see it: the
//! identified model simulated through it, then the hybrid EKF's covariance recursion run along
//! the simulated measurements with the coefficients appended to the state (paper eq. 22) and
//! their current covariance as prior, with the first fitted run's measurement and process
//! noise. The filter's final coefficient covariance is the posterior the manoeuvre gives in
//! the filter's own linearisation (Jazwinski 1970, section 8.3); with measurements equal to
//! the model's noise-free outputs the estimate stays at the current one, so only the
//! covariance moves, and the process noise limits what a manoeuvre can tell as it limits the
//! HEKF itself.

use super::candidate::{Candidate, Kind};
use super::prior::{Operating, Prior};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::inputs::Input;
use crate::dynamics::sim::steering::{Steering, Surface};
use crate::dynamics::sim::InputSeries;
use crate::model::models::Model;
use crate::numerics::estimation::hybrid_ekf::HybridEkf;
use nalgebra::DMatrix;

/// Default rudder rate of a candidate turn or zig-zag, deg/s (the bundled KVLCC2 model's,
/// 2.32 deg/s full scale times sqrt(45.7)).
pub const RUDDER_RATE_DEG_S: f64 = 15.8;

/// Initial variance of a state the run does not measure (SI^2).
const UNMEASURED_VARIANCE: f64 = 1e-6;

/// Added to the diagonal of the prior's correlation matrix (relative variance): a prior
/// built from few uncertainty directions is only semi-definite.
const PRIOR_JITTER: f64 = 1e-9;

/// A simulated candidate manoeuvre.
#[derive(Debug, Clone)]
pub struct Run {
    /// Sample times, s.
    pub times: Vec<f64>,
    /// The model's inputs.
    pub inputs: InputSeries,
    /// States at each sample.
    pub states: Vec<Vec<f64>>,
    /// Indices of the measured outputs.
    pub measured: Vec<usize>,
    /// Their noise standard deviations, SI.
    pub sigma: Vec<f64>,
}

/// Simulates candidate `c` with the identified model, `forcing(x, dt)` applied to the state
/// after each sample interval (a process noise; nothing for the prediction).
pub fn simulate_run<M: Model>(
    model: &M,
    prior: &Prior,
    op: &Operating,
    c: &Candidate,
    forcing: &mut dyn FnMut(&mut [f64], f64),
) -> Result<Run> {
    let fail = |e: String| Error::numerical("plan", format!("candidate '{}': {e}", c.name));
    let dt = c.dt_s.unwrap_or(op.dt);
    let k = (c.duration_s.unwrap_or(op.duration) / dt).round().max(1.0) as usize;
    let times: Vec<f64> = (0..=k).map(|i| i as f64 * dt).collect();
    let mut x0 = op.x0.clone();
    let speed = c.speed.unwrap_or(op.speed);
    let set = |x: &mut [f64], q: Quantity, v: f64| {
        if let Some(i) = model.state_index(q) {
            x[i] = v;
        }
    };
    set(&mut x0, Quantity::U, speed);
    set(&mut x0, Quantity::V, c.v0);
    set(&mut x0, Quantity::R, c.r0_deg_s.to_radians());
    let law = law(c).ok_or_else(|| fail("not a manoeuvre".into()))?;
    let quantities = model.input_quantities();
    let steered = law.map(|l| l.surface().input());
    let planes = (c.kind == Kind::Helix).then_some(c.planes_deg.to_radians());
    for q in steered.iter().chain(planes.map(|_| &Quantity::SternPlanes)) {
        if !quantities.contains(q) {
            return Err(fail(format!("the {} model has no {q} input", model.name())));
        }
    }
    let mut inputs = InputSeries {
        t: times.clone(),
        inputs: quantities
            .iter()
            .zip(&op.u0)
            .map(|(q, u)| match (Some(*q) == steered, *q, planes) {
                (true, _, _) => Input::Series(vec![0.0; times.len()]),
                (false, Quantity::SternPlanes, Some(p)) => Input::Constant(p),
                _ => Input::Constant(*u),
            })
            .collect(),
    };
    let states = crate::app::simulate::synth::per_sample(
        model,
        &prior.base,
        &x0,
        &mut inputs,
        law,
        op.substeps,
        forcing,
    )
    .map_err(|e| fail(e.to_string()))?;
    let mut measured = Vec::new();
    let mut sigma = Vec::new();
    for (q, s) in &op.measured {
        if let Some(i) = model.output_index(*q) {
            measured.push(i);
            sigma.push(c.noise.get(q.key()).map_or(*s, |n| n.si));
        }
    }
    Ok(Run {
        times,
        inputs,
        states,
        measured,
        sigma,
    })
}

/// The helm's law of a turn, zig-zag or helix from a straight approach at the default rudder
/// rate, the stern planes' of a vertical zig-zag (Some(None) for a free run; None for a
/// captive candidate).
fn law(c: &Candidate) -> Option<Option<Steering>> {
    let rudder = c.rudder_deg.to_radians();
    let rate = RUDDER_RATE_DEG_S.to_radians();
    match c.kind {
        Kind::Turn | Kind::Helix => Some(Some(Steering::Turn {
            rudder,
            rate,
            execute: 0.0,
            surface: Surface::Rudder,
        })),
        Kind::Zigzag => Some(Some(Steering::ZigZag {
            rudder,
            heading: c.heading_deg.to_radians(),
            rate,
            execute: 0.0,
            surface: Surface::Rudder,
        })),
        Kind::ZigzagVertical => Some(Some(Steering::ZigZag {
            rudder: c.planes_deg.to_radians(),
            heading: c.pitch_deg.to_radians(),
            rate,
            execute: 0.0,
            surface: Surface::SternPlanes,
        })),
        Kind::Free => Some(None),
        _ => None,
    }
}

/// The noise-free outputs the run measures, per sample.
pub fn outputs<M: Model>(model: &M, prior: &Prior, run: &Run) -> Vec<Vec<f64>> {
    let mut u = vec![0.0; run.inputs.len()];
    run.states
        .iter()
        .zip(&run.times)
        .map(|(x, &t)| {
            run.inputs.at(t, &mut u);
            let y = model.output_values(x, &u, &prior.base);
            run.measured.iter().map(|&i| y[i]).collect()
        })
        .collect()
}

/// The hybrid EKF along measurements `ys` of `run`, starting from the coefficients `theta0`
/// with the prior's covariance: the final coefficients and their covariance.
pub fn filter<M: Model>(
    model: &M,
    prior: &Prior,
    op: &Operating,
    run: &Run,
    theta0: &[f64],
    ys: &[Vec<f64>],
) -> Result<(Vec<f64>, DMatrix<f64>)> {
    let (nx, p) = (model.nx(), prior.est.len());
    let n = nx + p;
    let scale = prior.sigma();
    let mut x = run.states[0].clone();
    x.extend(theta0.iter().zip(&scale).map(|(t, s)| t / s));
    let mut p0 = vec![0.0; n * n];
    let outputs_are_states = model.outputs().is_empty();
    for i in 0..nx {
        let k = run
            .measured
            .iter()
            .position(|&m| m == i && outputs_are_states);
        p0[i * n + i] = k.map_or(UNMEASURED_VARIANCE, |k| run.sigma[k].powi(2));
    }
    for i in 0..p {
        for j in 0..p {
            // the prior's correlations, kept positive definite for the filter's Cholesky checks
            let jitter = if i == j { PRIOR_JITTER } else { 0.0 };
            p0[(nx + i) * n + nx + j] = prior.cov[(i, j)] / (scale[i] * scale[j]) + jitter;
        }
    }
    let mut q = op.q.clone();
    q.resize(n, 0.0);
    let dt = run.times.get(1).map_or(1.0, |t1| t1 - run.times[0]);
    let mut ekf = HybridEkf::new(n, nx, x, p0, q, dt / op.substeps as f64);
    let mut sys = ModelSystem::new(
        model,
        prior.base.clone(),
        &prior.est,
        &scale,
        &run.inputs,
        &run.measured,
    );
    let r: Vec<f64> = run.sigma.iter().map(|s| s * s).collect();
    let fail = |e: String| Error::numerical("plan", e);
    for (k, y) in ys.iter().enumerate() {
        if k > 0 {
            ekf.predict(&mut sys, run.times[k - 1], run.times[k], None)
                .map_err(|e| fail(e.to_string()))?;
        }
        ekf.update(&mut sys, run.times[k], y, &r)
            .map_err(|e| fail(e.to_string()))?;
    }
    let theta = (0..p).map(|j| ekf.x[nx + j] * scale[j]).collect();
    let cov = DMatrix::from_fn(p, p, |i, j| {
        ekf.p[(nx + i) * n + nx + j] * scale[i] * scale[j]
    });
    Ok((theta, 0.5 * (&cov + cov.transpose())))
}

/// The posterior covariance after a candidate manoeuvre.
pub fn posterior<M: Model>(
    model: &M,
    prior: &Prior,
    op: &Operating,
    c: &Candidate,
) -> Result<DMatrix<f64>> {
    let run = simulate_run(model, prior, op, c, &mut |_, _| {})?;
    let ys = outputs(model, prior, &run);
    let theta = prior.values();
    filter(model, prior, op, &run, &theta, &ys)
        .map(|(_, cov)| cov)
        .map_err(|e| Error::numerical("plan", format!("candidate '{}': {e}", c.name)))
}
