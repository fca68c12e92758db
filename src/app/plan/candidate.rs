//! Candidate runs: what a planned CFD run or basin test is (its kind and parameters, the noise
//! expected on its measurements, its cost), a user's own list read from TOML
//! (`--candidates FILE`, by [`super::limits::read`]), and the default set per model from what
//! the model can be run through: captive conditions when it gives captive forces, rudder
//! runs, turning circles and zig-zags when it has a rudder, vertical zig-zags and a helix when
//! it has stern planes, free runs from an initial sway or yaw when it has no rudder.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What kind of run a candidate is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A steady captive condition held for `duration_s` (ITTC 7.5-02-06-02): static drift
    /// (`drift_deg`), rudder (`rudder_deg`), circular motion (`yaw_rate_deg_s`) or any mix;
    /// a polar point is a static drift run.
    Static,
    /// Harmonic PMM pure sway (ITTC 7.5-02-06-04): v = `amplitude` sin(2 pi f t), m/s.
    PmmSway,
    /// Harmonic PMM pure yaw: r = `amplitude` sin(2 pi f t), deg/s, with v = 0.
    PmmYaw,
    /// Turning circle: the rudder to `rudder_deg` at t = 0 and held.
    Turn,
    /// Zig-zag `rudder_deg` / `heading_deg`.
    Zigzag,
    /// A free run from an initial sway `v0` (m/s) and yaw rate `r0_deg_s` with the inputs
    /// held (a vehicle without a rudder, as the spheroid's manoeuvres).
    Free,
    /// Vertical zig-zag `planes_deg` / `pitch_deg` on the stern planes (an underwater
    /// vehicle).
    ZigzagVertical,
    /// Helix: the rudder to `rudder_deg` and the stern planes held at `planes_deg`.
    Helix,
}

impl Kind {
    /// Whether the run is captive (forces measured along a prescribed motion).
    pub fn is_captive(self) -> bool {
        matches!(self, Kind::Static | Kind::PmmSway | Kind::PmmYaw)
    }

    /// Whether the run is a PMM run (a harmonic motion whose forces are fitted over whole
    /// periods).
    pub fn is_pmm(self) -> bool {
        matches!(self, Kind::PmmSway | Kind::PmmYaw)
    }
}

/// One candidate run. Angles in degrees and rates in deg/s as written; SI otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Candidate {
    /// A name for the table.
    pub name: String,
    /// Its kind.
    pub kind: Kind,
    /// Carriage or approach speed, m/s (default: the first fitted run's initial u).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// Drift angle beta, deg (static), with v = -U sin(beta).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub drift_deg: f64,
    /// Yaw rate, deg/s (static: circular motion).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub yaw_rate_deg_s: f64,
    /// Rudder angle, deg (static, turn, first rudder of a zig-zag).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rudder_deg: f64,
    /// Zig-zag heading change that reverses the rudder, deg.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub heading_deg: f64,
    /// Stern planes angle, deg (vertical zig-zag, helix).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub planes_deg: f64,
    /// Vertical zig-zag pitch change that reverses the planes, deg.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub pitch_deg: f64,
    /// PMM amplitude: sway velocity (m/s) or yaw rate (deg/s).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub amplitude: f64,
    /// PMM frequency, Hz.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub frequency_hz: f64,
    /// Initial sway velocity of a free run, m/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub v0: f64,
    /// Initial yaw rate of a free run, deg/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub r0_deg_s: f64,
    /// Duration, s (default: captive 10 s, a PMM run at least 3 periods; manoeuvres the first
    /// fitted run's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Sample interval, s (default: captive 0.01 s, manoeuvres the first fitted run's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt_s: Option<f64>,
    /// Expected noise standard deviation of each measured channel per sample, by quantity
    /// key (`fx`, `fy`, `mz`; `u`, `v`, `r`, `yaw` ...): a number in SI or a string with its
    /// unit (`"0.2 N"`, `"0.05 deg"`); missing ones take the planner's defaults
    /// (docs/planner.md).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub noise: BTreeMap<String, crate::base::si::Constant>,
    /// Cost, CPU hours (or any unit, the same for all candidates).
    #[serde(default = "one")]
    pub cost: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn one() -> f64 {
    1.0
}

