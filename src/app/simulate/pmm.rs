//! Harmonic captive runs for `hydroid simulate` (`kind = "pmm"`): the model moved by a planar
//! motion mechanism at speed U with one or more velocities oscillating as
//! A sin(2 pi f t) (pure sway: v; pure yaw: r; ITTC 7.5-02-06-04 practice), and the force
//! history its captive force function gives ([`Model::captive_forces`], accelerations
//! included), so that every harmonic captive path has a twin experiment.

use super::config::{Manoeuvre, SimConfig};
use super::synth::Columns;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::config::{motion_limits, Constant, Problems};
use crate::dynamics::sim::integrate::complete_coefficients;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{Model, ModelVisitor};
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A harmonic captive run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Pmm {
    /// Carriage speed U, m/s (the mean of u).
    pub speed: f64,
    /// Amplitude of each oscillating velocity, SI (m/s, rad/s).
    pub amplitude: BTreeMap<Quantity, f64>,
    /// Frequency of the oscillation, Hz.
    pub frequency: f64,
    /// Length of the history, s.
    pub duration: f64,
    /// Sample interval, s.
    pub dt: f64,
    /// The model's inputs, constant (`thrust`, `rudder`, `rpm`).
    pub inputs: BTreeMap<Quantity, Constant>,
}

/// The keys of a `pmm` manoeuvre as written.
pub(super) struct PmmKeys {
    pub(super) speed: Option<f64>,
    pub(super) amplitude: Option<BTreeMap<Quantity, Constant>>,
    pub(super) frequency: Option<f64>,
    pub(super) duration: Option<f64>,
    pub(super) dt: Option<f64>,
    pub(super) inputs: Option<BTreeMap<Quantity, Constant>>,
    /// The vehicle's length, m (the scale of r' and omega').
    pub(super) length: f64,
}

/// The velocities a PMM may oscillate: the body velocities and rates.
const OSCILLATING: &[Quantity] = Quantity::MOTION.split_at(6).0;

/// Checks the keys of a `pmm` manoeuvre for a model with `states`, `inputs` and `forces`.
pub(super) fn check(
    keys: PmmKeys,
    states: &[Quantity],
    inputs: &[Quantity],
    has_forces: bool,
    p: &mut Problems,
) -> Option<Manoeuvre> {
    if !has_forces {
        p.add(
            "model",
            "this model gives no forces for a prescribed motion, so it has no PMM runs",
        );
        return None;
    }
    missing_keys(&keys, p);
    let (Some(speed), Some(frequency), Some(duration), Some(dt), Some(given)) = (
        keys.speed,
        keys.frequency,
        keys.duration,
        keys.dt,
        keys.amplitude,
    ) else {
        return None;
    };
    p.positive("manoeuvre.speed", speed, "m/s");
    p.positive("manoeuvre.frequency", frequency, "Hz");
    p.positive("manoeuvre.duration", duration, "s");
    p.positive("manoeuvre.dt", dt, "s");
    if !(speed > 0.0 && frequency > 0.0 && duration > 0.0 && dt > 0.0) {
        return None;
    }
    let mut ok = sampling_fits(frequency, duration, dt, p);
    if let Some(m) = motion_limits::speed(speed) {
        p.add("manoeuvre.speed", m);
        ok = false;
    } else if let Some(m) = motion_limits::omega_prime(frequency, keys.length, speed) {
        p.add("manoeuvre.frequency", m);
        ok = false;
    }
    let amplitude = amplitudes(&given, states, (speed, keys.length), &mut ok, p);
    if given.is_empty() {
        p.add("manoeuvre.amplitude", "names no oscillating velocity");
        ok = false;
    }
    let inputs_given = keys.inputs.unwrap_or_default();
    ok &= inputs_match(inputs, &inputs_given, p);
    ok.then_some(Manoeuvre::Pmm(Pmm {
        speed,
        amplitude,
        frequency,
        duration,
        dt,
        inputs: inputs_given,
    }))
}

/// Reports each key a PMM needs and lacks.
fn missing_keys(keys: &PmmKeys, p: &mut Problems) {
    let need = |p: &mut Problems, key: &str, what: &str| {
        p.add(
            &format!("manoeuvre.{key}"),
            format!("a pmm manoeuvre needs `{key}` ({what})"),
        );
    };
    if keys.speed.is_none() {
        need(p, "speed", "the carriage speed U, m/s");
    }
    if keys.frequency.is_none() {
        need(p, "frequency", "of the oscillation, e.g. \"0.4 Hz\"");
    }
    if keys.duration.is_none() {
        need(p, "duration", "s");
    }
    if keys.dt.is_none() {
        need(p, "dt", "s");
    }
    if keys.amplitude.is_none() {
        need(
            p,
            "amplitude",
            "of each oscillating velocity, e.g. `{ v = \"0.2 m/s\" }` (pure sway) or \
             `{ r = \"10 deg/s\" }` (pure yaw)",
        );
    }
}

/// Whether the sampling resolves the oscillation (20 samples a period or more) within the
/// row limit; reports what does not.
fn sampling_fits(frequency: f64, duration: f64, dt: f64, p: &mut Problems) -> bool {
    let mut ok = true;
    if dt > 0.05 / frequency {
        p.add(
            "manoeuvre.dt",
            format!(
                "{dt} s resolves a period of {} s in fewer than 20 samples",
                1.0 / frequency
            ),
        );
        ok = false;
    }
    if duration / dt > super::config::limits::MAX_ROWS as f64 {
        p.add(
            "manoeuvre.duration",
            format!("gives more than {} rows", super::config::limits::MAX_ROWS),
        );
        ok = false;
    }
    ok
}

