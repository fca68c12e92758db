//! Polar points from records: sweep tables (one point per row) or steady-run histories (one
//! point per file, the mean over the last part of the run), in body-axis coefficients.

use super::config::{PolarAxes, PolarConfig, PolarData};
use crate::base::error::{InputError, Place, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::{FluidConfig, VehicleConfig};
use crate::io::record::Record;
use serde::Serialize;

/// One point of the polar, in body-axis coefficients.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarPoint {
    /// The record it came from.
    pub record: String,
    /// File line of the row (sweep tables), or None for a history mean.
    pub line: Option<usize>,
    /// Angle of attack (drift angle), rad.
    pub alpha: f64,
    /// The same in degrees, for reading.
    pub alpha_deg: f64,
    /// Flow speed, m/s, when the record gives one.
    pub speed: Option<f64>,
    /// Body-axis drag coefficient C_D = -X / (0.5 rho U^2 A_ref), -.
    pub cd: f64,
    /// Body-axis side-force coefficient C_L = Y / (0.5 rho U^2 A_ref), -.
    pub cl: f64,
    /// Yaw moment coefficient C_M = N / (0.5 rho U^2 A_ref L_ref), -.
    pub cm: f64,
    /// Standard error of the steady mean of C_D (histories only), -.
    pub cd_se: Option<f64>,
    /// Standard error of the steady mean of C_L (histories only), -.
    pub cl_se: Option<f64>,
    /// Standard error of the steady mean of C_M (histories only), -.
    pub cm_se: Option<f64>,
    /// Samples averaged (1 for a sweep row).
    pub samples: usize,
    /// Whether the point is inside the fitting range.
    pub used: bool,
}

/// Number of batches for the batch-means standard error of a steady mean.
const BATCHES: usize = 10;

/// Every point of every record, with `used` set from `alpha_max_deg`.
pub fn points(
    config: &PolarConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    records: &[Record],
) -> Result<(Vec<PolarPoint>, Vec<Warning>)> {
    let mut out = Vec::new();
    let mut warnings = Vec::new();
    let conv = Converter {
        config,
        vehicle,
        fluid,
    };
    for rec in records {
        if rec.channel(Quantity::Alpha).is_some() {
            for i in 0..rec.rows() {
                let alpha = rec.value_at(Quantity::Alpha, i).unwrap_or(f64::NAN);
                let speed = rec.value_at(Quantity::Speed, i);
                let [cd, cl, cm] = conv.row(rec, i, alpha)?;
                out.push(PolarPoint {
                    record: rec.name.clone(),
                    line: rec.lines.get(i).copied(),
                    alpha,
                    alpha_deg: alpha.to_degrees(),
                    speed,
                    cd,
                    cl,
                    cm,
                    cd_se: None,
                    cl_se: None,
                    cm_se: None,
                    samples: 1,
                    used: true,
                });
            }
        } else if let Some(&alpha) = rec.constants.get(&Quantity::Alpha) {
            let rows = steady_window(rec, config.steady_fraction);
            if rows.is_empty() {
                return Err(input(rec, "the record has no rows to average").into());
            }
            if rows.len() < 2 * BATCHES {
                warnings.push(
                    Warning::new(
                        super::STAGE,
                        format!("only {} samples in the steady window", rows.len()),
                        "the standard error of this point assumes independent samples; with \
                         correlated CFD samples the polar's sigmas are too small",
                    )
                    .for_run(&rec.name),
                );
            }
            let mut series = [vec![], vec![], vec![]];
            for i in rows.clone() {
                let c = conv.row(rec, i, alpha)?;
                for k in 0..3 {
                    series[k].push(c[k]);
                }
            }
            let speeds: Vec<f64> = rows
                .clone()
                .filter_map(|i| rec.value_at(Quantity::Speed, i))
                .collect();
            let speed = (!speeds.is_empty()).then(|| mean(&speeds));
            let stats = series.map(|s| steady_mean(&s));
            out.push(PolarPoint {
                record: rec.name.clone(),
                line: None,
                alpha,
                alpha_deg: alpha.to_degrees(),
                speed,
                cd: stats[0].0,
                cl: stats[1].0,
                cm: stats[2].0,
                cd_se: stats[0].1,
                cl_se: stats[1].1,
                cm_se: stats[2].1,
                samples: rows.len(),
                used: true,
            });
        } else {
            return Err(input(
                rec,
                "no angle of attack: give an `alpha` column (sweep table) or \
                 `constants = { alpha = \"4 deg\" }` (one steady run per angle)",
            )
            .into());
        }
    }
    if let Some(max) = config.alpha_max_deg {
        let limit = max.to_radians() * (1.0 + 1e-12);
        for p in &mut out {
            p.used = p.alpha.abs() <= limit;
        }
    }
    Ok((out, warnings))
}

fn input(rec: &Record, msg: impl Into<String>) -> InputError {
    InputError::new(
        Place::file(&rec.source),
        format!("polar run '{}': {}", rec.name, msg.into()),
    )
}

struct Converter<'a> {
    config: &'a PolarConfig,
    vehicle: &'a VehicleConfig,
    fluid: &'a FluidConfig,
}

