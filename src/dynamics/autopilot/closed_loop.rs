//! The autopilot closed around a ship in waves (the paper's experiment: Dinh, Hoang & Pham
//! 2016, ../shared/docs/nomoto-wave-ekf.md): the plant is an identified model with its
//! process noise (the waves), its compass is read with noise, and the PID is fed either the
//! raw compass (with its difference as the yaw rate) or the low-frequency heading and yaw
//! rate of a wave filter, the hybrid EKF on the same model run online.

use super::{Autopilot, Gains, ReferenceModel, RudderLimits};
use crate::base::quantity::Quantity;
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::{simulate, InputSeries};
use crate::model::models::Model;
use crate::numerics::estimation::hybrid_ekf::HybridEkf;
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};
use serde::Serialize;

/// What the autopilot is fed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Feed {
    /// The raw compass and a raw yaw-rate gyro (the model's compass and gyro outputs, which
    /// see the wave-induced yaw).
    Compass,
    /// The wave filter's low-frequency heading psi_L and yaw rate r_L.
    Filtered,
}

/// The scenario: a course change under the reference model, in waves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scenario {
    /// Duration, s.
    pub duration: f64,
    /// Sampling interval of the compass and the autopilot, s.
    pub dt: f64,
    /// The commanded course change, rad, ordered at `change_at`.
    pub course_change: f64,
    /// When the course change is ordered, s.
    pub change_at: f64,
    /// The controller's gains.
    pub gains: Gains,
    /// The reference model's natural frequency (rad/s) and damping.
    pub reference: (f64, f64),
    /// The steering gear.
    pub limits: RudderLimits,
    /// Compass noise standard deviation, rad.
    pub compass_noise: f64,
    /// Yaw-rate gyro noise standard deviation, rad/s (the raw feed's rate).
    pub gyro_noise: f64,
    /// Process noise of the plant per state (variance per second), and of the filter.
    pub process_noise: Vec<f64>,
    /// Seed of the waves and the compass noise (the same for both feeds).
    pub seed: u64,
    /// The wave filter's process noise on the low-frequency yaw rate (unmodelled yaw
    /// moments: wind, current, a model error), rad^2/s^3; the paper's w_L.
    pub rate_noise: f64,
}

/// One closed-loop run's histories and statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosedLoop {
    /// What the autopilot was fed.
    pub feed: Feed,
    /// RMS of the low-frequency heading error psi_L - psi_d, rad.
    pub heading_error_rms: f64,
    /// RMS rudder angle, rad.
    pub rudder_rms: f64,
    /// RMS rudder rate, rad/s.
    pub rudder_rate_rms: f64,
    /// Times, s.
    #[serde(skip)]
    pub times: Vec<f64>,
    /// psi_L - psi_d per sample, rad.
    #[serde(skip)]
    pub heading_error: Vec<f64>,
    /// Rudder angle per sample, rad.
    #[serde(skip)]
    pub rudder: Vec<f64>,
    /// The compass per sample, rad.
    #[serde(skip)]
    pub compass: Vec<f64>,
    /// What the autopilot saw as the heading, rad.
    #[serde(skip)]
    pub seen: Vec<f64>,
}

impl ClosedLoop {
    /// No samples yet, room for `n`.
    fn empty(feed: Feed, n: usize) -> Self {
        ClosedLoop {
            feed,
            heading_error_rms: 0.0,
            rudder_rms: 0.0,
            rudder_rate_rms: 0.0,
            times: Vec::with_capacity(n),
            heading_error: Vec::with_capacity(n),
            rudder: Vec::with_capacity(n),
            compass: Vec::with_capacity(n),
            seen: Vec::with_capacity(n),
        }
    }
}

