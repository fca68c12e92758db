//! Layer 4, the vehicle model: coefficient sets and their relations, the model trait and
//! registry with every vehicle model, and the analytic (Fossen, Lamb) values. Imports the
//! layers below.

pub mod analytic;
pub mod coefficients;
pub mod models;
