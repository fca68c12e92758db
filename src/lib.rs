//! hydroid: CFD exports of marine vehicles to manoeuvring models.
//!
//! The pipeline (see docs/architecture.md): configuration -> readers -> [`table::Table`] ->
//! [`record::Record`] -> stages (polar, surge, hekf) -> [`coefficients::CoefficientSet`] ->
//! reports. The command-line program `hydroid` is a thin shell over this library.

pub mod ad;
pub mod analytic;
pub mod coefficients;
pub mod config;
pub mod error;
pub mod formats;
pub mod quantity;
pub mod record;
pub mod stages;
pub mod suggest;
pub mod table;
pub mod units;

pub use error::{Error, Result};
