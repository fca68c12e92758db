//! The measures of one run, whichever manoeuvre it is: a zig-zag when its rudder changes side
//! at least twice, else a turning circle; with the IMO criteria that can be judged.

use super::history::{History, HistoryError};
use super::imo::{turning_checks, zigzag_criteria, Check, Criterion, Ship};
use super::measure::{Measure, Named};
use super::nominal::Nominal;
use super::turning::{turning_circle, TurningCircle, TurningOptions};
use super::zigzag::{zigzag, ZigZag, ZigZagOptions};
use crate::base::quantity::Quantity;
use serde::{Deserialize, Serialize};

/// What a run gave: its turning-circle or zig-zag measures and the criteria checked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunMeasures {
    /// The turning circle, when the run is one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turning_circle: Option<TurningCircle>,
    /// The zig-zag, when the run is one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zigzag: Option<ZigZag>,
    /// The IMO criteria checked (empty when none can be judged).
    pub checks: Vec<Check>,
    /// Why IMO criteria are not judged on this run (none applies to the test, the scale
    /// ratio or the approach speed is unknown), one sentence each.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_judged: Vec<String>,
}

impl RunMeasures {
    /// "turning circle" or "zig-zag".
    pub fn kind(&self) -> &'static str {
        if self.zigzag.is_some() {
            "zig-zag"
        } else {
            "turning circle"
        }
    }

    /// The measures in table order.
    pub fn measures(&self) -> Vec<Named> {
        match (&self.turning_circle, &self.zigzag) {
            (_, Some(z)) => z.measures(),
            (Some(t), None) => t.measures(),
            (None, None) => Vec::new(),
        }
    }

    /// The side of the (first) turn.
    pub fn side(&self) -> Option<super::measure::Side> {
        match (&self.turning_circle, &self.zigzag) {
            (_, Some(z)) => Some(z.side),
            (Some(t), None) => Some(t.side),
            (None, None) => None,
        }
    }

    /// Where the nominal angles the measures were taken at come from, in words.
    pub fn nominal_text(&self) -> Option<String> {
        match (&self.turning_circle, &self.zigzag) {
            (_, Some(z)) => Some(z.nominal_text()),
            (Some(t), None) => t.nominal_text(),
            (None, None) => None,
        }
    }

    /// The notes a table of these measures carries ([`super::table::ComparisonTable::with_notes`]):
    /// where the nominal angles come from and why IMO criteria are not judged, for `who`
    /// ("measured", "identified model").
    pub fn notes(&self, who: &str) -> Vec<String> {
        let nominal = self
            .nominal_text()
            .map(|t| format!("nominal angles ({who}): {t}"));
        let hold = self
            .turning_circle
            .as_ref()
            .map(|t| format!("turn ({who}): {}", t.hold_text()));
        nominal
            .into_iter()
            .chain(hold)
            .chain(
                self.not_judged
                    .iter()
                    .map(|r| format!("IMO criteria ({who}): {r}")),
            )
            .collect()
    }

    /// The approach speed, m/s, when the run gives it.
    pub fn approach_speed(&self) -> Option<f64> {
        match (&self.turning_circle, &self.zigzag) {
            (_, Some(z)) => z.approach_speed.value(),
            (Some(t), None) => t.approach_speed.value(),
            (None, None) => None,
        }
    }
}

/// The history of a run from its columns (`column(q)`, SI): time and heading are needed; the
/// track, the velocities and the rudder are added when present.
pub fn history_of(
    column: impl Fn(Quantity) -> Option<Vec<f64>>,
) -> Result<Option<History>, HistoryError> {
    let (Some(time), Some(heading)) = (column(Quantity::Time), column(Quantity::Yaw)) else {
        return Ok(None);
    };
    let mut h = History::new(time, heading)?;
    if let (Some(x), Some(y)) = (column(Quantity::X), column(Quantity::Y)) {
        h = h.with_track(x, y)?;
    }
    if let (Some(u), Some(v)) = (column(Quantity::U), column(Quantity::V)) {
        h = h.with_velocity(u, v)?;
    }
    if let Some(r) = column(Quantity::Rudder) {
        h = h.with_rudder(r)?;
    }
    Ok(Some(h))
}

