//! `[polar]` configuration: inputs, fitting range, weights and the switchable constraints.

use super::{yes, Config, InputSpec, Problems};
use crate::model::coefficients::YawMoment;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// `[polar]` configuration (see docs/stages.md for every key with an example).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolarConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The steady runs: sweep tables with an `alpha` column (one point per row), or one
    /// steady-run history per angle (alpha and speed as `constants`).
    pub runs: Vec<InputSpec>,
    /// What the files give: dimensionless coefficients (`cd`, `cl`, `cm`) or forces and
    /// moment in N and N m (`fx`, `fy`, `mz`, with `speed`).
    #[serde(default)]
    pub data: PolarData,
    /// Axes of the given forces or coefficients: `body` (x forward, y starboard) or `flow`
    /// (x along the vehicle's velocity, y 90 deg to starboard of it).
    #[serde(default)]
    pub axes: PolarAxes,
    /// Fit only points with |alpha| <= this angle, degrees (default: every point).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_max_deg: Option<f64>,
    /// History files: the steady value is the mean over this last fraction of the record
    /// (of its time span when it has a time column, else of its rows), - (default 0.25).
    #[serde(default = "default_steady_fraction")]
    pub steady_fraction: f64,
    /// Point weights: `uniform`, or `inverse_variance` (1 / standard error^2 of each steady
    /// mean; history files only).
    #[serde(default)]
    pub weights: PolarWeights,
    /// Speeds within this relative difference are one speed group, - (default 0.01).
    #[serde(default = "default_speed_tolerance")]
    pub speed_tolerance: f64,
    /// Constraints on C_D = a alpha^2 + b alpha + c.
    #[serde(default)]
    pub drag: DragFit,
    /// Model and constraints of C_L(alpha) (body side-force coefficient).
    #[serde(default)]
    pub lift: SlopeFit,
    /// Model and constraints of C_M(alpha) (yaw moment coefficient).
    #[serde(default)]
    pub moment: SlopeFit,
}

fn default_steady_fraction() -> f64 {
    0.25
}

fn default_speed_tolerance() -> f64 {
    0.01
}

/// What a polar file gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PolarData {
    /// `cd`, `cl`, `cm` columns: C_D = -X / (q_dyn), C_L = Y / q_dyn, C_M = N / (q_dyn L_ref)
    /// with q_dyn = 0.5 rho U^2 A_ref.
    #[default]
    Coefficients,
    /// `fx`, `fy` (N) and `mz` (N m) columns with a `speed` column or constant; made
    /// dimensionless with `vehicle.reference_area` and `vehicle.reference_length`.
    Forces,
}

/// Axes of the given forces or coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PolarAxes {
    /// Body axes: x forward, y starboard (the body is fixed and the inflow turned).
    #[default]
    Body,
    /// Flow axes: x along the vehicle's velocity (so `fx` is minus the drag), y 90 deg to
    /// starboard of it (the inflow is fixed and the body turned); rotated into body axes by
    /// alpha.
    Flow,
}

/// Point weights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PolarWeights {
    /// Every point counts the same.
    #[default]
    Uniform,
    /// Each steady mean weighted by 1 / its standard error squared (history files only).
    InverseVariance,
}

/// Sign constraint on a slope.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlopeSign {
    /// No constraint.
    #[default]
    Free,
    /// slope >= 0.
    Positive,
    /// slope <= 0.
    Negative,
}

/// Lower and upper bound on one fitted constant (same unit as the constant: -, 1/rad,
/// 1/rad^2, 1/rad^3).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bound {
    /// Lower bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
}

/// `[polar.drag]`: constraints on C_D = a alpha^2 + b alpha + c (alpha in rad).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DragFit {
    /// a >= 0 (drag grows with drift), 1/rad^2 (default true).
    #[serde(default = "yes")]
    pub a_nonnegative: bool,
    /// c >= 0 (drag at zero drift is not a thrust), - (default true).
    #[serde(default = "yes")]
    pub c_nonnegative: bool,
    /// b = 0: a body symmetric port and starboard has a polar even in alpha (default false;
    /// the paper's fit has b = -0.0273 /rad).
    #[serde(default)]
    pub symmetric: bool,
    /// Extra bounds on `a`, `b` or `c`, e.g. `bounds.c = { min = 0.05, max = 0.2 }`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub bounds: BTreeMap<String, Bound>,
}

