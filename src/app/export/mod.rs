//! `hydroid export`: an identified model packaged for other tools (docs/fmu.md).

pub mod fmu;
