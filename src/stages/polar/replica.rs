//! The polar's points as its pooled fit predicts them, for a parametric bootstrap
//! (`hydroid calibrate`): each sweep row's fitted body-axis coefficients and the record
//! values that give them back (the inverse of the stage's reading, `data.rs`).

use super::config::{PolarAxes, PolarConfig, PolarData};
use super::result::{ChannelFit, PolarResult};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::config::{FluidConfig, VehicleConfig};
use crate::io::record::Record;

/// A fitted row: the fitted body-axis (C_D, C_L, C_M) and the row's angle of attack (rad);
/// None for a row outside the fitting range (not fitted).
pub type FittedRow = Option<([f64; 3], f64)>;

/// The pooled fit's prediction of each record's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Predicted {
    /// Per record, per row.
    pub rows: Vec<Vec<FittedRow>>,
    /// The residual standard deviation of each channel (C_D, C_L, C_M), -.
    pub sigma: [f64; 3],
}

/// The fitted coefficients of every sweep row of `records`, read from the stage's result;
/// a steady-run history (one point per file) is refused, naming the run.
pub fn predicted(result: &PolarResult, records: &[Record]) -> Result<Predicted> {
    let fit = &result.pooled;
    let channels = [&fit.drag, &fit.lift, &fit.moment];
    let mut used = 0;
    let mut point = result.points.iter();
    let mut rows = Vec::new();
    for rec in records {
        if rec.channel(Quantity::Alpha).is_none() {
            return Err(Error::numerical(
                super::STAGE,
                format!(
                    "polar run '{}' is a steady-run history (one point per file): its replicas \
                     are not made yet; calibrate needs polar sweep tables",
                    rec.name
                ),
            ));
        }
        let mut per_row = Vec::with_capacity(rec.rows());
        for _ in 0..rec.rows() {
            let p = point.next().ok_or_else(|| mismatch(&rec.name))?;
            if p.used {
                let c = channels.map(|ch| ch.residuals.get(used).map(|r| r.fitted));
                let [Some(cd), Some(cl), Some(cm)] = c else {
                    return Err(mismatch(&rec.name));
                };
                used += 1;
                per_row.push(Some(([cd, cl, cm], p.alpha)));
            } else {
                per_row.push(None);
            }
        }
        rows.push(per_row);
    }
    Ok(Predicted {
        rows,
        sigma: channels.map(residual_sigma),
    })
}

fn mismatch(run: &str) -> Error {
    Error::numerical(
        super::STAGE,
        format!("polar run '{run}': the result's points do not match the run's rows"),
    )
}

/// A channel's residual standard deviation: sqrt(RSS / dof), or the residuals' RMS without
/// degrees of freedom left.
fn residual_sigma(ch: &ChannelFit) -> f64 {
    ch.residual_std.unwrap_or_else(|| {
        let n = ch.residuals.len().max(1) as f64;
        (ch.residuals.iter().map(|r| r.residual.powi(2)).sum::<f64>() / n).sqrt()
    })
}

/// The values of row `i` of `rec` that give the body-axis coefficients `c` = (C_D, C_L,
/// C_M) at angle `alpha`: the stage's reading (`data.rs`) inverted. Flow axes are rotated
/// back by -alpha (x_f = x_b cos a + y_b sin a, y_f = -x_b sin a + y_b cos a); forces are
/// coefficients times q_dyn = 0.5 rho U^2 A_ref (and L_ref for the moment; paper eq. 5-6).
pub fn row_values(
    config: &PolarConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    rec: &Record,
    i: usize,
    alpha: f64,
    c: [f64; 3],
) -> Result<[(Quantity, f64); 3]> {
    let (xb, yb, n) = (-c[0], c[1], c[2]);
    let (sa, ca) = alpha.sin_cos();
    let (x, y) = match config.axes {
        PolarAxes::Body => (xb, yb),
        PolarAxes::Flow => (xb * ca + yb * sa, -xb * sa + yb * ca),
    };
    Ok(match config.data {
        PolarData::Coefficients => [(Quantity::Cd, -x), (Quantity::Cl, y), (Quantity::Cm, n)],
        PolarData::Forces => {
            let u = rec.value_at(Quantity::Speed, i).ok_or_else(|| {
                Error::numerical(
                    super::STAGE,
                    format!("polar run '{}': no speed in row {}", rec.name, i + 1),
                )
            })?;
            let qd = 0.5 * fluid.rho * u * u * vehicle.reference_area;
            [
                (Quantity::Fx, x * qd),
                (Quantity::Fy, y * qd),
                (Quantity::Mz, n * qd * vehicle.reference_length),
            ]
        }
    })
}
