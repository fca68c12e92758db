//! Synthetic CFD runs: a manoeuvre simulated with a model (or the steady polar its
//! coefficients imply), with seeded measurement noise, as SI columns ready to export.

use super::config::{Manoeuvre, SimConfig};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::config::{Constant, Step};
use crate::dynamics::sim::inputs::{rate_limited, Input, InputSeries};
use crate::dynamics::sim::integrate::{complete_coefficients, simulate};
use crate::dynamics::sim::steering::Steering;
use crate::io::steps::{changes_of, stepped};
use crate::model::coefficients::{Coefficient, CoefficientSet, Source, YawMoment, SYMMETRY};
use crate::model::models::{with_model, InputRule, Model, ModelVisitor};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;

/// Mixed into the noise seed for the process noise, so that the two streams differ.
const PROCESS_SEED: u64 = 0x05ee_d0f0_a7e5;

/// Simulated quantities in SI, all of the same length.
pub type Columns = BTreeMap<Quantity, Vec<f64>>;

/// Runs the configured manoeuvre and adds the configured noise.
pub fn synthesize(cfg: &SimConfig) -> Result<Columns> {
    let mut set = CoefficientSet::new();
    for (n, v) in &cfg.coefficients {
        set.insert(Coefficient::new(n, *v, None, Source::Config));
    }
    let mut cols = match &cfg.manoeuvre {
        Manoeuvre::TimeHistory { .. } => with_model(
            cfg.model,
            &cfg.vehicle.for_model(&cfg.fluid),
            History { cfg, set: &set },
        )
        .map_err(Error::vehicle)??,
        Manoeuvre::PolarSweep {
            alpha_deg,
            speeds,
            moment_reference_length,
            cubic,
            moment,
        } => polar_sweep(
            cfg,
            &set,
            alpha_deg,
            speeds,
            (*moment_reference_length, *moment),
            cubic,
        )?,
        Manoeuvre::Pmm(_) => with_model(
            cfg.model,
            &cfg.vehicle.for_model(&cfg.fluid),
            super::pmm::History { cfg, set: &set },
        )
        .map_err(Error::vehicle)??,
        Manoeuvre::Captive { .. } => with_model(
            cfg.model,
            &cfg.vehicle.for_model(&cfg.fluid),
            Captive { cfg, set: &set },
        )
        .map_err(Error::vehicle)??,
    };
    let mut rng = StdRng::seed_from_u64(cfg.noise.seed);
    for (q, sigma) in &cfg.noise.sigma {
        let Some(col) = cols.get_mut(q) else {
            return Err(Error::Usage(format!(
                "noise is given for {q}, which this manoeuvre does not produce"
            )));
        };
        crate::numerics::noise::add_gaussian(col, sigma.si, &mut rng)
            .map_err(|e| Error::Usage(format!("noise.{q}: {e}")))?;
    }
    Ok(cols)
}

/// The model's coefficient vector from `set` ([`complete_coefficients`]: the model's
/// relations applied), or a usage error naming the free coefficients missing from `place`.
pub fn coefficients_for<M: Model>(
    model: &M,
    set: &CoefficientSet,
    place: &str,
) -> Result<Vec<f64>> {
    complete_coefficients(model, set).map_err(|missing| {
        Error::Usage(format!(
            "the {} model needs values for {} in {place}",
            model.name(),
            missing.join(", ")
        ))
    })
}

struct History<'a> {
    cfg: &'a SimConfig,
    set: &'a CoefficientSet,
}

