//! A heading autopilot tuned from Nomoto's K and T: a PID controller placed on the
//! first-order Nomoto model (Fossen 2011, Handbook of Marine Craft Hydrodynamics and Motion
//! Control, PID pole placement for the Nomoto ship: m = T/K, d = 1/K, K_p = m w_n^2,
//! K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10), fed by a third-order reference model of the
//! commanded heading (Fossen 2011, 10.2.1: a low-pass filter cascaded with a mass-damper-
//! spring), with the rudder limited in angle and rate as a steering gear is.

pub mod adaptive;
pub mod closed_loop;
pub mod lowpass;
mod pid;
pub mod plant;
pub mod plausibility;
mod reference;
mod result;
pub mod seas;
pub mod series;
mod sight;
pub mod wave_filter;

pub use closed_loop::{ClosedLoop, Feed};
pub use pid::{Autopilot, Gains, RudderLimits, TuningError};
pub use reference::ReferenceModel;
pub use result::{AutopilotResult, PlantIndices};
pub use series::Series;

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 deg course change of the first-order Nomoto frigate (K = 0.18 1/s, T = 27 s, Van
    /// Amerongen at 9 m/s) under the tuned autopilot: the heading follows the reference
    /// model within a degree and settles on the new course.
    #[test]
    fn a_course_change_follows_the_reference() {
        let (k, t) = (0.18, 27.0);
        let gains = Gains::pole_placement(k, t, 0.15, 0.9).unwrap();
        let mut ap = Autopilot::new(
            gains,
            RudderLimits {
                angle: 35f64.to_radians(),
                rate: 2.32f64.to_radians(),
                lag: 0.0,
            },
        );
        let mut reference = ReferenceModel::new(0.05, 1.0, 0.0);
        let (mut psi, mut r, dt) = (0.0f64, 0.0f64, 0.1);
        let target = 20f64.to_radians();
        let mut worst: f64 = 0.0;
        for _ in 0..3000 {
            reference.step(target, dt);
            let delta = ap.step(psi - reference.heading, r - reference.rate, dt);
            // T r_dot + r = K delta (explicit Euler at 0.1 s is fine against T = 27 s)
            r += dt * (k * delta - r) / t;
            psi += dt * r;
            worst = worst.max((psi - reference.heading).abs());
        }
        assert!((psi - target).abs() < 1e-3, "settles: {}", psi.to_degrees());
        assert!(
            worst < 1f64.to_radians(),
            "tracking error {} deg",
            worst.to_degrees()
        );
    }
}
