//! The physical quantities hydroid reads from CFD exports, with their SI units.
//!
//! Configuration column maps use the keys below (`time`, `u`, `yaw`, `cd`, ...). Body frame:
//! x forward, y starboard, z down (SNAME); Euler angles roll, pitch, yaw (zyx order).

use crate::base::units::{Dim, Unit};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt;

/// A quantity hydroid knows how to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Time, s.
    Time,
    /// Earth-frame position north (x), m.
    X,
    /// Earth-frame position east (y), m.
    Y,
    /// Earth-frame position down (z), m.
    Z,
    /// Roll angle phi, rad.
    Roll,
    /// Pitch angle theta, rad.
    Pitch,
    /// Yaw (heading) angle psi, rad.
    Yaw,
    /// Surge velocity, m/s.
    U,
    /// Sway velocity, m/s.
    V,
    /// Heave velocity, m/s.
    W,
    /// Roll rate, rad/s.
    P,
    /// Pitch rate, rad/s.
    Q,
    /// Yaw rate, rad/s.
    R,
    /// Surge acceleration, m/s^2.
    UDot,
    /// Force along body x, N.
    Fx,
    /// Force along body y, N.
    Fy,
    /// Force along body z, N.
    Fz,
    /// Moment about body x (roll), N m.
    Mx,
    /// Moment about body y (pitch), N m.
    My,
    /// Moment about body z (yaw), N m.
    Mz,
    /// Drag coefficient, -.
    Cd,
    /// Lift (side-force) coefficient, -.
    Cl,
    /// Moment coefficient, -.
    Cm,
    /// Side-force coefficient, -.
    Cs,
    /// Angle of attack (drift angle in the horizontal plane), rad.
    Alpha,
    /// Flow speed, m/s.
    Speed,
    /// Propulsive thrust along body x, N.
    Thrust,
    /// Rudder angle, rad.
    Rudder,
    /// Stern plane (elevator) angle, rad.
    SternPlanes,
    /// Bow plane angle, rad.
    BowPlanes,
    /// Propeller speed, rev/s (configured as rpm or rps).
    Rpm,
    /// Wave-induced heading psi_H, rad (a model state no export gives: the Nomoto wave
    /// filter's, Fossen 2011 section 8.2).
    WaveYaw,
    /// Integral of the wave-induced heading, xi = int psi_H dt, rad s (the wave filter's other
    /// state).
    WaveYawIntegral,
    /// Scalar part eta of the body-to-earth attitude quaternion (unit quaternion, scalar
    /// first; Fossen 2011, section 2.2.2). The four parts are read together and turned into
    /// roll, pitch and yaw (`crate::numerics::frames::zyx_from_quaternion`).
    QuatW,
    /// First vector part eps_1 of the attitude quaternion.
    QuatX,
    /// Second vector part eps_2 of the attitude quaternion.
    QuatY,
    /// Third vector part eps_3 of the attitude quaternion.
    QuatZ,
    /// Drift angle of a held motion, beta = atan(-v / u) (Yasukawa & Yoshimura 2015, eq. 5),
    /// rad: a captive condition's motion with `speed`.
    Drift,
    /// Non-dimensional yaw rate r' = r L / U of a held motion (L of the captive stage's
    /// `prime` system), -.
    RPrime,
    /// Non-dimensional surge force X' = X / (0.5 rho A U^2) (A of the `prime` system), -.
    XPrime,
    /// Non-dimensional sway force Y' = Y / (0.5 rho A U^2), -.
    YPrime,
    /// Non-dimensional yaw moment N' = N / (0.5 rho A L U^2), -.
    NPrime,
}

const ANGLE: Dim = [0, 0, 0, 1];
const LENGTH: Dim = [0, 1, 0, 0];
const SPEED: Dim = [0, 1, -1, 0];
const RATE: Dim = [0, 0, -1, 1];
const FORCE: Dim = [1, 1, -2, 0];
const MOMENT: Dim = [1, 2, -2, 0];
const NONE: Dim = [0, 0, 0, 0];

impl Quantity {
    /// Every quantity, in the order the documentation lists them.
    pub const ALL: [Quantity; 42] = [
        Quantity::Time,
        Quantity::X,
        Quantity::Y,
        Quantity::Z,
        Quantity::Roll,
        Quantity::Pitch,
        Quantity::Yaw,
        Quantity::U,
        Quantity::V,
        Quantity::W,
        Quantity::P,
        Quantity::Q,
        Quantity::R,
        Quantity::UDot,
        Quantity::Fx,
        Quantity::Fy,
        Quantity::Fz,
        Quantity::Mx,
        Quantity::My,
        Quantity::Mz,
        Quantity::Cd,
        Quantity::Cl,
        Quantity::Cm,
        Quantity::Cs,
        Quantity::Alpha,
        Quantity::Speed,
        Quantity::Thrust,
        Quantity::Rudder,
        Quantity::SternPlanes,
        Quantity::BowPlanes,
        Quantity::Rpm,
        Quantity::WaveYaw,
        Quantity::WaveYawIntegral,
        Quantity::QuatW,
        Quantity::QuatX,
        Quantity::QuatY,
        Quantity::QuatZ,
        Quantity::Drift,
        Quantity::RPrime,
        Quantity::XPrime,
        Quantity::YPrime,
        Quantity::NPrime,
    ];

