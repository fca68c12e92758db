//! Layer 3, input and output: tables and their time stamps, the CFD and basin formats, the
//! input specification of a run, the record (a run's signals in SI, body axes), Froude
//! scaling, and safe writing of output folders. Imports base and numerics.

pub mod formats;
pub(crate) mod froude;
pub(crate) mod input_spec;
pub mod output;
pub mod record;
pub(crate) mod steps;
pub mod table;
pub(crate) mod time_stamps;
