//! hydroid: CFD exports of marine vehicles to manoeuvring models.
//!
//! The pipeline (see docs/architecture.md): configuration -> readers -> [`io::table::Table`]
//! -> [`io::record::Record`] -> stages (polar, surge, captive, hekf) ->
//! [`model::coefficients::CoefficientSet`] -> reports. The command-line program `hydroid` is
//! a thin shell over this library.
//!
//! The modules are nine layers, lowest first: [`base`], [`numerics`], [`io`], [`model`],
//! [`dynamics`], [`config`], [`stages`], [`app`] and the command line [`cli`] (whose
//! [`cli::main`] is all that `src/main.rs` calls); each imports only from those below it
//! (docs/layers.txt, checked by tests/layers.rs).
//!
//! What a Rust user calls, re-exported here:
//!
//! * a configured run: [`load`] a configuration, [`run`] its stages, write the output folder
//!   with [`app::report::write`] into a [`io::output::Staging`] folder (written whole or not
//!   at all); the result is a [`RunOutput`] ([`RunResult`] is what results.json holds);
//! * a record: [`io::record::Record`] read from any export with a column map
//!   ([`config::InputSpec`], docs/formats.md);
//! * a model of your own: implement [`Model`] (states, inputs, coefficient table, dynamics and
//!   optionally a measurement function, generic over the scalar so that AD gives the
//!   Jacobians), add it to the registry in `src/model/models/mod.rs` (see
//!   docs/architecture.md, "How to add a model"), and the stages, `hydroid simulate` and the
//!   conformance suite pick it up; [`with_model`] builds a named model for a [`Vehicle`];
//! * a simulation: [`dynamics::sim::simulate`] of any model, or a synthetic export with
//!   [`app::simulate::run_file`];
//! * a filter of your own: [`HybridEkf`] over any [`System`], for instance
//!   [`dynamics::model_system::ModelSystem`], a model with coefficients appended to its state.
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
//! Numerical helpers (linear algebra, least squares, signal statistics, sampling, frames,
//! printed precision), number and Markdown formatting, name suggestions, the input
//! specification's internals, time-stamp repair, Froude scaling and the re-simulation are
//! internal to the crate. The run's vehicle is built once, when the configuration is loaded
//! ([`LoadedConfig::vehicle`]), and handed to every stage that builds a model.

// Numerical kernels index several arrays with one loop variable; iterator chains would hide
// the linear algebra.
#![allow(clippy::needless_range_loop)]

pub mod app;
pub mod base;
pub mod cli;
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
