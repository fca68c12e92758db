//! Analytic added mass of a prolate spheroid from Lamb's k-factors, as given by Fossen,
//! *Guidance and Control of Ocean Vehicles* (Wiley, 1994), section 2.4.1 (after Lamb,
//! *Hydrodynamics*, 1932, §373; Imlay 1961).
//!
//! The body is a prolate spheroid with semi-axes a > b (a along x), so that
//!
//! ```text
//! e      = sqrt(1 - (b/a)^2)                                          eccentricity
//! m_f    = 4/3 pi rho a b^2                                            displaced mass
//! alpha0 = 2 (1 - e^2) / e^3 * (0.5 ln((1+e)/(1-e)) - e)
//! beta0  = 1/e^2 - (1 - e^2) / (2 e^3) * ln((1+e)/(1-e))
//! k1 = alpha0 / (2 - alpha0),  k2 = beta0 / (2 - beta0)
//! k' = e^4 (beta0 - alpha0) / ((2 - e^2) (2 e^2 - (2 - e^2)(beta0 - alpha0)))
//! Xud = -k1 m_f,  Yvd = Zwd = -k2 m_f,  Nrd = Mqd = -k' I_f,  Kpd = 0,  Yrd = Nvd = 0
//! ```
//!
//! with I_f = m_f (a^2 + b^2) / 5 the displaced fluid's moment of inertia about a transverse
//! axis through the centre; Fossen writes the same N_rdot as
//! `-1/5 (b^2 - a^2)^2 (alpha0 - beta0) / (2 (b^2 - a^2) + (b^2 + a^2)(beta0 - alpha0)) m_f`.
//!
//! Numerics: the closed forms cancel catastrophically as the spheroid approaches a sphere
//! (e -> 0). With `S = (atanh(e) - e) / e^3 = sum_{n>=0} e^(2n) / (2n + 3)` one has
//! `alpha0 = 2 (1 - e^2) S`, `beta0 = 1 - (1 - e^2) S` (so alpha0 + 2 beta0 = 2), and
//! `alpha0 - beta0 = -6 sum_{n>=1} e^(2n) / ((2n + 1)(2n + 3))`; these series are used for
//! small e, the closed forms otherwise.

// crate::Error is large (its InputError variant); boxing it is a crate-wide choice.

use crate::base::error::{Error, Result};
use crate::model::coefficients::{Coefficient, Source};
use serde::Serialize;
use std::f64::consts::PI;

/// Below this eccentricity the series forms are used (at e = 0.5 the closed forms lose about
/// one digit and the series needs fewer than 30 terms).
const SERIES_BELOW: f64 = 0.5;

/// Lamb's k-factors and the added mass of a prolate spheroid (Fossen 1994, section 2.4.1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spheroid {
    /// Semi-major axis a (half the length), m.
    pub a: f64,
    /// Semi-minor axis b (half the diameter), m.
    pub b: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Eccentricity e = sqrt(1 - (b/a)^2), -.
    pub e: f64,
    /// Displaced fluid mass m_f = 4/3 pi rho a b^2, kg.
    pub displaced_mass: f64,
    /// Moment of inertia of the displaced fluid about a transverse axis through the centre,
    /// I_f = m_f (a^2 + b^2) / 5, kg m^2.
    pub displaced_inertia: f64,
    /// Lamb's alpha0, -.
    pub alpha0: f64,
    /// Lamb's beta0, -.
    pub beta0: f64,
    /// Axial k-factor k1 = alpha0 / (2 - alpha0), -.
    pub k1: f64,
    /// Transverse k-factor k2 = beta0 / (2 - beta0), -.
    pub k2: f64,
    /// Rotational k-factor k', -.
    pub k_prime: f64,
}

impl Spheroid {
    /// A spheroid of overall `length` and maximum `diameter` (m) in a fluid of density `rho`
    /// (kg/m^3). Needs length > diameter > 0 (prolate) and rho > 0.
    pub fn from_length_diameter(length: f64, diameter: f64, rho: f64) -> Result<Self> {
        Spheroid::new(0.5 * length, 0.5 * diameter, rho)
    }

