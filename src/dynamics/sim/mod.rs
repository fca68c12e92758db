//! Simulation of vehicle models: fixed-step RK4 integration, input time series between
//! samples and steering (the `simulate` command that writes synthetic exports is in
//! `app::simulate`).

pub mod inputs;
pub mod integrate;
pub mod steering;

pub use inputs::InputSeries;
pub use integrate::{complete_coefficients, simulate, SimError};
// the step-count rule lives with the stepper; re-exported for the callers that read it here
pub use crate::numerics::ode::{steps_for, MAX_STEPS_PER_INTERVAL};
