//! The third-order reference model of the commanded heading (Fossen 2011, 10.2.1):
//! psi_d / psi_r = w^3 / ((s + w)(s^2 + 2 zeta w s + w^2)), so that a course change asks the
//! ship for a smooth heading, yaw rate and yaw acceleration it can follow.

/// The reference model's state: desired heading, yaw rate and yaw acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceModel {
    omega: f64,
    zeta: f64,
    /// Desired heading psi_d, rad.
    pub heading: f64,
    /// Desired yaw rate r_d, rad/s.
    pub rate: f64,
    /// Desired yaw acceleration, rad/s^2.
    pub acceleration: f64,
}

impl ReferenceModel {
    /// A reference model of natural frequency `omega` (rad/s) and damping `zeta`, at rest
    /// on the heading `heading`.
    pub fn new(omega: f64, zeta: f64, heading: f64) -> Self {
        ReferenceModel {
            omega,
            zeta,
            heading,
            rate: 0.0,
            acceleration: 0.0,
        }
    }

    /// x_dot of x = [psi_d, r_d, a_d] towards `commanded`: the denominator
    /// s^3 + (2 zeta + 1) w s^2 + (2 zeta + 1) w^2 s + w^3 in companion form.
    fn derivative(&self, x: [f64; 3], commanded: f64) -> [f64; 3] {
        let (w, c) = (self.omega, 2.0 * self.zeta + 1.0);
        [
            x[1],
            x[2],
            w * w * w * (commanded - x[0]) - c * w * w * x[1] - c * w * x[2],
        ]
    }

    /// Advances the reference by `dt` towards the commanded heading (one RK4 step; the
    /// reference is far slower than any sampling a log has).
    pub fn step(&mut self, commanded: f64, dt: f64) {
        let x = [self.heading, self.rate, self.acceleration];
        let add =
            |a: [f64; 3], b: [f64; 3], h: f64| [a[0] + h * b[0], a[1] + h * b[1], a[2] + h * b[2]];
        let k1 = self.derivative(x, commanded);
        let k2 = self.derivative(add(x, k1, dt / 2.0), commanded);
        let k3 = self.derivative(add(x, k2, dt / 2.0), commanded);
        let k4 = self.derivative(add(x, k3, dt), commanded);
        for (i, v) in [&mut self.heading, &mut self.rate, &mut self.acceleration]
            .into_iter()
            .enumerate()
        {
            *v += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_command_is_reached_smoothly_without_overshoot_when_critically_damped() {
        let mut r = ReferenceModel::new(0.1, 1.0, 0.0);
        let target = 0.5;
        let mut peak: f64 = 0.0;
        for _ in 0..2000 {
            r.step(target, 0.1);
            peak = peak.max(r.heading);
        }
        assert!((r.heading - target).abs() < 1e-6, "{r:?}");
        assert!(peak <= target + 1e-9, "no overshoot: {peak}");
        assert!(r.rate.abs() < 1e-6);
    }
}
