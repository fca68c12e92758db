//! Manoeuvre measures from a history: the turning circle and the zig-zag as a naval architect
//! quotes them (IMO MSC.137(76) and its explanatory notes MSC/Circ.1053, ITTC
//! 7.5-04-02-01), and the IMO criteria they are judged by.
//!
//! Pure functions of a [`History`] (time, heading, and the track, velocities and rudder angle
//! where the run has them), measured or simulated: no model, no configuration. A measure the
//! run cannot give (a turn that never reaches 90 deg has no advance) is a
//! [`Measure::Missing`] with the reason, never a NaN. Everything is SI inside (m, s, rad);
//! the tables convert angles to degrees. Definitions and sign conventions: docs/manoeuvres.md.

mod circle_fit;
mod history;
pub mod imo;
mod measure;
pub mod nominal;
mod rudder;
mod run;
mod steady;
pub mod table;
mod turning;
mod zigzag;

pub use history::{History, HistoryError};
pub use imo::{Check, Criterion, Ship, Verdict};
pub use measure::{Kind, Measure, Named, Side};
pub use nominal::{AngleSource, Nominal};
pub use rudder::rudder_put_over;
pub use run::{history_of, measure_history, reversals, rudder_rate, RunMeasures};
pub use table::ComparisonTable;
pub use turning::{turning_circle, TurningCircle, TurningOptions};
pub use zigzag::{zigzag, ZigZag, ZigZagOptions};