    /// A spheroid with semi-axes `a` (along x) and `b` (m), density `rho` (kg/m^3).
    pub fn new(a: f64, b: f64, rho: f64) -> Result<Self> {
        let bad = |m: String| Err(Error::Usage(format!("prolate spheroid: {m}")));
        for (name, v, unit) in [
            ("length", a, "m"),
            ("diameter", b, "m"),
            ("rho", rho, "kg/m^3"),
        ] {
            if !(v.is_finite() && v > 0.0) {
                let shown = if unit == "m" { 2.0 * v } else { v };
                return bad(format!(
                    "{name} must be a positive number ({unit}), got {shown}"
                ));
            }
        }
        if b >= a {
            return bad(format!(
                "the diameter ({} m) must be smaller than the length ({} m); Lamb's prolate \
                 formulas need a > b (a sphere or an oblate body is not covered)",
                2.0 * b,
                2.0 * a
            ));
        }
        let ratio = b / a;
        // e = sqrt(1 - (b/a)^2) (Fossen 1994, section 2.4.1)
        let e2 = (1.0 - ratio) * (1.0 + ratio);
        let e = e2.sqrt();
        // m_f = 4/3 pi rho a b^2 (Fossen 1994, section 2.4.1)
        let displaced_mass = 4.0 / 3.0 * PI * rho * a * b * b;
        let displaced_inertia = displaced_mass * (a * a + b * b) / 5.0;

        let (alpha0, beta0, dn) = lamb_integrals(e, e < SERIES_BELOW);
        // k1 = alpha0 / (2 - alpha0), k2 = beta0 / (2 - beta0) (Fossen 1994, section 2.4.1)
        let k1 = alpha0 / (2.0 - alpha0);
        let k2 = beta0 / (2.0 - beta0);
        // k' = e^4 (beta0 - alpha0) / ((2 - e^2)(2 e^2 - (2 - e^2)(beta0 - alpha0)))
        // (Fossen 1994, section 2.4.1), divided through by e^2 so that it stays finite.
        let k_prime = -e2 * e2 * dn / ((2.0 - e2) * (2.0 + (2.0 - e2) * dn));
        let s = Spheroid {
            a,
            b,
            rho,
            e,
            displaced_mass,
            displaced_inertia,
            alpha0,
            beta0,
            k1,
            k2,
            k_prime,
        };
        if [s.alpha0, s.beta0, s.k1, s.k2, s.k_prime]
            .iter()
            .any(|v| !v.is_finite())
        {
            return Err(Error::numerical(
                "analytic",
                format!("Lamb's k-factors are not finite for a = {a} m, b = {b} m"),
            ));
        }
        Ok(s)
    }

    /// Surge added mass X_udot = -k1 m_f, kg (Fossen 1994, section 2.4.1).
    pub fn xud(&self) -> f64 {
        -self.k1 * self.displaced_mass
    }

    /// Sway (and heave) added mass Y_vdot = Z_wdot = -k2 m_f, kg (Fossen 1994, section 2.4.1).
    pub fn yvd(&self) -> f64 {
        -self.k2 * self.displaced_mass
    }

    /// Yaw (and pitch) added inertia N_rdot = M_qdot = -k' I_f, kg m^2 (Fossen 1994,
    /// section 2.4.1).
    pub fn nrd(&self) -> f64 {
        -self.k_prime * self.displaced_inertia
    }

    /// The added-mass coefficients as `Coefficient`s with `Source::Analytic`: Xud, Yvd, Zwd,
    /// Nrd, Mqd, Kpd, Yrd, Nvd (the last three zero by symmetry).
    pub fn coefficients(&self) -> Vec<Coefficient> {
        let note = |what: &str| format!("Fossen 1994, section 2.4.1 (Lamb's k-factors): {what}");
        vec![
            Coefficient::new("Xud", self.xud(), None, Source::Analytic)
                .with_note(note("Xud = -k1 m_f")),
            Coefficient::new("Yvd", self.yvd(), None, Source::Analytic)
                .with_note(note("Yvd = -k2 m_f")),
            Coefficient::new("Zwd", self.yvd(), None, Source::Analytic)
                .with_note(note("Zwd = Yvd")),
            Coefficient::new("Nrd", self.nrd(), None, Source::Analytic)
                .with_note(note("Nrd = -k' m_f (a^2 + b^2) / 5")),
            Coefficient::new("Mqd", self.nrd(), None, Source::Analytic)
                .with_note(note("Mqd = Nrd")),
            Coefficient::new("Kpd", 0.0, None, Source::Analytic)
                .with_note(note("Kpd = 0 for a body of revolution")),
            Coefficient::new("Yrd", 0.0, None, Source::Analytic)
                .with_note(note("Yrd = 0 for a body symmetric fore and aft")),
            Coefficient::new("Nvd", 0.0, None, Source::Analytic)
                .with_note(note("Nvd = 0 for a body symmetric fore and aft")),
        ]
    }
}

