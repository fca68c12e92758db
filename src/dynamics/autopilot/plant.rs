//! The plant the autopilot steers, apart from the model its wave filter and its tuning use:
//! any model with a rudder input (mmg3, ship_linear, nomoto_wave ...), its other inputs (the
//! propeller) held at the values of its approach, optionally changed once mid-run (a ship
//! that slows down: new coefficients, held inputs and surge speed from a given time on). Its
//! own Nomoto indices come from the course-stability linearisation (Fossen 2011, 7.2;
//! [`crate::dynamics::course_stability`]), or from its coefficients for a Nomoto model.

use super::closed_loop::{Channels, LoopError};
use crate::base::quantity::Quantity;
use crate::dynamics::course_stability::{sway_yaw, Nomoto, NotSteerable};
use crate::dynamics::sim::{simulate, InputSeries};
use crate::model::models::Model;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// A change of the plant mid-run.
#[derive(Debug, Clone, PartialEq)]
pub struct Change {
    /// When it happens, s.
    pub at: f64,
    /// The plant's coefficients from then on (the model's full vector, SI).
    pub coefficients: Vec<f64>,
    /// Its held inputs from then on (the rudder's entry is not read).
    pub inputs: Vec<f64>,
    /// The surge speed set at the change, m/s (None: the state goes on as it is).
    pub speed: Option<f64>,
}

/// How the plant starts and what it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup {
    /// Coefficients (the model's full vector, SI).
    pub coefficients: Vec<f64>,
    /// Held inputs, one per model input (the rudder's entry is not read).
    pub inputs: Vec<f64>,
    /// Initial state.
    pub x0: Vec<f64>,
    /// Process noise per state (variance per second): the plant's own waves. Empty: none.
    pub process_noise: Vec<f64>,
    /// A change mid-run.
    pub change: Option<Change>,
}

/// What the closed loop needs of a plant.
pub trait Plant {
    /// Back to its initial state and coefficients (each feed's run starts the same).
    fn reset(&mut self);
    /// Advances over the interval ending at `t` with the rudder held at `delta` (any
    /// rudder-equivalent disturbance included), then adds its process noise drawn from `rng`
    /// when there is one.
    fn step(
        &mut self,
        delta: f64,
        t: f64,
        dt: f64,
        rng: Option<&mut StdRng>,
    ) -> Result<(), LoopError>;
    /// Its true low-frequency heading (rad) and yaw rate (rad/s).
    fn heading(&self) -> (f64, f64);
    /// What its compass and yaw-rate gyro read before their noise (its own wave-induced yaw
    /// included, if it has one) with the rudder at `delta`.
    fn sensors(&self, delta: f64) -> (f64, f64);
    /// Its Nomoto indices now (its present coefficients, linearised about straight motion at
    /// its present speed).
    fn nomoto(&self) -> Result<Nomoto, NotSteerable>;
    /// When it changes mid-run, s.
    fn change_at(&self) -> Option<f64>;
    /// Its yaw acceleration per rudder angle now, d r_dot / d delta (1/s^2), by a central
    /// difference of 0.1 deg about the rudder amidships: how a yaw moment becomes a
    /// rudder-equivalent angle.
    fn yaw_per_rudder(&self) -> f64;
}

/// A registered model as the plant.
pub struct ModelPlant<'a, P: Model> {
    model: &'a P,
    setup: Setup,
    x: Vec<f64>,
    c: Vec<f64>,
    u: Vec<f64>,
    changed: bool,
    rudder_i: usize,
    psi_i: usize,
    r_i: usize,
    compass_i: usize,
    gyro_i: usize,
}

