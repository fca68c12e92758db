//! The FMU's model assembled from a run's parts: the model's coefficient vector (completed by
//! its relations), its inputs and its states with their start values, as resources/model.json
//! holds them (docs/fmu.md).

use super::spec::{self, FmuSpec, Named, Variable};
use crate::base::error::{Error, Result};
use crate::dynamics::sim::complete_coefficients;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{Model, ModelVisitor, RunVehicle};

/// The FMU's model: `model` built for `vehicle` with the coefficients of `set` (the model's
/// relations complete them), the states starting at `starts` (by state name; zero for a
/// state not there) and the inputs at zero.
pub fn from_parts(
    model: &str,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    starts: &[(String, f64)],
    max_step: f64,
    title: Option<String>,
) -> Result<FmuSpec> {
    let mut spec = FmuSpec {
        format: spec::FORMAT.to_string(),
        hydroid_version: env!("CARGO_PKG_VERSION").to_string(),
        title,
        model: model.to_string(),
        vehicle: vehicle.vehicle.clone(),
        yaw_moment: vehicle.yaw_moment,
        coefficients: Vec::new(),
        inputs: Vec::new(),
        states: Vec::new(),
        max_step,
    };
    let described = spec.visit(Describe { set, starts })?;
    let (coefficients, inputs, states) = described.map_err(|missing| {
        Error::Usage(format!(
            "the {model} model needs {}, which the run does not give",
            missing.join(", ")
        ))
    })?;
    spec.coefficients = coefficients;
    spec.inputs = inputs;
    spec.states = states;
    Ok(spec)
}

/// The model's coefficient vector, inputs and states, or the coefficients the set lacks.
struct Describe<'a> {
    set: &'a CoefficientSet,
    starts: &'a [(String, f64)],
}

type Described = (Vec<Named>, Vec<Variable>, Vec<Variable>);

impl ModelVisitor for Describe<'_> {
    type Output = std::result::Result<Described, Vec<String>>;
    fn visit<M: Model>(self, m: &M) -> Self::Output {
        let c = complete_coefficients(m, self.set)?;
        let coefficients = m
            .coefficient_names()
            .iter()
            .zip(c)
            .map(|(n, value)| Named {
                name: n.to_string(),
                value,
            })
            .collect();
        let inputs = m
            .inputs()
            .iter()
            .map(|i| Variable {
                name: i.quantity.key().to_string(),
                quantity: i.quantity.key().to_string(),
                unit: i.quantity.si_symbol().to_string(),
                start: 0.0,
            })
            .collect();
        let states = m
            .states()
            .iter()
            .map(|s| Variable {
                name: s.name.to_string(),
                quantity: s.quantity.key().to_string(),
                unit: s.quantity.si_symbol().to_string(),
                start: self
                    .starts
                    .iter()
                    .find(|(n, _)| n == s.name)
                    .map_or(0.0, |(_, v)| *v),
            })
            .collect();
        Ok((coefficients, inputs, states))
    }
}
