//! Layer 1, the base: errors, units and physical quantities, number and text formatting,
//! name suggestions, warnings, progress, and values with units as a configuration writes
//! them. It imports nothing from the crate above it (docs/layers.txt).

pub mod error;
pub(crate) mod markdown_text;
pub(crate) mod numfmt;
pub mod progress;
pub mod quantity;
pub(crate) mod si;
pub(crate) mod suggest;
pub mod units;
pub mod warning;
pub(crate) mod words;
