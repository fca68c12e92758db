//! The closed loop on a plant other than the identified model: the plant built from its
//! spec (coefficients completed, held inputs, surge speed, the change mid-run), its Nomoto
//! indices from the course-stability linearisation, one run per feed.

use super::spec::PlantSpec;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::config::autopilot_plant::internal;
use crate::config::Constant;
use crate::dynamics::autopilot::closed_loop::{self, ClosedLoop, Scenario};
use crate::dynamics::autopilot::plant::{nomoto_of, Change, ModelPlant, Setup};
use crate::dynamics::autopilot::{Feed, PlantIndices};
use crate::dynamics::sim::complete_coefficients;
use crate::model::coefficients::{Coefficient, Source};
use crate::model::models::{Model, ModelVisitor, VehicleProblem};
use std::collections::BTreeMap;

/// The plant's vehicle refused by its model, as an error naming where the vehicle came from.
pub(super) fn vehicle_error(spec: &PlantSpec, problems: Vec<VehicleProblem>) -> Error {
    let from = spec.cfg.vehicle_file.as_ref().map_or_else(
        || "the run's [vehicle]".to_string(),
        |f| format!("autopilot.plant.vehicle_file {}", f.display()),
    );
    let list: Vec<String> = problems
        .iter()
        .map(|p| format!("{}: {}", p.key, p.message))
        .collect();
    Error::numerical(
        "autopilot",
        format!(
            "the plant {} cannot be built from {from}: {}",
            spec.name,
            list.join("; ")
        ),
    )
}

/// Visits the plant's model with the identified one.
pub(super) struct PlantVisit<'a, M: Model> {
    /// The identified model (the wave filter's).
    pub model: &'a M,
    /// Its coefficients.
    pub c: &'a [f64],
    /// The scenario.
    pub scenario: &'a Scenario,
    /// The feeds asked for.
    pub feeds: &'a [Feed],
    /// The plant.
    pub spec: &'a PlantSpec,
}

impl<M: Model> ModelVisitor for PlantVisit<'_, M> {
    type Output = Result<(Vec<ClosedLoop>, PlantIndices)>;

    fn visit<P: Model>(self, plant_model: &P) -> Self::Output {
        let fail = |m: String| Error::numerical("autopilot", m);
        let (setup, x_after) = setup(plant_model, self.spec)?;
        super::plausible::at_rest(plant_model, &setup, self.spec)?;
        let before = nomoto_of(plant_model, &setup.coefficients, &setup.x0, &setup.inputs)
            .map_err(|e| fail(format!("the plant {}: {e}", plant_model.name())))?;
        let after = match (&setup.change, &x_after) {
            (Some(ch), Some(x)) => Some(
                nomoto_of(plant_model, &ch.coefficients, x, &ch.inputs).map_err(|e| {
                    fail(format!(
                        "the plant {} after its change: {e}",
                        plant_model.name()
                    ))
                })?,
            ),
            _ => None,
        };
        super::plausible::plant(
            plant_model,
            &setup,
            x_after.as_deref(),
            self.scenario,
            self.spec,
        )?;
        let change_at = setup.change.as_ref().map(|c| c.at);
        let mut plant = ModelPlant::new(plant_model, setup).map_err(|e| fail(e.to_string()))?;
        let feeds = self
            .feeds
            .iter()
            .map(|f| {
                closed_loop::run_plant(&mut plant, self.model, self.c, self.scenario, *f)
                    .map_err(|e| fail(e.to_string()))
            })
            .collect::<Result<Vec<_>>>()?;
        let indices = PlantIndices {
            model: plant_model.name().to_string(),
            before,
            after,
            change_at,
        };
        Ok((feeds, indices))
    }
}

/// The plant's setup from its spec (and the state it linearises about after the change).
fn setup<P: Model>(model: &P, spec: &PlantSpec) -> Result<(Setup, Option<Vec<f64>>)> {
    let fail = |m: String| Error::numerical("autopilot", m);
    let coefficients = complete_coefficients(model, &spec.coefficients).map_err(|missing| {
        fail(format!(
            "the plant {} has no value for {} (autopilot.plant.coefficients or its \
             vehicle_file's [coefficients])",
            model.name(),
            missing.join(", ")
        ))
    })?;
    let inputs = held_inputs(model, &spec.cfg.inputs, None);
    let mut x0 = vec![0.0; model.nx()];
    let iu = model.state_index(Quantity::U);
    if let (Some(iu), Some(s)) = (iu, spec.cfg.speed) {
        x0[iu] = s;
    }
    let Some(ch) = &spec.cfg.change else {
        let setup = Setup {
            coefficients,
            inputs,
            x0,
            process_noise: Vec::new(),
            change: None,
        };
        return Ok((setup, None));
    };
    let mut after = spec.coefficients.clone();
    for (n, v) in &ch.coefficients {
        after.insert(Coefficient::new(n, *v, None, Source::Config));
    }
    let after = complete_coefficients(model, &after).map_err(|m| {
        fail(format!(
            "the plant after its change: no value for {}",
            m.join(", ")
        ))
    })?;
    let inputs_after = held_inputs(model, &ch.inputs, Some(&inputs));
    let mut x_after = x0.clone();
    if let (Some(iu), Some(s)) = (iu, ch.speed) {
        x_after[iu] = s;
    }
    let setup = Setup {
        coefficients,
        inputs,
        x0,
        process_noise: Vec::new(),
        change: Some(Change {
            at: ch.at,
            coefficients: after,
            inputs: inputs_after,
            speed: ch.speed,
        }),
    };
    Ok((setup, Some(x_after)))
}

/// The held inputs: `given` by quantity name over `base` (or zero); the rudder's is the
/// autopilot's.
fn held_inputs<P: Model>(
    model: &P,
    given: &BTreeMap<String, Constant>,
    base: Option<&[f64]>,
) -> Vec<f64> {
    model
        .input_quantities()
        .iter()
        .enumerate()
        .map(|(i, q)| {
            given
                .get(q.key())
                .map(|c| internal(*q, c))
                .unwrap_or_else(|| base.map_or(0.0, |b| b[i]))
        })
        .collect()
}
