//! The one in-memory table every reader produces: named columns, values in SI where the file
//! states the unit, the file line of every row, and the header metadata.

use crate::base::error::{InputError, Place};
use crate::base::units::Unit;
use crate::io::formats::Format;
use std::path::PathBuf;

/// One column of a table.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The column's name as the file gives it, trimmed, without the unit.
    pub name: String,
    /// The header text exactly as read (name and unit).
    pub header: String,
    /// The unit the header states, if any. Values of a column with a unit are in SI.
    pub unit: Option<Unit>,
    /// Values, one per row; NaN marks a missing cell (see [`Table::missing`]).
    pub values: Vec<f64>,
}

impl Column {
    /// A column without unit.
    pub fn new(name: impl Into<String>, values: Vec<f64>) -> Self {
        let name = name.into();
        Column {
            header: name.clone(),
            name,
            unit: None,
            values,
        }
    }
}

/// A table read from one CFD export.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The file it was read from.
    pub source: PathBuf,
    /// The layout it was read as.
    pub format: Format,
    /// Columns, in file order.
    pub columns: Vec<Column>,
    /// 1-based file line of each row.
    pub lines: Vec<usize>,
    /// Index of the column the format declares as time, if any.
    pub time: Option<usize>,
    /// Header metadata (`magUInf`, `lRef`, `Aref`, `CofR`, titles ...), in file order.
    pub meta: Vec<(String, String)>,
    /// Cells that were empty or unparseable as a number but tolerated (row, column).
    pub missing: Vec<(usize, usize)>,
    /// Things the reader fixed or noticed (restarts, unwrapped angles ...).
    pub warnings: Vec<String>,
}

impl Table {
    /// An empty table for `source` in `format`.
    pub fn new(source: impl Into<PathBuf>, format: Format) -> Self {
        Table {
            source: source.into(),
            format,
            columns: Vec::new(),
            lines: Vec::new(),
            time: None,
            meta: Vec::new(),
            missing: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// Finds a column by name: exact, then ignoring case, spaces and the unit.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        if let Some(i) = self.columns.iter().position(|c| c.name == name) {
            return Some(i);
        }
        let norm = |s: &str| {
            s.chars()
                .filter(|c| !c.is_whitespace())
                .collect::<String>()
                .to_lowercase()
        };
        let n = norm(name);
        self.columns
            .iter()
            .position(|c| norm(&c.name) == n || norm(&c.header) == n)
    }

    /// The column names, for messages.
    pub fn names(&self) -> Vec<&str> {
        self.columns.iter().map(|c| c.name.as_str()).collect()
    }

    /// The value of a header metadata key (`magUInf`, `Aref` ...).
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(key))
            .map(|(_, v)| v.as_str())
    }

    /// The place of row `row` in the file.
    pub fn place(&self, row: usize) -> Place {
        match self.lines.get(row) {
            Some(&l) => Place::line(&self.source, l),
            None => Place::file(&self.source),
        }
    }

    /// Converts the columns whose unit is known to SI and, when the time column is known,
    /// checks it and tidies repeated time stamps ([`Table::drop_repeated_times`] with the
    /// sampling interval `dt` in s when the configuration gives one). Angles stay as written (in radians): only the record knows
    /// which column is an attitude history to unwrap ([`crate::base::quantity::unwrap_attitude`]).
    pub fn finish(&mut self, dt: Option<f64>) -> Result<(), InputError> {
        for c in &mut self.columns {
            if let Some(u) = &c.unit {
                if u.factor != 1.0 {
                    for v in &mut c.values {
                        *v *= u.factor;
                    }
                }
            }
        }
        if let Some(t) = self.time {
            self.drop_repeated_times(t, dt)?;
        }
        Ok(())
    }

    /// Tidies repeated time stamps of time column `t` (`crate::io::time_stamps`): identical
    /// rows dropped, a restart's overlap reduced to its last rows, a time column printed with
    /// too few digits rebuilt from its uniform sampling (interval `dt` in s, or detected);
    /// anything else, or a time that goes back, is an error at its line.
    pub fn drop_repeated_times(&mut self, t: usize, dt: Option<f64>) -> Result<(), InputError> {
        crate::io::time_stamps::tidy(self, t, dt)
    }

    /// Keeps the rows where `keep` is true.
    pub fn retain_rows(&mut self, keep: &[bool]) {
        let mut map = vec![usize::MAX; keep.len()];
        let mut next = 0;
        for (i, &k) in keep.iter().enumerate() {
            if k {
                map[i] = next;
                next += 1;
            }
        }
        for c in &mut self.columns {
            let mut it = keep.iter();
            c.values.retain(|_| *it.next().unwrap_or(&true));
        }
        let mut it = keep.iter();
        self.lines.retain(|_| *it.next().unwrap_or(&true));
        self.missing = self
            .missing
            .iter()
            .filter(|(r, _)| keep.get(*r).copied().unwrap_or(false))
            .map(|&(r, c)| (map[r], c))
            .collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(times: &[f64]) -> Table {
        let mut t = Table::new("run.csv", Format::Delimited);
        t.columns.push(Column::new("Time", times.to_vec()));
        t.columns.push(Column::new(
            "u",
            (0..times.len()).map(|i| i as f64).collect(),
        ));
        t.lines = (0..times.len()).map(|i| i + 2).collect();
        t.time = Some(0);
        t
    }

    #[test]
    fn restart_keeps_last_row() {
        let mut t = table(&[0.0, 0.1, 0.2, 0.2, 0.3]);
        t.finish(None).unwrap();
        assert_eq!(t.columns[0].values, vec![0.0, 0.1, 0.2, 0.3]);
        assert_eq!(t.columns[1].values, vec![0.0, 1.0, 3.0, 4.0]);
        assert_eq!(t.lines, vec![2, 3, 5, 6]);
        assert_eq!(t.warnings.len(), 1);
        assert!(t.warnings[0].contains("line 4"), "{}", t.warnings[0]);
    }

    #[test]
    fn restart_from_earlier_time_keeps_the_rewritten_rows() {
        let mut t = table(&[0.8, 0.9, 1.0, 0.9, 1.0, 1.1]);
        t.finish(None).unwrap();
        assert_eq!(t.columns[0].values, vec![0.8, 0.9, 1.0, 1.1]);
        assert_eq!(t.columns[1].values, vec![0.0, 3.0, 4.0, 5.0]);
    }

    #[test]
    fn decreasing_time_names_the_line() {
        let mut t = table(&[0.0, 0.1, 0.05]);
        let e = t.finish(None).unwrap_err();
        assert_eq!(e.place.line, Some(4));
        assert!(e.to_string().contains("backwards"));
    }

    #[test]
    fn degrees_become_radians_as_written() {
        let mut t = table(&[0.0, 1.0, 2.0]);
        t.columns[1].values = vec![179.0, -179.0, -170.0];
        t.columns[1].unit = Some(Unit::parse("deg").unwrap());
        t.finish(None).unwrap();
        let deg: Vec<f64> = t.columns[1].values.iter().map(|r| r.to_degrees()).collect();
        assert!((deg[1] + 179.0).abs() < 1e-9 && (deg[2] + 170.0).abs() < 1e-9);
    }
}