    /// The attitude quaternion's parts, scalar first.
    pub const QUATERNION: [Quantity; 4] = [
        Quantity::QuatW,
        Quantity::QuatX,
        Quantity::QuatY,
        Quantity::QuatZ,
    ];

    /// The motion of a body: velocities and rates (body frame), positions and attitude
    /// (earth frame).
    pub const MOTION: [Quantity; 12] = [
        Quantity::U,
        Quantity::V,
        Quantity::W,
        Quantity::P,
        Quantity::Q,
        Quantity::R,
        Quantity::X,
        Quantity::Y,
        Quantity::Z,
        Quantity::Roll,
        Quantity::Pitch,
        Quantity::Yaw,
    ];

    /// The configuration key of this quantity.
    pub fn key(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::X => "x",
            Quantity::Y => "y",
            Quantity::Z => "z",
            Quantity::Roll => "roll",
            Quantity::Pitch => "pitch",
            Quantity::Yaw => "yaw",
            Quantity::U => "u",
            Quantity::V => "v",
            Quantity::W => "w",
            Quantity::P => "p",
            Quantity::Q => "q",
            Quantity::R => "r",
            Quantity::UDot => "u_dot",
            Quantity::Fx => "fx",
            Quantity::Fy => "fy",
            Quantity::Fz => "fz",
            Quantity::Mx => "mx",
            Quantity::My => "my",
            Quantity::Mz => "mz",
            Quantity::Cd => "cd",
            Quantity::Cl => "cl",
            Quantity::Cm => "cm",
            Quantity::Cs => "cs",
            Quantity::Alpha => "alpha",
            Quantity::Speed => "speed",
            Quantity::Thrust => "thrust",
            Quantity::Rudder => "rudder",
            Quantity::SternPlanes => "stern_planes",
            Quantity::BowPlanes => "bow_planes",
            Quantity::Rpm => "rpm",
            Quantity::WaveYaw => "wave_yaw",
            Quantity::WaveYawIntegral => "wave_yaw_integral",
            Quantity::QuatW => "quat_w",
            Quantity::QuatX => "quat_x",
            Quantity::QuatY => "quat_y",
            Quantity::QuatZ => "quat_z",
            Quantity::Drift => "drift",
            Quantity::RPrime => "r_prime",
            Quantity::XPrime => "x_prime",
            Quantity::YPrime => "y_prime",
            Quantity::NPrime => "n_prime",
        }
    }

    /// Looks a quantity up by its configuration key.
    pub fn from_key(key: &str) -> Option<Quantity> {
        Quantity::ALL.iter().copied().find(|q| q.key() == key)
    }

    /// The dimension a column of this quantity must have.
    pub fn dim(self) -> Dim {
        match self {
            Quantity::Time => [0, 0, 1, 0],
            Quantity::X | Quantity::Y | Quantity::Z => LENGTH,
            Quantity::Roll | Quantity::Pitch | Quantity::Yaw | Quantity::WaveYaw => ANGLE,
            Quantity::WaveYawIntegral => [0, 0, 1, 1],
            Quantity::Alpha
            | Quantity::Drift
            | Quantity::Rudder
            | Quantity::SternPlanes
            | Quantity::BowPlanes => ANGLE,
            Quantity::U | Quantity::V | Quantity::W | Quantity::Speed => SPEED,
            Quantity::P | Quantity::Q | Quantity::R | Quantity::Rpm => RATE,
            Quantity::UDot => [0, 1, -2, 0],
            Quantity::Fx | Quantity::Fy | Quantity::Fz | Quantity::Thrust => FORCE,
            Quantity::Mx | Quantity::My | Quantity::Mz => MOMENT,
            Quantity::Cd | Quantity::Cl | Quantity::Cm | Quantity::Cs => NONE,
            Quantity::QuatW | Quantity::QuatX | Quantity::QuatY | Quantity::QuatZ => NONE,
            Quantity::RPrime | Quantity::XPrime | Quantity::YPrime | Quantity::NPrime => NONE,
        }
    }

    /// Hydroid's internal unit for this quantity (SI; propeller speed in rev/s).
    pub fn internal_unit(self) -> Unit {
        match self {
            Quantity::Rpm => Unit {
                text: "rev/s".into(),
                factor: 2.0 * PI,
                dim: RATE,
            },
            q => Unit::si(q.si_symbol(), q.dim()),
        }
    }

    /// The unit a column of this quantity is read in: `unit` itself, except that a propeller
    /// speed given per unit time counts revolutions (`Hz` is rev/s, `1/min` is rev/min).
    pub fn column_unit(self, unit: Unit) -> Unit {
        if self == Quantity::Rpm && unit.dim == [0, 0, -1, 0] {
            Unit {
                factor: unit.factor * 2.0 * PI,
                dim: RATE,
                ..unit
            }
        } else {
            unit
        }
    }

    /// The symbol of the internal unit, for tables and reports.
    pub fn si_symbol(self) -> &'static str {
        match self.dim() {
            [0, 0, 1, 0] => "s",
            LENGTH => "m",
            ANGLE => "rad",
            [0, 0, 1, 1] => "rad s",
            SPEED => "m/s",
            RATE if self == Quantity::Rpm => "rev/s",
            RATE => "rad/s",
            [0, 1, -2, 0] => "m/s^2",
            FORCE => "N",
            MOMENT => "N m",
            _ => "-",
        }
    }

    /// Euler angles, which are unwrapped after reading.
    pub fn is_euler_angle(self) -> bool {
        matches!(self, Quantity::Roll | Quantity::Pitch | Quantity::Yaw)
    }

    /// The largest magnitude a value of this quantity written by hand (an initial state, an
    /// input, a constant, a step, a noise level) can plausibly have, in SI, with what the
    /// bound stands for: beyond it the value is a unit or typing mistake (`1e300`, km for
    /// m), whatever the vehicle. `None` for time, which has no such bound.
    pub fn plausible_bound(self) -> Option<(f64, &'static str)> {
        use Quantity as Q;
        Some(match self {
            Q::Time | Q::WaveYawIntegral => return None,
            Q::X | Q::Y | Q::Z => (2e7, "2e7 m, half the Earth's circumference"),
            Q::Roll | Q::Pitch | Q::Yaw | Q::WaveYaw => (200.0 * PI, "628 rad, 100 turns"),
            Q::Alpha | Q::Drift => (PI, "3.142 rad, 180 deg"),
            Q::Rudder | Q::SternPlanes | Q::BowPlanes => (PI / 2.0, "1.571 rad, 90 deg"),
            Q::U | Q::V | Q::W | Q::Speed => (200.0, "200 m/s, 390 kn, faster than any vessel"),
            Q::P | Q::Q | Q::R => (20.0, "20 rad/s, three turns a second"),
            Q::Rpm => (2000.0 * PI, "1000 rev/s, 60,000 rpm"),
            Q::UDot => (100.0, "100 m/s^2, 10 g"),
            Q::Fx | Q::Fy | Q::Fz | Q::Thrust => (1e10, "1e10 N, the weight of a million tonnes"),
            Q::Mx | Q::My | Q::Mz => (1e13, "1e13 N m, 1e10 N at 1000 m"),
            Q::Cd | Q::Cl | Q::Cm | Q::Cs => (1e3, "1000"),
            Q::QuatW | Q::QuatX | Q::QuatY | Q::QuatZ => {
                (1.001, "1.001, a part of a unit quaternion")
            }
            Q::RPrime => (100.0, "100"),
            Q::XPrime | Q::YPrime | Q::NPrime => (1e3, "1000"),
        })
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.key())
    }
}

