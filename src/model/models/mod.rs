//! Vehicle models: one type per model implementing [`Model`], listed once in [`registry`];
//! filters, simulators and reports are generic over it.
//!
//! A model builds itself from the vehicle data ([`Vehicle`]) and validates it, declares its
//! states, outputs, inputs and coefficients ([`coefficient_table!`](crate::coefficient_table)
//! generates the index constants from the table) and gives the continuous dynamics
//! x_dot = f(x, u, c) and the measurement function y = h(x, u, c) once, generic over the scalar
//! type, so that the same code simulates (f64) and yields exact Jacobians (dual numbers, see
//! [`crate::numerics::ad`]).
//!
//! This module imports nothing from the stages, the simulator, the report or the pipeline.

pub mod coefficient;
pub mod registry;
pub mod rigid_body;
pub mod sname;
pub mod vehicle;

use crate::base::quantity::Quantity;
use crate::model::coefficients::{CompiledRelations, Relation, YawMoment};
use crate::numerics::ad::Scalar;

pub use coefficient::{AddedMass, AddedMassTerm, CoefDef, Range, Scales, Size};
pub use registry::ModelVisitor;
pub use vehicle::{BuildFrom, RunVehicle, Vehicle, VehicleProblem};

// Every model hydroid has: `Variant => module::Type`, one line per model (the module is the
// model's file in this folder).
registry::registry! {
    /// Horizontal-plane spheroid (Rasekh & Mahdi 2020, eq. 2): u, v, r, x, y, psi.
    Spheroid3 => spheroid3::Spheroid3,
    /// Axisymmetric 6-DOF spheroid: heave and pitch mirror sway and yaw.
    Spheroid6 => spheroid6::Spheroid6,
    /// One-degree-of-freedom surge: added mass, quadratic drag and thrust.
    Surge1 => surge1::Surge1,
    /// Surface ship, MMG standard method (Yasukawa & Yoshimura 2015): u, v, r, x, y, psi.
    Mmg3 => mmg3::Mmg3,
    /// Surface ship, reduced Abkowitz model linear in 16 parameters (Hajizadeh et al. 2015).
    ShipLinear => ship_linear::ShipLinear,
    /// Course keeping in waves: Nomoto steering with a rudder bias and wave-induced yaw.
    NomotoWave => nomoto_wave::NomotoWave,
    /// NPS AUV II, 6-DOF: Healey & Lienard (1993) terms, Fossen's rigid-body kinetics.
    NpsAuv => npsauv::NpsAuv,
}

/// One state of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateDef {
    /// Short name (`u`, `psi` ...).
    pub name: &'static str,
    /// The quantity a CFD export gives for it.
    pub quantity: Quantity,
}

/// The states of a body moving in the horizontal plane, in the order the planar models use:
/// body-frame u, v, r, then earth-frame x, y and heading psi.
pub const PLANAR_STATES: &[StateDef] = &[
    StateDef {
        name: "u",
        quantity: Quantity::U,
    },
    StateDef {
        name: "v",
        quantity: Quantity::V,
    },
    StateDef {
        name: "r",
        quantity: Quantity::R,
    },
    StateDef {
        name: "x",
        quantity: Quantity::X,
    },
    StateDef {
        name: "y",
        quantity: Quantity::Y,
    },
    StateDef {
        name: "psi",
        quantity: Quantity::Yaw,
    },
];

macro_rules! state {
    ($n:literal, $q:ident) => {
        StateDef {
            name: $n,
            quantity: Quantity::$q,
        }
    };
}

/// The states of a body moving in six degrees of freedom, in the order the 6-DOF models use:
/// body-frame u, v, w, p, q, r, then earth-frame x, y, z and the zyx Euler angles.
pub const SIX_DOF_STATES: &[StateDef] = &[
    state!("u", U),
    state!("v", V),
    state!("w", W),
    state!("p", P),
    state!("q", Q),
    state!("r", R),
    state!("x", X),
    state!("y", Y),
    state!("z", Z),
    state!("phi", Roll),
    state!("theta", Pitch),
    state!("psi", Yaw),
];

/// One output of a model's measurement function (a sensor reading).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputDef {
    /// Short name (`psi_compass`).
    pub name: &'static str,
    /// The quantity a record gives for it.
    pub quantity: Quantity,
}

/// How an input sampled in a run is read between its samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputRule {
    /// Linear interpolation between samples (a smoothly varying input: thrust, rpm).
    Interpolate,
    /// The last sample held until the next (a commanded step: rudder angle, planes).
    Hold,
}

/// One input of a model: a column of a run or a constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputDef {
    /// The quantity.
    pub quantity: Quantity,
    /// How a sampled series is read between samples.
    pub rule: InputRule,
}

