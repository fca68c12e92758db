//! What hydroid reads from one export: the report behind `hydroid inspect`.
//!
//! The report lists the detected format, every column (name, header text, unit, the
//! quantity it probably is, missing cells, range in SI), the time axis and its sampling, the
//! header metadata and everything the reader fixed or noticed.

mod guess;

use crate::base::error::InputError;
use crate::base::quantity::{unwrap_attitude, Quantity};
use crate::base::units::{dim_to_string, Unit};
use crate::io::formats::{self, FormatChoice, ReadOptions};
use crate::io::table::Table;
pub use guess::guess_quantity;
use serde::Serialize;
use std::io::{self, Write};
use std::path::Path;

/// Everything `hydroid inspect` shows about one file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InspectReport {
    /// The file.
    pub file: String,
    /// The format it was read as (`--format` name).
    pub format: String,
    /// Data rows after restart handling.
    pub rows: usize,
    /// First and last file line of the data.
    pub data_lines: Option<(usize, usize)>,
    /// One entry per column, in file order.
    pub columns: Vec<ColumnReport>,
    /// The time axis, when the file has one.
    pub time: Option<TimeReport>,
    /// Header metadata (`magUInf`, `CofR`, titles ...), in file order.
    pub meta: Vec<MetaEntry>,
    /// What the reader fixed or noticed, and what inspect noticed.
    pub warnings: Vec<String>,
}

/// One column of the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColumnReport {
    /// 1-based column number.
    pub index: usize,
    /// Name without unit.
    pub name: String,
    /// Header text as written.
    pub header: String,
    /// The unit as written in the file (or defined by the format), if any.
    pub unit: Option<String>,
    /// The SI unit the values are in, when the unit is known.
    pub si_unit: Option<String>,
    /// The quantity the column probably is (a guess from name and unit).
    pub quantity: Option<Quantity>,
    /// Empty or non-finite cells.
    pub missing: usize,
    /// Smallest finite value, in SI.
    pub min: Option<f64>,
    /// Largest finite value, in SI.
    pub max: Option<f64>,
}

/// The time axis and its sampling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimeReport {
    /// Name of the time column.
    pub column: String,
    /// First time, s (or the file's unit when it states none).
    pub start: f64,
    /// Last time.
    pub end: f64,
    /// `end - start`.
    pub span: f64,
    /// Mean time step.
    pub step_mean: Option<f64>,
    /// Smallest time step.
    pub step_min: Option<f64>,
    /// Largest time step.
    pub step_max: Option<f64>,
    /// Standard deviation of the time step.
    pub jitter: Option<f64>,
    /// Rows dropped because a later row repeats their time stamp (restart overlap).
    pub repeated: usize,
    /// True when the time column states no unit (then times are as written).
    pub unitless: bool,
}

/// One metadata entry.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetaEntry {
    /// Key (`magUInf`, `title` ...).
    pub key: String,
    /// Value as written.
    pub value: String,
}

/// Reads `path` as `choice` and reports on it.
pub fn inspect(path: &Path, choice: FormatChoice) -> Result<InspectReport, InputError> {
    let raw = formats::read_raw(path, choice, &ReadOptions::default())?;
    report(raw)
}

/// Reads `path` as `choice` for a program that wants the values: the table in SI as the
/// stages read it ([`formats::read`]) and the report `hydroid inspect` prints of it.
pub fn read(path: &Path, choice: FormatChoice) -> Result<(Table, InspectReport), InputError> {
    let raw = formats::read_raw(path, choice, &ReadOptions::default())?;
    let report = report(raw.clone())?;
    let mut table = raw;
    table.finish(None)?;
    Ok((table, report))
}

