//! Legacy OpenFOAM forces.dat (OpenFOAM 2.x to OpenFOAM.org 10 and older ESI):
//! `t ((px py pz) (vx vy vz) (ox oy oz)) ((mpx mpy mpz) (...) (...))` under
//! `# Time forces(pressure viscous porous) moment(pressure viscous porous)`; OpenFOAM.org 10
//! writes two parts, `forces(pressure viscous) moments(pressure viscous)`.
//!
//! Each vector becomes three columns named `<group>_<part>_<x|y|z>` (`force_pressure_x`,
//! `moment_viscous_z`) and each group gets a `<group>_total_<x|y|z>` sum of its parts.

use super::{header, vector_rows, Shape};
use crate::base::error::InputError;
use crate::io::formats::columns::{apply_names, assemble, Head};
use crate::io::formats::text::{parse_brackets, Node, Source};
use crate::io::formats::{Format, ReadOptions};
use crate::io::table::Table;

/// A bracketed group of the header: `forces(pressure viscous porous)`.
#[derive(Debug, Clone, PartialEq)]
struct Group {
    name: String,
    label: String,
    parts: Vec<String>,
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// Reads a legacy forces.dat.
pub(crate) fn read(src: &Source, options: &ReadOptions) -> Result<Table, InputError> {
    let h = header(src);
    let mut warnings = Vec::new();
    let groups = match &h.columns {
        Some((i, tokens)) => {
            let groups: Vec<Group> = tokens[1..].iter().filter_map(|t| group(t)).collect();
            if groups.is_empty() || groups.len() + 1 != tokens.len() {
                return Err(InputError::new(
                    src.at(*i),
                    format!("cannot read the column line '# {}'", tokens.join(" ")),
                )
                .expected(
                    "'# Time forces(pressure viscous porous) moment(pressure viscous porous)'",
                ));
            }
            groups
        }
        None => {
            let g = groups_from_row(src, &h.data)?;
            warnings.push(format!(
                "no '# Time forces(...) moment(...)' line; read {} groups of {} vectors as \
                 OpenFOAM writes them",
                g.len(),
                g.first().map_or(0, |g| g.parts.len())
            ));
            g
        }
    };

    let mut heads = vec![Head::si("Time", "s")];
    let mut shapes = Vec::new();
    for g in &groups {
        let unit = match g.name.as_str() {
            "force" => Some("N"),
            "moment" => Some("N m"),
            _ => None,
        };
        let mut parts = Vec::new();
        for p in &g.parts {
            parts.push(Shape::Vector {
                first: heads.len(),
                label: format!("{} {p}", g.name),
            });
            for a in AXES {
                heads.push(head(
                    format!("{}_{p}_{a}", g.name),
                    format!("{} {p} {a}", g.label),
                    unit,
                ));
            }
        }
        for a in AXES {
            heads.push(head(
                format!("{}_total_{a}", g.name),
                format!("{} sum of the parts {a}", g.label),
                unit,
            ));
        }
        shapes.push(Shape::Group {
            parts,
            label: g.label.clone(),
        });
    }
    let at = h.columns.as_ref().map_or(src.file(), |(i, _)| src.at(*i));
    apply_names(&mut heads, options, at)?;
    let names: Vec<String> = heads.iter().map(|h| h.name.clone()).collect();
    let mut rows = vector_rows(src, &h.data, &shapes, &names)?;

    // Totals: the sum of the parts of each group.
    let mut col = 1;
    for g in &groups {
        let n = g.parts.len();
        for a in 0..3 {
            let total: Vec<f64> = (0..rows.lines.len())
                .map(|r| (0..n).map(|p| rows.columns[col + 3 * p + a][r]).sum())
                .collect();
            rows.columns[col + 3 * n + a] = total;
        }
        col += 3 * n + 3;
    }
    Ok(assemble(
        src.path,
        Format::OpenFoamForcesLegacy,
        heads,
        rows,
        h.meta,
        warnings,
    ))
}

/// A flattened column; `header` says where in the row it came from.
fn head(name: String, header: String, unit: Option<&str>) -> Head {
    let mut h = match unit {
        Some(u) => Head::si(name, u),
        None => Head::plain(name),
    };
    h.header = header;
    h
}

/// `forces(pressure viscous porous)` or `moment(pressure, viscous)`.
fn group(token: &str) -> Option<Group> {
    let (name, rest) = token.split_once('(')?;
    let inner = rest.strip_suffix(')')?;
    let parts: Vec<String> = inner
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect();
    let lower = name.trim().to_ascii_lowercase();
    let name = match lower.as_str() {
        "forces" | "force" => "force".to_string(),
        "moments" | "moment" => "moment".to_string(),
        _ => lower,
    };
    (!parts.is_empty() && !name.is_empty()).then(|| Group {
        name,
        label: token.to_string(),
        parts,
    })
}

/// Groups from the first row when the column line is missing.
fn groups_from_row(src: &Source, data: &[usize]) -> Result<Vec<Group>, InputError> {
    let Some(&i) = data.first() else {
        return Err(InputError::new(src.file(), "no data rows")
            .expected("rows 't ((px py pz) (vx vy vz)) ((mx my mz) (...))'"));
    };
    let nodes = parse_brackets(src.lines[i]).map_err(|(_, msg)| {
        InputError::new(src.at(i), format!("unbalanced brackets: {msg}"))
            .expected("a row 't ((px py pz) (vx vy vz)) ((mx my mz) (...))'")
    })?;
    let mut groups = Vec::new();
    for (k, node) in nodes.iter().skip(1).enumerate() {
        let n = match node {
            Node::List(items, _) => items.len(),
            Node::Atom(..) => 0,
        };
        let parts: Vec<String> = match n {
            3 => vec!["pressure".into(), "viscous".into(), "porous".into()],
            2 => vec!["pressure".into(), "viscous".into()],
            _ => (1..=n.max(1)).map(|p| format!("part{p}")).collect(),
        };
        let name = match k {
            0 => "force".to_string(),
            1 => "moment".to_string(),
            _ => format!("group{}", k + 1),
        };
        groups.push(Group {
            label: format!("{name}({})", parts.join(" ")),
            name,
            parts,
        });
    }
    if groups.is_empty() {
        return Err(
            InputError::new(src.at(i), "no bracketed vectors after the time")
                .expected("a row 't ((px py pz) (vx vy vz)) ((mx my mz) (...))'"),
        );
    }
    Ok(groups)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_groups() {
        let g = group("forces(pressure viscous porous)").unwrap();
        assert_eq!(g.name, "force");
        assert_eq!(g.parts, ["pressure", "viscous", "porous"]);
        assert_eq!(group("moments(pressure, viscous)").unwrap().parts.len(), 2);
        assert_eq!(group("Time"), None);
    }
}
