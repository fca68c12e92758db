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
//! use hydroid::{load, run, output::Staging, progress::Silent};
//!
//! fn main() -> hydroid::Result<()> {
//!     let loaded = load(std::path::Path::new("configs/spheroid.toml"), &[])?;
//!     let out = run(&loaded, &mut Silent)?;
//!     for c in out.result.coefficients.iter() {
//!         println!("{} = {} {}", c.name, c.value, c.unit);
//!     }
//!     let staging = Staging::new(std::path::Path::new("out"))?;
//!     hydroid::report::write(&staging, &loaded, &out)?;
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

pub mod ad;
pub mod analytic;
pub mod autopilot;
pub mod catalogue;
pub mod coefficients;
pub mod config;
pub mod constrained_lsq;
pub mod course_stability;
pub mod error;
pub mod estimation;
pub mod formats;
pub(crate) mod frames;
pub mod froude;
pub mod inspect;
pub(crate) mod linalg;
pub(crate) mod lsq;
pub mod manoeuvre;
pub mod markdown_text;
pub mod models;
pub mod numfmt;
pub mod ode;
pub mod output;
pub mod pipeline;
pub mod printed;
pub mod progress;
pub mod quantity;
pub mod record;
pub mod report;
pub(crate) mod resim;
pub mod results;
pub(crate) mod sampling;
pub(crate) mod signal;
pub mod sim;
pub mod stages;
pub mod suggest;
pub mod table;
pub mod time_stamps;
pub mod units;
pub mod warning;

pub use config::{load, LoadedConfig};
pub use error::{Error, Result};
pub use estimation::{HybridEkf, System};
pub use models::{with_model, Model, ModelName, ModelVisitor, Vehicle};
pub use pipeline::run;
pub use results::{RunOutput, RunResult};