/// Reports on a table as a reader returned it (before [`Table::finish`]), finishing it.
pub fn report(mut table: Table) -> Result<InspectReport, InputError> {
    let repeated = table.time.map_or(0, |t| {
        let finite: Vec<u64> = table.columns[t]
            .values
            .iter()
            .filter(|v| v.is_finite())
            .map(|v| v.to_bits())
            .collect();
        let distinct: std::collections::HashSet<u64> = finite.iter().copied().collect();
        finite.len() - distinct.len()
    });
    table.finish(None)?;
    // Ranges as a stage sees them: an attitude history unwrapped, other angles as written.
    let time_history = table.time.is_some();
    for c in &mut table.columns {
        if let Some(q) = guess_quantity(&c.name, c.unit.as_ref()) {
            unwrap_attitude(q, time_history, &mut c.values);
        }
    }
    let mut warnings = table.warnings.clone();
    let columns: Vec<ColumnReport> = table
        .columns
        .iter()
        .enumerate()
        .map(|(j, c)| {
            let finite = c.values.iter().copied().filter(|v| v.is_finite());
            let min = finite.clone().reduce(f64::min);
            let max = finite.reduce(f64::max);
            let quantity = if table.time == Some(j) {
                Some(Quantity::Time)
            } else {
                guess_quantity(&c.name, c.unit.as_ref())
            };
            ColumnReport {
                index: j + 1,
                name: c.name.clone(),
                header: c.header.clone(),
                unit: c.unit.as_ref().map(ToString::to_string),
                si_unit: c.unit.as_ref().map(si_symbol),
                quantity,
                missing: c.values.iter().filter(|v| !v.is_finite()).count(),
                min,
                max,
            }
        })
        .collect();
    let missing: usize = columns.iter().map(|c| c.missing).sum();
    if missing > 0 {
        warnings.push(format!(
            "{missing} empty cell{} (counted per column under 'missing'); a stage that uses \
             such a column stops at the first one",
            if missing == 1 { "" } else { "s" }
        ));
    }
    let time = table.time.map(|t| time_report(&table, t, repeated));
    if let Some(tr) = &time {
        if let (Some(mean), Some(lo), Some(hi)) = (tr.step_mean, tr.step_min, tr.step_max) {
            if mean > 0.0 && (hi - lo) > 0.01 * mean {
                warnings.push(format!(
                    "the time step is not constant: from {} to {} (mean {})",
                    num(lo),
                    num(hi),
                    num(mean)
                ));
            }
        }
        if tr.unitless {
            warnings.push(format!(
                "the time column '{}' states no unit; give one in the configuration",
                tr.column
            ));
        }
    }
    Ok(InspectReport {
        file: table.source.display().to_string(),
        format: table.format.name().to_string(),
        rows: table.rows(),
        data_lines: table
            .lines
            .first()
            .zip(table.lines.last())
            .map(|(a, b)| (*a, *b)),
        columns,
        time,
        meta: table
            .meta
            .iter()
            .map(|(k, v)| MetaEntry {
                key: k.clone(),
                value: v.clone(),
            })
            .collect(),
        warnings,
    })
}

fn time_report(table: &Table, t: usize, repeated: usize) -> TimeReport {
    let col = &table.columns[t];
    let v: Vec<f64> = col
        .values
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .collect();
    let dt: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = (!dt.is_empty()).then(|| dt.iter().sum::<f64>() / dt.len() as f64);
    let jitter =
        mean.map(|m| (dt.iter().map(|d| (d - m).powi(2)).sum::<f64>() / dt.len() as f64).sqrt());
    let start = v.first().copied().unwrap_or(f64::NAN);
    let end = v.last().copied().unwrap_or(f64::NAN);
    TimeReport {
        column: col.name.clone(),
        start,
        end,
        span: end - start,
        step_mean: mean,
        step_min: dt.iter().copied().reduce(f64::min),
        step_max: dt.iter().copied().reduce(f64::max),
        jitter,
        repeated,
        unitless: col.unit.is_none(),
    }
}

/// The SI unit of `u`'s dimension, in the symbols engineers write.
fn si_symbol(u: &Unit) -> String {
    let named = match u.dim {
        [0, 0, 0, 0] => "1",
        [0, 0, 1, 0] => "s",
        [0, 1, 0, 0] => "m",
        [0, 0, 0, 1] => "rad",
        [0, 1, -1, 0] => "m/s",
        [0, 0, -1, 1] => "rad/s",
        [0, 1, -2, 0] => "m/s^2",
        [0, 0, -2, 1] => "rad/s^2",
        [0, 0, -1, 0] => "1/s",
        [1, 0, 0, 0] => "kg",
        [1, 1, -2, 0] => "N",
        [1, 2, -2, 0] => "N m",
        [1, -1, -2, 0] => "Pa",
        [1, 2, 0, 0] => "kg m^2",
        [1, 2, -3, 0] => "W",
        [0, 2, 0, 0] => "m^2",
        [0, 3, 0, 0] => "m^3",
        [1, -3, 0, 0] => "kg/m^3",
        d => return dim_to_string(d),
    };
    named.to_string()
}

