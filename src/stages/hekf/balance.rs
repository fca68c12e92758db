//! Is the approach an equilibrium? The surge equation at the start of each run, before any
//! input changes: a free-running test approaches at a steady speed, so the model's surge
//! acceleration there, with the logged inputs (a propeller at the basin's self-propulsion
//! point) and the coefficients it holds (a published resistance), must match the measured
//! one. A model that accelerates or decelerates where the ship did not has its thrust and
//! resistance out of balance, and every coefficient the filter estimates then absorbs the
//! surge force it lacks. The model names the coefficient that sets the balance
//! (`Model::surge_balance`: R'_0 for the MMG model); when the data contradict it, the stage
//! estimates it by default and says so.

use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::model::models::Model;

/// Fewest samples of an approach that are judged.
const MIN_SAMPLES: usize = 10;

/// Shortest approach judged, s.
const MIN_DURATION: f64 = 0.5;

/// Significance: the mismatch must exceed this many standard errors of the measured slope.
const SIGNIFICANCE: f64 = 5.0;

/// ... and change the speed by more than this share over [`HORIZON`].
const DRIFT: f64 = 0.02;

/// Seconds over which a mismatch of acceleration is judged against the speed.
const HORIZON: f64 = 30.0;

/// A surge imbalance at a run's approach.
#[derive(Debug, Clone, PartialEq)]
pub struct Imbalance {
    /// The run.
    pub run: String,
    /// The approach: from the first sample to the last before an input changes, s.
    pub until: f64,
    /// Mean speed over it, m/s.
    pub speed: f64,
    /// Measured surge acceleration (least-squares slope of u), m/s^2.
    pub measured: f64,
    /// The model's surge acceleration along the measured states with the logged inputs,
    /// m/s^2.
    pub model: f64,
}

impl Imbalance {
    /// The unbalanced surge force on a body of mass `mass` (kg), N: what the model lacks.
    pub fn force(&self, mass: f64) -> f64 {
        mass * (self.measured - self.model)
    }
}

/// The surge imbalance of `rec`'s approach for `model` with coefficients `c` (complete,
/// SI), when significant; None when it balances or cannot be judged (no surge velocity, a
/// model without a surge state, an approach too short).
pub fn approach<M: Model>(model: &M, c: &[f64], rec: &Record) -> Option<Imbalance> {
    let iu = model.state_index(Quantity::U)?;
    let (t, u) = (rec.time()?, rec.channel(Quantity::U)?);
    let end = approach_end(model, rec)?;
    if end < MIN_SAMPLES || t[end - 1] - t[0] < MIN_DURATION {
        return None;
    }
    let (slope, se) = slope(&t[..end], &u[..end])?;
    let mut x = vec![0.0; model.nx()];
    let mut inputs = vec![0.0; model.inputs().len()];
    let mut dx = vec![0.0; model.nx()];
    let mut sum = 0.0;
    for k in 0..end {
        for (i, s) in model.states().iter().enumerate() {
            x[i] = rec.value_at(s.quantity, k).unwrap_or(0.0);
        }
        for (i, d) in model.inputs().iter().enumerate() {
            inputs[i] = rec.value_at(d.quantity, k)?;
        }
        model.derivatives(&x, &inputs, c, &mut dx);
        sum += dx[iu];
    }
    let predicted = sum / end as f64;
    let speed = u[..end].iter().sum::<f64>() / end as f64;
    let gap = (predicted - slope).abs();
    (predicted.is_finite() && gap > SIGNIFICANCE * se && gap * HORIZON > DRIFT * speed.abs()).then(
        || Imbalance {
            run: rec.name.clone(),
            until: t[end - 1],
            speed,
            measured: slope,
            model: predicted,
        },
    )
}

/// The samples before the first input changes by more than 2 % of its range over the run
/// (at least 0.5 deg for an angle), capped at 60 s.
fn approach_end<M: Model>(model: &M, rec: &Record) -> Option<usize> {
    let t = rec.time()?;
    let mut end = t.len();
    for d in model.inputs() {
        let Some(v) = rec.channel(d.quantity) else {
            continue;
        };
        let (lo, hi) = crate::numerics::signal::range(v.iter().copied());
        let floor = if d.quantity.si_symbol() == "rad" {
            0.5f64.to_radians()
        } else {
            0.0
        };
        let tol = (0.02 * (hi - lo)).max(floor);
        if let Some(k) = v.iter().position(|x| (x - v[0]).abs() > tol) {
            end = end.min(k);
        }
    }
    Some(end.min(t.partition_point(|&x| x <= t[0] + 60.0)))
}

/// The least-squares slope of `y` against `t` and its standard error (residuals taken as
/// independent: the significance test is a screen, not a confidence statement).
fn slope(t: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = t.len() as f64;
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|v| (v - tm).powi(2)).sum();
    if stt.is_nan() || stt <= 0.0 {
        return None;
    }
    let b = t
        .iter()
        .zip(y)
        .map(|(a, c)| (a - tm) * (c - ym))
        .sum::<f64>()
        / stt;
    let res: f64 = t
        .iter()
        .zip(y)
        .map(|(a, c)| (c - ym - b * (a - tm)).powi(2))
        .sum();
    let se = (res / (n - 2.0).max(1.0) / stt).sqrt();
    Some((b, se))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::mmg3::{Mmg3, KVLCC2, KVLCC2_RPS, KVLCC2_SPEED};
    use std::collections::BTreeMap;

    /// A straight approach at the KVLCC2's speed held by the basin (u constant), the
    /// propeller at `rps`.
    fn approach_record(rps: f64) -> Record {
        let n = 200;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 0.05).collect();
        let mut ch = BTreeMap::new();
        ch.insert(Quantity::U, vec![KVLCC2_SPEED; n]);
        ch.insert(Quantity::Rudder, vec![0.0; n]);
        ch.insert(Quantity::Rpm, vec![rps; n]);
        ch.insert(Quantity::Time, t);
        Record::from_channels("approach", "approach.csv", ch)
    }

    #[test]
    fn the_published_resistance_at_its_balance_propeller_is_an_equilibrium() {
        let m = Mmg3::build(&crate::model::models::mmg3::kvlcc2_model_vehicle()).unwrap();
        let c = m.coefficient_vector(KVLCC2);
        assert_eq!(approach(&m, &c, &approach_record(KVLCC2_RPS)), None);
    }

    #[test]
    fn a_propeller_at_the_self_propulsion_point_leaves_the_published_resistance_unbalanced() {
        let m = Mmg3::build(&crate::model::models::mmg3::kvlcc2_model_vehicle()).unwrap();
        let c = m.coefficient_vector(KVLCC2);
        // the basin's 10.23 rps: the model decelerates where the ship held its speed
        let i = approach(&m, &c, &approach_record(10.23)).expect("imbalance");
        assert!(i.model < -1e-3, "{i:?}");
        assert!(i.measured.abs() < 1e-12, "{i:?}");
        assert!(i.force(3270.0) > 5.0, "{i:?}");
    }
}
