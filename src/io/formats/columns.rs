//! Column heads and tables: units written in headers, configured names, the rows every
//! reader collects, and the assembly into a [`Table`] with its time column.

use crate::base::error::{InputError, Place};
use crate::base::units::Unit;
use crate::io::table::{Column, Table};
use std::path::{Path, PathBuf};

/// A unit written in a header, interpreted.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum HeaderUnit {
    /// A mechanical unit hydroid converts to SI.
    Known(Unit),
    /// A real unit outside mass, length, time and angle (K, A, V ...): kept as written.
    Foreign(String),
    /// Not a unit hydroid recognises.
    Unknown(String),
}

/// Units that are real but outside what hydroid converts.
const FOREIGN: &[&str] = &[
    "K", "kelvin", "degC", "°C", "degF", "°F", "C", "A", "mA", "ampere", "V", "mV", "kV", "volt",
    "ohm", "Ohm", "S", "mol", "kmol", "cd", "lm", "lx", "T", "Wb", "H", "F", "Bq", "Gy", "Sv",
];

/// Interprets the text between the brackets of a header unit.
pub(crate) fn interpret_unit(text: &str) -> HeaderUnit {
    if let Ok(u) = Unit::parse(text) {
        return HeaderUnit::Known(u);
    }
    // Replace every foreign symbol by 1; if the rest parses, the unit is real but foreign.
    let mut replaced = String::new();
    let mut word = String::new();
    let mut any = false;
    let flush = |word: &mut String, out: &mut String, any: &mut bool| {
        if FOREIGN.contains(&word.as_str()) {
            out.push('1');
            *any = true;
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_alphabetic() || c == '°' {
            word.push(c);
        } else {
            flush(&mut word, &mut replaced, &mut any);
            if c != ' ' || !replaced.is_empty() {
                replaced.push(c);
            }
        }
    }
    let replaced = replaced.replace("°1", "1");
    if any && Unit::parse(&replaced).is_ok() {
        HeaderUnit::Foreign(text.trim().to_string())
    } else {
        HeaderUnit::Unknown(text.trim().to_string())
    }
}

/// Splits `name [ unit ]` or `name (unit)`: the trailing bracket group and the name before
/// it. With `need_space`, the bracket must follow whitespace (so `Cl(r)` stays a name).
pub(crate) fn split_unit_suffix(
    header: &str,
    open: char,
    close: char,
    need_space: bool,
) -> Option<(&str, &str)> {
    let h = header.trim();
    let body = h.strip_suffix(close)?;
    let mut depth = 1usize;
    for (i, c) in body.char_indices().rev() {
        if c == close {
            depth += 1;
        } else if c == open {
            depth -= 1;
            if depth == 0 {
                let name = &body[..i];
                if name.trim().is_empty() || (need_space && !name.ends_with(char::is_whitespace)) {
                    return None;
                }
                return Some((name.trim(), &body[i + c.len_utf8()..]));
            }
        }
    }
    None
}

/// The head of a column: its name, header text and unit.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Head {
    /// Name without unit.
    pub name: String,
    /// Header text as read.
    pub header: String,
    /// Unit, when known.
    pub unit: Option<Unit>,
}

impl Head {
    /// A head without unit.
    pub fn plain(name: impl Into<String>) -> Self {
        let name = name.into();
        Head {
            header: name.clone(),
            name,
            unit: None,
        }
    }

    /// A head with an SI unit defined by the format.
    pub fn si(name: impl Into<String>, unit: &str) -> Self {
        let mut h = Head::plain(name);
        h.unit = Unit::parse(unit).ok();
        h
    }
}

/// Replaces the names of `heads` by the configured names (units from the header stay).
pub(crate) fn apply_names(
    heads: &mut [Head],
    options: &crate::io::formats::ReadOptions,
    at: Place,
) -> Result<(), InputError> {
    let Some(names) = &options.names else {
        return Ok(());
    };
    let n = heads.len();
    if names.len() != n {
        return Err(InputError::new(
            at,
            format!(
                "the configuration gives {} column name{} but the file has {n} column{}",
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                if n == 1 { "" } else { "s" }
            ),
        )
        .expected(format!("{n} names in `names`")));
    }
    for (h, name) in heads.iter_mut().zip(names) {
        h.name.clone_from(name);
    }
    Ok(())
}