/// Unwraps `values` (radians, one per row) when they are an attitude history: the roll, pitch
/// or yaw (heading) of a record with a time axis, which a solver writes wrapped to
/// (-180, 180] deg. Nothing else is unwrapped: the rows of a polar sweep's angle of attack,
/// a drift angle or a rudder angle are settings, not a continuous history (a sweep from -120
/// to 120 deg repeated at a second speed must stay as written). Returns true when unwrapped.
pub fn unwrap_attitude(q: Quantity, time_history: bool, values: &mut [f64]) -> bool {
    let attitude = time_history && q.is_euler_angle();
    if attitude {
        crate::base::units::unwrap_angles(values);
    }
    attitude
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_round_trip() {
        for q in Quantity::ALL {
            assert_eq!(Quantity::from_key(q.key()), Some(q));
        }
        assert_eq!(Quantity::from_key("speedy"), None);
    }

    #[test]
    fn propeller_speed_per_unit_time_counts_revolutions() {
        let rps = Quantity::Rpm.internal_unit().factor;
        for (text, per_second) in [("Hz", 1.0), ("1/min", 1.0 / 60.0), ("rev/min", 1.0 / 60.0)] {
            let u = Quantity::Rpm.column_unit(Unit::parse(text).unwrap());
            assert_eq!(u.dim, RATE, "{text}");
            assert!((u.factor / rps - per_second).abs() < 1e-12, "{text}");
        }
        // only for the propeller speed
        let hz = Quantity::R.column_unit(Unit::parse("Hz").unwrap());
        assert_eq!(hz.dim, [0, 0, -1, 0]);
    }

    #[test]
    fn rpm_is_revolutions_per_second() {
        let rpm = Unit::parse("rpm").unwrap();
        let internal = Quantity::Rpm.internal_unit();
        assert!((600.0 * rpm.factor / internal.factor - 10.0).abs() < 1e-12);
    }
}
