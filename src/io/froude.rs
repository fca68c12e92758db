//! Froude scaling between a ship and its model, applied to an input when it is read.
//!
//! With the scale ratio lambda = L_ship / L_model and equal Froude numbers
//! (Fn = U / sqrt(g L), the same g at both scales), a quantity of dimension
//! mass^M length^L time^T scales from model to ship by lambda^(3M + L + T/2): lengths by
//! lambda, times and speeds by sqrt(lambda), rates and propeller speeds by 1/sqrt(lambda),
//! accelerations not at all, forces by lambda^3 and moments by lambda^4 (ITTC 7.5-02-06-01,
//! free-running model tests). Angles and coefficients are unchanged. Forces assume the same
//! water density at both scales: a model basin's fresh water and the sea differ by about
//! 2.5 %, which this scaling does not correct.

use crate::base::quantity::Quantity;
use serde::{Deserialize, Serialize};

/// How an input is scaled: `froude = { lambda = 45.7, to = "model" }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Froude {
    /// The scale ratio lambda = L_ship / L_model, greater than 1.
    pub lambda: f64,
    /// The scale the values are read at: `model` (the file is at full scale) or `full` (the
    /// file is at model scale).
    pub to: Scale,
}

/// A scale of a manoeuvring test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// The model in the basin (or a model-scale CFD run).
    Model,
    /// The ship.
    Full,
}

impl Froude {
    /// The factor that takes a value of `q` (in SI) from the file's scale to the target scale.
    pub fn factor(&self, q: Quantity) -> f64 {
        let [m, l, t, _] = q.dim();
        let exponent = 3.0 * f64::from(m) + f64::from(l) + 0.5 * f64::from(t);
        let up = self.lambda.powf(exponent);
        match self.to {
            Scale::Full => up,
            Scale::Model => 1.0 / up,
        }
    }

    /// What the scaling did, for the record's notes.
    pub fn describe(&self) -> String {
        let (from, to) = match self.to {
            Scale::Model => ("full", "model"),
            Scale::Full => ("model", "full"),
        };
        format!(
            "Froude-scaled from {from} scale to {to} scale with lambda = {} (lengths by \
             lambda, times and speeds by sqrt(lambda), rates and propeller speed by \
             1/sqrt(lambda), forces by lambda^3, moments by lambda^4, same water density; \
             angles unchanged)",
            self.lambda
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_by_dimension() {
        let up = Froude {
            lambda: 16.0,
            to: Scale::Full,
        };
        for (q, f) in [
            (Quantity::X, 16.0),
            (Quantity::Time, 4.0),
            (Quantity::U, 4.0),
            (Quantity::R, 0.25),
            (Quantity::Rpm, 0.25),
            (Quantity::UDot, 1.0),
            (Quantity::Fx, 4096.0),
            (Quantity::Mz, 65536.0),
            (Quantity::Yaw, 1.0),
            (Quantity::Rudder, 1.0),
            (Quantity::Cd, 1.0),
        ] {
            assert!((up.factor(q) - f).abs() < 1e-9 * f, "{q}: {}", up.factor(q));
            let down = Froude {
                to: Scale::Model,
                ..up
            };
            assert!((down.factor(q) * f - 1.0).abs() < 1e-12, "{q}");
        }
    }
}