impl<'a, P: Model> ModelPlant<'a, P> {
    /// The plant `model` set up as `setup`; refuses a model without a rudder input, heading
    /// and yaw-rate states, compass and yaw-rate outputs, or a setup of the wrong sizes.
    pub fn new(model: &'a P, setup: Setup) -> Result<Self, LoopError> {
        let missing = LoopError::Missing;
        let rudder_i = model
            .input_quantities()
            .iter()
            .position(|q| *q == Quantity::Rudder)
            .ok_or(missing("rudder input"))?;
        let Channels {
            psi_i,
            r_i,
            compass_i,
        } = Channels::of(model)?;
        let gyro_i = model
            .output_index(Quantity::R)
            .ok_or(missing("yaw-rate output"))?;
        let (nc, nu, nx) = (
            model.coefficient_names().len(),
            model.inputs().len(),
            model.nx(),
        );
        let sizes_ok = |c: &[f64], u: &[f64]| c.len() == nc && u.len() == nu;
        let change_ok = setup
            .change
            .as_ref()
            .is_none_or(|ch| sizes_ok(&ch.coefficients, &ch.inputs));
        let noise_ok = setup.process_noise.is_empty() || setup.process_noise.len() == nx;
        if !(sizes_ok(&setup.coefficients, &setup.inputs)
            && setup.x0.len() == nx
            && change_ok
            && noise_ok)
        {
            return Err(LoopError::Missing(
                "plant setup of its sizes (coefficients, inputs, states)",
            ));
        }
        let mut plant = ModelPlant {
            model,
            x: Vec::new(),
            c: Vec::new(),
            u: Vec::new(),
            changed: false,
            setup,
            rudder_i,
            psi_i,
            r_i,
            compass_i,
            gyro_i,
        };
        plant.reset();
        Ok(plant)
    }

    /// The inputs with the rudder at `delta`.
    fn inputs(&self, delta: f64) -> Vec<f64> {
        let mut u = self.u.clone();
        u[self.rudder_i] = delta;
        u
    }
}

impl<P: Model> Plant for ModelPlant<'_, P> {
    fn reset(&mut self) {
        self.x = self.setup.x0.clone();
        self.c = self.setup.coefficients.clone();
        self.u = self.setup.inputs.clone();
        self.changed = false;
    }

    fn step(
        &mut self,
        delta: f64,
        t: f64,
        dt: f64,
        rng: Option<&mut StdRng>,
    ) -> Result<(), LoopError> {
        if let Some(ch) = self.setup.change.as_ref().filter(|ch| t - dt >= ch.at) {
            if !self.changed {
                self.c = ch.coefficients.clone();
                self.u = ch.inputs.clone();
                if let (Some(speed), Some(iu)) = (ch.speed, self.model.state_index(Quantity::U)) {
                    self.x[iu] = speed;
                }
                self.changed = true;
            }
        }
        let held = InputSeries::constant(&self.inputs(delta));
        let xs = simulate(self.model, &self.c, &self.x, &held, &[t - dt, t], 4)
            .map_err(LoopError::Simulation)?;
        self.x.copy_from_slice(&xs[1]);
        let Some(rng) = rng else { return Ok(()) };
        // Euler-Maruyama, as hydroid simulate forces a state
        for (i, q) in self.setup.process_noise.iter().enumerate() {
            if *q > 0.0 {
                self.x[i] += Normal::new(0.0, (q * dt).sqrt())
                    .map_err(LoopError::Noise)?
                    .sample(rng);
            }
        }
        Ok(())
    }

    fn heading(&self) -> (f64, f64) {
        (self.x[self.psi_i], self.x[self.r_i])
    }

    fn sensors(&self, delta: f64) -> (f64, f64) {
        let y = self
            .model
            .output_values(&self.x, &self.inputs(delta), &self.c);
        (y[self.compass_i], y[self.gyro_i])
    }

    fn nomoto(&self) -> Result<Nomoto, NotSteerable> {
        nomoto_of(self.model, &self.c, &self.x, &self.u)
    }

    fn change_at(&self) -> Option<f64> {
        self.setup.change.as_ref().map(|c| c.at)
    }

    fn yaw_per_rudder(&self) -> f64 {
        yaw_per_rudder_at(self.model, &self.c, &self.x, &self.u).unwrap_or(0.0)
    }
}