/// Example values a model is checked at (the conformance suite, `hydroid coefficients`): a
/// plausible vehicle, coefficients, state and inputs, and the coefficients a run of it can
/// identify.
#[derive(Debug, Clone, PartialEq)]
pub struct Example {
    /// Coefficient values (SI); the model's relations complete the rest.
    pub coefficients: &'static [(&'static str, f64)],
    /// A state in motion.
    pub state: Vec<f64>,
    /// Constant inputs (SI).
    pub inputs: Vec<f64>,
    /// Coefficients a free run from `state` with `inputs` identifies.
    pub estimated: &'static [&'static str],
    /// Duration of that run, s.
    pub duration: f64,
}

/// A vehicle model: states, outputs, inputs, coefficients and continuous dynamics.
pub trait Model: Send + Sync + Sized {
    /// Short name used in configurations (`spheroid3`).
    const NAME: &'static str;

    /// What the model is, in a line, with its source.
    const DESCRIPTION: &'static str;

    /// Every coefficient the dynamics use, in vector order: free ones and those that
    /// [`Model::relations`] derive from them (a [`coefficient_table!`](crate::coefficient_table)).
    const COEFFICIENTS: &'static [CoefDef];

    /// The inputs (time series or constants), in vector order.
    const INPUTS: &'static [InputDef];

