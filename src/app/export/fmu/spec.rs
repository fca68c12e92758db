//! What an exported FMU holds of the model (`resources/model.json`): the registry name, the
//! vehicle, the completed coefficient vector, the inputs and states with their units and
//! start values, and the longest integration step; and one communication step of it, the
//! same RK4 as `hydroid simulate` with the inputs held over the step.

use crate::base::error::{Error, Result};
use crate::base::numfmt::short;
use crate::dynamics::sim::{simulate, steps_for, InputSeries};
use crate::model::coefficients::YawMoment;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle, Vehicle};
use crate::numerics::ode::{DEFAULT_MAX_STEP, MAX_STEPS_PER_INTERVAL};
use serde::{Deserialize, Serialize};

/// The format tag of model.json.
pub const FORMAT: &str = "hydroid-fmu/1";

/// The range of the longest RK4 step an FMU takes (`max_step`, `--max-step`), s. A
/// communication step of H takes ceil(H / max_step) steps and at most
/// [`MAX_STEPS_PER_INTERVAL`] (one million): 1e-5 s keeps communication steps up to 10 s
/// within that bound, and is a thousand times finer than the default (0.01 s). Above 1 s a
/// step no longer resolves the motions of the vehicles hydroid models, whose time scales are
/// seconds (docs/fmu.md).
pub const MAX_STEP_RANGE: (f64, f64) = (1e-5, 1.0);

/// Checks a longest step against [`MAX_STEP_RANGE`]; the error says why the bounds are there.
pub fn check_max_step(step: f64) -> std::result::Result<(), String> {
    let (lo, hi) = MAX_STEP_RANGE;
    if step.is_finite() && (lo..=hi).contains(&step) {
        return Ok(());
    }
    Err(format!(
        "{} s is not a step between {lo:e} s and {hi} s: a communication step of H takes \
         ceil(H / step) RK4 steps, at most {MAX_STEPS_PER_INTERVAL}, which {lo:e} s keeps \
         within reach for communication steps up to {} s, and a step above {hi} s no longer \
         resolves the vehicle's motion (the default is {DEFAULT_MAX_STEP} s)",
        short(step),
        lo * MAX_STEPS_PER_INTERVAL as f64
    ))
}

/// resources/model.json of an exported FMU.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FmuSpec {
    /// [`FORMAT`].
    pub format: String,
    /// The hydroid version that exported it.
    pub hydroid_version: String,
    /// The run's title.
    pub title: Option<String>,
    /// The model's registry name (`mmg3`).
    pub model: String,
    /// The vehicle the model is built from (SI).
    pub vehicle: Vehicle,
    /// The run's yaw-moment reading.
    pub yaw_moment: YawMoment,
    /// Every coefficient of the model in its order, relations applied (SI).
    pub coefficients: Vec<Named>,
    /// The model's inputs, in its order: held over each communication step.
    pub inputs: Vec<Variable>,
    /// The model's states, in its order: the FMU's outputs; their start values are the
    /// initial-state parameters.
    pub states: Vec<Variable>,
    /// Longest RK4 step, s: a communication step of H takes ceil(H / max_step) equal steps.
    pub max_step: f64,
}

/// A coefficient's name and value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Named {
    /// Name (`Yv_p`).
    pub name: String,
    /// Value, SI.
    pub value: f64,
}

/// An input or a state of the model as the FMU names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variable {
    /// The variable's name (a state's name, `psi`; an input's quantity key, `rudder`).
    pub name: String,
    /// hydroid's quantity key (`yaw`).
    pub quantity: String,
    /// The unit the value is in (hydroid's internal unit: SI, rev/s for a propeller speed).
    pub unit: String,
    /// Start value.
    pub start: f64,
}

impl FmuSpec {
    /// Reads model.json (`what` names it in messages).
    pub fn from_json(text: &str, what: &str) -> Result<FmuSpec> {
        let spec: FmuSpec = serde_json::from_str(text)
            .map_err(|e| Error::Usage(format!("{what}: not a hydroid FMU model file: {e}")))?;
        if spec.format != FORMAT {
            return Err(Error::Usage(format!(
                "{what}: format \"{}\", expected \"{FORMAT}\"",
                spec.format
            )));
        }
        check_max_step(spec.max_step).map_err(|e| Error::Usage(format!("{what}: max_step {e}")))?;
        Ok(spec)
    }