/// The oscillating velocities' amplitudes in SI: each a velocity of the model, in its
/// quantity's unit, positive, a translation within the speed and a rate within r' = 2 at
/// `(speed, length)` (clears `ok` at a problem).
fn amplitudes(
    given: &BTreeMap<Quantity, Constant>,
    states: &[Quantity],
    (speed, length): (f64, f64),
    ok: &mut bool,
    p: &mut Problems,
) -> BTreeMap<Quantity, f64> {
    let mut amplitude = BTreeMap::new();
    for (q, c) in given {
        let key = format!("manoeuvre.amplitude.{q}");
        if !OSCILLATING.contains(q) || !states.contains(q) {
            p.add(
                &key,
                format!(
                    "a PMM oscillates a velocity of the model ({})",
                    states
                        .iter()
                        .filter(|s| OSCILLATING.contains(s))
                        .map(|s| s.key())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            );
            *ok = false;
            continue;
        }
        if let Err(m) = c.expect_quantity(*q) {
            p.add(&key, m);
            *ok = false;
            continue;
        }
        if !(c.si.is_finite() && c.si > 0.0) {
            p.add(&key, format!("must be positive, got {}", c.text));
            *ok = false;
        }
        let rate = matches!(q, Quantity::P | Quantity::Q | Quantity::R);
        let absurd = match rate {
            true => {
                let shown = match c.unit {
                    Some(_) => c.text.clone(),
                    None => format!("{} rad/s", c.text),
                };
                motion_limits::rate_prime(c.si, length, speed, &shown)
            }
            false => motion_limits::translation_amplitude(c.si, speed),
        };
        if let Some(m) = absurd.filter(|_| speed > 0.0 && length > 0.0) {
            p.add(&key, m);
            *ok = false;
        }
        amplitude.insert(*q, c.si);
    }
    amplitude
}

/// Whether the constant inputs are exactly the model's inputs; reports a missing or foreign
/// one.
fn inputs_match(
    inputs: &[Quantity],
    inputs_given: &BTreeMap<Quantity, Constant>,
    p: &mut Problems,
) -> bool {
    let mut ok = true;
    for q in inputs {
        if !inputs_given.contains_key(q) {
            p.add(
                "manoeuvre.inputs",
                format!("the model needs {q}: give it, e.g. `inputs = {{ {q} = ... }}`"),
            );
            ok = false;
        }
    }
    for q in inputs_given.keys() {
        if !inputs.contains(q) {
            p.add(
                &format!("manoeuvre.inputs.{q}"),
                "is not an input of the model",
            );
            ok = false;
        }
    }
    ok
}

/// Synthesises the force history of a PMM run.
pub(super) struct History<'a> {
    pub(super) cfg: &'a SimConfig,
    pub(super) set: &'a CoefficientSet,
}

impl ModelVisitor for History<'_> {
    type Output = Result<Columns>;

    /// Every sample: time, the prescribed velocities u = U + A_u sin(w t), v = A_v sin(w t)
    /// ... with their rates A w cos(w t), the constant inputs and the model's captive forces.
    fn visit<M: Model>(self, model: &M) -> Result<Columns> {
        let Manoeuvre::Pmm(pmm) = &self.cfg.manoeuvre else {
            unreachable!("called for a pmm manoeuvre")
        };
        let c = complete_coefficients(model, self.set).map_err(|m| {
            Error::Usage(format!(
                "a PMM run needs {} in [coefficients]",
                m.join(", ")
            ))
        })?;
        let omega = 2.0 * PI * pmm.frequency;
        let forces = model.force_quantities();
        let u =
            crate::dynamics::sim::inputs::constant_inputs(&model.input_quantities(), &pmm.inputs);
        let rows = (pmm.duration / pmm.dt + 1e-9).floor() as usize + 1;
        let mut cols = Columns::new();
        let mut x = vec![0.0; model.nx()];
        let mut dx = vec![0.0; model.nx()];
        let mut f = vec![0.0; forces.len()];
        for k in 0..rows {
            let t = k as f64 * pmm.dt;
            let (s, co) = (omega * t).sin_cos();
            cols.entry(Quantity::Time).or_default().push(t);
            for (i, state) in model.states().iter().enumerate() {
                let q = state.quantity;
                if !OSCILLATING.contains(&q) {
                    continue;
                }
                let a = pmm.amplitude.get(&q).copied().unwrap_or(0.0);
                let mean = if q == Quantity::U { pmm.speed } else { 0.0 };
                x[i] = mean + a * s;
                dx[i] = a * omega * co;
                cols.entry(q).or_default().push(x[i]);
            }
            for (q, v) in model.input_quantities().iter().zip(&u) {
                cols.entry(*q).or_default().push(*v);
            }
            model.captive_forces(&x, &dx, &u, &c, &mut f);
            for (q, v) in forces.iter().zip(&f) {
                cols.entry(*q).or_default().push(*v);
            }
        }
        Ok(cols)
    }
}
