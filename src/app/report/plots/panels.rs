//! Which time-history panels a run's figures have, and in what order, read from the model's
//! own state list and inputs: every state the run measures (or, for a fit run, the smoother
//! estimates) gets a panel in the figure of its plane, and every control input that moves in
//! the run is drawn right under the state it drives (the rudder under the heading, the stern
//! and bow planes under the pitch, the propeller under the surge speed). A state hydroid does
//! not know how to place gets a panel in a figure of its own, so a new model's states always
//! appear.

use super::runs::RunView;
use crate::base::quantity::Quantity;

const DEG: f64 = 180.0 / std::f64::consts::PI;

/// The figure a panel belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Plane {
    /// Heading, yaw rate, sway and surge, and the rudder and propeller.
    Horizontal,
    /// Depth, pitch, heave and pitch rate, and the stern and bow planes.
    Vertical,
    /// Roll and roll rate.
    Roll,
    /// States of no plane hydroid knows.
    Other,
}

impl Plane {
    /// The figure family's file stem prefix.
    pub fn family(self) -> &'static str {
        match self {
            Plane::Horizontal => "states",
            Plane::Vertical => "vertical",
            Plane::Roll => "roll",
            Plane::Other => "other",
        }
    }

    /// What the figure is called, before the run's label.
    pub fn title(self) -> &'static str {
        match self {
            Plane::Horizontal => "Heading and horizontal motion",
            Plane::Vertical => "Depth and pitch",
            Plane::Roll => "Roll",
            Plane::Other => "Further states",
        }
    }
}

/// How a quantity is drawn: its figure, axis description (with the unit shown) and the
/// factor from SI to that unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Shown {
    /// The quantity.
    pub quantity: Quantity,
    /// The figure it is drawn in.
    pub plane: Plane,
    /// Axis description with the unit, e.g. "heading ψ (deg)".
    pub label: String,
    /// Factor from SI to the unit of the label.
    pub factor: f64,
    /// For a control input, the state it drives (drawn right under it).
    pub drives: Option<Quantity>,
}

/// How `q` is drawn.
pub fn shown(q: Quantity) -> Shown {
    use Plane::*;
    use Quantity as Q;
    let (plane, label, factor, drives): (Plane, &str, f64, Option<Quantity>) = match q {
        Q::Yaw => (Horizontal, "heading ψ (deg)", DEG, None),
        Q::R => (Horizontal, "yaw rate r (deg/s)", DEG, None),
        Q::V => (Horizontal, "sway v (m/s)", 1.0, None),
        Q::U => (Horizontal, "surge u (m/s)", 1.0, None),
        Q::WaveYaw => (Horizontal, "wave-induced yaw ψ_H (deg)", DEG, None),
        Q::WaveYawIntegral => (Horizontal, "ξ = ∫ψ_H dt (deg s)", DEG, None),
        Q::Z => (Vertical, "depth z (m)", 1.0, None),
        Q::Pitch => (Vertical, "pitch θ (deg)", DEG, None),
        Q::W => (Vertical, "heave w (m/s)", 1.0, None),
        Q::Q => (Vertical, "pitch rate q (deg/s)", DEG, None),
        Q::Roll => (Roll, "roll φ (deg)", DEG, None),
        Q::P => (Roll, "roll rate p (deg/s)", DEG, None),
        Q::Rudder => (Horizontal, "rudder δ (deg)", DEG, Some(Q::Yaw)),
        Q::SternPlanes => (Vertical, "stern planes (deg)", DEG, Some(Q::Pitch)),
        Q::BowPlanes => (Vertical, "bow planes (deg)", DEG, Some(Q::Pitch)),
        Q::Rpm => (Horizontal, "propeller n (rpm)", 60.0, Some(Q::U)),
        Q::Thrust => (Horizontal, "thrust T (N)", 1.0, Some(Q::U)),
        q => {
            return Shown {
                quantity: q,
                plane: Other,
                label: format!("{} ({})", q.key(), q.si_symbol()),
                factor: 1.0,
                drives: None,
            }
        }
    };
    Shown {
        quantity: q,
        plane,
        label: label.to_string(),
        factor,
        drives,
    }
}

/// The unit of an axis description: the text in its last parentheses.
pub fn unit_of(label: &str) -> &str {
    label
        .rsplit_once('(')
        .map_or("", |(_, u)| u.trim_end_matches(')'))
}

