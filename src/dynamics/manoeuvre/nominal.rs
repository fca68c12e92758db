//! The nominal angles of a test: the rudder angle delta it was ordered with and, for a
//! zig-zag delta/psi, the check (execute heading) angle psi at which the rudder is reversed.
//! Given by the user (per run in the configuration, or on the command line), or inferred
//! from the run by rounding the measured angle to the standard angle within reach.
//!
//! The measures are taken at the nominal angles: a basin or a helmsman reverses the rudder a
//! little late (HSVA's KVLCC2 zig-zags at 10.5-10.8 deg of heading change in 10/10 and 20/10
//! tests), yet the test is a 10/10 and its overshoots are the heading change beyond 10 deg
//! (MSC.137(76), annex, 4.2.6-4.2.8; ITTC 7.5-04-02-01, 2.2.2).

use serde::{Deserialize, Serialize};
use std::fmt;

/// The rudder angles of the standard tests, deg: the 35 deg turning circle (MSC.137(76),
/// annex, 4.2.2), the 10/10 and 20/20 zig-zags (4.2.6, 4.2.9) and the other delta/psi
/// combinations ITTC 7.5-04-02-01, 2.2.2 allows, in 5 deg steps.
pub const STANDARD_RUDDER_DEG: [f64; 7] = [5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0];

/// The check (execute heading) angles of the standard zig-zags, deg: 10 and 20 (MSC.137(76),
/// annex, 4.2.6, 4.2.9), 1 deg of the modified zig-zag (ITTC 7.5-04-02-01, 2.2.3), 5 and 15.
pub const STANDARD_CHECK_DEG: [f64; 5] = [1.0, 5.0, 10.0, 15.0, 20.0];

/// A measured angle is read as a standard angle when it is within this of it, deg ...
pub const SNAP_DEG: f64 = 2.0;

/// ... and within this share of it (so that 3 deg is not read as the 1 deg check).
pub const SNAP_SHARE: f64 = 0.3;

/// A measured angle that is no standard angle is kept to this step, deg.
pub const MEASURED_STEP_DEG: f64 = 0.1;

/// The nominal angles given for a run (rad, magnitudes); None: inferred from the run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Nominal {
    /// The test's rudder angle delta, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rudder: Option<f64>,
    /// The zig-zag's check (execute heading) angle psi, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<f64>,
}

impl Nominal {
    /// `self` where given, else `fallback` (the command line over the configuration).
    pub fn or(self, fallback: Nominal) -> Nominal {
        Nominal {
            rudder: self.rudder.or(fallback.rudder),
            check: self.check.or(fallback.check),
        }
    }
}

/// Where a nominal angle comes from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "from", rename_all = "snake_case")]
pub enum AngleSource {
    /// Given for the run (configuration or command line).
    Given,
    /// The standard angle nearest the angle measured in the run (rad, magnitude).
    Inferred {
        /// The measured angle, rad.
        measured: f64,
    },
    /// No standard angle is near the measured one (rad, magnitude): that angle to 0.1 deg.
    Measured {
        /// The measured angle, rad.
        measured: f64,
    },
}

impl AngleSource {
    /// In words for a table, e.g. "nominal 10 deg, inferred from the reversal at 10.7 deg";
    /// `nominal` in rad, `at` what was measured ("the reversal").
    pub fn describe(&self, nominal: f64, at: &str) -> String {
        let deg = |a: f64| format!("{:.1}", a.to_degrees());
        let whole = |a: f64| crate::base::numfmt::fixed_trimmed(a.to_degrees(), 1);
        match self {
            AngleSource::Given => format!("nominal {} deg, given", whole(nominal)),
            AngleSource::Inferred { measured } => format!(
                "nominal {} deg, inferred from {at} at {} deg",
                whole(nominal),
                deg(*measured)
            ),
            AngleSource::Measured { measured } => format!(
                "measured, {} deg at {at} (no standard angle within {SNAP_DEG} deg)",
                deg(*measured)
            ),
        }
    }
}

