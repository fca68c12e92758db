//! The PID heading controller with its pole-placement tuning and the steering gear's limits.

use crate::base::units::wrap_pi;
use serde::Serialize;

/// PID gains on the heading error (rad -> rad of rudder).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gains {
    /// Proportional gain K_p, rad/rad.
    pub kp: f64,
    /// Derivative gain K_d, s (on the yaw-rate error).
    pub kd: f64,
    /// Integral gain K_i, 1/s.
    pub ki: f64,
    /// Closed-loop natural frequency w_n the gains place, rad/s.
    pub omega_n: f64,
    /// Closed-loop relative damping zeta.
    pub zeta: f64,
}

/// Why the gains cannot be placed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct TuningError(String);

impl Gains {
    /// The gains that place the closed-loop poles of the first-order Nomoto ship
    /// T r_dot + r = K delta at natural frequency `omega_n` and damping `zeta`: with
    /// m = T/K and d = 1/K the ship is m r_dot + d r = delta, and
    /// K_p = m w_n^2, K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10 (Fossen 2011, PID pole
    /// placement; the integral pole a decade below w_n leaves the other two in place).
    ///
    /// K and T must be positive (a course-stable ship): an unstable one (T < 0) needs the
    /// derivative gain to stabilise it first, which this tuning does not give.
    pub fn pole_placement(k: f64, t: f64, omega_n: f64, zeta: f64) -> Result<Gains, TuningError> {
        let bad = |what: &str, v: f64| {
            Err(TuningError(format!(
                "{what} = {v}: the pole-placement tuning needs a course-stable Nomoto model \
                 (K > 0, T > 0) and a positive w_n and zeta"
            )))
        };
        for (what, v) in [("K", k), ("T", t), ("w_n", omega_n), ("zeta", zeta)] {
            if !(v.is_finite() && v > 0.0) {
                return bad(what, v);
            }
        }
        let (m, d) = (t / k, 1.0 / k);
        let kp = m * omega_n * omega_n;
        let kd = 2.0 * zeta * omega_n * m - d;
        if kd < 0.0 {
            return Err(TuningError(format!(
                "w_n = {omega_n} rad/s is below the ship's own yaw bandwidth 1/(2 zeta T) = {:.4} \
                 rad/s: the derivative gain would be negative; choose a larger w_n",
                1.0 / (2.0 * zeta * t)
            )));
        }
        Ok(Gains {
            kp,
            kd,
            ki: omega_n * kp / 10.0,
            omega_n,
            zeta,
        })
    }
}

/// The steering gear: largest rudder angle and rate, and an optional first-order lag.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RudderLimits {
    /// Largest rudder angle either side, rad.
    pub angle: f64,
    /// Largest rudder rate, rad/s.
    pub rate: f64,
    /// Time constant of the steering gear's first-order lag, s (0: none, the rudder moves to
    /// the command as fast as the rate limit lets it).
    pub lag: f64,
}

/// The PID autopilot in discrete time: the command from the heading error and the yaw-rate
/// error at each sample, the integral with anti-windup (it stops while the rudder is at its
/// angle limit), the rudder following the command within the steering gear's limits.
#[derive(Debug, Clone)]
pub struct Autopilot {
    gains: Gains,
    limits: RudderLimits,
    integral: f64,
    rudder: f64,
    command: f64,
}

impl Autopilot {
    /// An autopilot with the rudder amidships.
    pub fn new(gains: Gains, limits: RudderLimits) -> Self {
        Autopilot {
            gains,
            limits,
            integral: 0.0,
            rudder: 0.0,
            command: 0.0,
        }
    }

