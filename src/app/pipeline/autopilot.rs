//! The autopilot step: the PID tuned from the identified model's Nomoto K and T by pole
//! placement, closed around the identified model in waves (the HEKF's process noise, or a
//! recorded disturbance), once per feed asked for (src/dynamics/autopilot/closed_loop.rs).

mod plant;
mod plausible;
mod seas;
mod spec;

use crate::base::error::{Error, Result};
use crate::config::autopilot::AutopilotConfig;
use crate::dynamics::autopilot::closed_loop::{self, Scenario};
use crate::dynamics::autopilot::seas::Seas;
use crate::dynamics::autopilot::PlantIndices;
use crate::dynamics::autopilot::{AutopilotResult, Gains, RudderLimits};
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle};
use crate::stages::hekf::HekfConfig;

pub use plausible::{loop_warnings, MAX_SURGE_ACCELERATION};
pub use seas::{load_seas, MAX_WAVE_YAW_RMS};
pub use spec::{load_plant, PlantSpec};

/// The seas with the yaw inertia a recorded yaw moment accelerates: the configuration's, or
/// the plant's vehicle izz.
fn with_inertia(seas: &Seas, cfg: &AutopilotConfig, izz: f64) -> Seas {
    let mut seas = seas.clone();
    if let Seas::Recorded(r) = &mut seas {
        r.yaw_inertia = Some(cfg.yaw_inertia.unwrap_or(izz));
    }
    seas
}

/// Runs the step for the identified model `name` with the coefficient set `set` in `seas`,
/// on `plant` (None: the identified model).
pub fn run(
    name: ModelName,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    hekf: &HekfConfig,
    cfg: &AutopilotConfig,
    (seas, plant): (&Seas, Option<&PlantSpec>),
) -> Result<AutopilotResult> {
    let step = Step {
        set,
        hekf,
        cfg,
        seas,
        plant,
        izz: vehicle.vehicle.izz,
    };
    with_model(name, vehicle, step).map_err(Error::vehicle)?
}

struct Step<'a> {
    set: &'a CoefficientSet,
    hekf: &'a HekfConfig,
    cfg: &'a AutopilotConfig,
    seas: &'a Seas,
    plant: Option<&'a PlantSpec>,
    izz: f64,
}

impl ModelVisitor for Step<'_> {
    type Output = Result<AutopilotResult>;

    fn visit<M: Model>(self, model: &M) -> Self::Output {
        let fail = |m: String| Error::numerical("autopilot", m);
        let c = crate::dynamics::sim::complete_coefficients(model, self.set)
            .map_err(|missing| fail(format!("no value for {}", missing.join(", "))))?;
        let (k, t) = model
            .nomoto_gains(&c)
            .ok_or_else(|| {
                fail(format!(
                    "the {} model does not give Nomoto's K and T (the autopilot is tuned and \
                     its wave filter run on a Nomoto model such as nomoto_wave; another model \
                     can be the plant: [autopilot.plant])",
                    model.name()
                ))
            })?
            .map_err(|e| fail(format!("the identified {} model: {e}", model.name())))?;
        let a = self.cfg;
        let gains = Gains::pole_placement(k, t, a.omega_n, a.zeta)
            .map_err(|e| fail(format!("the identified K = {k:.4} 1/s, T = {t:.2} s: {e}")))?;
        // the plant's and the filter's process noise: the HEKF's, by state name
        let process_noise: Vec<f64> = model
            .states()
            .iter()
            .map(|s| self.hekf.process_noise.get(s.name).copied().unwrap_or(0.0))
            .collect();
        let izz = self.plant.map_or(self.izz, |p| p.vehicle.vehicle.izz);
        let seas = with_inertia(self.seas, a, izz);
        let scenario = scenario(a, gains, process_noise, &seas);
        let (mut feeds, plant) = match self.plant {
            None => {
                let feeds = a
                    .feeds
                    .iter()
                    .map(|f| {
                        closed_loop::run(model, &c, &scenario, *f).map_err(|e| fail(e.to_string()))
                    })
                    .collect::<Result<Vec<_>>>()?;
                (feeds, PlantIndices::identified(model.name(), k, t))
            }
            Some(spec) => {
                let visit = plant::PlantVisit {
                    model,
                    c: &c,
                    scenario: &scenario,
                    feeds: &a.feeds,
                    spec,
                };
                with_model(spec.name, &spec.vehicle, visit)
                    .map_err(|problems| plant::vehicle_error(spec, problems))??
            }
        };
        for l in &mut feeds {
            // written by the report (app/report/autopilot_series.rs)
            let dir = crate::dynamics::autopilot::series::DIR;
            l.series_file = Some(format!("{dir}/{}.csv", l.feed.name()));
        }
        Ok(AutopilotResult {
            k,
            t,
            gains,
            feeds,
            plant,
        })
    }
}

/// The closed-loop scenario of `a` with the `gains` placed, the identified model's
/// `process_noise` and the `seas`.
fn scenario(a: &AutopilotConfig, gains: Gains, process_noise: Vec<f64>, seas: &Seas) -> Scenario {
    Scenario {
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
        seas: seas.clone(),
        orders: a.orders.iter().map(|o| (o.at, o.course)).collect(),
        adaptive: a.adaptive.settings(),
        lowpass_cutoff: a.lowpass_cutoff,
    }
}
