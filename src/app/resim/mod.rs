//! Re-simulation: the identified model run open loop from a CFD run's initial state (each
//! measured state's value at the first sample, its noise averaged out by
//! [`signal::start_value`]) with its
//! inputs, compared with the CFD trajectory (RMS errors of u, v, r and heading, and the final
//! position error as a share of the distance travelled); for a ship's turning circle or
//! zig-zag, also the model steered through the same manoeuvre and measured as the run is
//! ([`manoeuvre`]).

pub mod forced;
pub mod manoeuvre;

use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::dynamics::sim::{complete_coefficients, simulate, steps_for, InputSeries};
use crate::io::record::Record;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle};
use crate::numerics::signal;
use serde::Serialize;
use std::collections::BTreeMap;

/// An RMS error above this share of the signal's peak-to-peak range is a poor re-simulation.
pub const POOR_RMS_SHARE: f64 = 0.1;

/// A signal whose range is below this many of its noise sigmas does not move beyond its
/// noise (a range within about +-4 sigma is the noise's own); its re-simulation error is
/// poor only above this many sigmas.
pub const NOISE_RANGE: f64 = 10.0;

/// A final position error above this percentage of the distance travelled is poor.
pub const POOR_POSITION_PCT: f64 = 10.0;

/// How well the model reproduces one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResimMetrics {
    /// Run name.
    pub run: String,
    /// Whether the run was used for identification (false: validation only).
    pub used_for_fit: bool,
    /// RMS error per compared quantity (SI).
    pub rms: BTreeMap<Quantity, f64>,
    /// Final position error divided by the distance travelled, percent (when x and y are
    /// measured).
    pub final_position_error_pct: Option<f64>,
    /// Distance travelled in the CFD run, m.
    pub distance: Option<f64>,
    /// Set when the simulation stopped early (it then covers part of the run).
    pub stopped: Option<String>,
    /// The run's turning circle or zig-zag measures beside the identified model's on the same
    /// manoeuvre (runs of a model with a rudder that make one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub manoeuvre: Option<manoeuvre::ManoeuvreComparison>,
}

/// The simulated trajectory of one run, for plots.
#[derive(Debug, Clone, PartialEq)]
pub struct ResimTrace {
    /// Sample times.
    pub times: Vec<f64>,
    /// Simulated states per sample (K x nx); shorter than `times` if it stopped.
    pub states: Vec<Vec<f64>>,
    /// State quantities, in state order.
    pub quantities: Vec<Quantity>,
    /// The quantities of the model's outputs (its sensors' readings), in output order; empty
    /// when the model declares no measurement function (its outputs are its states).
    pub outputs: Vec<Quantity>,
    /// The outputs per simulated sample (K x ny, in `outputs` order); empty with `outputs`.
    pub output_values: Vec<Vec<f64>>,
    /// The quantities of the model's inputs (rudder, planes, propeller ...), in input order.
    pub inputs: Vec<Quantity>,
}

impl ResimTrace {
    /// What the model's sensors read along the trace, by quantity: its outputs, or its
    /// states when it declares no measurement function.
    pub fn sensed(&self) -> (&[Quantity], &[Vec<f64>]) {
        if self.outputs.is_empty() {
            (&self.quantities, &self.states)
        } else {
            (&self.outputs, &self.output_values)
        }
    }
}

/// Re-simulates `rec` with the model `model` of `vehicle` and the coefficients of `set`;
/// `scale` is the data's scale ratio (for the IMO criteria of a ship's manoeuvre) and
/// `nominal` the nominal angles of the run's manoeuvre given in the configuration.
pub fn resimulate(
    model: ModelName,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    rec: &Record,
    used_for_fit: bool,
    scale: Option<f64>,
    nominal: crate::dynamics::manoeuvre::Nominal,
) -> Result<(ResimMetrics, ResimTrace)> {
    with_model(
        model,
        vehicle,
        Resim {
            set,
            rec,
            used_for_fit,
            run: manoeuvre::RunSettings {
                length: vehicle.vehicle.length,
                lambda: scale,
                nominal,
            },
        },
    )
    .map_err(Error::vehicle)?
}