    /// The rudder angle for the next interval of `dt`, from the heading error
    /// `psi - psi_d` (rad, wrapped to (-pi, pi]) and the yaw-rate error `r - r_d` (rad/s):
    /// delta_c = -(K_p e + K_d e_dot + K_i int e), moved towards at most at the rate limit
    /// and clipped at the angle limit.
    pub fn step(&mut self, heading_error: f64, rate_error: f64, dt: f64) -> f64 {
        let e = wrap_pi(heading_error);
        let g = &self.gains;
        let command = -(g.kp * e + g.kd * rate_error + g.ki * self.integral);
        let limited = command.clamp(-self.limits.angle, self.limits.angle);
        self.command = limited;
        // anti-windup: integrate only while the command is not held at the limit
        if limited == command {
            self.integral += e * dt;
        }
        // the steering gear: T_r delta_dot = delta_c - delta, exact over the sample, its rate
        // clipped (Van Amerongen 1982: a rate- and angle-limited first-order steering machine)
        let gap = limited - self.rudder;
        let wanted = if self.limits.lag > 0.0 {
            gap * (1.0 - (-dt / self.limits.lag).exp())
        } else {
            gap
        };
        let step = wanted.clamp(-self.limits.rate * dt, self.limits.rate * dt);
        self.rudder += step;
        self.rudder
    }

    /// Replaces the gains (the adaptive autopilot's retuning); the integral and the rudder
    /// go on.
    pub fn set_gains(&mut self, gains: Gains) {
        self.gains = gains;
    }

    /// The last rudder command, clipped at the angle limit, before the steering gear's rate
    /// limit and lag (rad).
    pub fn command(&self) -> f64 {
        self.command
    }

    /// The gains in use.
    pub fn gains(&self) -> Gains {
        self.gains
    }

    /// The rudder angle now, rad.
    pub fn rudder(&self) -> f64 {
        self.rudder
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gains_follow_the_pole_placement_formulas() {
        // K = 0.18 1/s, T = 27 s (the frigate at 9 m/s, Van Amerongen), w_n 0.1, zeta 0.8:
        // m = 150, d = 5.556; K_p = 1.5, K_d = 2*0.8*0.1*150 - 5.556 = 18.44, K_i = 0.015
        let g = Gains::pole_placement(0.18, 27.0, 0.1, 0.8).unwrap();
        assert!((g.kp - 1.5).abs() < 1e-12, "{g:?}");
        assert!((g.kd - (24.0 - 1.0 / 0.18)).abs() < 1e-12, "{g:?}");
        assert!((g.ki - 0.015).abs() < 1e-12, "{g:?}");
    }

    #[test]
    fn an_unstable_ship_or_a_slow_loop_is_refused_with_the_reason() {
        let e = Gains::pole_placement(-1.1, -86.0, 0.1, 0.8).unwrap_err();
        assert!(e.to_string().contains("course-stable"), "{e}");
        let e = Gains::pole_placement(0.18, 27.0, 0.01, 0.8).unwrap_err();
        assert!(
            e.to_string().contains("derivative gain would be negative"),
            "{e}"
        );
    }

    #[test]
    fn the_rudder_moves_within_the_steering_gear() {
        let g = Gains::pole_placement(0.18, 27.0, 0.1, 0.8).unwrap();
        let limits = RudderLimits {
            angle: 0.6,
            rate: 0.05,
            lag: 0.0,
        };
        let mut ap = Autopilot::new(g, limits);
        // a large heading error: the command saturates; the rudder moves 0.005 rad per 0.1 s
        let d1 = ap.step(-1.0, 0.0, 0.1);
        assert!((d1 - 0.005).abs() < 1e-12);
        for _ in 0..1000 {
            ap.step(-1.0, 0.0, 0.1);
        }
        assert!((ap.rudder() - 0.6).abs() < 1e-12, "held at the angle limit");
        // with a 2 s lag and no rate limit to speak of, a small command is approached as
        // 1 - exp(-t / 2)
        let limits = RudderLimits {
            angle: 0.6,
            rate: 10.0,
            lag: 2.0,
        };
        let mut ap = Autopilot::new(
            Gains {
                kp: 1.0,
                kd: 0.0,
                ki: 0.0,
                ..g
            },
            limits,
        );
        for _ in 0..20 {
            ap.step(-0.01, 0.0, 0.1);
        }
        assert!((ap.rudder() - 0.01 * (1.0 - (-1.0f64).exp())).abs() < 1e-12);
    }
}