/// Numbers read from the data lines, column by column.
#[derive(Debug, Default)]
pub(crate) struct Rows {
    /// One vector per column.
    pub columns: Vec<Vec<f64>>,
    /// 1-based file line of each row.
    pub lines: Vec<usize>,
    /// Empty cells (row, column), stored as NaN.
    pub missing: Vec<(usize, usize)>,
}

impl Rows {
    /// Empty rows for `n` columns.
    pub fn new(n: usize) -> Self {
        Rows {
            columns: vec![Vec::new(); n],
            ..Default::default()
        }
    }
}

/// Puts heads and rows together into a table and finds the time column.
pub(crate) fn assemble(
    path: &Path,
    format: crate::io::formats::Format,
    heads: Vec<Head>,
    rows: Rows,
    meta: Vec<(String, String)>,
    warnings: Vec<String>,
) -> Table {
    let mut table = Table::new(PathBuf::from(path), format);
    for (head, values) in heads.into_iter().zip(rows.columns) {
        table.columns.push(Column {
            name: head.name,
            header: head.header,
            unit: head.unit,
            values,
        });
    }
    table.lines = rows.lines;
    table.missing = rows.missing;
    table.meta = meta;
    table.warnings = warnings;
    table.time = time_column(&table);
    warn_duplicates(&mut table);
    table
}

/// The names a time column goes by, normalised (lower case, no spaces, `-` or `_`).
const TIME_NAMES: &[&str] = &[
    "time",
    "t",
    "flowtime",
    "physicaltime",
    "accumulatedtime",
    "simulationtime",
    "solutiontime",
    "totaltime",
];

/// The first column named like time (`Time`, `t`, `flow-time`, `Physical Time: Physical
/// Time` ...) whose unit, if any, is a time.
pub(crate) fn time_column(table: &Table) -> Option<usize> {
    table.columns.iter().position(|c| {
        let last = c.name.rsplit(':').next().unwrap_or(&c.name);
        let n = normalise(last);
        TIME_NAMES.contains(&n.as_str()) && c.unit.as_ref().is_none_or(|u| u.dim == [0, 0, 1, 0])
    })
}

/// Lower case without spaces, `-` and `_`.
pub(crate) fn normalise(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace() && *c != '-' && *c != '_')
        .flat_map(char::to_lowercase)
        .collect()
}

/// Warns about each column whose name an earlier column already has (one lookup per column,
/// so that a table of 300,000 columns takes no longer than a long one).
fn warn_duplicates(table: &mut Table) {
    let mut first: std::collections::HashMap<&str, usize> =
        std::collections::HashMap::with_capacity(table.columns.len());
    let mut warnings = Vec::new();
    for (i, c) in table.columns.iter().enumerate() {
        let name = &c.name;
        let j = *first.entry(name.as_str()).or_insert(i);
        if j != i {
            let w = format!(
                "column name '{name}' appears twice (columns {} and {}); a configuration that \
                 names it gets column {}, use `index = {}` for the other",
                j + 1,
                i + 1,
                j + 1,
                i + 1
            );
            warnings.push(w);
        }
    }
    // A file with thousands of repeated names gets a count, not thousands of lines.
    const SHOWN: usize = 10;
    if warnings.len() > SHOWN {
        let more = warnings.len() - SHOWN;
        warnings.truncate(SHOWN);
        warnings.push(format!(
            "{more} more columns repeat an earlier column's name"
        ));
    }
    table.warnings.append(&mut warnings);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_suffixes() {
        assert_eq!(
            split_unit_suffix("Velocity u [ m s^-1 ]", '[', ']', false),
            Some(("Velocity u", " m s^-1 "))
        );
        assert_eq!(
            split_unit_suffix("Position[X] (m)", '(', ')', true),
            Some(("Position[X]", "m"))
        );
        assert_eq!(split_unit_suffix("Cl(r)", '(', ')', true), None);
        assert_eq!(split_unit_suffix("(m)", '(', ')', false), None);
    }

    #[test]
    fn foreign_and_unknown_units() {
        assert!(matches!(interpret_unit("A/m^2"), HeaderUnit::Foreign(_)));
        assert!(matches!(interpret_unit("K"), HeaderUnit::Foreign(_)));
        assert!(matches!(interpret_unit("N-m"), HeaderUnit::Known(_)));
        assert!(matches!(interpret_unit("furlong"), HeaderUnit::Unknown(_)));
    }
}