/// Why the closed loop cannot run, or stopped.
#[derive(Debug, thiserror::Error)]
pub enum LoopError {
    /// The model lacks a state or an output the loop reads (`heading state`, ...).
    #[error("the model has no {0}")]
    Missing(&'static str),
    /// The model has an input other than the rudder.
    #[error("the closed loop drives models whose only input is the rudder")]
    NotRudderOnly,
    /// A noise's standard deviation is unusable.
    #[error("{0}")]
    Noise(rand_distr::NormalError),
    /// The plant's simulation stopped.
    #[error("{0}")]
    Simulation(crate::dynamics::sim::SimError),
    /// The wave filter diverged (the filter's reason).
    #[error("the wave filter diverged: {0}")]
    FilterDiverged(String),
}

/// Runs the scenario on `model` with coefficients `c`, feeding the autopilot `feed`. The
/// wave filter (for [`Feed::Filtered`]) is the hybrid EKF on the same model and
/// coefficients, with the scenario's process noise and compass noise.
pub fn run<M: Model>(
    model: &M,
    c: &[f64],
    s: &Scenario,
    feed: Feed,
) -> Result<ClosedLoop, LoopError> {
    let nx = model.nx();
    let Channels {
        psi_i,
        r_i,
        compass_i,
        gyro_i,
    } = channels(model)?;
    let n = (s.duration / s.dt).round() as usize + 1;
    let mut rng = StdRng::seed_from_u64(s.seed);
    let noise = Normal::new(0.0, s.compass_noise.max(0.0)).map_err(LoopError::Noise)?;
    let gyro_noise = Normal::new(0.0, s.gyro_noise.max(0.0)).map_err(LoopError::Noise)?;
    let mut x = vec![0.0; nx];
    let mut ap = Autopilot::new(s.gains, s.limits);
    let mut reference = ReferenceModel::new(s.reference.0, s.reference.1, 0.0);
    // the wave filter: the model's states only (no coefficient estimated)
    let measured = [compass_i];
    let mut ekf = wave_filter(nx, r_i, s);
    let r_var = [s.compass_noise.powi(2).max(1e-12)];
    let mut out = ClosedLoop::empty(feed, n);
    let mut delta = 0.0;
    for k in 0..n {
        let t = k as f64 * s.dt;
        if k > 0 {
            plant_step(model, c, &mut x, delta, t, s, &mut rng)?;
        }
        let y = model.output_values(&x, &[delta], c);
        let compass = y[compass_i] + noise.sample(&mut rng);
        // what the autopilot sees
        let (heading, rate) = match feed {
            Feed::Compass => {
                let gyro = y[gyro_i] + gyro_noise.sample(&mut rng);
                (compass, gyro)
            }
            Feed::Filtered => {
                let inputs = InputSeries::constant(&[delta]);
                let mut sys = ModelSystem::new(model, c.to_vec(), &[], &[], &inputs, &measured);
                if k > 0 {
                    ekf.predict(&mut sys, t - s.dt, t, None)
                        .map_err(|d| LoopError::FilterDiverged(d.reason))?;
                } else {
                    ekf.x[psi_i] = compass;
                }
                ekf.update(&mut sys, t, &[compass], &r_var)
                    .map_err(|d| LoopError::FilterDiverged(d.reason))?;
                (ekf.x[psi_i], ekf.x[r_i])
            }
        };
        let commanded = if t >= s.change_at {
            s.course_change
        } else {
            0.0
        };
        if k > 0 {
            reference.step(commanded, s.dt);
        }
        out.times.push(t);
        out.heading_error.push(x[psi_i] - reference.heading);
        out.rudder.push(delta);
        out.compass.push(compass);
        out.seen.push(heading);
        delta = ap.step(heading - reference.heading, rate - reference.rate, s.dt);
    }
    summarize(&mut out, s.dt);
    Ok(out)
}

/// Where the closed loop reads the model: its heading and yaw-rate states, its compass and
/// yaw-rate outputs.
struct Channels {
    psi_i: usize,
    r_i: usize,
    compass_i: usize,
    gyro_i: usize,
}

/// The model's heading and yaw-rate states and outputs; refuses a model without them or with
/// an input other than the rudder.
fn channels<M: Model>(model: &M) -> Result<Channels, LoopError> {
    let psi_i = model
        .state_index(Quantity::Yaw)
        .ok_or(LoopError::Missing("heading state"))?;
    let r_i = model
        .state_index(Quantity::R)
        .ok_or(LoopError::Missing("yaw-rate state"))?;
    let compass_i = model
        .output_index(Quantity::Yaw)
        .ok_or(LoopError::Missing("compass output"))?;
    let gyro_i = model
        .output_index(Quantity::R)
        .ok_or(LoopError::Missing("yaw-rate output"))?;
    if model.input_quantities() != [Quantity::Rudder] {
        return Err(LoopError::NotRudderOnly);
    }
    Ok(Channels {
        psi_i,
        r_i,
        compass_i,
        gyro_i,
    })
}

/// The wave filter: the hybrid EKF on the model's states only (no coefficient estimated),
/// unit initial variances, the plant's process noise and on every other state a small one.
fn wave_filter(nx: usize, r_i: usize, s: &Scenario) -> HybridEkf {
    HybridEkf::new(
        nx,
        nx,
        vec![0.0; nx],
        {
            let mut p0 = vec![0.0; nx * nx];
            for i in 0..nx {
                p0[i * nx + i] = 1.0;
            }
            p0
        },
        // the plant's process noise, and on every other state a small one (1e-9 SI^2/s) so
        // that no state's covariance collapses to zero and the filter keeps listening
        s.process_noise
            .iter()
            .enumerate()
            .map(|(i, q)| q.max(if i == r_i { s.rate_noise } else { 1e-9 }))
            .collect(),
        s.dt,
    )
}

/// The plant over the interval ending at `t` with the rudder held at `delta`, then its
/// process noise (Euler-Maruyama, as hydroid simulate forces a state).
fn plant_step<M: Model>(
    model: &M,
    c: &[f64],
    x: &mut [f64],
    delta: f64,
    t: f64,
    s: &Scenario,
    rng: &mut StdRng,
) -> Result<(), LoopError> {
    let held = InputSeries::constant(&[delta]);
    let xs = simulate(model, c, x, &held, &[t - s.dt, t], 4).map_err(LoopError::Simulation)?;
    x.copy_from_slice(&xs[1]);
    for (i, q) in s.process_noise.iter().enumerate() {
        if *q > 0.0 {
            x[i] += Normal::new(0.0, (q * s.dt).sqrt())
                .map_err(LoopError::Noise)?
                .sample(rng);
        }
    }
    Ok(())
}

/// The RMS heading error, rudder angle and rudder rate of the recorded loop.
fn summarize(out: &mut ClosedLoop, dt: f64) {
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    out.heading_error_rms = rms(&out.heading_error);
    out.rudder_rms = rms(&out.rudder);
    let rates: Vec<f64> = out.rudder.windows(2).map(|w| (w[1] - w[0]) / dt).collect();
    out.rudder_rate_rms = rms(&rates);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::nomoto_wave::{NomotoWave, FRIGATE_9MS};

    /// The paper's result on the frigate in 8 s waves (1 deg wave yaw, compass noise 0.1 deg):
    /// fed the filtered heading, the autopilot moves the rudder far less for the same
    /// heading-keeping.
    #[test]
    fn the_filtered_heading_calms_the_rudder_without_losing_the_heading() {
        let m = NomotoWave::build(&NomotoWave::example_vehicle()).unwrap();
        let c = m.coefficient_vector(FRIGATE_9MS);
        let s = Scenario {
            duration: 600.0,
            dt: 0.1,
            course_change: 10f64.to_radians(),
            change_at: 50.0,
            gains: Gains::pole_placement(0.18, 27.0, 0.05, 0.9).unwrap(),
            reference: (0.05, 1.0),
            limits: RudderLimits {
                angle: 35f64.to_radians(),
                rate: 2.32f64.to_radians(),
            },
            compass_noise: 0.1f64.to_radians(),
            gyro_noise: 0.01f64.to_radians(),
            process_noise: vec![0.0, 0.0, 0.0, 9.6e-5],
            seed: 7,
            rate_noise: 1e-7,
        };

        let raw = run(&m, &c, &s, Feed::Compass).unwrap();
        let filtered = run(&m, &c, &s, Feed::Filtered).unwrap();
        let deg = f64::to_degrees;
        println!(
            "raw: heading error {:.3} deg, rudder {:.3} deg, rudder rate {:.3} deg/s",
            deg(raw.heading_error_rms),
            deg(raw.rudder_rms),
            deg(raw.rudder_rate_rms)
        );
        println!(
            "filtered: heading error {:.3} deg, rudder {:.3} deg, rudder rate {:.3} deg/s",
            deg(filtered.heading_error_rms),
            deg(filtered.rudder_rms),
            deg(filtered.rudder_rate_rms)
        );
        assert!(filtered.rudder_rate_rms <= 0.5 * raw.rudder_rate_rms);
        // no worse than 20 % in heading keeping
        assert!(
            filtered.heading_error_rms <= 1.2 * raw.heading_error_rms,
            "heading error {} against {}",
            filtered.heading_error_rms,
            raw.heading_error_rms
        );
    }
}
