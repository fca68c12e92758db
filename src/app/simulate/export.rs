//! Writes simulated SI columns in the layouts CFD codes export (see docs/formats.md), so that
//! synthetic runs exercise the same readers real exports do.

use super::config::{ExportColumn, ExportConfig};
use super::synth::Columns;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::units::{wrap_pi, Unit};
use crate::io::formats::Format;
use crate::numerics::frames::rotation_zyx;
use std::fmt::Write;

/// Renders the export as text.
pub fn render(layout: Format, cfg: &ExportConfig, cols: &Columns, title: &str) -> Result<String> {
    if layout == Format::OpenFoamSixDof {
        return sixdof(cfg, cols);
    }
    if layout == Format::OpenFoamForcesLegacy {
        return forces(cfg, cols);
    }
    let prepared = prepare(cfg, cols)?;
    let rows = prepared.first().map_or(0, |c| c.1.len());
    let mut s = String::new();
    let num = |v: f64| fmt_num(v, cfg.digits);
    match layout {
        Format::Delimited => {
            let sep = cfg.separator.clone().unwrap_or_else(|| ",".into());
            let names: Vec<&str> = cfg.columns.iter().map(|c| c.name.as_str()).collect();
            writeln!(s, "{}", names.join(&sep)).ok();
            for k in 0..rows {
                let row: Vec<String> = prepared.iter().map(|c| num(c.1[k])).collect();
                writeln!(s, "{}", row.join(&sep)).ok();
            }
        }
        Format::Cfx => {
            writeln!(s, "[Name]\n{title}\n\n[Data]").ok();
            let names: Vec<String> = prepared
                .iter()
                .map(|(c, _, u)| format!("{} [ {} ]", c.name, cfx_unit(u)))
                .collect();
            writeln!(s, "{}", names.join(", ")).ok();
            for k in 0..rows {
                let row: Vec<String> = prepared.iter().map(|c| num(c.1[k])).collect();
                writeln!(s, "{}", row.join(", ")).ok();
            }
        }
        Format::StarCcm => {
            let names: Vec<String> = prepared
                .iter()
                .map(|(c, _, u)| format!("\"{} ({})\"", c.name, u))
                .collect();
            writeln!(s, "{}", names.join(",")).ok();
            for k in 0..rows {
                let row: Vec<String> = prepared.iter().map(|c| num(c.1[k])).collect();
                writeln!(s, "{}", row.join(",")).ok();
            }
        }
        Format::Fluent => {
            let quoted: Vec<String> = std::iter::once("Time Step".to_string())
                .chain(prepared.iter().map(|c| c.0.name.clone()))
                .map(|n| format!("\"{n}\""))
                .collect();
            writeln!(s, "\"{title}\"").ok();
            writeln!(s, "{}", quoted.join(" ")).ok();
            writeln!(s, "({})", quoted.join(" ")).ok();
            for k in 0..rows {
                let row: Vec<String> = std::iter::once(k.to_string())
                    .chain(prepared.iter().map(|c| num(c.1[k])))
                    .collect();
                writeln!(s, "{}", row.join(" ")).ok();
            }
        }
        _ => {
            return Err(Error::Usage(format!("cannot write the {layout} layout")));
        }
    }
    Ok(s)
}

/// Each column converted to its export unit: (column, values, unit text).
fn prepare<'a>(
    cfg: &'a ExportConfig,
    cols: &Columns,
) -> Result<Vec<(&'a ExportColumn, Vec<f64>, String)>> {
    let mut out = Vec::new();
    for c in &cfg.columns {
        let derived;
        let v = match cols.get(&c.quantity) {
            Some(v) => v,
            None if Quantity::QUATERNION.contains(&c.quantity) && cols.contains_key(&Quantity::Yaw) => {
                derived = quaternion_part(cols, c.quantity);
                &derived
            }
            None => {
                return Err(Error::Usage(format!(
                    "export column '{}' asks for {}, which this manoeuvre does not produce (it gives {})",
                    c.name,
                    c.quantity,
                    cols.keys().map(|q| q.key()).collect::<Vec<_>>().join(", ")
                )))
            }
        };
        let internal = c.quantity.internal_unit();
        let (unit_text, factor) = match &c.unit {
            Some(u) => {
                let unit = Unit::parse(u).map_err(|e| Error::Usage(e.to_string()))?;
                (u.clone(), unit.factor)
            }
            None => (internal.text.clone(), internal.factor),
        };
        let wrap = cfg.wrap_angles && c.quantity.is_euler_angle();
        let values = v
            .iter()
            .map(|x| {
                let si = x * internal.factor;
                let si = if wrap { wrap_pi(si) } else { si };
                si / factor
            })
            .collect();
        out.push((c, values, unit_text));
    }
    Ok(out)
}

/// One part of the attitude quaternion (scalar first) from the roll, pitch and yaw columns
/// (a missing roll or pitch is zero), as a 6-DOF solver that tracks its orientation as a
/// quaternion writes it.
fn quaternion_part(cols: &Columns, part: Quantity) -> Vec<f64> {
    let k = Quantity::QUATERNION
        .iter()
        .position(|q| *q == part)
        .unwrap_or(0);
    let yaw = cols.get(&Quantity::Yaw).map_or(&[][..], Vec::as_slice);
    let angle = |q: Quantity, i: usize| cols.get(&q).map_or(0.0, |v| v[i]);
    (0..yaw.len())
        .map(|i| {
            crate::numerics::frames::quaternion_from_zyx(
                angle(Quantity::Roll, i),
                angle(Quantity::Pitch, i),
                yaw[i],
            )[k]
        })
        .collect()
}

