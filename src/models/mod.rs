//! Vehicle models: one type per model implementing [`Model`]; filters, simulators and
//! reports are generic over it.
//!
//! A model declares its states, inputs and coefficients by name and gives the continuous
//! dynamics x_dot = f(x, u, c) once, generic over the scalar type, so that the same code
//! simulates (f64) and yields exact Jacobians (dual numbers, see [`crate::ad`]).

pub mod rigid_body;
pub mod spheroid3;
pub mod spheroid6;

use crate::ad::Scalar;
use crate::coefficients::CompiledRelations;
use crate::quantity::Quantity;

pub use spheroid3::Spheroid3;
pub use spheroid6::Spheroid6;

/// One state of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateDef {
    /// Short name (`u`, `psi` ...).
    pub name: &'static str,
    /// The quantity a CFD export gives for it.
    pub quantity: Quantity,
}

/// A vehicle model: states, inputs, coefficients and continuous dynamics.
pub trait Model: Send + Sync {
    /// Short name used in configurations (`spheroid3`).
    fn name(&self) -> &'static str;

    /// The states, in vector order.
    fn states(&self) -> &'static [StateDef];

    /// The inputs (time series or constants), in vector order.
    fn inputs(&self) -> &'static [Quantity];

    /// Every coefficient the dynamics use, in vector order: free ones and those that
    /// [`Model::relations`] derive from them.
    fn coefficient_names(&self) -> &'static [&'static str];

    /// The relations that define derived coefficients (applied before every evaluation).
    fn relations(&self) -> &CompiledRelations;

    /// A typical magnitude of a coefficient for this vehicle (SI), used to scale priors and
    /// the filter's parameter states.
    fn typical_magnitude(&self, name: &str) -> f64;

    /// The dynamics x_dot = f(x, u, c), with `c` already completed by the relations.
    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]);

    /// A physical sanity check of state and coefficients (e.g. m - Yvd > 0); the message
    /// says what went wrong.
    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), String>;

    /// Number of states.
    fn nx(&self) -> usize {
        self.states().len()
    }

    /// Index of a coefficient in [`Model::coefficient_names`].
    fn coefficient_index(&self, name: &str) -> Option<usize> {
        self.coefficient_names().iter().position(|n| *n == name)
    }

    /// Index of the state that a quantity measures.
    fn state_index(&self, q: Quantity) -> Option<usize> {
        self.states().iter().position(|s| s.quantity == q)
    }

    /// Whether a coefficient is derived by a relation (and so cannot be estimated directly).
    fn is_derived(&self, name: &str) -> bool {
        self.coefficient_index(name)
            .is_some_and(|i| self.relations().targets().any(|t| t == i))
    }
}

/// Analytic added mass of a vehicle (Lamb's k-factors for a spheroid, Fossen 1994).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AddedMass {
    /// Surge added mass X_udot, kg.
    pub xud: f64,
    /// Sway added mass Y_vdot, kg.
    pub yvd: f64,
    /// Yaw added inertia N_rdot, kg m^2.
    pub nrd: f64,
}

/// Typical coefficient sizes for the vehicle, used to scale priors (see
/// [`Model::typical_magnitude`]).
#[derive(Debug, Clone, Copy)]
pub struct Scales {
    /// 0.5 rho A_ref, kg/m: the force per speed squared.
    pub q: f64,
    /// Length, m.
    pub length: f64,
    /// Analytic (Lamb) added masses when the geometry gives them.
    pub added: Option<AddedMass>,
}

impl Scales {
    /// Size of a coefficient from its unit: damping terms from the prime system
    /// (q, q L, q L^2, q L^3 for kg/m, kg, kg m, kg m^2), added-mass terms from the
    /// analytic values where known (Yrd from the geometric mean of Yvd and Nrd, which has
    /// its unit kg m; Kpd, zero for a spheroid, from Nrd).
    pub fn of(&self, name: &str) -> f64 {
        let (q, l) = (self.q, self.length);
        if let Some(a) = self.added {
            match name {
                "Xud" => return a.xud.abs(),
                "Yvd" | "Zwd" => return a.yvd.abs(),
                "Nrd" | "Mqd" | "Kpd" => return a.nrd.abs(),
                "Yrd" | "Nvd" | "Zqd" | "Mwd" => return (a.yvd * a.nrd).abs().sqrt(),
                _ => {}
            }
        }
        match crate::coefficients::info(name).map(|i| i.unit) {
            Some("kg/m") => q,
            Some("kg") => q * l,
            Some("kg m") => q * l * l,
            Some("kg m^2") => q * l * l * l,
            _ => q,
        }
    }
}

impl Scales {
    /// Scales for a vehicle: q = 0.5 rho A_ref and its length, and the analytic added mass
    /// when the geometry gives one.
    pub fn for_vehicle(
        vehicle: &crate::config::VehicleConfig,
        fluid: &crate::config::FluidConfig,
        added: Option<AddedMass>,
    ) -> Self {
        Scales {
            q: 0.5 * fluid.rho * vehicle.reference_area,
            length: vehicle.length,
            added,
        }
    }
}

/// Something to do with a model whose type is chosen at run time (see [`with_model`]).
pub trait ModelVisitor {
    /// What the visit returns.
    type Output;
    /// Called with the model.
    fn visit<M: Model>(self, model: &M) -> Self::Output;
}

/// Which model, and the vehicle it describes.
#[derive(Debug, Clone, Copy)]
pub struct ModelSpec<'a> {
    /// The model.
    pub name: crate::stages::hekf::ModelName,
    /// The vehicle.
    pub vehicle: &'a crate::config::VehicleConfig,
    /// Prior scales.
    pub scales: Scales,
}

/// Builds the model `spec` names and hands it to `visitor`.
pub fn with_model<V: ModelVisitor>(spec: &ModelSpec, visitor: V) -> V::Output {
    use crate::stages::hekf::ModelName;
    let v = spec.vehicle;
    match spec.name {
        ModelName::Spheroid3 => visitor.visit(&Spheroid3::new(v.mass, v.izz, spec.scales)),
        ModelName::Spheroid6 => {
            let weight = v.mass * spheroid6::G;
            // validation requires ixx and iyy for this model; izz is a safe stand-in otherwise
            let ixx = v.ixx.unwrap_or(v.izz);
            let iyy = v.iyy.unwrap_or(v.izz);
            let model = Spheroid6::new(
                v.mass,
                [ixx, iyy, v.izz],
                v.buoyancy.unwrap_or(weight),
                v.bg.unwrap_or(0.0),
                spec.scales,
            );
            visitor.visit(&model)
        }
    }
}

/// Checks that `m_eff` (a rigid-body mass or inertia minus its added mass) stays positive.
pub(crate) fn positive_inertia(what: &str, value: f64) -> Result<(), String> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{what} = {value:.4} is not positive: the mass matrix is singular or indefinite"
        ))
    }
}
