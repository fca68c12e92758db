//! Siemens STAR-CCM+ CSV exports: table exports and monitor/plot exports.
//!
//! Comma-separated with every header cell quoted and units in parentheses after a space:
//! `"Position[X] (m)"`, `"Physical Time: Physical Time (s)"`,
//! `"Moment 1 Monitor: Moment (N-m)"`, `"rotation Monitor: Expression (deg)"`. The square
//! brackets of `Position[X]` belong to the name. Units that are real but outside mechanics
//! (`K`, `A/m^2`) are kept as written with a warning; anything else in the parentheses is an
//! error naming the column.

use super::columns::{interpret_unit, split_unit_suffix, HeaderUnit};
use super::delimited::{self, Dialect, Layout, UnitStyle};
use super::text::{Delim, Source};
use super::{Format, ReadOptions};
use crate::base::error::InputError;
use crate::io::table::Table;

/// STAR-CCM+: units in `( ... )`, unknown units are errors.
pub(crate) const DIALECT: Dialect = Dialect {
    format: Format::StarCcm,
    units: UnitStyle::Round,
};

/// Reads a STAR-CCM+ CSV export.
pub(crate) fn read(src: &Source, options: &ReadOptions) -> Result<Table, InputError> {
    delimited::read(src, options, DIALECT)
}

/// True when a delimited layout looks like STAR-CCM+: the header is the first line,
/// comma-separated, every cell quoted, none with a `[unit]`, and at least one ending in
/// ` (unit)` or naming a monitor (`... Monitor: ...`).
pub(crate) fn looks_like(_src: &Source, layout: &Layout) -> bool {
    let Some(h) = &layout.header else {
        return false;
    };
    layout.delim == Delim::Char(b',')
        && !h.commented
        && layout.preamble.is_empty()
        && !h
            .fields
            .iter()
            .any(|f| split_unit_suffix(&f.text, '[', ']', true).is_some())
        && h.fields.iter().all(|f| f.quoted)
        && h.fields.iter().any(|f| {
            f.text.contains("Monitor:")
                || split_unit_suffix(&f.text, '(', ')', true)
                    .is_some_and(|(_, u)| !matches!(interpret_unit(u), HeaderUnit::Unknown(_)))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn monitor_names_and_units() {
        let text = "\"Physical Time: Physical Time (s)\",\"Moment 1 Monitor: Moment (N-m)\",\
                    \"Position[X] (m)\"\n0.0,1.0,2.0\n0.1,1.5,2.5\n";
        let src = Source::new(Path::new("s.csv"), text);
        assert!(looks_like(&src, &delimited::scan(&src).unwrap()));
        let t = read(&src, &ReadOptions::default()).unwrap();
        assert_eq!(
            t.names(),
            [
                "Physical Time: Physical Time",
                "Moment 1 Monitor: Moment",
                "Position[X]"
            ]
        );
        assert_eq!(
            t.columns[1].unit.as_ref().map(|u| u.dim),
            Some([1, 2, -2, 0])
        );
        assert_eq!(t.time, Some(0));
    }

    #[test]
    fn unquoted_header_or_a_preamble_is_not_starccm() {
        for text in [
            "t (s),u (m/s)\n0,1\n1,2\n",
            "Run 3\n\"t (s)\",\"u (m/s)\"\n0,1\n1,2\n",
            "\"t (s)\",\"x [m]\"\n0,1\n1,2\n",
        ] {
            let src = Source::new(Path::new("s.csv"), text);
            assert!(!looks_like(&src, &delimited::scan(&src).unwrap()), "{text}");
        }
    }
}
