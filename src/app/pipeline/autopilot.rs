//! The autopilot step: the PID tuned from the identified model's Nomoto K and T by pole
//! placement, closed around the identified model in waves (the HEKF's process noise, or a
//! recorded disturbance), once per feed asked for (src/dynamics/autopilot/closed_loop.rs).

use crate::base::error::{Error, InputError, Place, Result};
use crate::config::autopilot::{AngleUnit, AutopilotConfig};
use crate::dynamics::autopilot::closed_loop::{self, Scenario};
use crate::dynamics::autopilot::seas::{Recording, Seas};
use crate::dynamics::autopilot::{AutopilotResult, Gains, RudderLimits};
use crate::io::formats::{self, FormatChoice, ReadOptions};
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle};
use crate::stages::hekf::HekfConfig;
use std::path::Path;

/// The seas `cfg` asks for: the generator, or its disturbance file (relative to `base`) read
/// with the table readers, in SI, refused when it does not cover the closed loop's duration.
pub fn load_seas(cfg: &AutopilotConfig, base: &Path) -> Result<Seas> {
    let Some(file) = &cfg.disturbance_file else {
        return Ok(Seas::Generated);
    };
    let path = base.join(file);
    let table = formats::read(&path, FormatChoice::Auto, &ReadOptions::default())?;
    let place = Place::file(&path);
    let expected = "two columns: time (s) and the disturbance (autopilot.disturbance, in \
                    autopilot.disturbance_unit unless the header states a unit), covering the \
                    closed loop's duration";
    let bad = |m: String| Error::from(InputError::new(place.clone(), m).expected(expected));
    if table.columns.len() != 2 {
        return Err(bad(format!("{} columns", table.columns.len())));
    }
    let t_i = table.time.unwrap_or(0);
    let value = &table.columns[1 - t_i];
    // degrees accepted and converted here, at the edge
    let scale = match (value.unit.is_some(), cfg.disturbance_unit) {
        (false, AngleUnit::Deg) => std::f64::consts::PI / 180.0,
        _ => 1.0,
    };
    let values = value.values.iter().map(|v| v * scale).collect();
    let recording = Recording::new(cfg.disturbance, table.columns[t_i].values.clone(), values)
        .map_err(|e| bad(e.to_string()))?;
    recording
        .covers(cfg.duration)
        .map_err(|e| bad(e.to_string()))?;
    Ok(Seas::Recorded(recording))
}

/// Runs the step for the identified model `name` with the coefficient set `set` in `seas`.
pub fn run(
    name: ModelName,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    hekf: &HekfConfig,
    cfg: &AutopilotConfig,
    seas: &Seas,
) -> Result<AutopilotResult> {
    let step = Step {
        set,
        hekf,
        cfg,
        seas,
    };
    with_model(name, vehicle, step).map_err(Error::vehicle)?
}

struct Step<'a> {
    set: &'a CoefficientSet,
    hekf: &'a HekfConfig,
    cfg: &'a AutopilotConfig,
    seas: &'a Seas,
}

impl ModelVisitor for Step<'_> {
    type Output = Result<AutopilotResult>;

    fn visit<M: Model>(self, model: &M) -> Self::Output {
        let fail = |m: String| Error::numerical("autopilot", m);
        let c = crate::dynamics::sim::complete_coefficients(model, self.set)
            .map_err(|missing| fail(format!("no value for {}", missing.join(", "))))?;
        let (k, t) = model.nomoto_gains(&c).ok_or_else(|| {
            fail(format!(
                "the {} model does not give Nomoto's K and T (the autopilot is tuned and \
                 closed around a Nomoto model such as nomoto_wave)",
                model.name()
            ))
        })?;
        let a = self.cfg;
        let gains = Gains::pole_placement(k, t, a.omega_n, a.zeta)
            .map_err(|e| fail(format!("the identified K = {k:.4} 1/s, T = {t:.2} s: {e}")))?;
        // the plant's and the filter's process noise: the HEKF's, by state name
        let process_noise: Vec<f64> = model
            .states()
            .iter()
            .map(|s| self.hekf.process_noise.get(s.name).copied().unwrap_or(0.0))
            .collect();
        let scenario = Scenario {
            duration: a.duration,
            dt: a.dt,
            course_change: a.course_change,
            change_at: a.change_at,
            gains,
            reference: (a.reference_omega, a.reference_zeta),
            limits: RudderLimits {
                angle: a.rudder_limit,
                rate: a.rudder_rate,
                lag: a.rudder_lag,
            },
            compass_noise: a.compass_noise,
            gyro_noise: a.gyro_noise,
            process_noise,
            seed: a.seed,
            rate_noise: a.rate_noise,
            seas: self.seas.clone(),
        };
        let feeds = a
            .feeds
            .iter()
            .map(|f| closed_loop::run(model, &c, &scenario, *f).map_err(|e| fail(e.to_string())))
            .collect::<Result<Vec<_>>>()?;
        Ok(AutopilotResult { k, t, gains, feeds })
    }
}
