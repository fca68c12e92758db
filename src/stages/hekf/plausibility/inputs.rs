//! Does a constant input fit the motion? An equation-error fit (Jategaonkar 2015, Flight
//! Vehicle System Identification, ch. 6): at each regular sample the measured state
//! derivative (central differences) minus the model's f(x, u, c) with the starting
//! coefficients is regressed on the derivatives of f with respect to the estimated
//! coefficients (automatic differentiation, through the model's relations) and to the
//! constant input (central difference). The input's correction is what the run implies
//! beyond anything the estimated coefficients can absorb; a large and significant one means
//! the configured constant (a thrust of 30 N where the run had 22 N) does not fit, which the
//! filter would otherwise turn into confidently wrong coefficients.

use super::{Finding, STAGE};
use crate::base::warning::Warning;
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::inputs::{Input, InputSeries};
use crate::io::record::Record;
use crate::model::models::Model;
use crate::numerics::estimation::System;
use crate::numerics::ode::StageTime;
use crate::stages::hekf::identify::RunData;
use nalgebra::{DMatrix, DVector};

/// Samples used at most (evenly spread): enough for a precise fit, bounded for long runs.
const MAX_SAMPLES: usize = 4000;
/// A correction above this share of the configured value ...
const RELATIVE: f64 = 0.2;
/// ... and this many of its standard errors is reported.
const SIGNIFICANT: f64 = 10.0;

/// The coefficient set-up the filter starts from.
pub struct Start<'a> {
    /// Full coefficient vector with the fixed values.
    pub base: &'a [f64],
    /// Indices of the estimated coefficients.
    pub est: &'a [usize],
    /// Their scales.
    pub scale: &'a [f64],
    /// Their starting values (SI).
    pub initial: &'a [f64],
}

/// Findings for the constant inputs of a run whose every state is measured.
pub fn constant_inputs<M: Model>(
    model: &M,
    rec: &Record,
    run: &RunData,
    start: &Start,
) -> Vec<Finding> {
    let nx = model.nx();
    let m = run.measured.len();
    if m != nx || run.len() < 20 {
        return Vec::new();
    }
    let Some(dt) = crate::numerics::sampling::median_interval(&run.times) else {
        return Vec::new();
    };
    // regular interior samples with every measurement present
    let regular: Vec<usize> = (1..run.len() - 1)
        .filter(|&k| {
            let (a, b) = (
                run.times[k] - run.times[k - 1],
                run.times[k + 1] - run.times[k],
            );
            (a - dt).abs() < 0.01 * dt
                && (b - dt).abs() < 0.01 * dt
                && (k - 1..=k + 1).all(|j| run.y[j * m..(j + 1) * m].iter().all(|v| v.is_finite()))
        })
        .collect();
    let stride = regular.len().div_ceil(MAX_SAMPLES).max(1);
    let samples: Vec<usize> = regular.into_iter().step_by(stride).collect();
    if samples.len() < 20 {
        return Vec::new();
    }
    let z0: Vec<f64> = start
        .initial
        .iter()
        .zip(start.scale)
        .map(|(v, s)| v / s)
        .collect();
    let mut out = Vec::new();
    for (j, input) in run.inputs.inputs.iter().enumerate() {
        let Input::Constant(value) = *input else {
            continue;
        };
        if value == 0.0 {
            continue;
        }
        if let Some(f) = check_one(model, rec, run, start, &z0, &samples, j, value) {
            out.push(f);
        }
    }
    out
}

/// The equation-error fit for constant input `j`, on the state equation where the input is
/// best determined.
#[allow(clippy::too_many_arguments)]
fn check_one<M: Model>(
    model: &M,
    rec: &Record,
    run: &RunData,
    start: &Start,
    z0: &[f64],
    samples: &[usize],
    j: usize,
    value: f64,
) -> Option<Finding> {
    let rows = equation_rows(model, run, start, z0, samples, j, value)?;
    let (correction, sigma, state) = best_equation(model, &rows, start.est.len())?;
    let significant = correction.abs() > SIGNIFICANT * sigma;
    if !(significant && correction.abs() > RELATIVE * value.abs()) {
        return None;
    }
    let q = model.inputs()[j].quantity;
    let unit = q.si_symbol();
    Some(Finding {
        warning: Warning::new(
            STAGE,
            format!(
                "the constant {q} of {} {unit} does not fit the motion: an equation-error fit \
                 of the {state} equation, with the estimated coefficients free, implies {} \
                 +- {} {unit}",
                num(value),
                num(value + correction),
                num(sigma)
            ),
            format!(
                "either the {q} is wrong or a coefficient held fixed in the {state} equation \
                 (from an earlier stage or the configuration) is; either way the filter makes \
                 the estimated coefficients absorb the difference and reports them with small \
                 sigmas: check the {q} of this run (or map a column for it) and the fixed \
                 coefficients"
            ),
        )
        .for_run(&rec.name),
        blocking: false,
    })
}

