//! The helmsman of the standard manoeuvres (ITTC 7.5-04-02-01, IMO MSC.137(76)): a turning
//! circle (rudder put over to a given angle at the execute time and held) and a zig-zag
//! (rudder put over to +delta; reversed to -delta when the heading has changed by psi_e
//! towards the turn; and so on), the rudder moving at most at the steering gear's rate.
//!
//! The same helm works the stern planes in the vertical plane: the vertical zig-zag
//! (overshoot manoeuvre) of submarine and AUV practice, the ITTC rule with the pitch angle in
//! place of the heading (planes to +delta, reversed when the pitch angle has changed by
//! theta_e from the execute pitch towards the current motion, and so on).
//!
//! Signs follow the model's own convention: the first deflection is the angle as the model
//! reads it (its sign chooses the side), and the zig-zag reverses the surface on the change
//! of the watched angle the vehicle actually makes, so the helm works whichever way a
//! positive deflection turns or pitches the model.

use crate::base::quantity::Quantity;
use serde::{Deserialize, Serialize};

/// The control surface a helm moves, and the attitude angle it watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Surface {
    /// The rudder, watching the heading (horizontal plane; today's helm).
    #[default]
    Rudder,
    /// The stern planes, watching the pitch angle (vertical plane).
    SternPlanes,
}

impl Surface {
    /// True for the rudder (the default surface).
    pub fn is_rudder(&self) -> bool {
        *self == Surface::Rudder
    }

    /// The model input the helm moves.
    pub fn input(self) -> Quantity {
        match self {
            Surface::Rudder => Quantity::Rudder,
            Surface::SternPlanes => Quantity::SternPlanes,
        }
    }

    /// The state the helm watches.
    pub fn watched(self) -> Quantity {
        match self {
            Surface::Rudder => Quantity::Yaw,
            Surface::SternPlanes => Quantity::Pitch,
        }
    }

    /// The surface in words ("rudder", "stern planes").
    pub fn words(self) -> &'static str {
        match self {
            Surface::Rudder => "rudder",
            Surface::SternPlanes => "stern planes",
        }
    }

    /// The watched angle in words ("heading", "pitch").
    pub fn watched_words(self) -> &'static str {
        match self {
            Surface::Rudder => "heading",
            Surface::SternPlanes => "pitch",
        }
    }

    /// The key of the surface-specific name of the first deflection (`rudder`) and of the
    /// reversing change (`heading`, `pitch`).
    fn keys(self) -> (Option<&'static str>, &'static str) {
        match self {
            Surface::Rudder => (Some("rudder"), "heading"),
            Surface::SternPlanes => (None, "pitch"),
        }
    }

    /// Largest reversing change, rad: a heading turns through up to 180 deg, a pitch angle
    /// stays within 90 deg of level (zyx Euler angles, Fossen 2011 sec. 2.2.1).
    fn largest_change(self) -> f64 {
        match self {
            Surface::Rudder => std::f64::consts::PI,
            Surface::SternPlanes => std::f64::consts::FRAC_PI_2,
        }
    }
}

/// A law of a standard manoeuvre (SI: rad, rad/s, s) on one control surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Steering {
    /// Turning circle (or, on the stern planes, a steady dive or climb): the surface to
    /// `rudder` at `execute`, then held.
    Turn {
        /// Deflection, rad (its sign chooses the side).
        rudder: f64,
        /// Largest deflection rate, rad/s.
        rate: f64,
        /// Execute time, s (the approach before it with the surface at zero).
        execute: f64,
        /// The surface moved (written only when not the rudder, so that results of ships
        /// read as before).
        #[serde(skip_serializing_if = "Surface::is_rudder")]
        surface: Surface,
    },
    /// Zig-zag delta/psi_e: the surface to `rudder`, reversed each time the watched angle's
    /// change from its execute value reaches `heading` towards the current motion.
    ZigZag {
        /// First deflection, rad (its sign chooses the side).
        rudder: f64,
        /// Change of the watched angle (heading, pitch) that reverses the surface, rad
        /// (positive).
        heading: f64,
        /// Largest deflection rate, rad/s.
        rate: f64,
        /// Execute time, s.
        execute: f64,
        /// The surface moved (written only when not the rudder, so that results of ships
        /// read as before).
        #[serde(skip_serializing_if = "Surface::is_rudder")]
        surface: Surface,
    },
}