impl Default for DragFit {
    fn default() -> Self {
        DragFit {
            a_nonnegative: true,
            c_nonnegative: true,
            symmetric: false,
            bounds: BTreeMap::new(),
        }
    }
}

/// `[polar.lift]` and `[polar.moment]`: C(alpha) = intercept + slope alpha (+ cubic alpha^3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlopeFit {
    /// C(0) = 0: the intercept is fixed at zero (default true: a body symmetric port and
    /// starboard has no side force or yaw moment at zero drift).
    #[serde(default = "yes")]
    pub through_origin: bool,
    /// Add a cubic term, 1/rad^3, so that a wide sweep (e.g. +-20 deg) still gives the slope
    /// at alpha = 0 (default false).
    #[serde(default)]
    pub cubic: bool,
    /// Sign of the slope at alpha = 0: `free`, `positive` or `negative` (default free).
    #[serde(default)]
    pub slope: SlopeSign,
    /// Extra bounds on `intercept` (-), `slope` (1/rad) or `cubic` (1/rad^3).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub bounds: BTreeMap<String, Bound>,
    /// `[polar.moment]` only: which part of the yaw moment C_M is, `total` (Munk moment
    /// included, what a CFD static drift run measures: the slope gives Nuv) or `lift-only`
    /// (the seed paper's reading: the slope gives Nuvl). Default total
    /// ([`PolarConfig::moment_part`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub part: Option<YawMoment>,
}

impl Default for SlopeFit {
    fn default() -> Self {
        SlopeFit {
            through_origin: true,
            cubic: false,
            slope: SlopeSign::Free,
            bounds: BTreeMap::new(),
            part: None,
        }
    }
}

/// The names of the drag constants.
pub const DRAG_NAMES: [&str; 3] = ["a", "b", "c"];
/// The names of the lift and moment constants.
pub const SLOPE_NAMES: [&str; 3] = ["intercept", "slope", "cubic"];

impl DragFit {
    /// The interval each constant is confined to by the switches and bounds (for the static
    /// feasibility check; the fit applies the same constraints).
    fn intervals(&self) -> [(f64, f64); 3] {
        let mut iv = [(f64::NEG_INFINITY, f64::INFINITY); 3];
        if self.a_nonnegative {
            iv[0].0 = 0.0;
        }
        if self.symmetric {
            iv[1] = (0.0, 0.0);
        }
        if self.c_nonnegative {
            iv[2].0 = 0.0;
        }
        apply_bounds(&mut iv, &DRAG_NAMES, &self.bounds);
        iv
    }
}

impl SlopeFit {
    fn intervals(&self) -> [(f64, f64); 3] {
        let mut iv = [(f64::NEG_INFINITY, f64::INFINITY); 3];
        if self.through_origin {
            iv[0] = (0.0, 0.0);
        }
        match self.slope {
            SlopeSign::Free => {}
            SlopeSign::Positive => iv[1].0 = 0.0,
            SlopeSign::Negative => iv[1].1 = 0.0,
        }
        apply_bounds(&mut iv, &SLOPE_NAMES, &self.bounds);
        iv
    }
}

fn apply_bounds(iv: &mut [(f64, f64); 3], names: &[&str; 3], bounds: &BTreeMap<String, Bound>) {
    for (name, b) in bounds {
        if let Some(k) = names.iter().position(|n| n == name) {
            if let Some(lo) = b.min {
                iv[k].0 = iv[k].0.max(lo);
            }
            if let Some(hi) = b.max {
                iv[k].1 = iv[k].1.min(hi);
            }
        }
    }
}