    /// The relations that complete a reported coefficient set for this model (symmetry,
    /// axisymmetry).
    const COMPLETING_RELATIONS: &'static [&'static [Relation]];

    /// Builds the model for a vehicle, or says every problem of the vehicle data for it.
    fn build(vehicle: &Vehicle) -> Result<Self, Vec<VehicleProblem>>;

    /// The model in the run's yaw-moment reading: which of N_uv and its lift part N_uvl is
    /// free and which a relation derives (see [`YawMoment`]). [`with_model`] applies it to
    /// every model it builds; a model without the split (the default) reads the same either
    /// way and returns itself.
    fn with_yaw_moment(self, _reading: YawMoment) -> Self {
        self
    }

    /// Short name used in configurations (`spheroid3`).
    fn name(&self) -> &'static str {
        Self::NAME
    }

    /// What the model is, in a line, with its source.
    fn description(&self) -> &'static str {
        Self::DESCRIPTION
    }

    /// The states, in vector order.
    fn states(&self) -> &'static [StateDef];

    /// The outputs of [`Model::measure`], in vector order; empty (the default) when every
    /// state is an output (y = x), a selection of which a run measures.
    fn outputs(&self) -> &'static [OutputDef] {
        &[]
    }

    /// The measurement function y = h(x, u, c) (length of [`Model::outputs`]); only called
    /// when the model declares outputs.
    fn measure<T: Scalar>(&self, x: &[T], _u: &[f64], _c: &[T], y: &mut [T]) {
        y.copy_from_slice(&x[..y.len()]);
    }

    /// The inputs (time series or constants), in vector order.
    fn inputs(&self) -> &'static [InputDef] {
        Self::INPUTS
    }

    /// Every coefficient, in vector order.
    fn coefficients(&self) -> &'static [CoefDef] {
        Self::COEFFICIENTS
    }

    /// The relations that define derived coefficients (applied before every evaluation).
    fn relations(&self) -> &CompiledRelations;

    /// The measured quantities a re-simulation of a run compares with the model (RMS error).
    fn compared(&self) -> &'static [Quantity];

    /// The coefficient that balances the surge equation in steady straight motion against
    /// the propulsion (the resistance, R'_0 of the MMG model), which the HEKF estimates when a
    /// run's approach contradicts it (`hekf.balance`); None when the model has none.
    fn surge_balance(&self) -> Option<&'static str> {
        None
    }

    /// A typical magnitude of a coefficient for this vehicle (SI), used to scale priors and
    /// the filter's parameter states.
    fn typical_magnitude(&self, name: &str) -> f64;

    /// The dynamics x_dot = f(x, u, c), with `c` already completed by the relations.
    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]);

    /// The force and moment components a captive run measures on this model, in the order
    /// [`Model::captive_forces`] writes them (`fx`, `fy`, `mz` for a body in the horizontal
    /// plane); empty (the default) when the model gives no forces for a prescribed motion.
    fn force_quantities(&self) -> &'static [Quantity] {
        &[]
    }

    /// The hydrodynamic forces (SI, body axes: hull, and rudder and propeller where the
    /// model has them) on the vehicle moved along a prescribed path with state `x`, its
    /// rate `x_dot` (the accelerations; zero in a steady run) and inputs `u`: what a
    /// captive run measures (ITTC 7.5-02-06-02: static drift, drift with rudder, circular
    /// motion; 7.5-02-06-04 practice: harmonic PMM pure sway and pure yaw, whose
    /// accelerations bring in the added masses). The rigid-body inertia of the body is not
    /// part of it. Called only when [`Model::force_quantities`] is not empty.
    fn captive_forces<T: Scalar>(
        &self,
        _x: &[T],
        _x_dot: &[T],
        _u: &[f64],
        _c: &[T],
        _out: &mut [T],
    ) {
    }

    /// A physical sanity check of state and coefficients (e.g. m - Yvd > 0); the message
    /// says what went wrong.
    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical>;

    /// A first value of the estimated coefficient `name` read from the runs' measurements,
    /// used when the configuration gives no `hekf.prior.NAME.initial` (None, the default:
    /// start at zero). The wave filter reads its wave frequency from the heading spectrum.
    fn initial_guess(&self, _name: &str, _runs: &[crate::io::record::Record]) -> Option<f64> {
        None
    }

    /// The peak frequency (rad/s) of a wave disturbance the model's compass sees on top of
    /// the heading it steers (Fossen 2011, 8.2), from its coefficients; None (the default)
    /// for a model whose heading is the measured one. The run's manoeuvre measures are then
    /// read from the heading low-passed below it, as the model sails only the slow part.
    fn wave_frequency(&self, _c: &[f64]) -> Option<f64> {
        None
    }

    /// Nomoto's K (1/s) and T (s) when the model is itself a Nomoto steering model (its
    /// coefficients hold them), for the autopilot's tuning, or why its coefficients give none
    /// (a 1/T of zero: no yaw damping); None (the default) when it is not a Nomoto model.
    fn nomoto_gains(&self, _c: &[f64]) -> Option<Result<(f64, f64), String>> {
        None
    }

    /// A vehicle the model is checked on (the conformance suite, `hydroid coefficients`).
    fn example_vehicle() -> Vehicle;

    /// Example values the model is checked at.
    fn example(&self) -> Example;

    /// Number of states.
    fn nx(&self) -> usize {
        self.states().len()
    }

    /// The coefficient names, in vector order.
    fn coefficient_names(&self) -> Vec<&'static str> {
        self.coefficients().iter().map(|c| c.name).collect()
    }

    /// Index of a coefficient in [`Model::coefficients`].
    fn coefficient_index(&self, name: &str) -> Option<usize> {
        self.coefficients().iter().position(|c| c.name == name)
    }

    /// Index of the state that a quantity measures.
    fn state_index(&self, q: Quantity) -> Option<usize> {
        self.states().iter().position(|s| s.quantity == q)
    }

    /// The quantities of the outputs, in vector order (the states' when the model declares
    /// no outputs).
    fn output_quantities(&self) -> Vec<Quantity> {
        if self.outputs().is_empty() {
            self.states().iter().map(|s| s.quantity).collect()
        } else {
            self.outputs().iter().map(|o| o.quantity).collect()
        }
    }

    /// Index of the output that a quantity measures.
    fn output_index(&self, q: Quantity) -> Option<usize> {
        self.output_quantities().iter().position(|o| *o == q)
    }

    /// The quantities of the inputs, in vector order.
    fn input_quantities(&self) -> Vec<Quantity> {
        self.inputs().iter().map(|i| i.quantity).collect()
    }

    /// Whether a coefficient is zero unless given or estimated (an offset or extension term
    /// a configuration need not list; [`CoefDef::optional`]).
    fn is_optional(&self, name: &str) -> bool {
        self.coefficients()
            .iter()
            .any(|d| d.name == name && d.optional)
    }

    /// Whether a coefficient is derived by a relation (and so cannot be estimated directly).
    fn is_derived(&self, name: &str) -> bool {
        self.coefficient_index(name)
            .is_some_and(|i| self.relations().targets().any(|t| t == i))
    }

    /// The model's coefficient vector from (name, value) pairs (names the model does not use
    /// are ignored, missing ones are 0), completed by the relations.
    fn coefficient_vector(&self, values: &[(&str, f64)]) -> Vec<f64> {
        let mut c = vec![0.0; self.coefficients().len()];
        for (n, v) in values {
            if let Some(i) = self.coefficient_index(n) {
                c[i] = *v;
            }
        }
        self.relations().apply(&mut c);
        c
    }

    /// The outputs y = h(x, u, c) for a state (f64).
    fn output_values(&self, x: &[f64], u: &[f64], c: &[f64]) -> Vec<f64> {
        if self.outputs().is_empty() {
            return x.to_vec();
        }
        let mut y = vec![0.0; self.outputs().len()];
        self.measure(x, u, c, &mut y);
        y
    }
}

/// The names of a coefficient table, in order.
pub fn names(table: &[CoefDef]) -> Vec<&'static str> {
    table.iter().map(|c| c.name).collect()
}

/// Checks that `m_eff` (a rigid-body mass or inertia minus its added mass) stays positive.
pub(crate) fn positive_inertia(what: &'static str, value: f64) -> Result<(), Unphysical> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Unphysical::NotPositive { what, value })
    }
}

pub use crate::base::error::Unphysical;