impl Converter<'_> {
    /// Body-axis (C_D, C_L, C_M) of row `i`.
    fn row(&self, rec: &Record, i: usize, alpha: f64) -> Result<[f64; 3]> {
        let get = |q: Quantity| {
            rec.value_at(q, i).ok_or_else(|| {
                let what = match self.config.data {
                    PolarData::Coefficients => "polar.data = \"coefficients\" needs cd, cl and cm",
                    PolarData::Forces => {
                        "polar.data = \"forces\" needs fx, fy, mz and speed (column or constant)"
                    }
                };
                input(rec, format!("no {q} column or constant ({what})"))
            })
        };
        let (sa, ca) = alpha.sin_cos();
        let (x, y, n) = match self.config.data {
            PolarData::Coefficients => {
                (-get(Quantity::Cd)?, get(Quantity::Cl)?, get(Quantity::Cm)?)
            }
            PolarData::Forces => {
                let u = get(Quantity::Speed)?;
                if !(u.is_finite() && u > 0.0) {
                    let line = rec.lines.get(i).copied().unwrap_or(0);
                    return Err(InputError::new(
                        Place::line(&rec.source, line),
                        format!(
                            "polar run '{}': speed {u} m/s cannot make forces dimensionless",
                            rec.name
                        ),
                    )
                    .expected("a positive speed")
                    .into());
                }
                // q_dyn = 0.5 rho U^2 A_ref; moments also divided by L_ref (paper eq. 5-6).
                let qd = 0.5 * self.fluid.rho * u * u * self.vehicle.reference_area;
                (
                    get(Quantity::Fx)? / qd,
                    get(Quantity::Fy)? / qd,
                    get(Quantity::Mz)? / (qd * self.vehicle.reference_length),
                )
            }
        };
        // (x, y) are the force coefficients along the given axes; flow axes are rotated into
        // body axes by alpha: x_b = x_f cos a - y_f sin a, y_b = x_f sin a + y_f cos a.
        let (xb, yb) = match self.config.axes {
            PolarAxes::Body => (x, y),
            PolarAxes::Flow => (x * ca - y * sa, x * sa + y * ca),
        };
        let c = [-xb, yb, n];
        if let Some(k) = c.iter().position(|v| !v.is_finite()) {
            let line = rec.lines.get(i).copied().unwrap_or(0);
            return Err(InputError::new(
                Place::line(&rec.source, line),
                format!(
                    "polar run '{}': non-finite {} coefficient",
                    rec.name,
                    ["drag", "side-force", "moment"][k]
                ),
            )
            .into());
        }
        Ok(c)
    }
}

/// The rows of the last `fraction` of a history: of its time span when it has a time
/// column, else of its rows.
fn steady_window(rec: &Record, fraction: f64) -> std::ops::Range<usize> {
    let n = rec.rows();
    if n == 0 {
        return 0..0;
    }
    match rec.time() {
        Some(t) if n > 1 => {
            let t_end = t[n - 1];
            let start = t_end - fraction * (t_end - t[0]);
            let first = t
                .iter()
                .position(|v| *v >= start - 1e-12 * t_end.abs().max(1.0));
            first.unwrap_or(n - 1)..n
        }
        _ => {
            let k = ((fraction * n as f64).ceil() as usize).clamp(1, n);
            n - k..n
        }
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Mean and its standard error. With enough samples the standard error comes from
/// non-overlapping batch means (Law & Kelton, Simulation Modeling and Analysis, section 9.5),
/// which stays honest when a CFD history is autocorrelated; otherwise s / sqrt(n).
pub fn steady_mean(v: &[f64]) -> (f64, Option<f64>) {
    let n = v.len();
    let m = mean(v);
    if n < 2 {
        return (m, None);
    }
    let sample_se = |x: &[f64]| {
        let k = x.len() as f64;
        let mx = mean(x);
        let var = x.iter().map(|a| (a - mx).powi(2)).sum::<f64>() / (k - 1.0);
        (var / k).sqrt()
    };
    if n < 2 * BATCHES {
        return (m, Some(sample_se(v)));
    }
    let size = n / BATCHES;
    let skip = n - size * BATCHES;
    let batch_means: Vec<f64> = v[skip..].chunks(size).map(mean).collect();
    (m, Some(sample_se(&batch_means)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_means_see_autocorrelation() {
        // A slow oscillation around 1.0: consecutive samples are nearly equal, so s/sqrt(n)
        // would claim a tiny error; batch means see the oscillation.
        let v: Vec<f64> = (0..1000)
            .map(|i| 1.0 + 0.01 * (i as f64 * 0.013).sin())
            .collect();
        let (m, se) = steady_mean(&v);
        let naive = {
            let var = v.iter().map(|a| (a - m).powi(2)).sum::<f64>() / 999.0;
            (var / 1000.0).sqrt()
        };
        let se = se.unwrap();
        assert!(se > 3.0 * naive, "batch {se} vs naive {naive}");
        // The mean of an oscillation is known to within its amplitude over the window.
        assert!((m - 1.0).abs() < 0.01);
    }
}
