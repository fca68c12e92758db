//! The quantity a column probably is, guessed from its name and unit for `hydroid inspect`.

use crate::base::quantity::Quantity;
use crate::base::units::Unit;

/// Splits a column name into lower-case words: `centreOfMass_x` -> centre of mass x,
/// `Position[X]` -> position x, `Monitor Point: Fy` -> monitor point fy.
fn words(name: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    let mut prev_lower = false;
    for c in name.chars() {
        if !c.is_alphanumeric() {
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            prev_lower = false;
            continue;
        }
        if c.is_uppercase() && prev_lower && !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
        prev_lower = c.is_lowercase() || c.is_ascii_digit();
        cur.extend(c.to_lowercase());
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The quantity a column probably is, from its name and unit; `None` when unsure.
///
/// A guess for `hydroid inspect`, never used to map columns silently: the configuration
/// maps columns. The unit, when given, must have the quantity's dimension.
pub fn guess_quantity(name: &str, unit: Option<&Unit>) -> Option<Quantity> {
    // Monitor names (`Drag Coefficient Monitor: Cd`): the quantity after the colon first.
    if let Some((_, last)) = name.rsplit_once(':') {
        if let Some(q) = guess_words(last, unit) {
            return Some(q);
        }
    }
    guess_words(name, unit)
}

/// The quantity a column's name (and unit, when given) names: by a single word, or by the
/// words of a phrase; None when the unit's dimension contradicts the guess.
fn guess_words(name: &str, unit: Option<&Unit>) -> Option<Quantity> {
    use Quantity::*;
    let w = name_words(name);
    let has = |s: &str| w.iter().any(|x| x == s);
    let dim = unit.map(|u| u.dim);
    let axis = ["x", "y", "z"].iter().position(|a| has(a));
    let pick = |qs: [Quantity; 3]| axis.map(|a| qs[a]);
    // `total_x` (ESI force.dat and moment.dat): force or moment by the unit.
    if words(name).iter().any(|x| x == "total") && axis.is_some() {
        return match dim {
            Some(d) if d == Fx.dim() => pick([Fx, Fy, Fz]),
            Some(d) if d == Mx.dim() => pick([Mx, My, Mz]),
            _ => None,
        };
    }
    let single = if w.len() == 1 { w[0].as_str() } else { "" };
    let guess = single_word(single, axis).or_else(|| phrase(&w, axis))?;
    match dim {
        Some(d) if d != guess.dim() => None,
        _ => Some(guess),
    }
}

/// The words of a column's name that may name a quantity: without filler words
/// (`monitor`, `report`, `of`, ...), numbers and repeats.
fn name_words(name: &str) -> Vec<String> {
    const NOISE: &[&str] = &[
        "monitor",
        "point",
        "expression",
        "report",
        "def",
        "physical",
        "flow",
        "value",
        "of",
        "the",
        "body",
        "total",
    ];
    let mut w: Vec<String> = Vec::new();
    for x in words(name) {
        if !NOISE.contains(&x.as_str()) && !x.chars().all(|c| c.is_ascii_digit()) && !w.contains(&x)
        {
            w.push(x);
        }
    }
    w
}

/// The quantity a single word names (`x`, `y`, `z` a position along `axis`).
fn single_word(single: &str, axis: Option<usize>) -> Option<Quantity> {
    use Quantity::*;
    match single {
        "time" | "t" => Some(Time),
        "x" | "y" | "z" => axis.map(|a| [X, Y, Z][a]),
        "roll" | "phi" => Some(Roll),
        "pitch" | "theta" => Some(Pitch),
        "yaw" | "psi" | "heading" => Some(Yaw),
        "u" => Some(U),
        "v" => Some(V),
        "w" => Some(W),
        "p" => Some(P),
        "q" => Some(Q),
        "r" => Some(R),
        "udot" => Some(UDot),
        "fx" => Some(Fx),
        "fy" => Some(Fy),
        "fz" => Some(Fz),
        "mx" => Some(Mx),
        "my" => Some(My),
        "mz" => Some(Mz),
        "cd" => Some(Cd),
        "cl" => Some(Cl),
        "cm" => Some(Cm),
        "cs" => Some(Cs),
        "alpha" | "aoa" | "drift" | "beta" => Some(Alpha),
        "speed" | "uinf" => Some(Speed),
        "thrust" => Some(Thrust),
        "rudder" | "delta" => Some(Rudder),
        "stern_planes" | "sternplanes" | "elevator" | "delta_s" => Some(SternPlanes),
        "bow_planes" | "bowplanes" | "delta_b" => Some(BowPlanes),
        "rpm" | "rps" | "revs" => Some(Rpm),
        _ => None,
    }
}

/// The quantity the words of a phrase name (`angular velocity z`, `rudder angle`, ...), with
/// `axis` the component an x, y or z among them picks.
fn phrase(w: &[String], axis: Option<usize>) -> Option<Quantity> {
    use Quantity::*;
    let has = |s: &str| w.iter().any(|x| x == s);
    let only = |s: &[&str]| w.len() == s.len() && s.iter().all(|x| has(x));
    let pick = |qs: [Quantity; 3]| axis.map(|a| qs[a]);
    if only(&["cm", "pitch"]) {
        Some(Cm)
    } else if only(&["u", "dot"]) || only(&["surge", "acceleration"]) {
        Some(UDot)
    } else if has("omega") || (has("angular") && has("velocity")) || has("rate") {
        match (
            axis,
            w.iter()
                .find(|x| ["p", "q", "r", "roll", "pitch", "yaw"].contains(&x.as_str())),
        ) {
            (Some(_), _) => pick([P, Q, R]),
            (None, Some(s)) => match s.as_str() {
                "p" | "roll" => Some(P),
                "q" | "pitch" => Some(Q),
                _ => Some(R),
            },
            _ => None,
        }
    } else if has("thrust") {
        Some(Thrust)
    } else if has("velocity") || has("vel") {
        if has("magnitude") || has("inlet") || has("freestream") || has("inflow") {
            Some(Speed)
        } else if let Some(a) = axis {
            Some([U, V, W][a])
        } else {
            ["u", "v", "w"]
                .iter()
                .position(|s| has(s))
                .map(|k| [U, V, W][k])
        }
    } else if has("force") && !has("pressure") && !has("viscous") && !has("porous") {
        pick([Fx, Fy, Fz])
    } else if has("moment") && !has("pressure") && !has("viscous") && !has("porous") {
        pick([Mx, My, Mz])
    } else if has("position") || has("centre") || has("center") || has("cog") {
        pick([X, Y, Z])
    } else if only(&["angle", "attack"]) || only(&["drift", "angle"]) {
        Some(Alpha)
    } else if only(&["rudder", "angle"]) {
        Some(Rudder)
    } else if only(&["propeller", "speed"]) {
        Some(Rpm)
    } else if only(&["stern", "planes"]) || only(&["stern", "plane"]) {
        // `stern_planes`, `Stern Planes`: the words of the single names above
        Some(SternPlanes)
    } else if only(&["bow", "planes"]) || only(&["bow", "plane"]) {
        Some(BowPlanes)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(name: &str, unit: Option<&str>) -> Option<Quantity> {
        let u = unit.map(|u| Unit::parse(u).unwrap());
        guess_quantity(name, u.as_ref())
    }

    #[test]
    fn guesses() {
        assert_eq!(g("Velocity u", Some("m s^-1")), Some(Quantity::U));
        assert_eq!(g("Position[X]", Some("m")), Some(Quantity::X));
        assert_eq!(g("centreOfMass_y", Some("m")), Some(Quantity::Y));
        assert_eq!(g("omega_z", Some("rad/s")), Some(Quantity::R));
        assert_eq!(
            g("Angular Velocity r", Some("degree s^-1")),
            Some(Quantity::R)
        );
        assert_eq!(g("Heading", Some("degree")), Some(Quantity::Yaw));
        assert_eq!(g("stern_planes", Some("deg")), Some(Quantity::SternPlanes));
        assert_eq!(g("Bow Planes", Some("degree")), Some(Quantity::BowPlanes));
        assert_eq!(g("Monitor Point: Fy", Some("N")), Some(Quantity::Fy));
        assert_eq!(g("Force X Monitor: Force", Some("N")), Some(Quantity::Fx));
        assert_eq!(g("total_z", Some("N m")), Some(Quantity::Mz));
        assert_eq!(g("force_total_x", Some("N")), Some(Quantity::Fx));
        assert_eq!(g("force_pressure_x", Some("N")), None);
        assert_eq!(g("CmPitch", None), Some(Quantity::Cm));
        assert_eq!(g("Cl(f)", None), None);
        assert_eq!(g("Cd", Some("1")), Some(Quantity::Cd));
        assert_eq!(
            g("u", Some("deg")),
            None,
            "a wrong dimension rules a guess out"
        );
        assert_eq!(g("Temperature", None), None);
        assert_eq!(
            g("Drag Coefficient Monitor: Cd", Some("-")),
            Some(Quantity::Cd)
        );
        assert_eq!(
            g("Thrust Monitor: Force", Some("N")),
            Some(Quantity::Thrust)
        );
        assert_eq!(g("Inlet Velocity", Some("m/s")), Some(Quantity::Speed));
        assert_eq!(
            g("yaw rate Monitor: Expression", Some("deg/s")),
            Some(Quantity::R)
        );
        assert_eq!(g("Angle of Attack", Some("deg")), Some(Quantity::Alpha));
    }
}