fn check_bounds(
    p: &mut Problems,
    key: &str,
    names: &[&str],
    bounds: &BTreeMap<String, Bound>,
    iv: &[(f64, f64); 3],
) {
    for (name, b) in bounds {
        let k = format!("{key}.bounds.{name}");
        let Some(idx) = names.iter().position(|n| n == name) else {
            p.add(
                &k,
                format!(
                    "unknown constant '{name}'{}",
                    crate::base::suggest::did_you_mean(name, names.iter().copied())
                ),
            );
            continue;
        };
        if let Some(v) = b.min {
            p.finite(&format!("{k}.min"), v);
        }
        if let Some(v) = b.max {
            p.finite(&format!("{k}.max"), v);
        }
        if let (Some(lo), Some(hi)) = (b.min, b.max) {
            if lo > hi {
                p.add(&k, format!("min {lo} is larger than max {hi}"));
                continue;
            }
        }
        let (lo, hi) = iv[idx];
        if lo > hi {
            p.add(
                &k,
                format!(
                    "the constraints on '{name}' cannot all hold (they leave [{lo}, {hi}]); \
                     relax a bound or a switch of [{key}]"
                ),
            );
        }
    }
}

impl PolarConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, _config: &Config, p: &mut Problems) {
        if self.runs.is_empty() {
            p.add("polar.runs", "no run to fit");
        }
        p.inputs(&self.inputs());
        if let Some(a) = self.alpha_max_deg {
            if !(a.is_finite() && a > 0.0 && a <= 90.0) {
                p.add(
                    "polar.alpha_max_deg",
                    format!("must be an angle in degrees in (0, 90], got {a}"),
                );
            }
        }
        if !(self.steady_fraction.is_finite()
            && self.steady_fraction > 0.0
            && self.steady_fraction <= 1.0)
        {
            p.add(
                "polar.steady_fraction",
                format!(
                    "must be a fraction in (0, 1] of each history, got {}",
                    self.steady_fraction
                ),
            );
        }
        p.within("polar.speed_tolerance", self.speed_tolerance, 0.0, 0.5);
        if self.lift.part.is_some() {
            p.add(
                "polar.lift.part",
                "says which part of the yaw moment C_M is, so it belongs in [polar.moment]",
            );
        }
        check_bounds(
            p,
            "polar.drag",
            &DRAG_NAMES,
            &self.drag.bounds,
            &self.drag.intervals(),
        );
        for (key, fit) in [("polar.lift", &self.lift), ("polar.moment", &self.moment)] {
            let names: &[&str] = if fit.cubic {
                &SLOPE_NAMES
            } else {
                &SLOPE_NAMES[..2]
            };
            if !fit.cubic && fit.bounds.contains_key("cubic") {
                p.add(
                    &format!("{key}.bounds.cubic"),
                    format!("bounds a cubic term, but {key}.cubic is false"),
                );
            }
            let bounds: BTreeMap<String, Bound> = fit
                .bounds
                .iter()
                .filter(|(n, _)| fit.cubic || n.as_str() != "cubic")
                .map(|(n, b)| (n.clone(), *b))
                .collect();
            check_bounds(p, key, names, &bounds, &fit.intervals());
        }
    }

    /// Which part of the yaw moment the polar's C_M is (`polar.moment.part`, default total:
    /// a CFD static drift run measures the whole moment, Munk moment included).
    pub fn moment_part(&self) -> YawMoment {
        self.moment.part.unwrap_or(YawMoment::Total)
    }

    /// The input files this section names.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("polar.runs[{i}]"), r))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_from_a_minimal_table() {
        let c: PolarConfig = toml::from_str("runs = []\n").unwrap();
        assert!(c.enabled && c.drag.a_nonnegative && c.drag.c_nonnegative);
        assert!(!c.drag.symmetric && c.lift.through_origin && !c.lift.cubic);
        assert_eq!(c.steady_fraction, 0.25);
        assert_eq!(c.data, PolarData::Coefficients);
        assert_eq!(c.moment_part(), YawMoment::Total);
    }

    #[test]
    fn the_moment_part_is_read_and_unknown_words_name_the_choices() {
        let c: PolarConfig = toml::from_str("runs = []\nmoment.part = \"lift-only\"\n").unwrap();
        assert_eq!(c.moment_part(), YawMoment::LiftOnly);
        let e = toml::from_str::<PolarConfig>("runs = []\n[moment]\npart = \"munk\"\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("total") && e.contains("lift-only"), "{e}");
    }

    #[test]
    fn unknown_keys_are_rejected() {
        let e = toml::from_str::<PolarConfig>("runs = []\n[drag]\nsymetric = true\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("symetric"), "{e}");
    }
}