impl ModelVisitor for History<'_> {
    type Output = Result<Columns>;

    fn visit<M: Model>(self, model: &M) -> Result<Columns> {
        let Manoeuvre::TimeHistory {
            duration,
            dt,
            substeps,
            initial,
            inputs,
            steps,
            rates,
            steering,
            process_noise,
        } = &self.cfg.manoeuvre
        else {
            unreachable!("called for time histories only")
        };
        let c = coefficients_for(model, self.set, "[coefficients]")?;
        let x0 = initial_state(model, initial)?;
        // bounded by the loader (sim::config::limits)
        let n = (duration / dt).round() as usize + 1;
        let times: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
        check_inputs(model, inputs, steps)?;
        let series = input_samples(model, inputs, steps, rates, *steering, &times);
        let mut input_series = InputSeries {
            t: times,
            inputs: series,
        };
        // inputs are read between samples as the filter and re-simulation read them
        // (`between = "auto"`): a surface moving at its rate or by the helm linearly, a step
        // by the model's rule (an interpolated step at a sample time ramps over the interval
        // before it)
        // process noise (waves, gusts): a Gaussian increment of variance q dt on each forced
        // state after every sample interval (Euler-Maruyama on dx = f dt + sqrt(q) dW), from
        // its own seed so that the measurement noise does not change the motion
        let forced: Vec<(usize, f64)> = process_noise
            .iter()
            .filter_map(|(q, v)| model.state_index(*q).map(|i| (i, *v)))
            .collect();
        let mut rng = StdRng::seed_from_u64(self.cfg.noise.seed ^ PROCESS_SEED);
        let mut forcing = |x: &mut [f64], dt: f64| {
            for &(i, q) in &forced {
                let d = Normal::new(0.0, (q * dt).sqrt()).expect("q >= 0, checked by the loader");
                x[i] += d.sample(&mut rng);
            }
        };
        let xs = match (steering, forced.is_empty()) {
            (None, true) => simulate(model, &c, &x0, &input_series, &input_series.t, *substeps),
            (law, _) => per_sample(
                model,
                &c,
                &x0,
                &mut input_series,
                *law,
                *substeps,
                &mut forcing,
            ),
        }
        .map_err(|e| Error::numerical("simulate", e.to_string()))?;
        let InputSeries {
            t: times,
            inputs: series,
        } = input_series;
        let output_cols = sensor_outputs(model, &c, &xs, &times, &series);
        Ok(columns(model, times, &xs, output_cols, series))
    }
}

/// The export's columns: time, the states, the sensors' outputs and the inputs that vary.
fn columns<M: Model>(
    model: &M,
    times: Vec<f64>,
    xs: &[Vec<f64>],
    output_cols: Vec<(Quantity, Vec<f64>)>,
    series: Vec<Input>,
) -> Columns {
    let mut cols = Columns::new();
    cols.insert(Quantity::Time, times);
    for (i, s) in model.states().iter().enumerate() {
        cols.insert(s.quantity, xs.iter().map(|x| x[i]).collect());
    }
    cols.extend(output_cols);
    for (def, v) in model.inputs().iter().zip(series) {
        if let Input::Series(v) | Input::Held(v) = v {
            cols.insert(def.quantity, v);
        }
    }
    cols
}

/// The initial state: zero but for the states the manoeuvre sets.
fn initial_state<M: Model>(model: &M, initial: &BTreeMap<Quantity, Constant>) -> Result<Vec<f64>> {
    let mut x0 = vec![0.0; model.nx()];
    for (q, v) in initial {
        let i = model.state_index(*q).ok_or_else(|| {
            Error::Usage(format!(
                "initial {q} is not a state of the {} model",
                model.name()
            ))
        })?;
        x0[i] = v.si;
    }
    Ok(x0)
}

