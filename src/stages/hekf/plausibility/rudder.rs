//! The rudder against the model: its unit and sign.
//!
//! A rudder angle delta gives a yaw acceleration b delta at once, before the hull has
//! answered (Fossen 2011, 7.1: nu_dot = A nu + b delta; the MMG rudder moment N_R =
//! -(x_R + a_H x_H) F_N cos delta with F_N proportional to U_R^2 sin delta, Yasukawa &
//! Yoshimura 2015, eqs. 18-20). The run shows it through an equation-error fit of the yaw
//! equation in the non-dimensional form of the manoeuvring models (hull and rudder forces
//! scale with U^2, so r_dot = a U r + d U v + b U^2 delta + c, U = sqrt(u^2 + v^2)), in
//! increments over windows: r(t1) - r(t0) = a int U r + d int U v + b int U^2 delta + c (t1 -
//! t0). The model shows it as d r_dot / d delta at the run's approach speed with its
//! starting coefficients. The two agree within a factor of about 2 for a sound
//! configuration (on the KVLCC2 logs of MARIN and HSVA, 0.90 to 1.19); a rudder read in the
//! wrong unit is off by 57.3, one of the opposite sign convention turns the other way.

use super::{
    approach, file, integral, median_of, named, sig, window_lengths, windows, Expectation, Finding,
};
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::model::models::Model;
use nalgebra::{DMatrix, DVector};

const DEG: f64 = 180.0 / std::f64::consts::PI;

/// No rudder turns further than this (rad, 45 deg); a larger angle after conversion is a
/// unit mistake unless the model's response agrees with it.
const MAX_RUDDER: f64 = 45.0 / DEG;

/// Ratios of run to model within this factor (the geometric middle of 1 and 57.3) agree.
const AGREE: f64 = 7.57;

/// A ratio within this factor of 57.3 (or 1 / 57.3) is the degree-radian factor.
const UNIT_BAND: f64 = 4.0;

/// An effect smaller than this many of its standard errors is not judged.
const SIGNIFICANT: f64 = 5.0;

/// The yaw acceleration per rudder angle at the approach speed, as the run shows it and as
/// the model says.
struct Response {
    run: f64,
    model: f64,
    speed: f64,
    windows: usize,
    window: f64,
}

/// The rudder's unit and sign; `rate_trusted` is false when the yaw-rate column failed its
/// own check (the heading's rate is used instead).
pub(super) fn check<M: Model>(
    model: &M,
    rec: &Record,
    expect: &Expectation,
    rate_trusted: bool,
) -> Option<Finding> {
    let delta = rec.channel(Quantity::Rudder)?;
    if !model.input_quantities().contains(&Quantity::Rudder) {
        return None;
    }
    let largest = delta.iter().fold(0.0f64, |a, d| a.max(d.abs()));
    let response = response(model, rec, expect, rate_trusted);
    let ratio = response.as_ref().map(|r| r.run / r.model);
    // the size of the model's response is judged only when it carries over to this vehicle
    let sized = expect.sizes_known;
    let near = |x: f64, f: f64| sized && (x / f).abs().max((f / x).abs()) < UNIT_BAND;
    let agrees =
        sized && ratio.is_some_and(|x| x > 0.0 && x.abs() < AGREE && x.abs() > 1.0 / AGREE);
    let too_large = largest > MAX_RUDDER && largest / DEG <= MAX_RUDDER && !agrees;
    let (unit, sign) = match ratio {
        Some(x) if near(x, DEG) => (Some("radians read as degrees"), x < 0.0),
        Some(x) if near(x, 1.0 / DEG) => (Some("degrees read as radians"), x < 0.0),
        Some(x) => (too_large.then_some("degrees read as radians"), x < 0.0),
        None => (too_large.then_some("degrees read as radians"), false),
    };
    let scaled = rec.columns.get(&Quantity::Rudder).map_or(1.0, |c| c.scale);
    let mut fixes = Vec::new();
    if let Some(words) = unit {
        let right = if words.starts_with("rad") {
            "rad"
        } else {
            "deg"
        };
        fixes.push(format!(
            "the rudder looks like {words}: give `unit = \"{right}\"` in its column entry"
        ));
    }
    if sign {
        fixes.push(sign_fix(model, response.as_ref(), scaled));
    }
    let mut seen = seen(model, rec, response.as_ref(), largest);
    if response.is_some() && !sized {
        seen.push_str(
            " (only the signs are compared: the model's dimensional coefficients that the \
             configuration does not give are its example vehicle's)",
        );
    }
    if !fixes.is_empty() {
        return Some(Finding::new(rec, true, seen, fixes.join("; ")));
    }
    // neither a unit nor a sign: a ratio outside the agreeing band is only a warning
    let x = ratio.filter(|_| sized && !agrees)?;
    Some(Finding::new(
        rec,
        false,
        seen,
        format!(
            "the rudder turns the vehicle {} times as strongly as the {} model expects: check the \
             rudder column's unit and scale, and the model's rudder coefficients and \
             particulars",
            sig(x),
            model.name()
        ),
    ))
}

