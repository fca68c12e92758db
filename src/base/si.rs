//! Configuration numbers that carry a dimension: given as a bare number (SI) or as a string
//! with a unit (`"50 kg"`, `"10 ms"`), checked against the dimension the key expects and
//! converted to SI while the file is read.
//!
//! Used with serde's `deserialize_with`, e.g.
//! `#[serde(deserialize_with = "si::value::<_, si::Mass>")]`.

use crate::config::Constant;
use crate::base::units::Dim;
use serde::de::{Deserialize, Deserializer, Error};

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