/// A number for people: up to 6 significant digits, exponent for very large or small.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        crate::base::numfmt::fixed_trimmed(v, (5 - a.log10().floor() as i32).max(0) as usize)
    } else {
        format!("{v:.5e}")
    }
}

impl InspectReport {
    /// Writes the time column's span and sampling.
    fn write_time(&self, out: &mut impl Write) -> io::Result<()> {
        match &self.time {
            Some(t) => {
                let u = if t.unitless { "" } else { " s" };
                writeln!(
                    out,
                    "time      '{}' from {}{u} to {}{u} (span {}{u})",
                    t.column,
                    num(t.start),
                    num(t.end),
                    num(t.span)
                )?;
                match (t.step_mean, t.step_min, t.step_max, t.jitter) {
                    (Some(m), Some(lo), Some(hi), Some(j)) => writeln!(
                        out,
                        "sampling  dt mean {}{u}, min {}{u}, max {}{u}, jitter (std) {}{u}; {} repeated time stamp{}",
                        num(m),
                        num(lo),
                        num(hi),
                        num(j),
                        t.repeated,
                        if t.repeated == 1 { "" } else { "s" }
                    )?,
                    _ => writeln!(out, "sampling  one time stamp only")?,
                }
            }
            None => writeln!(out, "time      no time column")?,
        }
        Ok(())
    }

    /// Writes the aligned column table: numbers right-aligned, text left-aligned.
    fn write_columns(&self, out: &mut impl Write) -> io::Result<()> {
        let head = [
            "#", "name", "header", "unit", "SI", "quantity", "missing", "min (SI)", "max (SI)",
        ];
        let rows: Vec<[String; 9]> = self
            .columns
            .iter()
            .map(|c| {
                [
                    c.index.to_string(),
                    c.name.clone(),
                    c.header.clone(),
                    c.unit.clone().unwrap_or_else(|| "-".into()),
                    c.si_unit.clone().unwrap_or_else(|| "-".into()),
                    c.quantity
                        .map_or_else(|| "-".into(), |q| q.key().to_string()),
                    c.missing.to_string(),
                    c.min.map_or_else(|| "-".into(), num),
                    c.max.map_or_else(|| "-".into(), num),
                ]
            })
            .collect();
        let mut width = head.map(str::len);
        for r in &rows {
            for (w, cell) in width.iter_mut().zip(r) {
                *w = (*w).max(cell.chars().count());
            }
        }
        let right = |k: usize| k == 0 || k >= 6;
        let line = |cells: &[String]| {
            let mut s = String::new();
            for (k, cell) in cells.iter().enumerate() {
                let pad = width[k] - cell.chars().count();
                if k > 0 {
                    s.push_str("  ");
                }
                if right(k) {
                    s.push_str(&" ".repeat(pad));
                    s.push_str(cell);
                } else {
                    s.push_str(cell);
                    if k + 1 < cells.len() {
                        s.push_str(&" ".repeat(pad));
                    }
                }
            }
            s
        };
        writeln!(out, "{}", line(&head.map(String::from)))?;
        for r in &rows {
            writeln!(out, "{}", line(r))?;
        }
        Ok(())
    }

    /// Writes the report for people: a summary, an aligned column table, metadata and
    /// warnings.
    pub fn write_text(&self, out: &mut impl Write) -> io::Result<()> {
        writeln!(out, "file      {}", self.file)?;
        writeln!(out, "format    {}", self.format)?;
        match self.data_lines {
            Some((a, b)) => writeln!(out, "rows      {} (lines {a}-{b})", self.rows)?,
            None => writeln!(out, "rows      {}", self.rows)?,
        }
        self.write_time(out)?;
        writeln!(out)?;
        self.write_columns(out)?;
        if !self.meta.is_empty() {
            writeln!(out)?;
            writeln!(out, "metadata")?;
            let w = self
                .meta
                .iter()
                .map(|m| m.key.chars().count())
                .max()
                .unwrap_or(0);
            for m in &self.meta {
                writeln!(out, "  {:w$}  {}", m.key, m.value)?;
            }
        }
        if !self.warnings.is_empty() {
            writeln!(out)?;
            writeln!(out, "warnings")?;
            for w in &self.warnings {
                writeln!(out, "  - {w}")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(-12.5), "-12.5");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(2.0e7), "2.00000e7");
        assert_eq!(num(0.0), "0");
    }
}
