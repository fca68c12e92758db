//! Does a constant input fit the motion? An equation-error fit (Jategaonkar 2015, Flight
//! Vehicle System Identification, ch. 6): at each regular sample the measured state
//! derivative (central differences) minus the model's f(x, u, c) with the starting
//! coefficients is regressed on the derivatives of f with respect to the estimated
//! coefficients (automatic differentiation, through the model's relations) and to the
//! constant input (central difference). The input's correction is what the run implies
//! beyond anything the estimated coefficients can absorb; a large and significant one means
//! the configured constant (a thrust of 30 N where the run had 22 N) does not fit, which the
//! filter would otherwise turn into confidently wrong coefficients.
//!
//! The same misfit can come from a coefficient held at an earlier stage's estimate (X_uu of
//! a noisy polar, X_udot of a noisy surge run): each such coefficient is fitted in the
//! input's place on the same equation, and one that explains the misfit within
//! [`EXPLAINS`] of that stage's own sigmas is named beside the input.

use crate::base::warning::Warning;
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::inputs::{Input, InputSeries};
use crate::io::record::Record;
use crate::model::models::Model;
use crate::numerics::estimation::System;
use crate::numerics::ode::StageTime;
use crate::stages::hekf::identify::RunData;
use crate::stages::hekf::STAGE;
use crate::stages::plausible::Finding;
use nalgebra::{DMatrix, DVector};

/// Samples used at most (evenly spread): enough for a precise fit, bounded for long runs.
const MAX_SAMPLES: usize = 4000;
/// A correction above this share of the configured value ...
const RELATIVE: f64 = 0.2;
/// ... and this many of its standard errors is reported.
const SIGNIFICANT: f64 = 10.0;

/// A held coefficient within this many of its stage's sigmas of the value that explains a
/// misfit is named as a possible cause.
const EXPLAINS: f64 = 3.0;

