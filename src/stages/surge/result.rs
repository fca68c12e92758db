//! The surge stage's result types (all `serde::Serialize`; see docs/stages.md).

use super::DragFrom;
use crate::model::coefficients::{directions_of, Coefficient, CoefficientSet, Direction};
use crate::stages::spread::Spread;
use serde::Serialize;

/// An estimate with its standard deviation split by cause.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// Value, SI.
    pub value: f64,
    /// Total standard deviation (statistical and from X_uu, in quadrature).
    pub sigma: Option<f64>,
    /// Standard deviation from the fit residuals alone.
    pub sigma_statistical: Option<f64>,
    /// Standard deviation carried over from the uncertainty of the X_uu used.
    pub sigma_from_xuu: Option<f64>,
    /// d X_udot / d X_uu of the fit (`coefficients`), kg per kg/m: how an error in X_uu moves
    /// X_udot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity_to_xuu: Option<f64>,
    /// The factor by which `sigma_statistical` was widened because the residuals of u are
    /// autocorrelated (a misfit the model leaves, or coloured noise: the Newey-West long-run
    /// variance over the white one, docs/stages.md); absent when they look white.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub misfit_factor: Option<f64>,
}

/// The X_uu the stage used.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct XuuUsed {
    /// Value, kg/m.
    pub value: f64,
    /// Standard deviation, kg/m.
    pub sigma: Option<f64>,
    /// Where it came from.
    pub source: String,
}

/// The fit of one run or of one speed bin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartFit {
    /// X_udot, kg.
    pub xud: Estimate,
    /// X_uu fitted with it (`drag_from = "force"` only), kg/m.
    pub xuu: Option<Estimate>,
    /// Samples used.
    pub n_samples: usize,
    /// Residual standard deviation of u, m/s.
    pub residual_std: f64,
    /// Coefficient of determination of u.
    pub r_squared: Option<f64>,
    /// Covariance of X_udot and X_uu fitted together (`force`), kg^2/m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub covariance_xud_xuu: Option<f64>,
}

/// One run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunFit {
    /// The record.
    pub record: String,
    /// First and last time used, s.
    pub t_span: [f64; 2],
    /// Speed at the first and last sample used, m/s.
    pub u_span: [f64; 2],
    /// The fit of this run alone (None if it cannot be fitted alone; see `note`).
    pub fit: Option<PartFit>,
    /// Why there is no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// One speed bin (paper fig. 8: X_udot per speed band).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BinFit {
    /// Lower edge, m/s.
    pub u_min: f64,
    /// Upper edge, m/s.
    pub u_max: f64,
    /// Samples in stretches long enough to use.
    pub n_samples: usize,
    /// Stretches of runs in the bin (each with its own u(t0)).
    pub n_segments: usize,
    /// The fit (None when the bin has too little data; see `note`).
    pub fit: Option<PartFit>,
    /// Why there is no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// Residuals of one run, for plots.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunResiduals {
    /// The record.
    pub record: String,
    /// Time, s.
    pub time: Vec<f64>,
    /// Measured u, m/s.
    pub u: Vec<f64>,
    /// Fitted u, m/s.
    pub fitted: Vec<f64>,
    /// u - fitted, m/s.
    pub residual: Vec<f64>,
}

/// The momentum balance m (u - u0) = integral (F + X_prop) dt of a run that exports both the
/// axial force and the thrust (`drag_from = "force"`): a check of the export, not a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MomentumCheck {
    /// The record.
    pub record: String,
    /// RMS of m u - integral (F + X_prop) dt about its mean, N s.
    pub rms: f64,
    /// rms / (m (max u - min u)), -.
    pub relative: f64,
}