struct Resim<'a> {
    set: &'a CoefficientSet,
    rec: &'a Record,
    used_for_fit: bool,
    run: manoeuvre::RunSettings,
}

impl ModelVisitor for Resim<'_> {
    type Output = Result<(ResimMetrics, ResimTrace)>;

    fn visit<M: Model>(self, model: &M) -> Self::Output {
        let rec = self.rec;
        let Prepared { times, c, inputs } = prepared(model, self.set, rec)?;
        let x0 = start_state(model, rec, &times);
        let (xs, stopped) = integrate(model, &c, x0, &inputs, &times, &mut |_, _| {});
        let (regular, max_step) = step_bounds(&times);
        let ys = outputs_of(model, &xs, &times, &inputs, &c);
        let rms = rms_errors(model, rec, if ys.is_empty() { &xs } else { &ys });
        let (final_err, distance) = position_error(model, rec, &xs).unzip();
        let steps = steps_for(regular, max_step).unwrap_or(1);
        let manoeuvre = manoeuvre::compare(model, &c, rec, &inputs, steps, self.run);
        Ok((
            ResimMetrics {
                run: rec.name.clone(),
                used_for_fit: self.used_for_fit,
                rms,
                final_position_error_pct: final_err,
                distance,
                stopped,
                manoeuvre,
            },
            trace(model, times, xs, ys),
        ))
    }
}

/// What a re-simulation of a run starts from: its times, the model's complete coefficient
/// vector and the run's inputs.
pub(crate) struct Prepared {
    pub times: Vec<f64>,
    pub c: Vec<f64>,
    pub inputs: InputSeries,
}

/// The run's times, the coefficients of `set` completed for the model, and the run's inputs;
/// an error names the run and what is missing.
pub(crate) fn prepared<M: Model>(
    model: &M,
    set: &CoefficientSet,
    rec: &Record,
) -> Result<Prepared> {
    let fail = |m: String| Error::numerical("resimulation", format!("run '{}': {m}", rec.name));
    let times = rec
        .time()
        .ok_or_else(|| fail("no time column".into()))?
        .to_vec();
    let c = complete_coefficients(model, set)
        .map_err(|missing| fail(format!("no value for {}", missing.join(", "))))?;
    let inputs = InputSeries::from_record(model.inputs(), rec)
        .map_err(|q| fail(format!("the model needs {q}, which the run does not give")))?;
    Ok(Prepared { times, c, inputs })
}

/// The trace of simulated states `xs` and outputs `ys` (empty: the states are the outputs).
pub(crate) fn trace<M: Model>(
    model: &M,
    times: Vec<f64>,
    xs: Vec<Vec<f64>>,
    ys: Vec<Vec<f64>>,
) -> ResimTrace {
    ResimTrace {
        times,
        quantities: model.states().iter().map(|s| s.quantity).collect(),
        outputs: if ys.is_empty() {
            Vec::new()
        } else {
            model.output_quantities()
        },
        states: xs,
        output_values: ys,
        inputs: model.input_quantities(),
    }
}

/// The run's initial state: each measured state's value at the first sample (a gross outlier
/// there replaced by its neighbours' median, the noise averaged over the first samples so
/// that a slow mode does not carry it through the whole run); unmeasured states start at 0.
pub(crate) fn start_state<M: Model>(model: &M, rec: &Record, times: &[f64]) -> Vec<f64> {
    let states = model.states();
    let mut x0 = vec![0.0; states.len()];
    for (i, s) in states.iter().enumerate() {
        if let Some(v) = rec.channel(s.quantity) {
            let spikes = signal::outliers(v);
            x0[i] = if spikes.first().is_some_and(|o| o.index == 0) {
                signal::cleaned(v, &spikes)[0]
            } else {
                signal::start_value(times, v)
            };
        }
    }
    x0
}

