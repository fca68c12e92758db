//! A plant checked before the loop closes around it, so that a loop that could only spin is
//! refused with its cause rather than reported: a ship that starts at rest, a rudder that
//! turns the plant the other way from the identified model the autopilot is tuned on (a
//! reversed rudder sign), held inputs that do not hold its speed (a propeller speed in rpm
//! read as rev/s); and after the run, the warning of a loop that holds no course, with what
//! to check.

use super::spec::PlantSpec;
use crate::base::error::{Error, Result};
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::autopilot::AutopilotConfig;
use crate::config::Constant;
use crate::dynamics::autopilot::closed_loop::Scenario;
use crate::dynamics::autopilot::plant::{surge_acceleration, yaw_per_rudder_at, Setup};
use crate::dynamics::autopilot::plausibility;
use crate::dynamics::autopilot::AutopilotResult;
use crate::model::models::Model;
use std::collections::BTreeMap;

/// Largest surge acceleration of a plant at its start under its held inputs, m/s^2 (0.1 g):
/// a ship's propeller at the approach's rate balances its resistance, and no ship or model
/// accelerates or brakes near this under a held propeller.
pub const MAX_SURGE_ACCELERATION: f64 = 1.0;

/// Refuses a plant with a surge state that starts at rest: a ship at rest does not answer
/// its rudder (and its Nomoto indices there mean nothing).
pub(super) fn at_rest<P: Model>(model: &P, setup: &Setup, spec: &PlantSpec) -> Result<()> {
    match model.state_index(Quantity::U) {
        Some(iu) if setup.x0[iu] <= 0.0 => Err(Error::numerical(
            "autopilot",
            format!(
                "the plant {}: it starts at rest (autopilot.plant.speed not given, or 0): a \
                 ship at rest does not answer its rudder; give the speed it keeps its course at",
                spec.name
            ),
        )),
        _ => Ok(()),
    }
}

/// Refuses the plant of `spec` set up as `setup` (its state after its change `x_after`)
/// when the loop around it could only spin: a rudder that turns it the other way from the
/// identified model, held inputs that do not hold its speed; naming the cause and the key.
pub(super) fn plant<P: Model>(
    model: &P,
    setup: &Setup,
    x_after: Option<&[f64]>,
    scenario: &Scenario,
    spec: &PlantSpec,
) -> Result<()> {
    let fail = |m: String| Error::numerical("autopilot", format!("the plant {}: {m}", spec.name));
    // the identified K / T, what the tuning assumes a positive rudder does
    let g = scenario.gains;
    let identified = g.omega_n * g.omega_n / g.kp;
    let mut states = vec![(
        "at its start",
        &setup.coefficients,
        setup.x0.as_slice(),
        &setup.inputs,
        &spec.cfg.inputs,
    )];
    if let (Some(ch), Some(x), Some(cfg)) = (&setup.change, x_after, &spec.cfg.change) {
        states.push((
            "after its change",
            &ch.coefficients,
            x,
            &ch.inputs,
            &cfg.inputs,
        ));
    }
    for (when, c, x, u, given) in states {
        if let Some(b) = yaw_per_rudder_at(model, c, x, u) {
            if b <= 0.0 || !b.is_finite() {
                return Err(fail(reversed(b, identified, when, x, model)));
            }
        }
        if let Some(a) = surge_acceleration(model, c, x, u) {
            if a.abs() > MAX_SURGE_ACCELERATION || !a.is_finite() {
                let speed = model.state_index(Quantity::U).map_or(0.0, |i| x[i]);
                return Err(fail(unbalanced(a, speed, when, given)));
            }
        }
    }
    Ok(())
}

/// The message of a plant whose rudder turns it the other way (or not at all).
fn reversed<P: Model>(b: f64, identified: f64, when: &str, x: &[f64], model: &P) -> String {
    let speed = model
        .state_index(Quantity::U)
        .map_or(String::new(), |i| format!(" at {} m/s", num(x[i])));
    if b == 0.0 || !b.is_finite() {
        return format!(
            "its rudder moves no yaw {when}{speed} (d r_dot / d delta = {b}): the autopilot \
             cannot steer it; check its speed and its rudder coefficients"
        );
    }
    format!(
        "its rudder works the other way from the identified model's {when}{speed}: a positive \
         rudder gives it a yaw acceleration of {} 1/s^2 per radian, where the identified model \
         the autopilot is tuned on gives +{} (K / T): closed around it, the loop steers away \
         from its course; a rudder sign reversed in autopilot.plant.coefficients or its \
         vehicle file, or a model whose positive rudder turns the other way (autopilot.plant.\
         model)",
        num(b),
        num(identified)
    )
}

/// The message of held inputs that do not hold the plant's speed.
fn unbalanced(a: f64, speed: f64, when: &str, given: &BTreeMap<String, Constant>) -> String {
    let inputs: Vec<String> = given
        .iter()
        .map(|(k, c)| format!("{k} = {}", c.text))
        .collect();
    let held = if inputs.is_empty() {
        "none given: held at 0".to_string()
    } else {
        inputs.join(", ")
    };
    let rpm = given.get("rpm").map_or(String::new(), |c| {
        let rev_s = crate::config::autopilot_plant::internal(Quantity::Rpm, c);
        format!(
            "; autopilot.plant.inputs.rpm is in rev/s: {} rev/s is {} rpm (write \"{} rpm\" \
             for a propeller speed in rpm)",
            num(rev_s),
            num(60.0 * rev_s),
            c.text
        )
    });
    format!(
        "its held inputs ({held}) accelerate it at {} m/s^2 ({} g) at {} m/s {when}: they do \
         not hold its speed, as the approach's propeller rate would (at most {} m/s^2){rpm}",
        num(a),
        num(a / 9.80665),
        num(speed),
        MAX_SURGE_ACCELERATION
    )
}

/// Warnings on the loops that hold no course, with what to check about the plant.
pub fn loop_warnings(
    r: &AutopilotResult,
    cfg: &AutopilotConfig,
    plant: Option<&PlantSpec>,
) -> Vec<Warning> {
    let causes = match plant {
        None => "check the gains (autopilot.omega_n, zeta), the steering gear \
                 (rudder_limit, rudder_rate) and a recorded disturbance's unit"
            .to_string(),
        Some(p) => {
            let inputs: Vec<String> = p
                .cfg
                .inputs
                .iter()
                .map(|(k, c)| format!("{k} = {}", c.text))
                .collect();
            format!(
                "check the plant {} (autopilot.plant): its rudder's sign, its held inputs \
                 ({}; rpm in rev/s unless a unit is given), its speed, and the gains \
                 (autopilot.omega_n, zeta)",
                p.name,
                if inputs.is_empty() {
                    "none".to_string()
                } else {
                    inputs.join(", ")
                }
            )
        }
    };
    plausibility::closed_loop_warnings(r, cfg.rudder_limit, &causes)
}
