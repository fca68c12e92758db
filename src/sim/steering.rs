//! The helmsman of the standard manoeuvres (ITTC 7.5-04-02-01, IMO MSC.137(76)): a turning
//! circle (rudder put over to a given angle at the execute time and held) and a zig-zag
//! (rudder put over to +delta; reversed to -delta when the heading has changed by psi_e
//! towards the turn; and so on), the rudder moving at most at the steering gear's rate.
//!
//! Signs follow the model's own convention: `rudder` is the first rudder angle as the model
//! reads it (its sign chooses the side), and the zig-zag reverses the rudder on the heading
//! change the ship actually makes, so the helm works whichever way a positive rudder turns
//! the model.

use serde::{Deserialize, Serialize};

/// A rudder law of a standard manoeuvre (SI: rad, rad/s, s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Steering {
    /// Turning circle: rudder to `rudder` at `execute`, then held.
    Turn {
        /// Rudder angle, rad (its sign chooses the side).
        rudder: f64,
        /// Largest rudder rate, rad/s.
        rate: f64,
        /// Execute time, s (the approach before it with the rudder amidships).
        execute: f64,
    },
    /// Zig-zag delta/psi_e: rudder to `rudder`, reversed each time the heading change from
    /// the execute heading reaches `heading` towards the current turn.
    ZigZag {
        /// First rudder angle, rad (its sign chooses the side).
        rudder: f64,
        /// Heading change that reverses the rudder, rad (positive).
        heading: f64,
        /// Largest rudder rate, rad/s.
        rate: f64,
        /// Execute time, s.
        execute: f64,
    },
}

/// How a configuration writes a steering law (`[manoeuvre.steering]`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteeringFile {
    /// `turn` or `zigzag`.
    pub kind: SteeringKind,
    /// First rudder angle (`"35 deg"`; its sign chooses the side).
    #[serde(deserialize_with = "crate::config::si::value::<_, crate::config::si::Angle>")]
    pub rudder: f64,
    /// Zig-zag heading change that reverses the rudder (`"20 deg"`).
    #[serde(
        default,
        deserialize_with = "crate::config::si::option::<_, crate::config::si::Angle>"
    )]
    pub heading: Option<f64>,
    /// Largest rudder rate (`"2.32 deg/s"`, IMO's full-scale steering gear; faster at model
    /// scale by sqrt(lambda)).
    #[serde(deserialize_with = "crate::config::si::value::<_, crate::config::si::Rate>")]
    pub rate: f64,
    /// Execute time (default 0 s).
    #[serde(
        default,
        deserialize_with = "crate::config::si::option::<_, crate::config::si::Time>"
    )]
    pub execute: Option<f64>,
}

/// The kinds of steering.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SteeringKind {
    /// Turning circle.
    Turn,
    /// Zig-zag.
    Zigzag,
}

impl SteeringFile {
    /// The law, or every problem with its key under `key`.
    pub fn check(&self, key: &str) -> Result<Steering, Vec<(String, String)>> {
        let mut p = Vec::new();
        if !(self.rudder.is_finite() && self.rudder != 0.0 && self.rudder.abs() <= 1.0) {
            p.push((
                format!("{key}.rudder"),
                format!(
                    "must be a rudder angle other than 0 and at most 57 deg either side, got {} deg",
                    self.rudder.to_degrees()
                ),
            ));
        }
        if !(self.rate.is_finite() && self.rate > 0.0) {
            p.push((
                format!("{key}.rate"),
                "must be a positive rudder rate, e.g. \"2.32 deg/s\"".to_string(),
            ));
        }
        let execute = self.execute.unwrap_or(0.0);
        if !(execute.is_finite() && execute >= 0.0) {
            p.push((
                format!("{key}.execute"),
                "must be a time from 0 s on".to_string(),
            ));
        }
        let law = match self.kind {
            SteeringKind::Turn => {
                if self.heading.is_some() {
                    p.push((
                        format!("{key}.heading"),
                        "is not used by a turning circle (only by a zigzag)".to_string(),
                    ));
                }
                Steering::Turn {
                    rudder: self.rudder,
                    rate: self.rate,
                    execute,
                }
            }
            SteeringKind::Zigzag => {
                let heading = self.heading.unwrap_or(f64::NAN);
                if !(heading.is_finite() && heading > 0.0 && heading < std::f64::consts::PI) {
                    p.push((
                        format!("{key}.heading"),
                        "a zigzag needs the heading change that reverses the rudder, from 0 to \
                         180 deg, e.g. heading = \"20 deg\""
                            .to_string(),
                    ));
                }
                Steering::ZigZag {
                    rudder: self.rudder,
                    heading,
                    rate: self.rate,
                    execute,
                }
            }
        };
        if p.is_empty() {
            Ok(law)
        } else {
            Err(p)
        }
    }
}

