//! The `simulate` command: synthetic CFD exports from a model (its configuration, the
//! export writer, PMM runs and sweeps).

pub mod config;
pub mod export;
mod plausible;
pub mod pmm;
pub mod run;
pub mod sweep;
pub mod synth;

pub use run::run_file;
