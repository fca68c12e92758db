//! The IMO manoeuvrability criteria (Standards for ship manoeuvrability, resolution
//! MSC.137(76), annex, 5.3): each check gives the value, the limit and the verdict with the
//! rule cited. Ship length and speed are full-scale values (L/V is not Froude-invariant).

use super::measure::{Kind, Measure};
use super::turning::TurningCircle;
use super::zigzag::ZigZag;
use serde::{Deserialize, Serialize};

/// The ship the criteria are scaled by: length between perpendiculars L (m) and test
/// (approach) speed V (m/s), both full scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ship {
    /// L, m.
    pub length: f64,
    /// V, m/s.
    pub speed: f64,
}

/// A ship length or speed that cannot scale the criteria.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct ShipError(String);

impl Ship {
    /// A ship of length `length` (m) at speed `speed` (m/s), both positive and finite.
    pub fn new(length: f64, speed: f64) -> Result<Ship, ShipError> {
        for (name, v) in [("ship length L", length), ("ship speed V", speed)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ShipError(format!(
                    "{name}: expected a positive number, got {v}"
                )));
            }
        }
        Ok(Ship { length, speed })
    }

    /// L/V, s.
    pub fn l_over_v(&self) -> f64 {
        self.length / self.speed
    }
}

/// One IMO criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Turning ability: advance <= 4.5 L.
    Advance,
    /// Turning ability: tactical diameter <= 5 L.
    TacticalDiameter,
    /// Initial turning ability: 10 deg rudder, 10 deg heading change within 2.5 L travelled.
    InitialTurning,
    /// 10/10 zig-zag first overshoot angle.
    FirstOvershoot10,
    /// 10/10 zig-zag second overshoot angle.
    SecondOvershoot10,
    /// 20/20 zig-zag first overshoot angle <= 25 deg.
    FirstOvershoot20,
}

impl Criterion {
    /// The paragraph of MSC.137(76), annex, that states it.
    pub fn rule(self) -> &'static str {
        match self {
            Criterion::Advance | Criterion::TacticalDiameter => "MSC.137(76) 5.3.1",
            Criterion::InitialTurning => "MSC.137(76) 5.3.2",
            Criterion::FirstOvershoot10 => "MSC.137(76) 5.3.3.1",
            Criterion::SecondOvershoot10 => "MSC.137(76) 5.3.3.2",
            Criterion::FirstOvershoot20 => "MSC.137(76) 5.3.3.3",
        }
    }

    /// The key of the measure it judges (as in [`super::Named::key`]).
    pub fn measure_key(self) -> &'static str {
        match self {
            Criterion::Advance => "advance",
            Criterion::TacticalDiameter => "tactical_diameter",
            Criterion::InitialTurning => "initial_turning_distance",
            Criterion::FirstOvershoot10 | Criterion::FirstOvershoot20 => "first_overshoot",
            Criterion::SecondOvershoot10 => "second_overshoot",
        }
    }

    /// What it judges, as the standard names it.
    pub fn label(self) -> &'static str {
        match self {
            Criterion::Advance => "advance",
            Criterion::TacticalDiameter => "tactical diameter",
            Criterion::InitialTurning => "distance to 10 deg heading change (10 deg rudder)",
            Criterion::FirstOvershoot10 => "10/10 first overshoot angle",
            Criterion::SecondOvershoot10 => "10/10 second overshoot angle",
            Criterion::FirstOvershoot20 => "20/20 first overshoot angle",
        }
    }

    /// The kind of its value and limit.
    pub fn kind(self) -> Kind {
        match self {
            Criterion::Advance | Criterion::TacticalDiameter | Criterion::InitialTurning => {
                Kind::Length
            }
            _ => Kind::Angle,
        }
    }

    /// Whether the limit depends on the full-scale L/V (the 10/10 overshoots), so that a
    /// model-scale run is judged only when its scale ratio is known.
    pub fn needs_full_scale_speed(self) -> bool {
        matches!(
            self,
            Criterion::FirstOvershoot10 | Criterion::SecondOvershoot10
        )
    }

    /// The limit for `ship`, SI (m or rad).
    pub fn limit(self, ship: &Ship) -> f64 {
        let l = ship.length;
        match self {
            Criterion::Advance => 4.5 * l,
            Criterion::TacticalDiameter => 5.0 * l,
            Criterion::InitialTurning => 2.5 * l,
            Criterion::FirstOvershoot10 => first_overshoot_limit_10_10(ship.l_over_v()),
            Criterion::SecondOvershoot10 => second_overshoot_limit_10_10(ship.l_over_v()),
            Criterion::FirstOvershoot20 => 25f64.to_radians(),
        }
    }
}

/// The 10/10 first overshoot limit (MSC.137(76) 5.3.3.1), rad: 10 deg if L/V < 10 s, 20 deg
/// if L/V >= 30 s, (5 + L/V / 2) deg in between (L/V in s).
pub fn first_overshoot_limit_10_10(l_over_v: f64) -> f64 {
    by_l_over_v(l_over_v, 10.0, 5.0, 0.5, 20.0)
}

/// The 10/10 second overshoot limit (MSC.137(76) 5.3.3.2), rad: 25 deg if L/V < 10 s, 40 deg
/// if L/V >= 30 s, (17.5 + 0.75 L/V) deg in between (L/V in s).
pub fn second_overshoot_limit_10_10(l_over_v: f64) -> f64 {
    by_l_over_v(l_over_v, 25.0, 17.5, 0.75, 40.0)
}

