//! The surge runs as the stage's pooled fit predicts them, for a parametric bootstrap
//! (`hydroid calibrate`; Efron & Tibshirani 1993, ch. 6.5, the residual bootstrap of a
//! regression with fixed regressors): the fitted u of every row the fit used, with the noise
//! the fit's residuals show.
//!
//! The regressors (the thrust, or the exported axial force `fx`, and the integral of u|u|)
//! stay as recorded: the fitted u already carries what the recorded force integrates to, so a
//! replica's scatter is that of u about the fit. With difference windows (`window`, the
//! default for `drag_from = "force"`) a window's residual is the difference of two samples'
//! noise, so the noise on each u is the residual standard deviation over sqrt(2).

use super::config::SurgeConfig;
use super::estimate::window_seconds;
use super::result::SurgeResult;
use super::STAGE;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::io::record::Record;

/// One run's u as the fit predicts it.
#[derive(Debug, Clone, PartialEq)]
pub struct PredictedRun {
    /// Per row of the record, the fitted u (m/s), or None for a row outside the fit's time
    /// window (`t_start`, `t_end`).
    pub u: Vec<Option<f64>>,
    /// Standard deviation of the noise on u, m/s.
    pub sigma: f64,
}

/// The fitted u of every row of `records` that the surge fit used, read from the stage's
/// result (its residuals are in the records' order, rows inside the time window only).
pub fn predicted(
    config: &SurgeConfig,
    result: &SurgeResult,
    records: &[Record],
) -> Result<Vec<PredictedRun>> {
    let lo = config.t_start.unwrap_or(f64::NEG_INFINITY);
    let hi = config.t_end.unwrap_or(f64::INFINITY);
    // a window's residual is a difference of two samples' noise (see the module's comment)
    let per_sample = match window_seconds(config) {
        Some(_) => std::f64::consts::FRAC_1_SQRT_2,
        None => 1.0,
    };
    let sigma = result.residual_std * per_sample;
    if !sigma.is_finite() {
        return Err(Error::numerical(
            STAGE,
            "the surge fit has no finite residual standard deviation, so no replica of its \
             runs can be made",
        ));
    }
    records
        .iter()
        .enumerate()
        .map(|(k, rec)| {
            let fit = result
                .residuals
                .get(k)
                .filter(|r| r.record == rec.name)
                .ok_or_else(|| mismatch(&rec.name))?;
            let t = rec.time().ok_or_else(|| mismatch(&rec.name))?;
            let u = window_rows(t, (lo, hi), &fit.fitted)
                .filter(|_| rec.has(Quantity::U))
                .ok_or_else(|| mismatch(&rec.name))?;
            Ok(PredictedRun { u, sigma })
        })
        .collect()
}

/// Per time of `t`, the next of `fitted` when the time is inside [lo, hi], else None; None
/// when `fitted` has more or fewer values than the window has rows.
fn window_rows(t: &[f64], (lo, hi): (f64, f64), fitted: &[f64]) -> Option<Vec<Option<f64>>> {
    let mut next = fitted.iter();
    let mut out = Vec::with_capacity(t.len());
    for &ti in t {
        if ti >= lo && ti <= hi {
            out.push(Some(*next.next()?));
        } else {
            out.push(None);
        }
    }
    next.next().is_none().then_some(out)
}

fn mismatch(name: &str) -> Error {
    Error::numerical(
        STAGE,
        format!("surge run '{name}': the stage's fit does not match the run's rows"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows outside the time window are not predicted; the fitted values fill the rest in
    /// order, and a fit with more or fewer values than the window's rows is refused.
    #[test]
    fn the_fitted_u_fills_the_window_rows() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        let w = (1.0, 3.0);
        assert_eq!(
            window_rows(&t, w, &[2.1, 3.1, 4.1]),
            Some(vec![None, Some(2.1), Some(3.1), Some(4.1), None])
        );
        assert_eq!(window_rows(&t, w, &[2.1, 3.1, 4.1, 5.1]), None);
        assert_eq!(window_rows(&t, w, &[2.1, 3.1]), None);
        assert_eq!(
            window_rows(&t, (f64::NEG_INFINITY, f64::INFINITY), &[1.0; 5]).map(|v| v.len()),
            Some(5)
        );
    }
}
