//! Layer 5, dynamics: the simulator (integration, inputs between samples, steering), a model
//! with its coefficients appended to the state for the filter, course stability, the
//! autopilot and the IMO manoeuvre measures. Imports the layers below.

pub mod autopilot;
pub mod course_stability;
pub mod manoeuvre;
pub mod model_system;
pub mod sim;