/// The shape of both 10/10 limits, rad: `short` deg below 10 s, `long` deg from 30 s,
/// `base + slope L/V` deg in between (continuous at both ends).
fn by_l_over_v(l_over_v: f64, short: f64, base: f64, slope: f64, long: f64) -> f64 {
    let deg = if l_over_v < 10.0 {
        short
    } else if l_over_v >= 30.0 {
        long
    } else {
        base + slope * l_over_v
    };
    deg.to_radians()
}

/// A check's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Within the limit.
    Pass,
    /// Beyond the limit.
    Fail,
    /// The run does not give the value; why.
    NotAssessed(String),
}

/// One criterion applied to one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// The criterion.
    pub criterion: Criterion,
    /// The measured value, SI.
    pub value: Measure,
    /// The limit, SI.
    pub limit: f64,
    /// Pass, fail, or why it cannot be judged.
    pub verdict: Verdict,
    /// The rule cited.
    pub rule: String,
}

impl Check {
    /// `criterion` applied to `value` for `ship`.
    pub fn new(criterion: Criterion, value: &Measure, ship: &Ship) -> Check {
        let limit = criterion.limit(ship);
        let verdict = match value {
            Measure::Value(v) if *v <= limit => Verdict::Pass,
            Measure::Value(_) => Verdict::Fail,
            Measure::Missing(r) => Verdict::NotAssessed(r.clone()),
        };
        Check {
            criterion,
            value: value.clone(),
            limit,
            verdict,
            rule: criterion.rule().to_string(),
        }
    }

    /// The verdict as a table writes it.
    pub fn verdict_text(&self) -> &'static str {
        match self.verdict {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::NotAssessed(_) => "not assessed",
        }
    }
}

/// The turning-ability checks (advance, tactical diameter) of a turning circle. The standard
/// asks for the turn at the largest rudder angle at the test speed; that is the caller's
/// choice of run.
pub fn turning_checks(turn: &TurningCircle, ship: &Ship) -> Vec<Check> {
    vec![
        Check::new(Criterion::Advance, &turn.advance, ship),
        Check::new(Criterion::TacticalDiameter, &turn.tactical_diameter, ship),
    ]
}

/// Tolerance on a test's nominal angles when naming it 10/10 or 20/20, rad (0.5 deg).
const NOMINAL: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The criteria a zig-zag is subject to, with the measure each judges: a 10/10 gives the
/// first and second overshoot (MSC.137(76) 5.3.3.1-2) and the initial turning ability
/// (5.3.2), a 20/20 its first overshoot (5.3.3.3); any other test none, and the reason. The
/// rudder angle, when the run lacks it, is taken equal to the check angle.
pub fn zigzag_criteria(z: &ZigZag) -> Result<Vec<(Criterion, &Measure)>, String> {
    let rudder = z.rudder_angle.value().unwrap_or(z.heading_angle);
    let is = |deg: f64| {
        (rudder - deg.to_radians()).abs() <= NOMINAL
            && (z.heading_angle - deg.to_radians()).abs() <= NOMINAL
    };
    if is(10.0) {
        Ok(vec![
            (Criterion::FirstOvershoot10, &z.first_overshoot),
            (Criterion::SecondOvershoot10, &z.second_overshoot),
            (Criterion::InitialTurning, &z.initial_turning_distance),
        ])
    } else if is(20.0) {
        Ok(vec![(Criterion::FirstOvershoot20, &z.first_overshoot)])
    } else {
        Err(format!(
            "no IMO criterion applies to a {} zig-zag: MSC.137(76) 5.3.2-5.3.3 judge the \
             10/10 and the 20/20 zig-zags",
            z.test_name()
        ))
    }
}

/// The checks a zig-zag is subject to ([`zigzag_criteria`]) for `ship`; none for a test no
/// criterion applies to.
pub fn zigzag_checks(z: &ZigZag, ship: &Ship) -> Vec<Check> {
    zigzag_criteria(z)
        .unwrap_or_default()
        .into_iter()
        .map(|(c, m)| Check::new(c, m, ship))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deg(limit: f64) -> f64 {
        (limit.to_degrees() * 1e9).round() / 1e9
    }

    #[test]
    fn overshoot_limits_follow_l_over_v() {
        assert_eq!(deg(first_overshoot_limit_10_10(9.99)), 10.0);
        assert_eq!(deg(first_overshoot_limit_10_10(10.0)), 10.0);
        assert_eq!(deg(first_overshoot_limit_10_10(20.0)), 15.0);
        assert_eq!(deg(first_overshoot_limit_10_10(30.0)), 20.0);
        assert_eq!(deg(second_overshoot_limit_10_10(5.0)), 25.0);
        assert_eq!(deg(second_overshoot_limit_10_10(20.0)), 32.5);
        assert_eq!(deg(second_overshoot_limit_10_10(29.9)), 39.925);
        assert_eq!(deg(second_overshoot_limit_10_10(45.0)), 40.0);
    }

    #[test]
    fn checks_pass_fail_or_say_why_not() {
        let ship = Ship::new(100.0, 5.0).unwrap();
        let pass = Check::new(Criterion::Advance, &Measure::Value(450.0), &ship);
        assert_eq!((pass.verdict, pass.limit), (Verdict::Pass, 450.0));
        let fail = Check::new(Criterion::TacticalDiameter, &Measure::Value(501.0), &ship);
        assert_eq!(fail.verdict, Verdict::Fail);
        assert_eq!(fail.rule, "MSC.137(76) 5.3.1");
        let none = Check::new(Criterion::Advance, &Measure::missing("no turn"), &ship);
        assert_eq!(none.verdict, Verdict::NotAssessed("no turn".into()));
        assert!(Ship::new(0.0, 5.0).is_err());
        assert!(Ship::new(100.0, f64::NAN).is_err());
    }
}
