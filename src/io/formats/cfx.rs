//! ANSYS CFX exports: CFX-Post chart and table exports and monitor exports (`cfx5mondata`).
//!
//! Comma-separated, a few preamble lines (`[Name]`, `Chart 1`, `[Data]`, run descriptions),
//! then a header whose names carry units in square brackets, often with spaces inside and a
//! leading space before the name: `Time [ s ]`, ` Velocity u [ m s^-1 ]`,
//! `Monitor Point: P1 [ N ]`. No real export was available when this was written, so the
//! reader is tolerant: any preamble above the header is kept as metadata, names are trimmed,
//! and a bracket that is not a unit is an error naming the column.

use super::columns::split_unit_suffix;
use super::delimited::{self, Dialect, Layout, UnitStyle};
use super::text::Source;
use super::{Format, ReadOptions};
use crate::base::error::InputError;
use crate::io::table::Table;

/// CFX: units in `[ ... ]`, unknown units are errors.
pub(crate) const DIALECT: Dialect = Dialect {
    format: Format::Cfx,
    units: UnitStyle::Square,
};

/// Reads a CFX CSV export.
pub(crate) fn read(src: &Source, options: &ReadOptions) -> Result<Table, InputError> {
    delimited::read(src, options, DIALECT)
}

/// True when a delimited layout looks like CFX: a `[Data]`/`[Name]` preamble section, or a
/// header with at least one `name [ unit ]` cell (a space inside the brackets, as CFX writes).
pub(crate) fn looks_like(src: &Source, layout: &Layout) -> bool {
    let section = layout.preamble.iter().any(|&i| {
        let t = src.lines[i].trim().to_ascii_lowercase();
        t == "[data]" || t == "[name]"
    });
    let bracketed = layout.header.as_ref().is_some_and(|h| {
        h.fields.iter().any(|f| {
            split_unit_suffix(&f.text, '[', ']', false)
                .is_some_and(|(_, u)| u.starts_with(' ') && u.ends_with(' ') || u.trim().is_empty())
        })
    });
    section || bracketed
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn units_in_square_brackets() {
        let text = "[Name]\nMonitor 1\n\n[Data]\n\"Time [ s ]\", Velocity u [ m s^-1 ],\
                    \" Heading [ degree ]\"\n0.0, 1.0, 10\n0.5, 1.5, 20\n";
        let src = Source::new(Path::new("m.csv"), text);
        let layout = delimited::scan(&src).unwrap();
        assert!(looks_like(&src, &layout));
        let t = read(&src, &ReadOptions::default()).unwrap();
        assert_eq!(t.names(), ["Time", "Velocity u", "Heading"]);
        assert_eq!(
            t.columns[1].unit.as_ref().map(|u| u.dim),
            Some([0, 1, -1, 0])
        );
        assert_eq!(t.meta("Name"), Some("Monitor 1"));
        assert_eq!(t.time, Some(0));
    }

    #[test]
    fn unknown_unit_names_line_and_column() {
        let src = Source::new(
            Path::new("m.csv"),
            "Time [ s ],Drift [ furlong ]\n0,1\n1,2\n",
        );
        let e = read(&src, &ReadOptions::default()).unwrap_err();
        assert_eq!(e.place.line, Some(1));
        assert_eq!(e.place.column, Some(2));
        assert!(e.to_string().contains("furlong"), "{e}");
    }
}