impl fmt::Display for AngleSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AngleSource::Given => "given",
            AngleSource::Inferred { .. } => "inferred",
            AngleSource::Measured { .. } => "measured",
        })
    }
}

/// The nominal angle of `measured` (rad, magnitude taken) among `standard_deg`: the nearest
/// standard angle when within [`SNAP_DEG`] and [`SNAP_SHARE`] of it, else the measured angle
/// to [`MEASURED_STEP_DEG`]. Returns the angle (rad) and where it comes from.
pub fn infer(measured: f64, standard_deg: &[f64]) -> (f64, AngleSource) {
    let m = measured.abs().to_degrees();
    let nearest = standard_deg
        .iter()
        .copied()
        .min_by(|a, b| (a - m).abs().total_cmp(&(b - m).abs()));
    let measured = measured.abs();
    match nearest {
        Some(s) if (s - m).abs() <= SNAP_DEG.min(SNAP_SHARE * s) => {
            (s.to_radians(), AngleSource::Inferred { measured })
        }
        _ => (
            ((m / MEASURED_STEP_DEG).round() * MEASURED_STEP_DEG).to_radians(),
            AngleSource::Measured { measured },
        ),
    }
}

/// `given` if set (magnitude), else the nominal angle of `measured` among `standard_deg`.
pub fn nominal(given: Option<f64>, measured: f64, standard_deg: &[f64]) -> (f64, AngleSource) {
    match given {
        Some(a) => (a.abs(), AngleSource::Given),
        None => infer(measured, standard_deg),
    }
}

impl Nominal {
    /// The nominal angles a run's configuration gives (`manoeuvre = { ... }`), rad
    /// (magnitudes).
    pub fn given(spec: &crate::io::input_spec::ManoeuvreSpec) -> Self {
        Nominal {
            rudder: spec.rudder.as_ref().map(|c| c.si.abs()),
            check: spec.check.as_ref().map(|c| c.si.abs()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deg(a: f64) -> f64 {
        (a.to_degrees() * 1e9).round() / 1e9
    }

    #[test]
    fn measured_angles_round_to_the_standard_within_reach() {
        let (a, s) = infer(10.7f64.to_radians(), &STANDARD_CHECK_DEG);
        assert_eq!(deg(a), 10.0);
        assert!(matches!(s, AngleSource::Inferred { measured } if deg(measured) == 10.7));
        assert_eq!(deg(infer(-21f64.to_radians(), &STANDARD_CHECK_DEG).0), 20.0);
        assert_eq!(
            deg(infer(19.5f64.to_radians(), &STANDARD_RUDDER_DEG).0),
            20.0
        );
        assert_eq!(deg(infer(6f64.to_radians(), &STANDARD_CHECK_DEG).0), 5.0);
        // 3 deg is neither the 1 deg nor the 5 deg check: kept as measured, to 0.1 deg
        let (a, s) = infer(3.04f64.to_radians(), &STANDARD_CHECK_DEG);
        assert_eq!((deg(a), s.to_string()), (3.0, "measured".to_string()));
        assert_eq!(
            deg(infer(27.46f64.to_radians(), &STANDARD_CHECK_DEG).0),
            27.5
        );
        let (a, s) = nominal(Some(-0.2), 0.5, &STANDARD_RUDDER_DEG);
        assert_eq!((a, s), (0.2, AngleSource::Given));
    }

    #[test]
    fn sources_in_words() {
        let ten = 10f64.to_radians();
        assert_eq!(
            AngleSource::Given.describe(ten, "the reversal"),
            "nominal 10 deg, given"
        );
        let s = AngleSource::Inferred {
            measured: 10.7f64.to_radians(),
        };
        assert_eq!(
            s.describe(ten, "the reversal"),
            "nominal 10 deg, inferred from the reversal at 10.7 deg"
        );
    }
}