impl Steering {
    /// The surface the law moves.
    pub fn surface(&self) -> Surface {
        match self {
            Steering::Turn { surface, .. } | Steering::ZigZag { surface, .. } => *surface,
        }
    }
}

/// How a configuration writes a steering law (`[manoeuvre.steering]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteeringFile {
    /// `turn` or `zigzag`.
    pub kind: SteeringKind,
    /// The surface: `rudder` (default, watches the heading) or `stern_planes` (watches the
    /// pitch angle).
    #[serde(default)]
    pub surface: Surface,
    /// First rudder angle (`"35 deg"`; its sign chooses the side); the rudder only.
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Angle>"
    )]
    pub rudder: Option<f64>,
    /// First deflection of any surface (`"10 deg"`), instead of `rudder`.
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Angle>"
    )]
    pub deflection: Option<f64>,
    /// Zig-zag heading change that reverses the rudder (`"20 deg"`); the rudder only.
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Angle>"
    )]
    pub heading: Option<f64>,
    /// Zig-zag pitch change that reverses the stern planes (`"10 deg"`); the planes only.
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Angle>"
    )]
    pub pitch: Option<f64>,
    /// Zig-zag change of the watched angle of any surface, instead of `heading` or `pitch`.
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Angle>"
    )]
    pub angle: Option<f64>,
    /// Largest deflection rate (`"2.32 deg/s"`, IMO's full-scale steering gear; faster at
    /// model scale by sqrt(lambda)).
    #[serde(deserialize_with = "crate::base::si::value::<_, crate::base::si::Rate>")]
    pub rate: f64,
    /// Execute time (default 0 s).
    #[serde(
        default,
        deserialize_with = "crate::base::si::option::<_, crate::base::si::Time>"
    )]
    pub execute: Option<f64>,
}

/// The kinds of steering.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SteeringKind {
    /// Turning circle.
    #[default]
    Turn,
    /// Zig-zag.
    Zigzag,
}

