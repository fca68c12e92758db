//! The polar stage's result types (all `serde::Serialize`; see docs/stages.md).

use super::{PolarAxes, PolarData, PolarPoint, PolarWeights};
use crate::model::coefficients::{Coefficient, Direction};
use crate::stages::spread::Spread;
use serde::Serialize;

/// The reference quantities used, stated so that a report can print them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub mu: f64,
    /// Reference area A_ref, m^2.
    pub reference_area: f64,
    /// Moment reference length L_ref, m (1 m reproduces the paper, whose C_M is referred to
    /// A_f only).
    pub reference_length: f64,
    /// q = 0.5 rho A_ref, kg/m (paper eq. 5).
    pub q: f64,
    /// Length in the Reynolds number Re = rho U L / mu (the vehicle length), m.
    pub reynolds_length: f64,
    /// What the files gave.
    pub data: PolarData,
    /// Axes of the given forces or coefficients.
    pub axes: PolarAxes,
    /// Fitting range, degrees (None: every point).
    pub alpha_max_deg: Option<f64>,
    /// Point weights.
    pub weights: PolarWeights,
    /// Which part of the yaw moment C_M is: `total` (Munk moment included; the slope gives
    /// Nuv) or `lift-only` (the slope gives Nuvl).
    pub moment: crate::model::coefficients::YawMoment,
    /// The definitions in words.
    pub statement: String,
}

/// A fitted residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residual {
    /// The record the point came from.
    pub record: String,
    /// Angle of attack, rad.
    pub alpha: f64,
    /// Observed coefficient.
    pub observed: f64,
    /// Fitted coefficient.
    pub fitted: f64,
    /// observed - fitted.
    pub residual: f64,
}

/// One channel's constrained fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelFit {
    /// `drag`, `lift` or `moment`.
    pub channel: String,
    /// The fitted model.
    pub model: String,
    /// Names of the constants (`a`, `b`, `c` or `intercept`, `slope`, `cubic`).
    pub names: Vec<String>,
    /// Units of the constants.
    pub units: Vec<String>,
    /// Fitted values.
    pub values: Vec<f64>,
    /// Standard errors (zero for a constant fixed by an active constraint; None without
    /// residual degrees of freedom).
    pub std_errors: Vec<Option<f64>>,
    /// Covariance of the constants, in `names` order.
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The constraints active at the solution (equalities always are), as configured.
    pub active_constraints: Vec<String>,
    /// The inequality constraints among them: where the data pull against a constraint.
    pub binding_inequalities: Vec<String>,
    /// Points fitted.
    pub n_points: usize,
    /// Residual degrees of freedom (points minus free constants).
    pub dof: usize,
    /// Weighted residual sum of squares.
    pub rss: f64,
    /// sqrt(rss / dof), the residual standard deviation (relative weights).
    pub residual_std: Option<f64>,
    /// Weighted coefficient of determination.
    pub r_squared: Option<f64>,
    /// Residual of every point, for plots.
    pub residuals: Vec<Residual>,
}

impl ChannelFit {
    /// The fitted value of constant `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.values[i])
    }

    /// The standard error of constant `name`.
    pub fn std_error(&self, name: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == name)?;
        self.std_errors[i]
    }
}

/// The three channel fits over one set of points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarFit {
    /// Points fitted.
    pub n_points: usize,
    /// C_D = a alpha^2 + b alpha + c.
    pub drag: ChannelFit,
    /// C_L = intercept + slope alpha (+ cubic alpha^3).
    pub lift: ChannelFit,
    /// C_M = intercept + slope alpha (+ cubic alpha^3).
    pub moment: ChannelFit,
}

/// The fit at one speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedFit {
    /// Mean speed of the group, m/s.
    pub speed: f64,
    /// Reynolds number rho U L / mu with the vehicle length, -.
    pub reynolds: f64,
    /// Points at this speed in the fitting range.
    pub n_points: usize,
    /// The fit (None when this speed alone cannot be fitted; see `error`).
    pub fit: Option<PolarFit>,
    /// Coefficients from this speed's fit (paper eq. 5).
    pub coefficients: Vec<Coefficient>,
    /// Why this speed has no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// Everything the polar stage found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarResult {
    /// Reference quantities and conventions used.
    pub reference: Reference,
    /// The fit over every point in range, all speeds together in coefficient form.
    pub pooled: PolarFit,
    /// The fit at each speed (empty when no record gives a speed).
    pub per_speed: Vec<SpeedFit>,
    /// Spread of each coefficient between speeds (two or more speeds).
    pub spread: Vec<Spread>,
    /// Coefficients from the pooled fit (paper eq. 5), `Source::Polar`.
    pub coefficients: Vec<Coefficient>,
    /// Every point read, with `used` telling whether it was in the fitting range.
    pub points: Vec<PolarPoint>,
    /// Things worth reading.
    pub warnings: Vec<crate::base::warning::Warning>,
    /// The coefficients' uncertainty as independent directions (for propagation through the
    /// later stages; summarised per coefficient in the report).
    #[serde(skip)]
    pub directions: Vec<Direction>,
}

impl PolarResult {
    /// The coefficients of the pooled fit.
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }
}
