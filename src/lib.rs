//! hydroid: CFD exports of marine vehicles to manoeuvring models.
//!
//! The pipeline (see docs/architecture.md): configuration -> readers -> [`table::Table`] ->
//! [`record::Record`] -> stages (polar, surge, hekf) -> [`coefficients::CoefficientSet`] ->
//! reports. The command-line program `hydroid` is a thin shell over this library.

// Numerical kernels index several arrays with one loop variable; iterator chains would hide
// the linear algebra.
#![allow(clippy::needless_range_loop)]

pub mod ad;
pub mod analytic;
pub mod catalogue;
pub mod coefficients;
pub mod config;
pub mod error;
pub mod estimation;
pub mod formats;
pub mod frames;
pub mod inspect;
pub mod linalg;
pub mod lsq;
pub mod models;
pub mod numfmt;
pub mod ode;
pub mod output;
pub mod pipeline;
pub mod progress;
pub mod quantity;
pub mod record;
pub mod report;
pub mod resim;
pub mod sampling;
pub mod signal;
pub mod sim;
pub mod stages;
pub mod suggest;
pub mod table;
pub mod units;
pub mod warning;

pub use error::{Error, Result};
