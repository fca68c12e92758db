//! hydroid: CFD exports of marine vehicles to manoeuvring models.
//!
//! The pipeline (see docs/architecture.md): configuration -> readers -> [`table::Table`] ->
//! [`record::Record`] -> stages (polar, surge, captive, hekf) -> [`coefficients::CoefficientSet`] ->
//! reports. The command-line program `hydroid` is a thin shell over this library.
//!
//! What a Rust user calls, re-exported here:
//!
//! * a configured run: [`load`] a configuration, [`run`] its stages, write the output folder
//!   with [`report::write`] into a [`output::Staging`] folder (written whole or not at all);
//! * a model of your own: implement [`Model`] (states, inputs, coefficient table, dynamics and
//!   optionally a measurement function, generic over the scalar so that AD gives the
//!   Jacobians), add it to the registry in `src/models/mod.rs` (see docs/architecture.md,
//!   "How to add a model"), and the stages, `hydroid simulate` and the conformance suite pick
//!   it up;
//! * a filter of your own: [`HybridEkf`] over any [`System`], for instance
//!   [`stages::hekf::system::ModelSystem`], a model with coefficients appended to its state.
//!
//! ```no_run
//! use hydroid::{load, run, io::output::Staging, base::progress::Silent};
//!
//! fn main() -> hydroid::Result<()> {
//!     let loaded = load(std::path::Path::new("configs/spheroid.toml"), &[])?;
//!     let out = run(&loaded, &mut Silent)?;
//!     for c in out.result.coefficients.iter() {
//!         println!("{} = {} {}", c.name, c.value, c.unit);
//!     }
//!     let staging = Staging::new(std::path::Path::new("out"))?;
//!     hydroid::app::report::write(&staging, &loaded, &out)?;
//!     staging.commit()?;
//!     Ok(())
//! }
//! ```
//!
//! Numerical helpers (linear algebra, least squares, signal statistics, sampling, frames)
//! and the re-simulation are internal to the crate.

// Numerical kernels index several arrays with one loop variable; iterator chains would hide
// the linear algebra.
#![allow(clippy::needless_range_loop)]

pub mod app;
pub mod base;
pub mod config;
pub mod dynamics;
pub mod io;
pub mod model;
pub mod numerics;
pub mod stages;

pub use app::pipeline::run;
pub use app::results::{RunOutput, RunResult};
pub use base::error::{Error, Result};
pub use config::{load, LoadedConfig};
pub use model::models::{with_model, Model, ModelName, ModelVisitor, Vehicle};
pub use numerics::estimation::{HybridEkf, System};