/// CFX writes units with spaces between factors and `^-1` powers: `m s^-1`.
fn cfx_unit(u: &str) -> String {
    match u {
        "m/s" => "m s^-1".into(),
        "rad/s" => "radian s^-1".into(),
        "deg/s" => "degree s^-1".into(),
        "deg" => "degree".into(),
        "rad" => "radian".into(),
        "N m" | "N-m" => "N m".into(),
        other => other.to_string(),
    }
}

/// `t (x y z) (x y z) (roll pitch yaw) (u v w) (p q r)` with earth-frame velocities, as the
/// sixDoFRigidBodyState function object writes (docs/cfd-formats.md); angles and angular
/// velocity in the unit its `Angle Units` line names.
/// An OpenFOAM.org forces.dat (the `forces` function object of OpenFOAM.org 10: pressure
/// and viscous parts of the force and the moment about the centre of rotation, in N and
/// N m): the whole force written as the pressure part, the viscous part zero.
fn forces(cfg: &ExportConfig, cols: &Columns) -> Result<String> {
    let time = cols
        .get(&Quantity::Time)
        .ok_or_else(|| Error::Usage("a forces export needs time".into()))?;
    let n = time.len();
    let zero = vec![0.0; n];
    let g = |q: Quantity| cols.get(&q).unwrap_or(&zero);
    let num = |v: f64| fmt_num(v, cfg.digits);
    let mut s = String::new();
    writeln!(s, "# Forces").ok();
    writeln!(s, "# CofR        : (0 0 0)").ok();
    writeln!(
        s,
        "# Time        forces(pressure viscous)\tmoments(pressure viscous)"
    )
    .ok();
    for k in 0..n {
        let v = |a: Quantity, b: Quantity, c: Quantity| {
            format!("({} {} {})", num(g(a)[k]), num(g(b)[k]), num(g(c)[k]))
        };
        writeln!(
            s,
            "{}\t({} (0 0 0)) ({} (0 0 0))",
            num(time[k]),
            v(Quantity::Fx, Quantity::Fy, Quantity::Fz),
            v(Quantity::Mx, Quantity::My, Quantity::Mz)
        )
        .ok();
    }
    Ok(s)
}

fn sixdof(cfg: &ExportConfig, cols: &Columns) -> Result<String> {
    let get = |q: Quantity| cols.get(&q);
    let time =
        get(Quantity::Time).ok_or_else(|| Error::Usage("a sixDoF export needs time".into()))?;
    let n = time.len();
    let zero = vec![0.0; n];
    let g = |q: Quantity| get(q).unwrap_or(&zero);
    let degrees = cfg
        .columns
        .iter()
        .find(|c| c.quantity.is_euler_angle())
        .and_then(|c| c.unit.as_deref())
        .is_some_and(|u| u.starts_with("deg"));
    let ang = |a: f64| {
        let a = if cfg.wrap_angles { wrap_pi(a) } else { a };
        if degrees {
            a.to_degrees()
        } else {
            a
        }
    };
    let num = |v: f64| fmt_num(v, cfg.digits);
    let mut s = String::new();
    writeln!(s, "# Motion State").ok();
    writeln!(
        s,
        "# Angle Units : {}",
        if degrees { "degrees" } else { "radians" }
    )
    .ok();
    writeln!(
        s,
        "# Time  centreOfRotation  centreOfMass  rotation  velocity  omega"
    )
    .ok();
    for k in 0..n {
        let (phi, th, psi) = (
            g(Quantity::Roll)[k],
            g(Quantity::Pitch)[k],
            g(Quantity::Yaw)[k],
        );
        let r = rotation_zyx(phi, th, psi);
        let body = [g(Quantity::U)[k], g(Quantity::V)[k], g(Quantity::W)[k]];
        let rates = [g(Quantity::P)[k], g(Quantity::Q)[k], g(Quantity::R)[k]];
        let earth =
            |v: [f64; 3]| [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2]);
        let vel = earth(body);
        // the angular velocity is written in the file's angle unit, per second
        let om = earth(rates).map(|w| if degrees { w.to_degrees() } else { w });
        let pos = [g(Quantity::X)[k], g(Quantity::Y)[k], g(Quantity::Z)[k]];
        let v3 = |a: [f64; 3]| format!("({} {} {})", num(a[0]), num(a[1]), num(a[2]));
        writeln!(
            s,
            "{} {} {} ({} {} {}) {} {}",
            num(time[k]),
            v3(pos),
            v3(pos),
            num(ang(phi)),
            num(ang(th)),
            num(ang(psi)),
            v3(vel),
            v3(om)
        )
        .ok();
    }
    Ok(s)
}

/// A number rounded to `digits` significant digits, written plainly for moderate
/// magnitudes and in exponent form otherwise, as CFD codes do.
fn fmt_num(v: f64, digits: usize) -> String {
    let rounded: f64 = format!("{:.*e}", digits.saturating_sub(1), v)
        .parse()
        .unwrap_or(v);
    if rounded == 0.0 {
        "0".into()
    } else if (1e-4..1e7).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip() {
        for v in [3.0, -0.001234567891234, 12345.678, 1e-9, -2.5e7] {
            let s = fmt_num(v, 10);
            let back: f64 = s.parse().unwrap();
            assert!((back - v).abs() <= 1e-9 * v.abs(), "{v} -> {s}");
        }
        assert_eq!(fmt_num(3.0, 10), "3");
        assert_eq!(fmt_num(0.5, 10), "0.5");
        assert_eq!(fmt_num(1.23456789012e-6, 4), "1.235e-6");
        assert_eq!(fmt_num(-12.0, 8), "-12");
    }
}