/// What one panel shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// How its quantity is drawn.
    pub shown: Shown,
    /// A control input (drawn as given, without a model or a difference).
    pub control: bool,
    /// The run measures it (a difference panel goes under it).
    pub measured: bool,
}

/// The panels of `run` by figure, in the figures' order; states in the model's order within
/// their plane's order, each control under the state it drives.
pub fn panels(run: &RunView) -> Vec<(Plane, Vec<Panel>)> {
    let mut states: Vec<Panel> = run
        .sim
        .quantities
        .iter()
        .filter(|q| !matches!(q, Quantity::X | Quantity::Y))
        .filter(|q| run.measured(**q).is_some() || run.smoothed(**q).is_some())
        .map(|q| Panel {
            shown: shown(*q),
            control: false,
            measured: run.measured(*q).is_some(),
        })
        .collect();
    states.sort_by_key(|p| (p.shown.plane, order(p.shown.quantity)));
    let controls: Vec<Panel> = run
        .sim
        .inputs
        .iter()
        .filter(|q| run.measured(**q).is_some_and(moves))
        .map(|q| Panel {
            shown: shown(*q),
            control: true,
            measured: true,
        })
        .collect();
    let mut out: Vec<(Plane, Vec<Panel>)> = Vec::new();
    for p in states {
        match out.last_mut() {
            Some((plane, v)) if *plane == p.shown.plane => v.push(p),
            _ => out.push((p.shown.plane, vec![p])),
        }
    }
    for c in controls {
        place_control(&mut out, c);
    }
    out
}

/// Puts a control panel under the state it drives, else at the end of its plane's figure
/// (a figure of its own when the plane has none).
fn place_control(out: &mut Vec<(Plane, Vec<Panel>)>, c: Panel) {
    let plane = c.shown.plane;
    if let Some((_, v)) = out.iter_mut().find(|(p, _)| *p == plane) {
        let at = v
            .iter()
            .rposition(|p| Some(p.shown.quantity) == c.shown.drives || p.control)
            .map_or(v.len(), |i| i + 1);
        v.insert(at, c);
    } else {
        let at = out.partition_point(|(p, _)| *p < plane);
        out.insert(at, (plane, vec![c]));
    }
}

/// The order of the states within a figure: the attitude and position a naval architect
/// reads first, then the rates and velocities.
fn order(q: Quantity) -> usize {
    const ORDER: [Quantity; 12] = [
        Quantity::Yaw,
        Quantity::R,
        Quantity::V,
        Quantity::U,
        Quantity::WaveYaw,
        Quantity::WaveYawIntegral,
        Quantity::Z,
        Quantity::Pitch,
        Quantity::W,
        Quantity::Q,
        Quantity::Roll,
        Quantity::P,
    ];
    ORDER.iter().position(|x| *x == q).unwrap_or(ORDER.len())
}

/// Whether a control input moves in the run (a constant one is named in the caption
/// instead of drawn).
fn moves(v: &[f64]) -> bool {
    let (lo, hi) = crate::numerics::signal::range(v.iter().copied());
    hi - lo > 1e-12 * (1.0 + hi.abs().max(lo.abs()))
}

/// The control inputs of `run` that are constant over it, in words ("propeller n 500 rpm"),
/// from its columns or its configured constants.
pub fn constant_inputs(run: &RunView) -> Vec<String> {
    run.sim
        .inputs
        .iter()
        .filter_map(|q| {
            let value = match run.measured(*q) {
                Some(v) if !moves(v) => *v.first()?,
                Some(_) => return None,
                None => *run.record.constants.get(q)?,
            };
            let s = shown(*q);
            let name = s.label.rsplit_once(" (").map_or(s.label.as_str(), |x| x.0);
            Some(format!(
                "{name} {} {}",
                crate::base::numfmt::num(value * s.factor),
                unit_of(&s.label)
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_motion_state_has_a_place_and_a_unit() {
        for q in Quantity::MOTION {
            let s = shown(q);
            if !matches!(q, Quantity::X | Quantity::Y) {
                assert_ne!(s.plane, Plane::Other, "{q}");
            }
            assert!(!unit_of(&s.label).is_empty(), "{q}");
        }
        let other = shown(Quantity::Cd);
        assert_eq!(other.plane, Plane::Other);
        assert_eq!(other.label, "cd (-)");
        assert_eq!(unit_of("heading ψ (deg)"), "deg");
    }
}