/// A coefficient the filter holds at an earlier stage's estimate, with that stage's sigma.
#[derive(Debug, Clone)]
pub struct Held {
    /// Index in the model's coefficient vector.
    pub index: usize,
    /// The stage's standard deviation, SI.
    pub sigma: f64,
    /// The stage it comes from (`polar`, `surge`, `captive`).
    pub stage: String,
}

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
    /// The held coefficients that carry an earlier stage's uncertainty.
    pub held: &'a [Held],
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
    let mut out = Vec::new();
    for (j, input) in run.inputs.inputs.iter().enumerate() {
        let Input::Constant(value) = *input else {
            continue;
        };
        if value == 0.0 {
            continue;
        }
        if let Some(f) = check_one(model, rec, run, start, &samples, j, value) {
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
    samples: &[usize],
    j: usize,
    value: f64,
) -> Option<Finding> {
    let rows = equation_rows(model, run, start, samples, j, value)?;
    let best = best_equation(&rows, start.est.len())?;
    let significant = best.value.abs() > SIGNIFICANT * best.sigma;
    if !(significant && best.value.abs() > RELATIVE * value.abs()) {
        return None;
    }
    let q = model.inputs()[j].quantity;
    let unit = q.si_symbol();
    let state = model.states()[best.state].name;
    let held = held_explanations(model, run, start, samples, best.state, j, value);
    let (also, hint) = if held.is_empty() {
        (
            String::new(),
            format!(
                "either the {q} is wrong or a coefficient held fixed in the {state} equation \
                 (from an earlier stage or the configuration) is; either way the filter makes \
                 the estimated coefficients absorb the difference and reports them with small \
                 sigmas: check the {q} of this run (or map a column for it) and the fixed \
                 coefficients"
            ),
        )
    } else {
        (
            format!(
                "; or a coefficient held at an earlier stage's estimate: {} would explain it",
                held.join("; ")
            ),
            format!(
                "the misfit is within the earlier stage's own uncertainty: its data (a noisy \
                 polar or surge run, a short captive table) rather than this run's {q} may be \
                 the cause; check that stage's fit, or estimate the coefficient here \
                 (hekf.estimate) and let the runs decide. Either way the filter makes the \
                 estimated coefficients absorb the difference and reports them with small sigmas"
            ),
        )
    };
    Some(Finding {
        warning: Warning::new(
            STAGE,
            format!(
                "the constant {q} of {} {unit} does not fit the motion: an equation-error fit \
                 of the {state} equation, with the estimated coefficients free, implies {} \
                 +- {} {unit}{also}",
                num(value),
                num(value + best.value),
                num(best.sigma)
            ),
            hint,
        )
        .for_run(&rec.name),
        blocking: false,
    })
}

/// The held coefficients that explain the misfit of input `j` on state equation `state`
/// within [`EXPLAINS`] of their stage's sigmas, in words: each fitted in the input's place
/// (the estimated coefficients free, the input at its configured value).
fn held_explanations<M: Model>(
    model: &M,
    run: &RunData,
    start: &Start,
    samples: &[usize],
    state: usize,
    j: usize,
    value: f64,
) -> Vec<String> {
    let names = model.coefficient_names();
    let mut out = Vec::new();
    for h in start.held {
        let name = names[h.index];
        let held_scale = model.typical_magnitude(name).max(f64::MIN_POSITIVE);
        let est: Vec<usize> = start.est.iter().copied().chain([h.index]).collect();
        let scale: Vec<f64> = start.scale.iter().copied().chain([held_scale]).collect();
        let initial: Vec<f64> = start
            .initial
            .iter()
            .copied()
            .chain([start.base[h.index]])
            .collect();
        let with = Start {
            base: start.base,
            est: &est,
            scale: &scale,
            initial: &initial,
            held: &[],
        };
        let Some(rows) = equation_rows(model, run, &with, samples, j, value) else {
            continue;
        };
        // the input's column dropped: the held coefficient takes its place
        let eq: Vec<(f64, Vec<f64>)> = rows[state]
            .iter()
            .map(|(r, reg)| (*r, reg[..est.len()].to_vec()))
            .collect();
        let Some(fit) = last_regressor(&eq, est.len() - 1) else {
            continue;
        };
        let shift = fit.value * held_scale;
        let held_value = start.base[h.index];
        if (shift / h.sigma).abs() <= EXPLAINS {
            let unit = crate::model::models::registry::coefficient(name).map_or("", |c| c.unit);
            out.push(format!(
                "{name} = {} +- {} {unit} from the {} stage, at {} ({:.1} of that stage's \
                 sigmas)",
                num(held_value),
                num(h.sigma),
                h.stage,
                num(held_value + shift),
                (shift / h.sigma).abs()
            ));
        }
    }
    out
}

/// Per state equation, the equation-error rows at the sampled times: the residual of the
/// measured central-difference derivative and the regressors (the estimated coefficients,
/// then input `j` by central differences). None when the model gives no finite value.
#[allow(clippy::type_complexity)]
fn equation_rows<M: Model>(
    model: &M,
    run: &RunData,
    start: &Start,
    samples: &[usize],
    j: usize,
    value: f64,
) -> Option<Vec<Vec<(f64, Vec<f64>)>>> {
    // the estimated coefficients' starts in the filter's scaled units
    let z0: Vec<f64> = start
        .initial
        .iter()
        .zip(start.scale)
        .map(|(v, s)| v / s)
        .collect();
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
        x[nx..].copy_from_slice(&z0);
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

/// A least-squares correction on one state equation.
struct Correction {
    /// The correction, in the regressor's units.
    value: f64,
    /// Its standard deviation.
    sigma: f64,
    /// The state whose equation gave it.
    state: usize,
}

/// The equation that determines the input best (its column is regressor `nb`): its
/// least-squares correction to the input and the correction's sigma.
fn best_equation(rows: &[Vec<(f64, Vec<f64>)>], nb: usize) -> Option<Correction> {
    let mut best: Option<Correction> = None;
    for (i, eq) in rows.iter().enumerate() {
        let Some(mut c) = last_regressor(eq, nb) else {
            continue;
        };
        c.state = i;
        if best.as_ref().is_none_or(|b| c.sigma < b.sigma) {
            best = Some(c);
        }
    }
    best
}

/// The least-squares value of regressor `last` (the last one) of one equation's rows, with
/// the others free; only the regressors that vary enter (a coefficient that does not enter
/// this equation would make the fit singular). None when `last` does not vary or the fit
/// fails.
fn last_regressor(eq: &[(f64, Vec<f64>)], last: usize) -> Option<Correction> {
    if eq.iter().all(|(_, reg)| reg[last] == 0.0) {
        return None;
    }
    let kk = eq.len();
    let cols: Vec<usize> = (0..=last)
        .filter(|&c| eq.iter().any(|(_, reg)| reg[c] != 0.0))
        .collect();
    let xm = DMatrix::from_fn(kk, cols.len(), |r, c| eq[r].1[cols[c]]);
    let ym = DVector::from_fn(kk, |r, _| eq[r].0);
    let fit =
        crate::numerics::lsq::scaled_least_squares(&xm, &ym, kk.saturating_sub(cols.len()).max(1))?;
    let at = cols.len() - 1;
    let (value, sigma) = (fit.theta[at], fit.covariance[at][at].max(0.0).sqrt());
    (value.is_finite() && sigma.is_finite()).then_some(Correction {
        value,
        sigma,
        state: 0,
    })
}

fn num(v: f64) -> String {
    crate::base::numfmt::num(v)
}