/// The one value given under either of two keys, `specific` (if the surface has one) and
/// `general`; a problem names the key when both or the wrong one are given. Returns the
/// value (None when neither) and the key it came from.
fn one_of(
    key: &str,
    surface: Surface,
    specific: (Option<&'static str>, Option<f64>),
    others: &[(&'static str, Option<f64>)],
    general: (&'static str, Option<f64>),
    p: &mut Vec<(String, String)>,
) -> (Option<f64>, &'static str) {
    for (name, value) in others {
        if value.is_some() {
            p.push((
                format!("{key}.{name}"),
                format!(
                    "is not used by the helm of the {}: write `{}`",
                    surface.words(),
                    specific.0.unwrap_or(general.0)
                ),
            ));
        }
    }
    match (specific, general.1) {
        ((Some(name), Some(_)), Some(_)) => {
            p.push((
                format!("{key}.{}", general.0),
                format!("gives the same value as `{name}`: keep one"),
            ));
            (None, general.0)
        }
        ((Some(name), Some(v)), None) => (Some(v), name),
        (_, Some(v)) => (Some(v), general.0),
        ((name, _), None) => (None, name.unwrap_or(general.0)),
    }
}

impl SteeringFile {
    /// The law, or every problem with its key under `key`.
    pub fn check(&self, key: &str) -> Result<Steering, Vec<(String, String)>> {
        let mut p = Vec::new();
        let surface = self.surface;
        let (rudder_key, change_key) = surface.keys();
        // `rudder` is the rudder's own word: for another surface it is a wrong key
        let rudder_elsewhere = [("rudder", self.rudder)];
        let (first, first_key) = one_of(
            key,
            surface,
            (rudder_key, rudder_key.and(self.rudder)),
            if rudder_key.is_none() {
                &rudder_elsewhere[..]
            } else {
                &[]
            },
            ("deflection", self.deflection),
            &mut p,
        );
        let (wrong_change, other_change) = match surface {
            Surface::Rudder => ("pitch", self.pitch),
            Surface::SternPlanes => ("heading", self.heading),
        };
        let own_change = match surface {
            Surface::Rudder => self.heading,
            Surface::SternPlanes => self.pitch,
        };
        let (change, change_key) = one_of(
            key,
            surface,
            (Some(change_key), own_change),
            &[(wrong_change, other_change)],
            ("angle", self.angle),
            &mut p,
        );
        let first = first.unwrap_or(f64::NAN);
        let execute = self.check_limits(key, first, first_key, &mut p);
        let law = self.law(key, first, change, change_key, execute, &mut p);
        if p.is_empty() {
            Ok(law)
        } else {
            Err(p)
        }
    }

    /// Checks the first deflection, the rate and the time of execution; the execution time
    /// (0 s when not given).
    fn check_limits(
        &self,
        key: &str,
        first: f64,
        first_key: &str,
        p: &mut Vec<(String, String)>,
    ) -> f64 {
        if !(first.is_finite() && first != 0.0 && first.abs() <= 1.0) {
            p.push((
                format!("{key}.{first_key}"),
                format!(
                    "must be a {} angle other than 0 and at most 57 deg either side, got {} deg",
                    self.surface.words(),
                    first.to_degrees()
                ),
            ));
        }
        if !(self.rate.is_finite() && self.rate > 0.0) {
            p.push((
                format!("{key}.rate"),
                format!(
                    "must be a positive {} rate, e.g. \"2.32 deg/s\"",
                    self.surface.words()
                ),
            ));
        }
        let execute = self.execute.unwrap_or(0.0);
        if !(execute.is_finite() && execute >= 0.0) {
            p.push((
                format!("{key}.execute"),
                "must be a time from 0 s on".to_string(),
            ));
        }
        execute
    }

    /// The law of the helm's kind: a turn (which uses no heading change) or a zigzag
    /// (which needs one within the surface's largest change).
    fn law(
        &self,
        key: &str,
        first: f64,
        change: Option<f64>,
        change_key: &str,
        execute: f64,
        p: &mut Vec<(String, String)>,
    ) -> Steering {
        let surface = self.surface;
        match self.kind {
            SteeringKind::Turn => {
                if change.is_some() {
                    p.push((
                        format!("{key}.{change_key}"),
                        "is not used by a turning circle (only by a zigzag)".to_string(),
                    ));
                }
                Steering::Turn {
                    rudder: first,
                    rate: self.rate,
                    execute,
                    surface,
                }
            }
            SteeringKind::Zigzag => {
                let heading = change.unwrap_or(f64::NAN);
                let largest = surface.largest_change();
                if !(heading.is_finite() && heading > 0.0 && heading < largest) {
                    p.push((
                        format!("{key}.{change_key}"),
                        format!(
                            "a zigzag needs the {0} change that reverses the {1}, from 0 to {2} \
                             deg, e.g. {change_key} = \"{3} deg\"",
                            surface.watched_words(),
                            surface.words(),
                            largest.to_degrees(),
                            if surface == Surface::Rudder { 20 } else { 10 }
                        ),
                    ));
                }
                Steering::ZigZag {
                    rudder: first,
                    heading,
                    rate: self.rate,
                    execute,
                    surface,
                }
            }
        }
    }
}

/// The helm during a run: the surface's command and its angle, sample by sample. The
/// names speak of the rudder and the heading; on the stern planes read planes and pitch.
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
                ..
            }
            | Steering::ZigZag {
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
            surface: Surface::Rudder,
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
                surface: Surface::Rudder,
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
            rudder: Some(0.0),
            rate: -1.0,
            ..SteeringFile::default()
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
        // the stern planes: `rudder` and `heading` are the rudder's words, a pitch change
        // beyond 90 deg is no pitch
        let f = SteeringFile {
            kind: SteeringKind::Zigzag,
            surface: Surface::SternPlanes,
            rudder: Some(0.1),
            heading: Some(0.1),
            pitch: Some(2.0),
            rate: 0.1,
            ..SteeringFile::default()
        };
        let e = f.check("s").unwrap_err();
        let keys: Vec<&str> = e.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(
            keys,
            ["s.rudder", "s.heading", "s.deflection", "s.pitch"],
            "{e:?}"
        );
        // `deflection` and `angle` read for any surface; `heading` and `angle` together are
        // one value twice
        let f = SteeringFile {
            kind: SteeringKind::Zigzag,
            surface: Surface::SternPlanes,
            deflection: Some(0.1),
            angle: Some(0.1),
            rate: 0.1,
            ..SteeringFile::default()
        };
        assert_eq!(f.check("s").unwrap().surface(), Surface::SternPlanes);
        let f = SteeringFile {
            kind: SteeringKind::Zigzag,
            rudder: Some(0.1),
            heading: Some(0.1),
            angle: Some(0.1),
            rate: 0.1,
            ..SteeringFile::default()
        };
        let e = f.check("s").unwrap_err();
        assert_eq!(e[0].0, "s.angle", "{e:?}");
    }
}