/// The helm during a run: the rudder command and the rudder angle, sample by sample.
#[derive(Debug, Clone)]
pub struct Helm {
    law: Steering,
    /// The rudder command, rad.
    command: f64,
    /// The heading at the execute time, rad.
    initial_heading: Option<f64>,
    /// +1 when a positive rudder turns the model to a positive heading change, -1 when to a
    /// negative one (learnt on the first reversal of a zig-zag).
    response: Option<f64>,
}

impl Helm {
    /// The helm of `law`, rudder amidships.
    pub fn new(law: Steering) -> Self {
        Helm {
            law,
            command: 0.0,
            initial_heading: None,
            response: None,
        }
    }

    /// The rudder angle at the next sample, `dt` after the sample at time `t` where the
    /// heading is `psi` and the rudder `rudder`: the command follows the law, the rudder
    /// follows the command at most at the rate.
    pub fn next(&mut self, t: f64, psi: f64, rudder: f64, dt: f64) -> f64 {
        let (first, rate, execute) = match self.law {
            Steering::Turn {
                rudder,
                rate,
                execute,
            } => (rudder, rate, execute),
            Steering::ZigZag {
                rudder,
                rate,
                execute,
                ..
            } => (rudder, rate, execute),
        };
        if t >= execute - 1e-9 * dt.max(1.0) {
            let psi0 = *self.initial_heading.get_or_insert(psi);
            if self.command == 0.0 {
                self.command = first;
            }
            if let Steering::ZigZag { heading, .. } = self.law {
                let change = psi - psi0;
                let towards = match self.response {
                    // the first reversal: the heading change so far is the turn the first
                    // rudder made
                    None => change.abs() >= heading,
                    Some(k) => {
                        change.abs() >= heading && change.signum() == k * self.command.signum()
                    }
                };
                if towards {
                    self.response
                        .get_or_insert(change.signum() * self.command.signum());
                    self.command = -self.command;
                }
            }
        }
        let step = (self.command - rudder).clamp(-rate * dt, rate * dt);
        rudder + step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A first-order yaw response psi_ddot = (K delta - r) / T sampled at dt: enough to
    /// steer a zig-zag.
    fn run(law: Steering, k: f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut helm = Helm::new(law);
        let (mut psi, mut r, mut delta) = (0.0, 0.0, 0.0);
        let (mut psis, mut deltas) = (vec![psi], vec![delta]);
        for i in 0..n {
            let t = i as f64 * dt;
            let next = helm.next(t, psi, delta, dt);
            r += dt * (k * delta - r) / 5.0;
            psi += dt * r;
            delta = next;
            psis.push(psi);
            deltas.push(delta);
        }
        (psis, deltas)
    }

    #[test]
    fn a_turn_puts_the_rudder_over_at_the_rate_and_holds_it() {
        let law = Steering::Turn {
            rudder: 0.6,
            rate: 0.1,
            execute: 1.0,
        };
        let (_, d) = run(law, -0.5, 0.1, 200);
        assert_eq!(d[10], 0.0, "amidships before the execute time");
        assert!((d[11] - 0.01).abs() < 1e-12, "at most rate * dt per sample");
        assert!((d[80] - 0.6).abs() < 1e-12 && (d[200] - 0.6).abs() < 1e-12);
    }

    #[test]
    fn a_zigzag_reverses_on_the_heading_change_whichever_way_the_rudder_turns() {
        for k in [0.5, -0.5] {
            let law = Steering::ZigZag {
                rudder: 0.35,
                heading: 0.35,
                rate: 0.2,
                execute: 0.0,
            };
            let (psi, d) = run(law, k, 0.05, 4000);
            // the rudder reverses only after the heading passed psi_e towards the turn
            let first_reversal = d.windows(2).position(|w| w[1] < w[0]).unwrap();
            assert!(psi[first_reversal].abs() >= 0.35 - 1e-9, "k = {k}");
            assert!(psi[first_reversal].abs() < 0.40, "k = {k}");
            // it keeps zig-zagging: the rudder reaches both sides several times
            let sides = d
                .windows(2)
                .filter(|w| (w[0] - 0.35).abs() < 1e-9 && w[1] < w[0])
                .count();
            assert!(sides >= 3, "k = {k}: {sides}");
            // and the heading swings to both sides
            assert!(psi.iter().any(|p| *p > 0.35) && psi.iter().any(|p| *p < -0.35));
        }
    }

    #[test]
    fn bad_laws_name_their_keys() {
        let f = SteeringFile {
            kind: SteeringKind::Zigzag,
            rudder: 0.0,
            heading: None,
            rate: -1.0,
            execute: None,
        };
        let e = f.check("manoeuvre.steering").unwrap_err();
        let keys: Vec<&str> = e.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(
            keys,
            [
                "manoeuvre.steering.rudder",
                "manoeuvre.steering.rate",
                "manoeuvre.steering.heading"
            ]
        );
    }
}