/// The run's regular sampling interval and the longest integration step: the interval split
/// into equal steps no longer than 10 ms.
fn step_bounds(times: &[f64]) -> (f64, f64) {
    let regular = crate::numerics::sampling::median_interval(times).unwrap_or(0.01);
    let max_step =
        regular / steps_for(regular, crate::numerics::ode::DEFAULT_MAX_STEP).unwrap_or(1) as f64;
    (regular, max_step)
}

/// The model from `x0` through `times` with `inputs`, sample by sample so that a divergence
/// keeps the part before it, in steps no longer than the regular interval nor 10 ms (a gap
/// is crossed in such steps); `forcing` acts on the state after each interval (given its
/// length: a process noise's increment). Also why it stopped early, if it did.
pub(crate) fn integrate<M: Model>(
    model: &M,
    c: &[f64],
    x0: Vec<f64>,
    inputs: &InputSeries,
    times: &[f64],
    forcing: &mut dyn FnMut(&mut [f64], f64),
) -> (Vec<Vec<f64>>, Option<String>) {
    let max_step = step_bounds(times).1;
    let mut xs = vec![x0];
    for k in 1..times.len() {
        let Some(steps) = steps_for(times[k] - times[k - 1], max_step) else {
            let why = format!(
                "the interval after t = {} s is too long to integrate",
                times[k - 1]
            );
            return (xs, Some(why));
        };
        match simulate(model, c, &xs[k - 1], inputs, &times[k - 1..=k], steps) {
            Ok(mut step) => {
                let mut x = step.swap_remove(1);
                forcing(&mut x, times[k] - times[k - 1]);
                xs.push(x);
            }
            Err(e) => return (xs, Some(e.to_string())),
        }
    }
    (xs, None)
}

/// What the model's sensors would have read along the simulated states `xs`: its outputs,
/// or nothing when it declares no measurement function (its states are its outputs).
pub(crate) fn outputs_of<M: Model>(
    model: &M,
    xs: &[Vec<f64>],
    times: &[f64],
    inputs: &InputSeries,
    c: &[f64],
) -> Vec<Vec<f64>> {
    if model.outputs().is_empty() {
        return Vec::new();
    }
    let mut u = vec![0.0; inputs.len()];
    xs.iter()
        .zip(times)
        .map(|(x, &t)| {
            inputs.at(t, &mut u);
            model.output_values(x, &u, c)
        })
        .collect()
}

/// The RMS difference of each compared quantity between the model's outputs `ys` and the
/// run, leaving out the run's gross outliers (they are not the model's error).
fn rms_errors<M: Model>(model: &M, rec: &Record, ys: &[Vec<f64>]) -> BTreeMap<Quantity, f64> {
    let mut rms = BTreeMap::new();
    for &q in model.compared() {
        let (Some(i), Some(meas)) = (model.output_index(q), rec.channel(q)) else {
            continue;
        };
        let n = ys.len();
        let spikes = signal::outliers(&meas[..n]);
        let used: Vec<usize> = (0..n)
            .filter(|k| spikes.binary_search_by_key(k, |o| o.index).is_err())
            .collect();
        let s: f64 = used.iter().map(|&k| (ys[k][i] - meas[k]).powi(2)).sum();
        rms.insert(q, (s / used.len().max(1) as f64).sqrt());
    }
    rms
}

/// The distance between the model's and the run's final positions as a percentage of the
/// distance the run travelled, and that distance (m); None without x and y or travel.
fn position_error<M: Model>(model: &M, rec: &Record, xs: &[Vec<f64>]) -> Option<(f64, f64)> {
    let (ix, iy) = (
        model.state_index(Quantity::X)?,
        model.state_index(Quantity::Y)?,
    );
    let (mx, my) = (rec.channel(Quantity::X)?, rec.channel(Quantity::Y)?);
    let n = xs.len();
    let d: f64 = (1..n)
        .map(|k| ((mx[k] - mx[k - 1]).powi(2) + (my[k] - my[k - 1]).powi(2)).sqrt())
        .sum();
    let e = ((xs[n - 1][ix] - mx[n - 1]).powi(2) + (xs[n - 1][iy] - my[n - 1]).powi(2)).sqrt();
    (d > 0.0).then(|| (100.0 * e / d, d))
}