/// The measures of `h`: a zig-zag when the rudder changes side at least twice, else a turning
/// circle, at the `nominal` angles given (the others inferred from the run). `length` is the
/// ship length L of the run (m) and `scale` the scale ratio lambda of the run (1 at full
/// scale, None when unknown): criteria in ship lengths are Froude-invariant and judged on the
/// run's own scale; the 10/10 overshoot limits depend on the full-scale
/// L/V = sqrt(lambda) L/U (MSC.137(76) 5.3.3) and are judged only when `scale` is known.
pub fn measure_history(
    h: &History,
    length: f64,
    scale: Option<f64>,
    nominal: Nominal,
) -> Result<RunMeasures, HistoryError> {
    let reversals = h.rudder().map_or(0, reversals);
    let mut m = RunMeasures {
        turning_circle: None,
        zigzag: None,
        checks: Vec::new(),
        not_judged: Vec::new(),
    };
    if reversals >= 2 {
        let options = ZigZagOptions {
            execute_time: None,
            rudder_angle: nominal.rudder,
            heading_angle: nominal.check,
        };
        let z = zigzag(h, &options)?;
        match zigzag_criteria(&z) {
            Ok(criteria) => {
                let speed = z.approach_speed.clone();
                (m.checks, m.not_judged) = judge(&criteria, &speed, length, scale);
            }
            Err(reason) => m.not_judged.push(reason),
        }
        m.zigzag = Some(z);
    } else {
        let options = TurningOptions {
            execute_time: None,
            rudder_angle: nominal.rudder,
        };
        let t = turning_circle(h, &options)?;
        match Ship::new(length, t.approach_speed.value().unwrap_or(0.0)) {
            Ok(s) => m.checks = turning_checks(&t, &s),
            Err(e) => m
                .not_judged
                .push(format!("the IMO criteria are not judged: {e}")),
        }
        m.turning_circle = Some(t);
    }
    Ok(m)
}

/// The `criteria` checked for a ship of the run's `length` at its approach `speed` on the
/// run's `scale`, and why any is not: the 10/10 overshoot limits depend on the full-scale
/// L/V (a ship of the run's length at U / sqrt(lambda) has it), so they wait for the scale.
fn judge(
    criteria: &[(Criterion, &Measure)],
    speed: &Measure,
    length: f64,
    scale: Option<f64>,
) -> (Vec<Check>, Vec<String>) {
    let u = match speed {
        Measure::Value(u) => *u,
        Measure::Missing(r) => {
            return (
                Vec::new(),
                vec![format!(
                    "the IMO criteria are not judged: the approach speed is missing ({r})"
                )],
            )
        }
    };
    let (mut checks, mut not_judged) = (Vec::new(), Vec::new());
    for (c, value) in criteria {
        let lambda = if c.needs_full_scale_speed() {
            scale
        } else {
            Some(1.0)
        };
        let Some(lambda) = lambda else {
            not_judged.push(format!(
                "{} ({}) not judged: its limit depends on the full-scale L/V; give the scale \
                 ratio (vehicle.scale, or --scale of hydroid manoeuvre; 1 for full-scale data)",
                c.label(),
                c.rule()
            ));
            continue;
        };
        match Ship::new(length, u / lambda.sqrt()) {
            Ok(s) => checks.push(Check::new(*c, value, &s)),
            Err(e) => not_judged.push(format!("{} ({}) not judged: {e}", c.label(), c.rule())),
        }
    }
    (checks, not_judged)
}

/// How often the rudder changes side (sign, ignoring amidships).
pub fn reversals(rudder: &[f64]) -> usize {
    let mut last = 0.0f64;
    let mut n = 0;
    for &d in rudder {
        if d.abs() < 1e-6 {
            continue;
        }
        if last != 0.0 && d.signum() != last.signum() {
            n += 1;
        }
        last = d;
    }
    n
}

/// The largest rudder rate of a rudder history, rad/s (the steering gear's rate a turn or a
/// zig-zag was steered at), or None when the rudder never moves.
pub fn rudder_rate(time: &[f64], rudder: &[f64]) -> Option<f64> {
    let rate = time
        .windows(2)
        .zip(rudder.windows(2))
        .filter(|(t, _)| t[1] > t[0])
        .map(|(t, d)| (d[1] - d[0]).abs() / (t[1] - t[0]))
        .fold(0.0f64, f64::max);
    (rate > 0.0).then_some(rate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reversals_ignore_amidships() {
        assert_eq!(reversals(&[0.0, 0.3, 0.3, 0.0, -0.3, 0.0, 0.3]), 2);
        assert_eq!(reversals(&[0.0, 0.6, 0.6]), 0);
    }

    #[test]
    fn the_rudder_rate_is_the_steepest_move() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let rate = rudder_rate(&t, &[0.0, 0.1, 0.3, 0.3]).unwrap();
        assert!((rate - 0.2).abs() < 1e-12, "{rate}");
        assert_eq!(rudder_rate(&t, &[0.2; 4]), None);
    }
}
