//! OpenFOAM function-object output under `postProcessing/`.
//!
//! All of these files open with `#` lines: a title (`# Force coefficients`), `# key : value`
//! lines (`magUInf`, `lRef`, `Aref`, `CofR`, direction vectors, `Angle Units`) and a column
//! line starting with `Time`. Rows are whitespace-separated; some hold bracketed vectors.
//! The format defines the units: time in s, forces in N, moments in N m, coefficients
//! dimensionless, sixDoF angles per its `Angle Units` line.
//!
//! - [`scalar`]: forceCoeffs.dat, ESI coefficient.dat, ESI force.dat / moment.dat.
//! - [`forces`]: legacy forces.dat, `t ((p) (v) (o)) ((p) (v) (o))`.
//! - [`sixdof`]: sixDoFRigidBodyState, `t (x y z) (x y z) (roll pitch yaw) (u v w) (p q r)`.

mod forces;
mod scalar;
mod sixdof;

pub(crate) use forces::read as read_forces;
pub(crate) use scalar::read as read_scalar;
pub(crate) use sixdof::read as read_sixdof;

use super::columns::Rows;
use super::text::{bracketed_tokens, cell_error, parse_brackets, Node, Source};
use super::Format;
use crate::base::error::InputError;

/// The `#` lines of an OpenFOAM file and where its rows are.
#[derive(Debug, Default)]
pub(crate) struct Header {
    /// `key : value` lines, and `title` for the first line without a colon.
    pub meta: Vec<(String, String)>,
    /// 0-based line of each `meta` entry.
    pub meta_lines: Vec<usize>,
    /// The column line (`# Time ...`): its index and tokens after `#`, `Time` included.
    pub columns: Option<(usize, Vec<String>)>,
    /// Data lines (0-based): every non-blank line that is not a comment.
    pub data: Vec<usize>,
}

impl Header {
    /// The value of a metadata key, ignoring case and spaces, with its line.
    pub fn get(&self, key: &str) -> Option<(&str, usize)> {
        let want = super::columns::normalise(key);
        self.meta
            .iter()
            .zip(&self.meta_lines)
            .find(|((k, _), _)| super::columns::normalise(k) == want)
            .map(|((_, v), &l)| (v.as_str(), l))
    }

    /// Column tokens after `Time`, lower case.
    fn tokens_lower(&self) -> Vec<String> {
        self.columns
            .as_ref()
            .map(|(_, t)| t.iter().skip(1).map(|s| s.to_ascii_lowercase()).collect())
            .unwrap_or_default()
    }
}

/// Reads the `#` lines. Comment lines after the first row (a concatenated restart) are
/// skipped.
pub(crate) fn header(src: &Source) -> Header {
    let mut h = Header::default();
    for (i, line) in src.content() {
        let t = line.trim();
        let Some(text) = t.strip_prefix('#') else {
            h.data.push(i);
            continue;
        };
        if !h.data.is_empty() {
            continue;
        }
        let text = text.trim();
        if text.is_empty() {
            continue;
        }
        let tokens = bracketed_tokens(text);
        if tokens
            .first()
            .is_some_and(|t| t.eq_ignore_ascii_case("time"))
        {
            h.columns = Some((i, tokens.iter().map(|s| s.to_string()).collect()));
        } else if let Some((k, v)) = text.split_once(':') {
            h.meta.push((k.trim().to_string(), v.trim().to_string()));
            h.meta_lines.push(i);
        } else if !h.meta.iter().any(|(k, _)| k == "title") {
            h.meta.push(("title".into(), text.to_string()));
            h.meta_lines.push(i);
        }
    }
    h
}

/// Which OpenFOAM file this is, if any: decided by the column line, the metadata and the
/// first row; the file name breaks ties when the column line is missing.
///
/// A `#` first line alone does not make a file OpenFOAM (a CSV may open with a `#` title or
/// units line): the first row after the `#` lines must also be an OpenFOAM row, a time value
/// then values or brackets separated by blanks, without commas or semicolons.
pub(crate) fn detect(src: &Source) -> Option<Format> {
    let first = src.content().next()?.1.trim_start();
    if !first.starts_with('#') {
        return None;
    }
    let h = header(src);
    if !h.data.first().is_some_and(|&i| is_row(src.lines[i])) {
        return None;
    }
    let tokens = h.tokens_lower();
    let has = |names: &[&str]| tokens.iter().any(|t| names.contains(&t.as_str()));
    let meta_has = |keys: &[&str]| keys.iter().any(|k| h.get(k).is_some());
    let row = h.data.first().map(|&i| src.lines[i]).unwrap_or("");
    if row.contains('(') {
        let motion = meta_has(&["Angle Units"])
            || h.get("title")
                .is_some_and(|(t, _)| t.to_ascii_lowercase().contains("motion"))
            || has(&[
                "centreofrotation",
                "centreofmass",
                "rotation",
                "orientation",
                "omega",
            ]);
        let grouped = tokens
            .iter()
            .any(|t| t.starts_with("force") || t.starts_with("moment"))
            || row.contains("((");
        return Some(if motion || !grouped {
            Format::OpenFoamSixDof
        } else {
            Format::OpenFoamForcesLegacy
        });
    }
    if has(&["cmroll", "cmpitch", "cmyaw", "cs", "cs(f)", "cs(r)"])
        || meta_has(&["sideDir", "rollAxis", "yawAxis"])
    {
        return Some(Format::OpenFoamCoefficient);
    }
    if has(&["cd", "cl", "cm", "cl(f)", "cl(r)"]) {
        return Some(Format::OpenFoamForceCoeffs);
    }
    if tokens.iter().any(|t| {
        ["total_", "pressure_", "viscous_", "porous_"]
            .iter()
            .any(|p| t.starts_with(p))
    }) {
        return Some(Format::OpenFoamForce);
    }
    if h.columns.is_none() {
        let name = src.path.file_name()?.to_str()?.to_ascii_lowercase();
        return match name.as_str() {
            "forcecoeffs.dat" => Some(Format::OpenFoamForceCoeffs),
            "coefficient.dat" => Some(Format::OpenFoamCoefficient),
            "force.dat" | "moment.dat" => Some(Format::OpenFoamForce),
            _ => None,
        };
    }
    None
}