/// The fitted constants of the whole fit, with their covariance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Constants {
    /// Names: `inv_inertia` = 1/(m - Xud) (1/kg) for `coefficients`; `inv_xud` = 1/Xud
    /// (1/kg) and `xuu_over_xud` = -Xuu/Xud (1/m) for `force`.
    pub names: Vec<String>,
    /// Values.
    pub values: Vec<f64>,
    /// Covariance.
    pub covariance: Vec<Vec<f64>>,
    /// u(t0) of each run, m/s.
    pub u0: Vec<f64>,
}

/// Everything the surge stage found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurgeResult {
    /// The method in words.
    pub method: String,
    /// Where the drag term came from.
    pub drag_from: DragFrom,
    /// Vehicle mass used, kg.
    pub mass: f64,
    /// X_uu used (`coefficients`) or fitted (`force`).
    pub xuu: XuuUsed,
    /// X_udot over every run together, kg.
    pub xud: Estimate,
    /// X_uu fitted with X_udot (`force` only), kg/m.
    pub xuu_fitted: Option<Estimate>,
    /// Covariance of X_udot and X_uu fitted together (`force` only), kg^2/m.
    pub covariance_xud_xuu: Option<f64>,
    /// m - X_udot, kg.
    pub inertia: Estimate,
    /// The fitted constants and their covariance.
    pub constants: Constants,
    /// Samples used.
    pub n_samples: usize,
    /// Residual standard deviation of u, m/s.
    pub residual_std: f64,
    /// Coefficient of determination of u.
    pub r_squared: Option<f64>,
    /// Lag-1 autocorrelation of the residuals of u (near 0 when the model explains the run and
    /// the rest is measurement noise; near 1 when a systematic misfit remains, and then the
    /// standard deviations are too small). Whole-integral fits only.
    pub residual_lag1: Option<f64>,
    /// Each run alone.
    pub runs: Vec<RunFit>,
    /// Each speed bin.
    pub bins: Vec<BinFit>,
    /// Spread of X_udot between the bins that have a fit (statistical sigmas: the X_uu
    /// uncertainty is common to all bins).
    pub bin_spread: Option<Spread>,
    /// Momentum balance of each run with force and thrust (`force` only).
    pub momentum: Vec<MomentumCheck>,
    /// Residuals of every run.
    pub residuals: Vec<RunResiduals>,
    /// Coefficients: Xud (and Xuu for `force`), `Source::Surge`.
    pub coefficients: Vec<Coefficient>,
    /// Things worth reading.
    pub warnings: Vec<crate::base::warning::Warning>,
}

impl SurgeResult {
    /// The coefficients this stage estimated.
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }

    /// Adds this stage's coefficients to `set` with their uncertainty directions: its own
    /// statistics, and (with X_uu from an earlier stage) X_udot's share of every direction that
    /// moves X_uu, through d X_udot / d X_uu.
    pub fn merge_into(&self, set: &mut CoefficientSet) {
        let own = match self.drag_from {
            DragFrom::Coefficients => self
                .xud
                .sigma_statistical
                .map(|s| Direction {
                    source: "surge statistics".into(),
                    deltas: [("Xud".to_string(), s)].into_iter().collect(),
                })
                .into_iter()
                .collect(),
            DragFrom::Force => {
                let (sx, su) = (
                    self.xud.sigma.unwrap_or(0.0),
                    self.xuu_fitted.and_then(|e| e.sigma).unwrap_or(0.0),
                );
                let c = self.covariance_xud_xuu.unwrap_or(0.0);
                directions_of(
                    "surge statistics",
                    &["Xud", "Xuu"],
                    &[vec![sx * sx, c], vec![c, su * su]],
                )
            }
        };
        let mut directions = own;
        if let (DragFrom::Coefficients, Some(k)) = (self.drag_from, self.xud.sensitivity_to_xuu) {
            for d in &set.directions {
                if let Some(dx) = d.deltas.get("Xuu") {
                    directions.push(Direction {
                        source: d.source.clone(),
                        deltas: [("Xud".to_string(), k * dx)].into_iter().collect(),
                    });
                }
            }
        }
        set.merge_stage(self.coefficients(), directions);
    }
}
