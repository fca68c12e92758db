//! Layer 8, the application: the pipeline that runs a configuration's stages, its results,
//! the re-simulation, reports, the model catalogue, `inspect`, and the `simulate` command
//! (synthetic exports, PMM runs, sweeps). Imports every layer below; the command line is
//! above it.

pub mod calibrate;
pub mod catalogue;
pub mod check;
pub mod export;
pub mod inspect;
pub mod pipeline;
pub mod plan;
pub mod report;
pub(crate) mod resim;
pub mod results;
pub mod simulate;
