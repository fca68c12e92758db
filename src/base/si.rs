//! Configuration numbers that carry a dimension: given as a bare number (SI) or as a string
//! with a unit (`"50 kg"`, `"10 ms"`), checked against the dimension the key expects and
//! converted to SI while the file is read.
//!
//! Used with serde's `deserialize_with`, e.g.
//! `#[serde(deserialize_with = "si::value::<_, si::Mass>")]`.

use crate::base::quantity::Quantity;
use crate::base::units::{check_dim, Dim, Unit};
use serde::de::{self, Deserialize, Deserializer, Error, Visitor};
use serde::{Serialize, Serializer};
use std::fmt;

/// A dimension a configuration key expects.
pub trait Kind {
    /// Exponents of (kg, m, s, rad).
    const DIM: Dim;
}

macro_rules! kinds {
    ($($(#[$doc:meta])* $name:ident = $dim:expr;)*) => {
        $(
            $(#[$doc])*
            #[derive(Debug)]
            pub struct $name;
            impl Kind for $name {
                const DIM: Dim = $dim;
            }
        )*
    };
}

kinds! {
    /// kg.
    Mass = [1, 0, 0, 0];
    /// m.
    Length = [0, 1, 0, 0];
    /// m^2.
    Area = [0, 2, 0, 0];
    /// s.
    Time = [0, 0, 1, 0];
    /// m/s.
    Speed = [0, 1, -1, 0];
    /// N.
    Force = [1, 1, -2, 0];
    /// kg m^2.
    Inertia = [1, 2, 0, 0];
    /// kg/m^3.
    Density = [1, -3, 0, 0];
    /// Pa s.
    Viscosity = [1, -1, -1, 0];
    /// rad.
    Angle = [0, 0, 0, 1];
    /// rad/s.
    Rate = [0, 0, -1, 1];
    /// Hz (cycles per second).
    Frequency = [0, 0, -1, 0];
}

/// A number in SI or a string with a unit of dimension `K`, as SI.
pub fn value<'de, D: Deserializer<'de>, K: Kind>(d: D) -> Result<f64, D::Error> {
    let c = Constant::deserialize(d)?;
    c.expect_dim(K::DIM).map_err(D::Error::custom)?;
    Ok(c.si)
}

/// Like [`value`], for an optional key.
pub fn option<'de, D: Deserializer<'de>, K: Kind>(d: D) -> Result<Option<f64>, D::Error> {
    value::<D, K>(d).map(Some)
}

/// Like [`value`], for an optional list.
pub fn list<'de, D: Deserializer<'de>, K: Kind>(d: D) -> Result<Option<Vec<f64>>, D::Error> {
    let items = Vec::<Constant>::deserialize(d)?;
    let mut out = Vec::with_capacity(items.len());
    for (i, c) in items.iter().enumerate() {
        c.expect_dim(K::DIM)
            .map_err(|m| D::Error::custom(format!("entry {}: {m}", i + 1)))?;
        out.push(c.si);
    }
    Ok(Some(out))
}

/// A constant value, given as a number in SI or as a string with a unit (`"4 deg"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// The value as written.
    pub text: String,
    /// The value in SI (radians for angles).
    pub si: f64,
    /// The unit written, if any.
    pub unit: Option<Unit>,
}

impl Constant {
    /// A constant given in SI.
    pub fn si(value: f64) -> Self {
        Constant {
            text: format!("{value}"),
            si: value,
            unit: None,
        }
    }

    /// Parses `"22 N"`, `"4 deg"` or `"3.0"` (a bare number is SI). The number must be
    /// finite; the unit is only parsed here: [`Constant::expect_dim`] checks that it fits.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let split = t
            .find(|c: char| c.is_whitespace() || (c.is_alphabetic() && c != 'e' && c != 'E'))
            .unwrap_or(t.len());
        let (num, unit) = t.split_at(split);
        let value: f64 = num.trim().parse().map_err(|_| {
            format!("\"{t}\" is not a number with an optional unit, like \"4 deg\"")
        })?;
        let unit = unit.trim();
        let (si, unit) = if unit.is_empty() {
            (value, None)
        } else {
            let u = Unit::parse(unit).map_err(|e| e.to_string())?;
            (u.to_si(value), Some(u))
        };
        if !si.is_finite() {
            return Err(format!("\"{t}\" is not a finite number"));
        }
        Ok(Constant {
            text: t.to_string(),
            si,
            unit,
        })
    }

    /// [`Constant::expect_dim`] for the dimension of `q`, and a magnitude within
    /// [`Quantity::plausible_bound`]: `"1e300 m/s"` for a speed is an error that says what
    /// the bound is, not a run that overflows later.
    pub fn expect_quantity(&self, q: Quantity) -> Result<(), String> {
        self.expect_dim(q.dim())?;
        match q.plausible_bound() {
            Some((bound, what)) if self.si.abs() > bound => {
                // a bare number's text is its full decimal expansion: shown short
                let shown = match self.unit {
                    Some(_) => self.text.clone(),
                    None => crate::base::numfmt::short(self.si),
                };
                Err(format!(
                    "{shown} is beyond any plausible {q}: at most {what} in magnitude; a unit or \
                     typing mistake?"
                ))
            }
            _ => Ok(()),
        }
    }

    /// Checks that the value is finite and that its unit measures `dim` (a bare number is
    /// SI and fits any dimension); the error names the unit, what it measures and what was
    /// expected.
    pub fn expect_dim(&self, dim: Dim) -> Result<(), String> {
        if !self.si.is_finite() {
            return Err(format!("must be a finite number, got {}", self.text));
        }
        match &self.unit {
            Some(u) => check_dim(u, dim).map_err(|m| format!("\"{}\": {m}", self.text)),
            None => Ok(()),
        }
    }
}

impl Serialize for Constant {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match &self.unit {
            Some(_) => s.serialize_str(&self.text),
            None => s.serialize_f64(self.si),
        }
    }
}

impl<'de> Deserialize<'de> for Constant {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Constant;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number in SI units or a string with a unit, like \"4 deg\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Constant, E> {
                Ok(Constant::si(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Constant, E> {
                Ok(Constant::si(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Constant, E> {
                Ok(Constant::si(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Constant, E> {
                Constant::parse(v).map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    struct T {
        #[serde(deserialize_with = "value::<_, Mass>")]
        m: f64,
        #[serde(default, deserialize_with = "option::<_, Time>")]
        t: Option<f64>,
    }

    #[test]
    fn numbers_and_units() {
        let t: T = toml::from_str("m = \"2 t\"\nt = \"10 ms\"\n").unwrap();
        assert_eq!(t.m, 2000.0);
        assert_eq!(t.t, Some(0.01));
        let t: T = toml::from_str("m = 50\n").unwrap();
        assert_eq!((t.m, t.t), (50.0, None));
        let e = toml::from_str::<T>("m = \"50 m/s\"\n").err().unwrap();
        assert!(
            e.message().contains("expected a mass (kg)"),
            "{}",
            e.message()
        );
    }
}