/// Refuses an input or a step setting a quantity that is not an input of the model.
fn check_inputs<M: Model>(
    model: &M,
    inputs: &BTreeMap<Quantity, Constant>,
    steps: &[Step],
) -> Result<()> {
    for q in inputs
        .keys()
        .chain(steps.iter().flat_map(|s| s.values.keys()))
    {
        if !model.input_quantities().contains(q) {
            return Err(Error::Usage(format!(
                "{q} is not an input of the {} model (inputs: {})",
                model.name(),
                model
                    .input_quantities()
                    .iter()
                    .map(|q| q.key())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    Ok(())
}

/// Each input of the model sampled at `times`: its start value, then its steps (held between
/// steps, or ramped at the input's rate), in hydroid's internal unit.
fn input_samples<M: Model>(
    model: &M,
    inputs: &BTreeMap<Quantity, Constant>,
    steps: &[Step],
    rates: &BTreeMap<Quantity, f64>,
    steering: Option<Steering>,
    times: &[f64],
) -> Vec<Input> {
    // inputs: start values, then steps (held between steps, or ramped at the input's
    // rate), in one sweep per input
    model
        .inputs()
        .iter()
        .map(|def| {
            let q = &def.quantity;
            let start = inputs.get(q).map_or(0.0, |c| c.si);
            // in hydroid's internal unit, as a record holds it (rev/s for rpm)
            let factor = q.internal_unit().factor;
            let changes = changes_of(steps, *q);
            let si = match rates.get(q) {
                Some(rate) => rate_limited(start, &changes, times, *rate),
                None => stepped(start, &changes, times),
            };
            let samples: Vec<f64> = si.into_iter().map(|v| v / factor).collect();
            let moved =
                rates.contains_key(q) || steering.is_some_and(|l| l.surface().input() == *q);
            between_samples(def.rule, moved, samples)
        })
        .collect()
}

/// What the sensors read: the model's outputs where it declares a measurement function (a
/// compass reads psi_L + psi_H); empty when the states are read directly.
fn sensor_outputs<M: Model>(
    model: &M,
    c: &[f64],
    xs: &[Vec<f64>],
    times: &[f64],
    series: &[Input],
) -> Vec<(Quantity, Vec<f64>)> {
    // what the sensors read: the model's outputs where it declares a measurement
    // function (a compass reads psi_L + psi_H), its states elsewhere
    if model.outputs().is_empty() {
        Vec::new()
    } else {
        let replay = InputSeries {
            t: times.to_vec(),
            inputs: series.to_vec(),
        };
        let mut u = vec![0.0; replay.len()];
        let ys: Vec<Vec<f64>> = xs
            .iter()
            .zip(times)
            .map(|(x, &t)| {
                replay.at(t, &mut u);
                model.output_values(x, &u, c)
            })
            .collect();
        model
            .output_quantities()
            .into_iter()
            .enumerate()
            .map(|(a, q)| (q, ys.iter().map(|y| y[a]).collect()))
            .collect()
    }
}

/// An input of the simulated run as the samples are read between sample times: linear for a
/// surface that moves continuously (at its rate, or by the helm), as a real one does and as
/// `between = "auto"` reads its logged samples; a step by the model's rule.
fn between_samples(rule: InputRule, moved: bool, samples: Vec<f64>) -> Input {
    match (rule, moved) {
        (InputRule::Interpolate, _) | (_, true) => Input::Series(samples),
        (InputRule::Hold, false) => Input::Held(samples),
    }
}

/// Integrates sample by sample with the helm of `law` moving its surface: at each sample the
/// helm sees the watched angle (heading, pitch) and sets the surface of the next sample
/// (written into the surface's series, which the interval's integration then reads as it
/// is read between samples: linearly for a surface the helm moves).
pub(crate) fn steered<M: Model>(
    model: &M,
    c: &[f64],
    x0: &[f64],
    inputs: &mut InputSeries,
    law: crate::dynamics::sim::steering::Steering,
    substeps: usize,
) -> std::result::Result<Vec<Vec<f64>>, crate::dynamics::sim::SimError> {
    per_sample(model, c, x0, inputs, Some(law), substeps, &mut |_, _| {})
}

/// Integrates sample by sample, with the helm of `law` (if any) moving its surface, and
/// `forcing(x, dt)` applied to the state after each interval of `dt` (a process noise).
pub(crate) fn per_sample<M: Model>(
    model: &M,
    c: &[f64],
    x0: &[f64],
    inputs: &mut InputSeries,
    law: Option<crate::dynamics::sim::steering::Steering>,
    substeps: usize,
    forcing: &mut dyn FnMut(&mut [f64], f64),
) -> std::result::Result<Vec<Vec<f64>>, crate::dynamics::sim::SimError> {
    // the helm watches the surface's angle (heading or pitch) and moves its input
    let mut helm = match law {
        None => None,
        Some(law) => {
            let surface = law.surface();
            let watched = model.state_index(surface.watched());
            let moved = model
                .input_quantities()
                .iter()
                .position(|q| *q == surface.input());
            let (Some(watched), Some(moved)) = (watched, moved) else {
                return Err(crate::dynamics::sim::SimError {
                    time: 0.0,
                    reason: format!(
                        "the {} model has no {} input or no {} state to steer",
                        model.name(),
                        surface.words(),
                        surface.watched_words()
                    ),
                });
            };
            Some((
                crate::dynamics::sim::steering::Helm::new(law),
                watched,
                moved,
            ))
        }
    };
    let times = inputs.t.clone();
    let mut xs = Vec::with_capacity(times.len());
    xs.push(x0.to_vec());
    for k in 1..times.len() {
        let dt = times[k] - times[k - 1];
        if let Some((helm, yaw, ri)) = &mut helm {
            match &mut inputs.inputs[*ri] {
                Input::Series(s) | Input::Held(s) => {
                    s[k] = helm.next(times[k - 1], xs[k - 1][*yaw], s[k - 1], dt);
                }
                Input::Constant(_) => {
                    return Err(crate::dynamics::sim::SimError {
                        time: times[k - 1],
                        reason: "the steered surface is not a series".into(),
                    })
                }
            }
        }
        let step = simulate(model, c, &xs[k - 1], inputs, &times[k - 1..=k], substeps)?;
        let mut x = step[1].clone();
        forcing(&mut x, dt);
        xs.push(x);
    }
    Ok(xs)
}

/// The steady polar implied by the coefficients: paper eq. 5 inverted with q = 0.5 rho A_ref,
/// C_D = a alpha^2 + b alpha + c with c = -Xuu/q, b = -Xuv/q, a = -Xvv/q - c/2,
/// C_L = (Yuvl/q) alpha + c3 alpha^3, C_M = (Nuvl/(q L_ref)) alpha + c3 alpha^3 when C_M is
/// the lift moment only (`moment` lift-only, the paper's reading), or with the total
/// Nuv = Nuva + Nuvl of the truth completed by symmetry (paper eq. 2 and 4) in place of Nuvl
/// when C_M is the whole yaw moment, as a CFD static drift run measures it.
fn polar_sweep(
    cfg: &SimConfig,
    set: &CoefficientSet,
    alpha_deg: &[f64],
    speeds: &[f64],
    (l_ref, moment): (f64, YawMoment),
    cubic: &BTreeMap<Quantity, f64>,
) -> Result<Columns> {
    let q = 0.5 * cfg.fluid.rho * cfg.vehicle.reference_area;
    let mut completed = set.clone();
    completed.complete(SYMMETRY, cfg.vehicle.yaw_moment);
    let get = |n: &str| {
        completed
            .value(n)
            .ok_or_else(|| Error::Usage(format!("a polar sweep needs {n} in [coefficients]")))
    };
    let c = -get("Xuu")? / q;
    let b = -get("Xuv")? / q;
    let a = -get("Xvv")? / q - c / 2.0;
    let cla = get("Yuvl")? / q;
    let cma = get(moment.polar_coefficient())? / (q * l_ref);
    let c3l = cubic.get(&Quantity::Cl).copied().unwrap_or(0.0);
    let c3m = cubic.get(&Quantity::Cm).copied().unwrap_or(0.0);
    let mut cols = Columns::new();
    for &u in speeds {
        for &ad in alpha_deg {
            let al = ad.to_radians();
            cols.entry(Quantity::Speed).or_default().push(u);
            cols.entry(Quantity::Alpha).or_default().push(al);
            cols.entry(Quantity::Cd)
                .or_default()
                .push(a * al * al + b * al + c);
            cols.entry(Quantity::Cl)
                .or_default()
                .push(cla * al + c3l * al.powi(3));
            cols.entry(Quantity::Cm)
                .or_default()
                .push(cma * al + c3m * al.powi(3));
        }
    }
    Ok(cols)
}

struct Captive<'a> {
    cfg: &'a SimConfig,
    set: &'a CoefficientSet,
}

impl ModelVisitor for Captive<'_> {
    type Output = Result<Columns>;

    /// Every condition of the programme: the state of the held motion (u = U cos beta,
    /// v = -U sin beta, r = r' U / L; Y&Y 2015 eq. 5 and 7), the inputs, and the model's
    /// steady forces.
    fn visit<M: Model>(self, model: &M) -> Result<Columns> {
        let Manoeuvre::Captive {
            speeds,
            drift_deg,
            yaw_rate_prime,
            rudder_deg,
            inputs,
        } = &self.cfg.manoeuvre
        else {
            unreachable!("called for a captive manoeuvre")
        };
        let c = complete_coefficients(model, self.set).map_err(|m| {
            Error::Usage(format!(
                "a captive programme needs {} in [coefficients]",
                m.join(", ")
            ))
        })?;
        let length = self.cfg.vehicle.length;
        let forces = model.force_quantities();
        let mut f = vec![0.0; forces.len()];
        let quantities = model.input_quantities();
        let held = crate::dynamics::sim::inputs::constant_inputs(&quantities, inputs);
        let rudder = quantities.iter().position(|q| *q == Quantity::Rudder);
        let mut cols = Columns::new();
        for &speed in speeds {
            for &beta in drift_deg {
                for &rp in yaw_rate_prime {
                    for &delta in rudder_deg {
                        let beta = beta.to_radians();
                        let mut x = vec![0.0; model.nx()];
                        let motion = [
                            (Quantity::U, speed * beta.cos()),
                            (Quantity::V, -speed * beta.sin()),
                            (Quantity::R, rp * speed / length),
                        ];
                        for (q, v) in motion {
                            if let Some(i) = model.state_index(q) {
                                x[i] = v;
                                cols.entry(q).or_default().push(v);
                            }
                        }
                        let mut u = held.clone();
                        if let Some(i) = rudder {
                            u[i] = delta.to_radians();
                        }
                        for (q, v) in model.input_quantities().iter().zip(&u) {
                            cols.entry(*q).or_default().push(*v);
                        }
                        model.captive_forces(&x, &vec![0.0; x.len()], &u, &c, &mut f);
                        for (q, v) in forces.iter().zip(&f) {
                            cols.entry(*q).or_default().push(*v);
                        }
                    }
                }
            }
        }
        Ok(cols)
    }
}