/// What the run and the model show, in words.
fn seen<M: Model>(model: &M, rec: &Record, r: Option<&Response>, largest: f64) -> String {
    let mut s = format!(
        "in {}, the {} reaches {} deg",
        file(rec),
        named(rec, Quantity::Rudder),
        sig(largest * DEG)
    );
    if let Some(r) = r {
        s.push_str(&format!(
            "; the yaw acceleration it gives at the approach speed of {} m/s is {} 1/s^2 per \
             rad in the run (fit of the yaw rate's increments on U r, U v and U^2 delta over {} \
             windows of {} s) and {} 1/s^2 per rad in the {} model at its starting \
             coefficients: a ratio of {}",
            sig(r.speed),
            sig(r.run),
            r.windows,
            sig(r.window),
            sig(r.model),
            model.name(),
            sig(r.run / r.model)
        ));
    }
    s
}

/// The fix of a rudder turning the other way from the model's.
fn sign_fix<M: Model>(model: &M, r: Option<&Response>, scaled: f64) -> String {
    // hydroid's axes: z down, so a positive yaw rate turns to starboard
    let side = if r.is_some_and(|r| r.model > 0.0) {
        "starboard (positive yaw rate); basin logs often count the rudder positive to port"
    } else {
        "port (negative yaw rate)"
    };
    let action = if scaled < 0.0 {
        "remove the `scale = -1` from the rudder's column entry"
    } else {
        "flip it with `scale = -1` in the rudder's column entry"
    };
    format!(
        "the vehicle turns the other way from the {} model for the same rudder angle: the \
         log's rudder sign convention is the opposite of the model's (a positive rudder turns \
         the model to {side}): {action}",
        model.name()
    )
}

/// The run's and the model's yaw acceleration per rudder angle, when both can be judged.
fn response<M: Model>(
    model: &M,
    rec: &Record,
    expect: &Expectation,
    rate_trusted: bool,
) -> Option<Response> {
    let times = rec.time()?;
    let n = times.len();
    let speed = speeds(rec);
    let range = approach(rec).unwrap_or(0..n);
    let u0 = median_of(range.clone().map(|k| speed[k]))?;
    // windows of about a 200th of the run, at least 5 samples (the fit hardly depends on it)
    let len = window_lengths(times)
        .into_iter()
        .take_while(|l| l * 200 <= n)
        .last()
        .unwrap_or(super::WINDOW);
    let yaw_rate = yaw_rate(rec, rate_trusted, 2 * len)?;
    let wins = windows(times, len);
    let (b, se) = fit(rec, times, &wins, &yaw_rate, &speed)?;
    // a NaN standard error judges nothing either
    if b.abs() <= SIGNIFICANT * se || se.is_nan() {
        return None;
    }
    let model_b = model_response(model, rec, expect, range, u0)?;
    let dt = crate::numerics::sampling::median_interval(times)?;
    Some(Response {
        run: b * u0 * u0,
        model: model_b,
        speed: u0,
        windows: wins.len(),
        window: len as f64 * dt,
    })
}

