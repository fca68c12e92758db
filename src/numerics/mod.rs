//! Layer 2, numerics: automatic differentiation, linear algebra, (constrained) least squares,
//! the ODE integrator, signal statistics, sampling, reference frames, the printed precision of
//! logged values, and the estimators (hybrid EKF, Kalman-Bucy, RTS smoother, NIS): generic,
//! without I/O. Imports only the base layer.

pub mod ad;
pub(crate) mod constrained_lsq;
pub mod estimation;
pub(crate) mod frames;
pub mod hac;
pub(crate) mod linalg;
pub(crate) mod lsq;
pub mod noise;
pub mod ode;
pub(crate) mod printed;
pub(crate) mod sampling;
pub(crate) mod signal;