/// Per state equation, the equation-error rows at the sampled times: the residual of the
/// measured central-difference derivative and the regressors (the estimated coefficients,
/// then input `j` by central differences). None when the model gives no finite value.
#[allow(clippy::type_complexity)]
fn equation_rows<M: Model>(
    model: &M,
    run: &RunData,
    start: &Start,
    z0: &[f64],
    samples: &[usize],
    j: usize,
    value: f64,
) -> Option<Vec<Vec<(f64, Vec<f64>)>>> {
    let nx = model.nx();
    let nb = start.est.len();
    let n = nx + nb;
    let delta = 1e-6 * value.abs();
    let with = |v: f64| {
        let mut s = run.inputs.clone();
        s.inputs[j] = Input::Constant(v);
        s
    };
    let (plus, minus): (InputSeries, InputSeries) = (with(value + delta), with(value - delta));
    let system = |inputs| {
        ModelSystem::new(
            model,
            start.base.to_vec(),
            start.est,
            start.scale,
            inputs,
            &run.measured,
        )
    };
    let (mut sys, mut sys_p, mut sys_m) = (system(&run.inputs), system(&plus), system(&minus));
    let m = nx;
    // per state equation: residual, regressors (estimated coefficients, then the input)
    let mut rows: Vec<Vec<(f64, Vec<f64>)>> = vec![Vec::new(); nx];
    let mut x = vec![0.0; n];
    let (mut f, mut jac) = (vec![0.0; nx], vec![0.0; nx * n]);
    let (mut fp, mut fm) = (vec![0.0; nx], vec![0.0; nx]);
    for &k in samples {
        // the augmented state at the measured states (measurements in `measured` order)
        for (a, &i) in run.measured.iter().enumerate() {
            x[i] = run.y[k * m + a];
        }
        x[nx..].copy_from_slice(z0);
        let t = StageTime::at(run.times[k]);
        sys.jacobian(t, &x, &mut f, &mut jac);
        sys_p.derivative(t, &x, &mut fp);
        sys_m.derivative(t, &x, &mut fm);
        if f.iter().chain(&jac).any(|v| !v.is_finite()) {
            return None;
        }
        let span = run.times[k + 1] - run.times[k - 1];
        for (a, &i) in run.measured.iter().enumerate() {
            let measured = (run.y[(k + 1) * m + a] - run.y[(k - 1) * m + a]) / span;
            let mut reg: Vec<f64> = (0..nb).map(|c| jac[i * n + nx + c]).collect();
            reg.push((fp[i] - fm[i]) / (2.0 * delta));
            rows[i].push((measured - f[i], reg));
        }
    }
    Some(rows)
}

/// The equation that determines the input best: its least-squares correction to the input,
/// the correction's sigma, and the state it is the equation of.
fn best_equation<M: Model>(
    model: &M,
    rows: &[Vec<(f64, Vec<f64>)>],
    nb: usize,
) -> Option<(f64, f64, String)> {
    let mut best: Option<(f64, f64, String)> = None;
    for (i, eq) in rows.iter().enumerate() {
        if eq.iter().all(|(_, reg)| reg[nb] == 0.0) {
            continue;
        }
        let (kk, p) = (eq.len(), nb + 1);
        // only the regressors that vary (a coefficient that does not enter this equation
        // would make the fit singular)
        let cols: Vec<usize> = (0..p)
            .filter(|&c| eq.iter().any(|(_, reg)| reg[c] != 0.0))
            .collect();
        let xm = DMatrix::from_fn(kk, cols.len(), |r, c| eq[r].1[cols[c]]);
        let ym = DVector::from_fn(kk, |r, _| eq[r].0);
        let Some(fit) = crate::numerics::lsq::scaled_least_squares(
            &xm,
            &ym,
            kk.saturating_sub(cols.len()).max(1),
        ) else {
            continue;
        };
        let last = cols.len() - 1;
        let (correction, var) = (fit.theta[last], fit.covariance[last][last]);
        let sigma = var.max(0.0).sqrt();
        if !(correction.is_finite() && sigma.is_finite()) {
            continue;
        }
        let state = model.states()[i].name.to_string();
        if best.as_ref().is_none_or(|b| sigma < b.1) {
            best = Some((correction, sigma, state));
        }
    }
    best
}

fn num(v: f64) -> String {
    crate::base::numfmt::num(v)
}
