//! The autopilot step: the PID tuned from the identified model's Nomoto K and T by pole
//! placement, closed around the identified model in waves (the HEKF's process noise), once
//! fed the raw compass and gyro and once the wave filter (src/dynamics/autopilot/closed_loop.rs).

use crate::base::error::{Error, Result};
use crate::config::autopilot::AutopilotConfig;
use crate::dynamics::autopilot::closed_loop::{self, Feed, Scenario};
use crate::dynamics::autopilot::{AutopilotResult, Gains, RudderLimits};
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle};
use crate::stages::hekf::HekfConfig;

/// Runs the step for the identified model `name` with the coefficient set `set`.
pub fn run(
    name: ModelName,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    hekf: &HekfConfig,
    cfg: &AutopilotConfig,
) -> Result<AutopilotResult> {
    with_model(name, vehicle, Step { set, hekf, cfg }).map_err(Error::vehicle)?
}

struct Step<'a> {
    set: &'a CoefficientSet,
    hekf: &'a HekfConfig,
    cfg: &'a AutopilotConfig,
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
            },
            compass_noise: a.compass_noise,
            gyro_noise: a.gyro_noise,
            process_noise,
            seed: a.seed,
            rate_noise: a.rate_noise,
        };
        let raw = closed_loop::run(model, &c, &scenario, Feed::Compass)
            .map_err(|e| fail(e.to_string()))?;
        let filtered = closed_loop::run(model, &c, &scenario, Feed::Filtered)
            .map_err(|e| fail(e.to_string()))?;
        Ok(AutopilotResult {
            k,
            t,
            gains,
            raw,
            filtered,
        })
    }
}