/// The yaw acceleration per rudder angle d r_dot / d delta (1/s^2) of `model` with
/// coefficients `c` at the state `x` with the inputs `u` (their rudder replaced), by a
/// central difference of 0.1 deg about amidships: positive when a positive rudder turns the
/// ship to a positive yaw rate, as the autopilot's tuning assumes (K / T of a Nomoto model).
/// None without a rudder input or a yaw-rate state.
pub fn yaw_per_rudder_at<P: Model>(model: &P, c: &[f64], x: &[f64], u: &[f64]) -> Option<f64> {
    let rudder_i = model
        .input_quantities()
        .iter()
        .position(|q| *q == Quantity::Rudder)?;
    let r_i = model.state_index(Quantity::R)?;
    let h = 0.1f64.to_radians();
    let f = |delta: f64| {
        let mut inputs = u.to_vec();
        inputs[rudder_i] = delta;
        let mut dx = vec![0.0; x.len()];
        model.derivatives(x, &inputs, c, &mut dx);
        dx[r_i]
    };
    Some((f(h) - f(-h)) / (2.0 * h))
}

/// The surge acceleration u_dot (m/s^2) of `model` with `c` at the state `x` with the held
/// inputs `u` and the rudder amidships: how far the held inputs are from balancing its speed.
/// None without a surge state.
pub fn surge_acceleration<P: Model>(model: &P, c: &[f64], x: &[f64], u: &[f64]) -> Option<f64> {
    let iu = model.state_index(Quantity::U)?;
    let mut inputs = u.to_vec();
    if let Some(i) = model
        .input_quantities()
        .iter()
        .position(|q| *q == Quantity::Rudder)
    {
        inputs[i] = 0.0;
    }
    let mut dx = vec![0.0; x.len()];
    model.derivatives(x, &inputs, c, &mut dx);
    Some(dx[iu])
}

/// Nomoto's indices of `model` with `c` about straight motion at the state `x` with the
/// inputs `u`: a Nomoto model's own K and T, or the sway-yaw linearisation's (Fossen 2011,
/// 7.2).
pub fn nomoto_of<P: Model>(
    model: &P,
    c: &[f64],
    x: &[f64],
    u: &[f64],
) -> Result<Nomoto, NotSteerable> {
    if let Some(gains) = model.nomoto_gains(c) {
        let (k, t) = gains.map_err(NotSteerable)?;
        return Ok(Nomoto {
            speed: None,
            k,
            t,
            t1: Some(t),
            t2: None,
            t3: 0.0,
            course_stable: t > 0.0,
        });
    }
    sway_yaw(model, c, x, u)?.nomoto()
}

/// The wave-induced yaw of the identified model run on its own (rudder amidships, its process
/// noise on every state but the heading and the yaw rate): its compass less its heading and
/// its gyro less its yaw rate (Fossen 2011, 8.2.1: compass = psi_L + psi_H). The generated
/// seas of a plant that has no wave states of its own.
pub(super) struct WaveGenerator<'a, M: Model> {
    pub(super) plant: ModelPlant<'a, M>,
}

impl<'a, M: Model> WaveGenerator<'a, M> {
    /// The generator on `model` with coefficients `c` and the process noise `q` per state
    /// (its heading and yaw-rate entries are not used).
    pub(super) fn new(model: &'a M, c: &[f64], q: &[f64]) -> Result<Self, LoopError> {
        let psi_i = model.state_index(Quantity::Yaw);
        let r_i = model.state_index(Quantity::R);
        let process_noise = (0..model.nx())
            .map(|i| {
                let own = Some(i) == psi_i || Some(i) == r_i;
                if own {
                    0.0
                } else {
                    q.get(i).copied().unwrap_or(0.0)
                }
            })
            .collect();
        let setup = Setup {
            coefficients: c.to_vec(),
            inputs: vec![0.0; model.inputs().len()],
            x0: vec![0.0; model.nx()],
            process_noise,
            change: None,
        };
        Ok(WaveGenerator {
            plant: ModelPlant::new(model, setup)?,
        })
    }

    /// The wave yaw and its rate now.
    pub(super) fn wave(&self) -> (f64, f64) {
        let (compass, gyro) = self.plant.sensors(0.0);
        let (psi, r) = self.plant.heading();
        (compass - psi, gyro - r)
    }
}