impl Candidate {
    /// A candidate of `kind` named `name` with every parameter at its default.
    pub fn new(name: impl Into<String>, kind: Kind, cost: f64) -> Self {
        Candidate {
            name: name.into(),
            kind,
            speed: None,
            drift_deg: 0.0,
            yaw_rate_deg_s: 0.0,
            rudder_deg: 0.0,
            heading_deg: 0.0,
            planes_deg: 0.0,
            pitch_deg: 0.0,
            amplitude: 0.0,
            frequency_hz: 0.0,
            v0: 0.0,
            r0_deg_s: 0.0,
            duration_s: None,
            dt_s: None,
            noise: BTreeMap::new(),
            cost,
        }
    }

    /// The parameters in words, for the table.
    pub fn parameters(&self) -> String {
        let mut p = Vec::new();
        if let Some(s) = self.speed {
            p.push(format!("U {s} m/s"));
        }
        let mut add = |v: f64, what: &str| {
            if v != 0.0 {
                p.push(format!("{what} {v}"));
            }
        };
        add(self.drift_deg, "beta deg");
        add(self.yaw_rate_deg_s, "r deg/s");
        add(self.rudder_deg, "rudder deg");
        add(self.heading_deg, "psi deg");
        add(self.planes_deg, "planes deg");
        add(self.pitch_deg, "theta deg");
        match self.kind {
            Kind::PmmSway => add(self.amplitude, "v_a m/s"),
            Kind::PmmYaw => add(self.amplitude, "r_a deg/s"),
            _ => {}
        }
        add(self.frequency_hz, "f Hz");
        add(self.v0, "v0 m/s");
        add(self.r0_deg_s, "r0 deg/s");
        p.join(", ")
    }
}

/// Cost of a default captive run, CPU hours (a placeholder: a user's list gives its own).
pub const CAPTIVE_COST: f64 = 40.0;
/// Cost of a default PMM run, CPU hours (a placeholder).
pub const PMM_COST: f64 = 80.0;
/// Cost of a default free-running manoeuvre, CPU hours (a placeholder).
pub const MANOEUVRE_COST: f64 = 150.0;

/// What a model can be run through, for its default candidates.
#[derive(Debug, Clone, Copy)]
pub struct Abilities {
    /// It gives captive forces.
    pub captive: bool,
    /// It has a rudder input.
    pub rudder: bool,
    /// It has stern planes.
    pub planes: bool,
    /// Its operating speed, m/s, and length, m.
    pub speed: f64,
    /// Length, m.
    pub length: f64,
}

/// The default candidates of a model: captive conditions (static drift, polar points at half
/// the speed, circular motion, PMM pure sway and yaw) when it gives captive forces, rudder
/// and drift-with-yaw conditions, turning circles and zig-zags when it has a rudder, free
/// runs from an initial sway or yaw when it has none.
pub fn defaults(a: Abilities) -> Vec<Candidate> {
    let mut out = Vec::new();
    if a.captive {
        for beta in [2.0, 5.0, 10.0, 15.0, 20.0] {
            let mut c = Candidate::new(
                format!("static drift {beta} deg"),
                Kind::Static,
                CAPTIVE_COST,
            );
            c.drift_deg = beta;
            out.push(c);
        }
        for beta in [5.0, 10.0] {
            let mut c = Candidate::new(
                format!("polar point {beta} deg at U/2"),
                Kind::Static,
                CAPTIVE_COST,
            );
            c.drift_deg = beta;
            c.speed = Some(round3(0.5 * a.speed));
            out.push(c);
        }
        // circular motion at r' = r L / U of 0.2, 0.4, 0.6
        for rp in [0.2, 0.4, 0.6] {
            let r = (rp * a.speed / a.length).to_degrees();
            let mut c = Candidate::new(
                format!("circular motion r' {rp}"),
                Kind::Static,
                CAPTIVE_COST,
            );
            c.yaw_rate_deg_s = round3(r);
            out.push(c);
            let mut c = Candidate::new(
                format!("drift 10 deg in circular motion r' {rp}"),
                Kind::Static,
                CAPTIVE_COST,
            );
            c.yaw_rate_deg_s = round3(r);
            c.drift_deg = 10.0;
            out.push(c);
        }
        out.extend(pmm_defaults(a));
    }
    if a.planes {
        out.extend(planes_defaults());
    }
    if a.rudder {
        out.extend(rudder_defaults(a));
    } else {
        out.extend(free_defaults(a));
    }
    out
}

