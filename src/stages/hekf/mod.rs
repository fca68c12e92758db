//! Hybrid EKF stage (paper section 4, eq. 9-19 and 22): coefficients appended to the state of
//! a vehicle model and estimated from CFD motion histories.

mod config;

pub use config::{HekfConfig, ModelName, Preset, Prior};