    /// The model's registry entry.
    pub fn model_name(&self) -> Result<ModelName> {
        ModelName::from_name(&self.model).ok_or_else(|| {
            Error::Usage(format!(
                "unknown model \"{}\" (this hydroid has {})",
                self.model,
                ModelName::NAMES.join(", ")
            ))
        })
    }

    /// The vehicle as the run built its models.
    pub fn run_vehicle(&self) -> RunVehicle {
        RunVehicle {
            vehicle: self.vehicle.clone(),
            yaw_moment: self.yaw_moment,
        }
    }

    /// Checks that the longest step is in [`MAX_STEP_RANGE`] and that the model builds from
    /// the vehicle and has exactly the coefficients, inputs and states listed (an FMU of
    /// another hydroid version is refused, not misread).
    pub fn check(&self) -> Result<()> {
        check_max_step(self.max_step).map_err(|e| Error::Usage(format!("max_step {e}")))?;
        self.visit(Check(self))?
    }

    /// The state after one communication step from `t` to `t + h` starting at `x`, the
    /// inputs `u` held over it: `ceil(h / max_step)` RK4 steps of [`simulate`], as `hydroid
    /// simulate` integrates a sample interval with a held input.
    pub fn advance(&self, x: &[f64], u: &[f64], t: f64, h: f64) -> Result<Vec<f64>> {
        let steps = steps_for(h, self.max_step).ok_or_else(|| {
            Error::Usage(format!(
                "a communication step of {h} s takes more than a million steps of {} s",
                self.max_step
            ))
        })?;
        let c: Vec<f64> = self.coefficients.iter().map(|c| c.value).collect();
        self.visit(Advance {
            c: &c,
            x,
            u,
            times: [t, t + h],
            steps,
        })?
    }

    /// Builds the model for the vehicle and hands it to `visitor`.
    pub(super) fn visit<V: ModelVisitor>(&self, visitor: V) -> Result<V::Output> {
        let name = self.model_name()?;
        with_model(name, &self.run_vehicle(), visitor).map_err(|problems| {
            let list: Vec<String> = problems
                .iter()
                .map(|p| format!("{}: {}", p.key, p.message))
                .collect();
            Error::Usage(format!(
                "the vehicle does not build the {} model: {}",
                self.model,
                list.join("; ")
            ))
        })
    }
}

/// Compares a model with the spec.
struct Check<'a>(&'a FmuSpec);

impl<'a> ModelVisitor for Check<'a> {
    type Output = Result<()>;
    fn visit<M: Model>(self, m: &M) -> Result<()> {
        let spec = self.0;
        let differs = |what: &str, want: Vec<&str>, have: Vec<&str>| {
            (want != have).then(|| {
                Error::Usage(format!(
                    "the {} model of this hydroid has the {what} {}, the FMU lists {}",
                    spec.model,
                    want.join(", "),
                    have.join(", ")
                ))
            })
        };
        let states: Vec<&str> = m.states().iter().map(|s| s.name).collect();
        let inputs: Vec<&str> = m.inputs().iter().map(|i| i.quantity.key()).collect();
        let names = |v: &'a [Variable]| v.iter().map(|v| v.name.as_str()).collect::<Vec<_>>();
        let coefs: Vec<&str> = spec.coefficients.iter().map(|c| c.name.as_str()).collect();
        let problem = differs("coefficients", m.coefficient_names(), coefs)
            .or_else(|| differs("states", states, names(&spec.states)))
            .or_else(|| differs("inputs", inputs, names(&spec.inputs)));
        problem.map_or(Ok(()), Err)
    }
}

/// One communication step.
struct Advance<'a> {
    c: &'a [f64],
    x: &'a [f64],
    u: &'a [f64],
    times: [f64; 2],
    steps: usize,
}

impl ModelVisitor for Advance<'_> {
    type Output = Result<Vec<f64>>;
    fn visit<M: Model>(self, m: &M) -> Result<Vec<f64>> {
        let inputs = InputSeries::constant(self.u);
        let mut xs = simulate(m, self.c, self.x, &inputs, &self.times, self.steps)
            .map_err(|e| Error::numerical("fmu", e.to_string()))?;
        Ok(xs.pop().unwrap_or_default())
    }
}