/// The speed U = sqrt(u^2 + v^2) at each sample (1 when the run has no u: the fit is then
/// dimensional).
fn speeds(rec: &Record) -> Vec<f64> {
    let n = rec.rows();
    match rec.channel(Quantity::U) {
        Some(u) => (0..n)
            .map(|k| u[k].hypot(rec.channel(Quantity::V).map_or(0.0, |v| v[k])))
            .collect(),
        None => vec![1.0; n],
    }
}

/// The yaw rate: the column when it passed its check, else the heading's central difference
/// over `span` samples on each side (a derivative of a noisy heading, or one that carries
/// wave-induced yaw, needs the span to average them out).
fn yaw_rate(rec: &Record, rate_trusted: bool, span: usize) -> Option<Vec<f64>> {
    if let Some(r) = rec.channel(Quantity::R).filter(|_| rate_trusted) {
        return Some(r.to_vec());
    }
    let (t, psi) = (rec.time()?, rec.channel(Quantity::Yaw)?);
    let n = t.len();
    Some(
        (0..n)
            .map(|k| {
                let (a, b) = (k.saturating_sub(span), (k + span).min(n - 1));
                (psi[b] - psi[a]) / (t[b] - t[a])
            })
            .collect(),
    )
}

/// The rudder term b of the windowed yaw equation and its standard error.
fn fit(
    rec: &Record,
    times: &[f64],
    wins: &[(usize, usize)],
    r: &[f64],
    speed: &[f64],
) -> Option<(f64, f64)> {
    let delta = rec.channel(Quantity::Rudder)?;
    let v = rec.channel(Quantity::V);
    let cols = if v.is_some() { 4 } else { 3 };
    if wins.len() < 2 * cols {
        return None;
    }
    let mut x = DMatrix::zeros(wins.len(), cols);
    let mut y = DVector::zeros(wins.len());
    for (i, &w) in wins.iter().enumerate() {
        y[i] = r[w.1] - r[w.0];
        x[(i, 0)] = integral(times, w, |k| speed[k] * r[k]);
        x[(i, 1)] = integral(times, w, |k| speed[k] * speed[k] * delta[k]);
        x[(i, 2)] = times[w.1] - times[w.0];
        if let Some(v) = v {
            x[(i, 3)] = integral(times, w, |k| speed[k] * v[k]);
        }
    }
    let s = crate::numerics::lsq::scaled_least_squares(&x, &y, wins.len() - cols)?;
    let (b, var) = (s.theta[1], s.covariance[1][1]);
    (b.is_finite() && var.is_finite()).then(|| (b, var.max(0.0).sqrt()))
}

/// d r_dot / d delta of the model at straight motion at speed `u0` (its other inputs at
/// their approach values), by a central difference (the models take inputs as numbers).
fn model_response<M: Model>(
    model: &M,
    rec: &Record,
    expect: &Expectation,
    range: std::ops::Range<usize>,
    u0: f64,
) -> Option<f64> {
    let ir = model.state_index(Quantity::R)?;
    let mut x = vec![0.0; model.nx()];
    if let Some(iu) = model.state_index(Quantity::U) {
        x[iu] = u0;
    }
    let quantities = model.input_quantities();
    let mut inputs: Vec<f64> = quantities
        .iter()
        .map(|q| match rec.channel(*q) {
            Some(v) => median_of(range.clone().map(|k| v[k])).unwrap_or(0.0),
            None => rec.constants.get(q).copied().unwrap_or(0.0),
        })
        .collect();
    let j = quantities.iter().position(|q| *q == Quantity::Rudder)?;
    let h = 1e-3;
    let mut at = |d: f64| {
        inputs[j] = d;
        let mut dx = vec![0.0; model.nx()];
        model.derivatives(&x, &inputs, &expect.coefficients, &mut dx);
        dx[ir]
    };
    let b = (at(h) - at(-h)) / (2.0 * h);
    (b.is_finite() && b != 0.0).then_some(b)
}
