//! OpenFOAM `sixDoFRigidBodyState` output: `# Motion State`, `# Angle Units : radians` (or
//! degrees), `# Time centreOfRotation centreOfMass rotation velocity omega`, then rows
//! `t (x y z) (x y z) (roll pitch yaw) (u v w) (p q r)` with earth-frame velocities.
//!
//! No real file was available, so the reader goes by the column line: each name after
//! `Time` is a vector whose unit follows from the name (positions m, rotation per
//! `Angle Units`, velocities m/s, angular velocities in the angle unit per second). The
//! rotation vector becomes `roll`, `pitch`, `yaw`; other vectors `<name>_x`, `_y`, `_z`.

use super::{header, vector_rows, Shape};
use crate::base::error::InputError;
use crate::io::formats::columns::{apply_names, assemble, normalise, Head};
use crate::io::formats::text::Source;
use crate::io::formats::{Format, ReadOptions};
use crate::io::table::Table;

/// The columns OpenFOAM writes when the column line is missing.
const USUAL: [&str; 5] = [
    "centreOfRotation",
    "centreOfMass",
    "rotation",
    "velocity",
    "omega",
];

/// What a vector of the motion state is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Position,
    Angles,
    Velocity,
    AngularVelocity,
    Acceleration,
    AngularAcceleration,
    Other,
}

fn kind(name: &str) -> Kind {
    let n = normalise(name);
    let has = |w: &str| n.contains(w);
    if has("angularacceleration") || has("omegadot") {
        Kind::AngularAcceleration
    } else if has("omega") || has("angularvelocity") {
        Kind::AngularVelocity
    } else if has("acceleration") {
        Kind::Acceleration
    } else if has("velocity") || n == "v" || n == "u" {
        Kind::Velocity
    } else if has("centre") || has("center") || has("position") || has("displacement") {
        Kind::Position
    } else if has("rotation") || has("orientation") || has("angle") || has("euler") {
        Kind::Angles
    } else {
        Kind::Other
    }
}

/// Reads a sixDoFRigidBodyState file.
pub(crate) fn read(src: &Source, options: &ReadOptions) -> Result<Table, InputError> {
    let h = header(src);
    let mut warnings = Vec::new();
    let angle = match h.get("Angle Units") {
        Some((v, line)) => match normalise(v).as_str() {
            "radians" | "radian" | "rad" => "rad",
            "degrees" | "degree" | "deg" => "deg",
            _ => {
                return Err(InputError::new(
                    src.at(line),
                    format!("unknown angle unit '{v}' in the Angle Units line"),
                )
                .expected("'# Angle Units : radians' or '# Angle Units : degrees'"))
            }
        },
        None => {
            warnings.push("no '# Angle Units' line; angles read as radians".into());
            "rad"
        }
    };
    let groups: Vec<String> = match &h.columns {
        Some((i, tokens)) if tokens.len() < 2 => {
            return Err(
                InputError::new(src.at(*i), "the column line names no vectors")
                    .expected(format!("'# Time {}'", USUAL.join(" "))),
            )
        }
        Some((_, tokens)) => tokens[1..].to_vec(),
        None => {
            warnings.push(format!(
                "no '# Time ...' column line; vectors read as {}",
                USUAL.join(" ")
            ));
            USUAL.iter().map(|s| s.to_string()).collect()
        }
    };
    let mut heads = vec![Head::si("Time", "s")];
    let mut shapes = Vec::new();
    let mut angles_named = false;
    for g in &groups {
        let k = kind(g);
        let unit = match k {
            Kind::Position => Some("m".to_string()),
            Kind::Angles => Some(angle.to_string()),
            Kind::Velocity => Some("m/s".to_string()),
            Kind::AngularVelocity => Some(format!("{angle}/s")),
            Kind::Acceleration => Some("m/s^2".to_string()),
            Kind::AngularAcceleration => Some(format!("{angle}/s^2")),
            Kind::Other => {
                warnings.push(format!("vector '{g}' is not one hydroid knows; no unit"));
                None
            }
        };
        shapes.push(Shape::Vector {
            first: heads.len(),
            label: g.clone(),
        });
        let names: [String; 3] = if k == Kind::Angles && !angles_named {
            angles_named = true;
            ["roll".into(), "pitch".into(), "yaw".into()]
        } else {
            ["x", "y", "z"].map(|a| format!("{g}_{a}"))
        };
        for (n, a) in names.into_iter().zip(["x", "y", "z"]) {
            let mut h = match &unit {
                Some(u) => Head::si(n, u),
                None => Head::plain(n),
            };
            h.header = format!("{g} {a}");
            heads.push(h);
        }
    }
    let at = h.columns.as_ref().map_or(src.file(), |(i, _)| src.at(*i));
    apply_names(&mut heads, options, at)?;
    let names: Vec<String> = heads.iter().map(|h| h.name.clone()).collect();
    let rows = vector_rows(src, &h.data, &shapes, &names)?;
    Ok(assemble(
        src.path,
        Format::OpenFoamSixDof,
        heads,
        rows,
        h.meta,
        warnings,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds() {
        assert_eq!(kind("centreOfMass"), Kind::Position);
        assert_eq!(kind("centreOfRotation"), Kind::Position);
        assert_eq!(kind("rotation"), Kind::Angles);
        assert_eq!(kind("velocity"), Kind::Velocity);
        assert_eq!(kind("omega"), Kind::AngularVelocity);
        assert_eq!(kind("angularVelocity"), Kind::AngularVelocity);
        assert_eq!(kind("pressure"), Kind::Other);
    }
}