/// Rounds to three significant decimals (readable defaults).
fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// PMM pure sway at v_a of 5 and 10 % of U and pure yaw at r' of 0.2 and 0.4, each at two
/// frequencies (non-dimensional omega' = omega L / U of 1 and 2).
fn pmm_defaults(a: Abilities) -> Vec<Candidate> {
    let mut out = Vec::new();
    for wp in [1.0, 2.0] {
        let f = round3(wp * a.speed / a.length / (2.0 * std::f64::consts::PI));
        for share in [0.05, 0.1] {
            let mut c = Candidate::new(
                format!("PMM pure sway {share} U, {f} Hz"),
                Kind::PmmSway,
                PMM_COST,
            );
            c.amplitude = round3(share * a.speed);
            c.frequency_hz = f;
            out.push(c);
        }
        for rp in [0.2, 0.4] {
            let mut c = Candidate::new(
                format!("PMM pure yaw r' {rp}, {f} Hz"),
                Kind::PmmYaw,
                PMM_COST,
            );
            c.amplitude = round3((rp * a.speed / a.length).to_degrees());
            c.frequency_hz = f;
            out.push(c);
        }
    }
    out
}

/// Vertical zig-zags 10/10 and 20/10 and a helix (rudder 20 deg, planes 10 deg).
fn planes_defaults() -> Vec<Candidate> {
    let mut out = Vec::new();
    for d in [10.0, 20.0] {
        let mut c = Candidate::new(
            format!("vertical zig-zag {d}/10"),
            Kind::ZigzagVertical,
            MANOEUVRE_COST,
        );
        c.planes_deg = d;
        c.pitch_deg = 10.0;
        out.push(c);
    }
    let mut c = Candidate::new(
        "helix rudder 20 deg, planes 10 deg",
        Kind::Helix,
        MANOEUVRE_COST,
    );
    c.rudder_deg = 20.0;
    c.planes_deg = 10.0;
    out.push(c);
    out
}

/// Rudder conditions, turning circles and zig-zags.
fn rudder_defaults(a: Abilities) -> Vec<Candidate> {
    let mut out = Vec::new();
    if a.captive {
        for d in [10.0, 20.0, 35.0] {
            let mut c =
                Candidate::new(format!("static rudder {d} deg"), Kind::Static, CAPTIVE_COST);
            c.rudder_deg = d;
            out.push(c);
        }
    }
    for d in [10.0, 20.0, 35.0] {
        let mut c = Candidate::new(
            format!("turning circle {d} deg"),
            Kind::Turn,
            MANOEUVRE_COST,
        );
        c.rudder_deg = d;
        out.push(c);
    }
    for d in [10.0, 20.0] {
        let mut c = Candidate::new(format!("zig-zag {d}/{d}"), Kind::Zigzag, MANOEUVRE_COST);
        c.rudder_deg = d;
        c.heading_deg = d;
        out.push(c);
    }
    out
}

/// Free runs from an initial sway of a sixth and a third of U, from an initial yaw rate of
/// r' 0.3, and both.
fn free_defaults(a: Abilities) -> Vec<Candidate> {
    let r = round3((0.3 * a.speed / a.length).to_degrees());
    [
        (a.speed / 6.0, 0.0),
        (a.speed / 3.0, 0.0),
        (0.0, r),
        (a.speed / 6.0, r),
    ]
    .into_iter()
    .map(|(v0, r0)| {
        let mut c = Candidate::new(
            format!("free run v0 {:.3} m/s, r0 {r0} deg/s", v0),
            Kind::Free,
            MANOEUVRE_COST,
        );
        c.v0 = round3(v0);
        c.r0_deg_s = r0;
        c
    })
    .collect()
}
