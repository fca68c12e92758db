//! One measure's value or the reason it is missing, and what kind of quantity it is.

use serde::{Deserialize, Serialize};
use std::fmt;

/// A measure of a manoeuvre (SI: m, s, rad, m/s), or why the run cannot give it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// The value, in SI units.
    Value(f64),
    /// Why the run does not give this measure.
    Missing(String),
}

impl Measure {
    /// The value if there is one.
    pub fn value(&self) -> Option<f64> {
        match self {
            Measure::Value(v) => Some(*v),
            Measure::Missing(_) => None,
        }
    }

    /// A missing measure with its reason.
    pub fn missing(reason: impl Into<String>) -> Self {
        Measure::Missing(reason.into())
    }

    /// `f` applied to the value; a missing measure stays missing with its reason.
    pub fn map(&self, f: impl FnOnce(f64) -> f64) -> Measure {
        match self {
            Measure::Value(v) => Measure::Value(f(*v)),
            Measure::Missing(r) => Measure::Missing(r.clone()),
        }
    }

    /// The value written for people in the unit of `kind` (degrees for angles), or "-".
    pub fn display(&self, kind: Kind) -> String {
        match self {
            Measure::Value(v) => crate::base::numfmt::num(kind.to_display(*v)),
            Measure::Missing(_) => "-".to_string(),
        }
    }
}

/// What a measure is, for its unit when written for people.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A distance, m.
    Length,
    /// A time, s.
    Time,
    /// An angle, rad inside, written in degrees.
    Angle,
    /// A speed, m/s.
    Speed,
    /// A ratio, -.
    Ratio,
}

impl Kind {
    /// The unit a table writes this kind in.
    pub fn unit(self) -> &'static str {
        match self {
            Kind::Length => "m",
            Kind::Time => "s",
            Kind::Angle => "deg",
            Kind::Speed => "m/s",
            Kind::Ratio => "-",
        }
    }

    /// An SI value converted to the unit of [`Kind::unit`].
    pub fn to_display(self, si: f64) -> f64 {
        match self {
            Kind::Angle => si.to_degrees(),
            _ => si,
        }
    }
}

/// A measure with its name, for tables and criteria.
#[derive(Debug, Clone, PartialEq)]
pub struct Named {
    /// Stable key (`advance`, `first_overshoot`, ...), as in results.json.
    pub key: &'static str,
    /// What a naval architect calls it.
    pub label: &'static str,
    /// Its kind (unit).
    pub kind: Kind,
    /// The value or the reason it is missing.
    pub value: Measure,
}

impl Named {
    /// A named measure (the value cloned).
    pub fn new(key: &'static str, label: &'static str, kind: Kind, value: &Measure) -> Self {
        Named {
            key,
            label,
            kind,
            value: value.clone(),
        }
    }
}

/// The side a ship turns to, from its heading change (heading positive clockwise seen from
/// above, as in the earth frame x north, y east, z down: a turn to starboard increases it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Heading increasing.
    Starboard,
    /// Heading decreasing.
    Port,
}

impl Side {
    /// +1 to starboard, -1 to port.
    pub fn sign(self) -> f64 {
        match self {
            Side::Starboard => 1.0,
            Side::Port => -1.0,
        }
    }

    /// The side of a heading change's sign (zero counts as starboard).
    pub fn of(change: f64) -> Side {
        if change < 0.0 {
            Side::Port
        } else {
            Side::Starboard
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::Starboard => "starboard",
            Side::Port => "port",
        })
    }
}