/// True for a line shaped like an OpenFOAM row: a number first, blanks between values, no
/// commas or semicolons (which no OpenFOAM function object writes).
fn is_row(line: &str) -> bool {
    let t = line.trim_start();
    let first = t.split([' ', '\t', '(']).next().unwrap_or("");
    !t.contains([',', ';']) && super::text::parse_number(first).is_some()
}

/// What one bracketed node of a row must look like.
#[derive(Debug, Clone)]
pub(crate) enum Shape {
    /// `(x y z)` filling columns `first..first + 3`.
    Vector {
        /// First of the three columns.
        first: usize,
        /// What the vector is, for messages (`force viscous`).
        label: String,
    },
    /// `( ... )` holding these shapes.
    Group {
        /// The parts.
        parts: Vec<Shape>,
        /// What the group is, for messages (`forces(pressure viscous porous)`).
        label: String,
    },
}

impl Shape {
    fn first_column(&self) -> usize {
        match self {
            Shape::Vector { first, .. } => *first,
            Shape::Group { parts, .. } => parts.first().map_or(0, Shape::first_column),
        }
    }
}

/// Reads rows of `time shape shape ...` into `ncols` columns (column 0 is time).
pub(crate) fn vector_rows(
    src: &Source,
    data: &[usize],
    shapes: &[Shape],
    names: &[String],
) -> Result<Rows, InputError> {
    let mut rows = Rows::new(names.len());
    let mut cells = vec![0.0; names.len()];
    let expected_row = format!(
        "a row 'time {}'",
        shapes.iter().map(describe).collect::<Vec<_>>().join(" ")
    );
    for &i in data {
        let line = src.lines[i];
        let nodes = parse_brackets(line).map_err(|(_, msg)| {
            InputError::new(
                src.at(i),
                format!("unbalanced brackets: {msg}{}", src.truncation_hint(i)),
            )
            .expected(expected_row.clone())
        })?;
        match nodes.first() {
            Some(Node::Atom(t, _)) => cells[0] = number(src, i, 0, names, t)?,
            _ => {
                return Err(InputError::new(
                    src.at(i).with_column(1).with_column_name(&names[0]),
                    "the row does not start with a time value",
                )
                .expected(expected_row))
            }
        }
        let rest = &nodes[1..];
        if rest.len() != shapes.len() {
            let col = shapes
                .get(rest.len())
                .or(shapes.last())
                .map_or(0, Shape::first_column);
            return Err(InputError::new(
                src.at(i).with_column(col + 1).with_column_name(&names[col]),
                format!(
                    "{} bracketed group{} after the time, expected {}{}",
                    rest.len(),
                    if rest.len() == 1 { "" } else { "s" },
                    shapes.len(),
                    src.truncation_hint(i)
                ),
            )
            .expected(expected_row));
        }
        for (node, shape) in rest.iter().zip(shapes) {
            fill(src, i, node, shape, names, &mut cells)?;
        }
        for (col, v) in rows.columns.iter_mut().zip(&cells) {
            col.push(*v);
        }
        rows.lines.push(i + 1);
    }
    Ok(rows)
}

fn describe(shape: &Shape) -> String {
    match shape {
        Shape::Vector { .. } => "(x y z)".into(),
        Shape::Group { parts, .. } => {
            format!(
                "({})",
                parts.iter().map(describe).collect::<Vec<_>>().join(" ")
            )
        }
    }
}

fn fill(
    src: &Source,
    i: usize,
    node: &Node,
    shape: &Shape,
    names: &[String],
    cells: &mut [f64],
) -> Result<(), InputError> {
    let col = shape.first_column();
    let wrong = |found: String, label: &str| {
        InputError::new(
            src.at(i).with_column(col + 1).with_column_name(&names[col]),
            format!(
                "{label}: {found} at character {}{}",
                node.pos(),
                src.truncation_hint(i)
            ),
        )
        .expected(describe(shape))
    };
    match (shape, node) {
        (Shape::Vector { first, label }, Node::List(items, _)) => {
            if items.len() != 3 {
                return Err(wrong(
                    format!("{} components instead of 3", items.len()),
                    label,
                ));
            }
            for (k, item) in items.iter().enumerate() {
                match item {
                    Node::Atom(t, _) => cells[first + k] = number(src, i, first + k, names, t)?,
                    Node::List(..) => {
                        return Err(wrong("a nested bracket".into(), label));
                    }
                }
            }
        }
        (Shape::Group { parts, label }, Node::List(items, _)) => {
            if items.len() != parts.len() {
                return Err(wrong(
                    format!("{} vectors instead of {}", items.len(), parts.len()),
                    label,
                ));
            }
            for (item, part) in items.iter().zip(parts) {
                fill(src, i, item, part, names, cells)?;
            }
        }
        (Shape::Vector { label, .. } | Shape::Group { label, .. }, Node::Atom(t, _)) => {
            return Err(wrong(
                format!("a bare value '{t}' instead of brackets"),
                label,
            ));
        }
    }
    Ok(())
}

fn number(
    src: &Source,
    i: usize,
    col: usize,
    names: &[String],
    text: &str,
) -> Result<f64, InputError> {
    match super::text::parse_number(text) {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err(cell_error(src, i, col, &names[col], text)),
    }
}