/// Warnings about one re-simulation: stopped early, or errors large against the motion
/// (RMS beyond the measurement noise above [`POOR_RMS_SHARE`] of a signal's range, or a
/// final position error above
/// [`POOR_POSITION_PCT`] % of the distance travelled).
pub fn warnings(m: &ResimMetrics, rec: &Record) -> Vec<Warning> {
    let what = if m.used_for_fit {
        "a run used for the fit"
    } else {
        "a validation run"
    };
    let mut out = Vec::new();
    if let Some(s) = &m.stopped {
        out.push(
            Warning::new(
                "resimulation",
                format!("the re-simulation stopped early: {s}"),
                format!(
                    "the identified model does not reproduce {what}; its coefficients should \
                     not be used for prediction without understanding why"
                ),
            )
            .for_run(&rec.name),
        );
    }
    let mut poor = Vec::new();
    for (q, rms) in &m.rms {
        let Some(raw) = rec.channel(*q) else { continue };
        let v = signal::cleaned(raw, &signal::outliers(raw));
        let (lo, hi) = signal::range(v.iter().copied());
        let range = hi - lo;
        // the measurement noise is in the RMS error but is not the model's: only the excess
        // over it counts (errors add in quadrature), which matters for a quantity that moves
        // little more than its noise
        let noise = signal::noise_sigma(&v).unwrap_or(0.0);
        let excess = (rms * rms - noise * noise).max(0.0).sqrt();
        // a quantity that hardly moves beyond its noise (the heading in a vertical zig-zag)
        // has a range made of noise, and the open-loop model drifts from the noise of its
        // first sample: its error is poor only beyond ten noise sigmas
        let limit = if range < NOISE_RANGE * noise {
            NOISE_RANGE * noise
        } else {
            POOR_RMS_SHARE * range
        };
        if range > 0.0 && excess > limit {
            poor.push(format!(
                "{q} (RMS error {} of its range{})",
                percent(100.0 * rms / range),
                if noise > 0.1 * rms {
                    format!(
                        ", {} beyond its measurement noise",
                        percent(100.0 * excess / range)
                    )
                } else {
                    String::new()
                }
            ));
        }
    }
    if let Some(p) = m
        .final_position_error_pct
        .filter(|p| *p > POOR_POSITION_PCT)
    {
        poor.push(format!(
            "the final position ({} of the distance travelled)",
            percent(p)
        ));
    }
    if let Some(cmp) = &m.manoeuvre {
        out.extend(manoeuvre::warnings(cmp, &rec.name));
    }
    if !poor.is_empty() {
        out.push(
            Warning::new(
                "resimulation",
                format!("poor re-simulation of {}", poor.join(", ")),
                format!(
                    "the identified model does not reproduce {what} although each coefficient \
                     may look well determined: the model structure, a fixed coefficient or an \
                     input is wrong, or the run lies outside what the fit runs covered"
                ),
            )
            .for_run(&rec.name),
        );
    }
    // each is a failed re-simulation test
    out.into_iter()
        .map(|w| w.failed(crate::base::warning::Test::Resimulation))
        .collect()
}

/// A share in percent as the warnings print it: a model that ran away (a re-simulation
/// that stopped on a non-finite state grows its errors without bound) is "over 1000 %",
/// not a number of fifty digits.
fn percent(p: f64) -> String {
    if p.is_finite() && p <= 1000.0 {
        format!("{p:.0} %")
    } else {
        "over 1000 %".to_string()
    }
}
