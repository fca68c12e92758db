//! The captive runs' forces as a coefficient set predicts them, row by row, for a
//! parametric bootstrap (`hydroid calibrate`): each row's prescribed motion (with the
//! accelerations of a harmonic run) through the model's captive force function.

use super::{check_columns, motion_columns, run_error, CaptiveConfig, Frame, Table};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::dynamics::sim::integrate::complete_coefficients;
use crate::io::record::Record;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelVisitor, RunVehicle};

/// Each force the model gives (its column) with the model's value at every row of a run.
pub type RunForces = Vec<(Quantity, Vec<f64>)>;

/// Per run, each force the model gives (its column) with the model's value at every row of
/// the run, for the coefficients of `set`. A run that gives a force by its prime column or
/// as a constant is refused, naming the run.
pub fn predicted(
    cfg: &CaptiveConfig,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    runs: &[Record],
) -> Result<Vec<RunForces>> {
    let rho = vehicle.vehicle.rho;
    with_model(
        cfg.model,
        vehicle,
        Predict {
            cfg,
            set,
            runs,
            rho,
        },
    )
    .map_err(Error::vehicle)?
}

struct Predict<'a> {
    cfg: &'a CaptiveConfig,
    set: &'a CoefficientSet,
    runs: &'a [Record],
    rho: f64,
}

impl ModelVisitor for Predict<'_> {
    type Output = Result<Vec<RunForces>>;

    fn visit<M: Model>(self, model: &M) -> Self::Output {
        let c = complete_coefficients(model, self.set).map_err(|missing| {
            Error::numerical(super::STAGE, format!("no value for {}", missing.join(", ")))
        })?;
        let frame = Frame {
            prime: self.cfg.prime,
            rho: self.rho,
        };
        self.runs
            .iter()
            .map(|rec| run_forces(model, &c, rec, &frame, self.cfg))
            .collect()
    }
}

/// The model's forces at every row of one run.
fn run_forces<M: Model>(
    model: &M,
    c: &[f64],
    rec: &Record,
    frame: &Frame,
    cfg: &CaptiveConfig,
) -> Result<RunForces> {
    let forces = model.force_quantities();
    if let Some(q) = forces.iter().find(|q| rec.channel(**q).is_none()) {
        return Err(run_error(
            rec,
            format!(
                "gives {q} as a prime column or a constant: calibrate makes replicas of SI \
                 force columns only"
            ),
        ));
    }
    check_columns(model, rec, frame)?;
    let oscillation = cfg.oscillations.get(&rec.name);
    let table = Table {
        rec,
        frame,
        oscillation,
        by_drift: motion_columns(rec, oscillation)?,
    };
    let mut out: Vec<(Quantity, Vec<f64>)> = forces
        .iter()
        .map(|q| (*q, Vec::with_capacity(rec.rows())))
        .collect();
    let mut f = vec![0.0; forces.len()];
    for k in 0..rec.rows() {
        let row = table.condition(model, k)?;
        let x_dot = table.rates(model, k);
        model.captive_forces(&row.x, &x_dot, &row.u, c, &mut f);
        for (column, fk) in out.iter_mut().zip(&f) {
            column.1.push(*fk);
        }
    }
    Ok(out)
}

impl Table<'_> {
    /// The state's rate at row `k`: the derivative of each prescribed oscillation,
    /// d/dt (A sin(2 pi f t + phase)) = 2 pi f A cos(2 pi f t + phase); zero for a held
    /// motion (a steady condition).
    fn rates<M: Model>(&self, model: &M, k: usize) -> Vec<f64> {
        let t = self.rec.time().map(|t| t[k]);
        model
            .states()
            .iter()
            .map(|s| match (self.oscillation, t) {
                (Some(o), Some(t)) => o.amplitude.get(&s.quantity).map_or(0.0, |a| {
                    let w = 2.0 * std::f64::consts::PI * o.frequency;
                    a.si * w * (w * t + o.phase).cos()
                }),
                _ => 0.0,
            })
            .collect()
    }
}
