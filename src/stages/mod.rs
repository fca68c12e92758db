//! The pipeline stages: each takes the coefficients known so far and returns more.
//!
//! polar (paper eq. 5-6) -> surge (paper eq. 21) -> hekf (paper eq. 9-19, 22).

pub mod captive;
pub mod hekf;
pub mod plausible;
pub mod polar;
pub mod spread;
pub mod surge;