/// Lamb's alpha0, beta0 and (alpha0 - beta0) / e^2 (finite as e -> 0), from the series
/// (`series = true`) or the closed forms (Fossen 1994, section 2.4.1).
fn lamb_integrals(e: f64, series_form: bool) -> (f64, f64, f64) {
    let e2 = e * e;
    if series_form {
        // S = (atanh e - e) / e^3 = sum e^(2n) / (2n + 3); alpha0 = 2 (1 - e^2) S,
        // beta0 = 1 - (1 - e^2) S, (alpha0 - beta0) / e^2 = -6 sum e^(2n) / ((2n+3)(2n+5)).
        let s = series(e2, |n| 1.0 / (2 * n + 3) as f64);
        let dn = -6.0 * series(e2, |n| 1.0 / ((2 * n + 3) * (2 * n + 5)) as f64);
        (2.0 * (1.0 - e2) * s, 1.0 - (1.0 - e2) * s, dn)
    } else {
        let log = ((1.0 + e) / (1.0 - e)).ln();
        // alpha0 = 2 (1 - e^2)/e^3 (0.5 ln((1+e)/(1-e)) - e) (Fossen 1994, section 2.4.1)
        let alpha0 = 2.0 * (1.0 - e2) / (e * e2) * (0.5 * log - e);
        // beta0 = 1/e^2 - (1 - e^2)/(2 e^3) ln((1+e)/(1-e)) (Fossen 1994, section 2.4.1)
        let beta0 = 1.0 / e2 - (1.0 - e2) / (2.0 * e * e2) * log;
        (alpha0, beta0, (alpha0 - beta0) / e2)
    }
}

/// sum_{n >= 0} c(n) x^n, to machine precision (x < 1).
fn series(x: f64, c: impl Fn(usize) -> f64) -> f64 {
    let mut sum = 0.0;
    let mut p = 1.0;
    for n in 0..400 {
        let term = c(n) * p;
        sum += term;
        if term.abs() < 1e-18 * sum.abs() {
            break;
        }
        p *= x;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_and_closed_forms_agree() {
        // Where both are accurate (the closed forms lose about log10(3/e^2) digits).
        for e in [0.3, 0.5, 0.7] {
            let (a1, b1, d1) = lamb_integrals(e, true);
            let (a2, b2, d2) = lamb_integrals(e, false);
            for (x, y) in [(a1, a2), (b1, b2), (d1, d2)] {
                assert!((x - y).abs() < 1e-12 * x.abs(), "e = {e}: {x} vs {y}");
            }
        }
    }

    #[test]
    fn lamb_identity_alpha0_plus_two_beta0() {
        // alpha0 + 2 beta0 = 2 holds for every prolate spheroid (Lamb 1932, §373).
        for ratio in [0.01, 0.1, 0.3, 0.7, 0.95, 0.999] {
            let s = Spheroid::new(1.0, ratio, 1.0).unwrap();
            assert!((s.alpha0 + 2.0 * s.beta0 - 2.0).abs() < 1e-12, "{ratio}");
        }
    }

    #[test]
    fn fossens_nrd_expression_matches_k_prime() {
        // Fossen's direct N_rdot formula, evaluated where it is well conditioned.
        let s = Spheroid::new(0.6, 0.1, 1025.0).unwrap();
        let (a2, b2) = (s.a * s.a, s.b * s.b);
        let nrd = -0.2 * (b2 - a2).powi(2) * (s.alpha0 - s.beta0)
            / (2.0 * (b2 - a2) + (b2 + a2) * (s.beta0 - s.alpha0))
            * s.displaced_mass;
        assert!((nrd - s.nrd()).abs() < 1e-12 * nrd.abs());
    }

    #[test]
    fn bad_geometry_is_an_error_not_nan() {
        for (a, b, rho) in [
            (0.1, 0.1, 1025.0),
            (0.1, 0.2, 1025.0),
            (0.0, 0.1, 1025.0),
            (0.6, -0.1, 1025.0),
            (0.6, 0.1, 0.0),
            (f64::NAN, 0.1, 1025.0),
        ] {
            let e = Spheroid::new(a, b, rho).unwrap_err().to_string();
            assert!(e.contains("prolate spheroid"), "{e}");
        }
    }
}
