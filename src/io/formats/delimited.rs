//! Delimited tables: the generic reader, and the engine under the CFX and STAR-CCM+ readers.
//!
//! A light pre-scan finds the layout (delimiter, header line, preamble, comment lines, a
//! trailing delimiter); polars parses the data lines of single-character-delimited files.
//! Whitespace-separated files, and any file polars rejects, are read line by line, which is
//! also what gives an exact error (line, column, offending text).

use super::columns::{assemble, interpret_unit, split_unit_suffix, Head, HeaderUnit, Rows};
use super::layout::{is_section, number};
pub(crate) use super::layout::{scan, Layout};
use super::text::{
    comment, count_error, split_fields, whitespace_rows, Delim, Source, DECIMAL_COMMA_HINT,
};
use super::{Format, ReadOptions};
use crate::base::error::InputError;
use crate::io::table::Table;
use polars::prelude::{CsvReadOptions, DataType, Schema, SerReader};
use std::io::Cursor;
use std::sync::Arc;

/// How a dialect writes units in header cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum UnitStyle {
    /// `name (unit)` or `name [unit]` when the bracket holds a known unit; else part of the name.
    Loose,
    /// `name [ unit ]` (CFX); an unknown unit is an error.
    Square,
    /// `name (unit)` (STAR-CCM+); an unknown unit is an error.
    Round,
}

/// The variations of the delimited readers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dialect {
    /// The format the table is labelled with.
    pub format: Format,
    /// How header cells carry units.
    pub units: UnitStyle,
}

/// The generic reader: units in `(..)` or `[..]` when they parse, otherwise part of the name.
pub(crate) const GENERIC: Dialect = Dialect {
    format: Format::Delimited,
    units: UnitStyle::Loose,
};

/// Reads a delimited file in `dialect`.
pub(crate) fn read(
    src: &Source,
    options: &ReadOptions,
    dialect: Dialect,
) -> Result<Table, InputError> {
    let layout = scan(src)?;
    let mut warnings = Vec::new();
    let heads = heads(src, &layout, options, dialect, &mut warnings)?;
    let names: Vec<String> = heads.iter().map(|h| h.name.clone()).collect();
    let rows = match layout.delim {
        Delim::Char(d) => polars_rows(src, &layout, d, &names),
        Delim::Whitespace => whitespace_rows(src, layout.data.iter().copied(), &names),
    }
    .map_err(|e| title_hint(e, &layout))?;
    if rows.lines.is_empty() {
        return Err(InputError::new(src.file(), "no data rows").expected("rows of numbers"));
    }
    if let Some(&first) = layout.repeated_headers.first() {
        warnings.push(format!(
            "the header line is repeated {} time{} further down (first at line {}); skipped",
            layout.repeated_headers.len(),
            if layout.repeated_headers.len() == 1 {
                ""
            } else {
                "s"
            },
            first + 1
        ));
    }
    if layout.decimal_comma_suspect {
        warnings.push(format!(
            "the rows have {} values under {} name and no decimal point; if they are numbers \
             such as 0,5, {DECIMAL_COMMA_HINT}",
            layout.ncols,
            layout.ncols / 2
        ));
    }
    if let Some((i, m)) = layout.unfit_header {
        warnings.push(format!(
            "line {} ('{}') reads like a header of {m} names, but the rows below have {} \
             values: it is kept as a title and the columns are named col1 to col{}; name them \
             in the configuration (`names = [...]`) or correct the header",
            i + 1,
            super::layout::shorten(src.lines[i].trim(), 60),
            layout.ncols,
            layout.ncols
        ));
    }
    let meta = preamble_meta(src, &layout.preamble, layout.delim);
    Ok(assemble(
        src.path,
        dialect.format,
        heads,
        rows,
        meta,
        warnings,
    ))
}

/// An error on the first row of a table without header may be a title line that opens with
/// a number: the message says how to skip it.
fn title_hint(mut e: InputError, layout: &Layout) -> InputError {
    let first = layout.data.first().map(|i| i + 1);
    if layout.header.is_none() && e.place.line.is_some() && e.place.line == first {
        e.message.push_str(
            "; if this line is a title above the table, skip the title lines with \
             `skip_lines = N` in the configuration",
        );
    }
    e
}

/// Column heads from the header (or the configured names, or `col1..colN`).
fn heads(
    src: &Source,
    layout: &Layout,
    options: &ReadOptions,
    dialect: Dialect,
    warnings: &mut Vec<String>,
) -> Result<Vec<Head>, InputError> {
    let n = layout.ncols;
    let mut heads: Vec<Head> = match &layout.header {
        Some(h) => {
            let mut heads = Vec::with_capacity(n);
            for j in 0..n {
                let text = h.fields.get(j).map_or("", |f| f.text.as_str());
                if text.is_empty() {
                    warnings.push(format!(
                        "column {} has no name in the header (line {}); called it col{}",
                        j + 1,
                        h.index + 1,
                        j + 1
                    ));
                    heads.push(Head::plain(format!("col{}", j + 1)));
                } else {
                    heads.push(head(src, h.index, j, text, dialect.units, warnings)?);
                }
            }
            heads
        }
        None => (1..=n).map(|j| Head::plain(format!("col{j}"))).collect(),
    };
    let at = layout.data.first().map_or(src.file(), |&i| src.at(i));
    super::columns::apply_names(&mut heads, options, at)?;
    Ok(heads)
}

/// One header cell: name and unit according to the dialect.
fn head(
    src: &Source,
    line: usize,
    col: usize,
    text: &str,
    style: UnitStyle,
    warnings: &mut Vec<String>,
) -> Result<Head, InputError> {
    let split = match style {
        UnitStyle::Square => split_unit_suffix(text, '[', ']', false),
        UnitStyle::Round => split_unit_suffix(text, '(', ')', true),
        UnitStyle::Loose => split_unit_suffix(text, '[', ']', true)
            .or_else(|| split_unit_suffix(text, '(', ')', true)),
    };
    let mut head = Head::plain(text.trim());
    let Some((name, unit_text)) = split else {
        return Ok(head);
    };
    match interpret_unit(unit_text) {
        HeaderUnit::Known(u) => {
            head.name = name.to_string();
            head.unit = Some(u);
        }
        HeaderUnit::Foreign(u) => {
            head.name = name.to_string();
            warnings.push(format!(
                "column {} '{name}': unit '{u}' is not converted (hydroid converts mass, \
                 length, time and angle units); values kept as written",
                col + 1
            ));
        }
        HeaderUnit::Unknown(u) if style == UnitStyle::Loose => {
            warnings.push(format!(
                "column {} '{}': '{u}' is not a unit hydroid knows; kept as part of the name",
                col + 1,
                text.trim()
            ));
        }
        HeaderUnit::Unknown(u) => {
            let e = crate::base::units::Unit::parse(&u)
                .err()
                .map_or_else(|| format!("unknown unit '{u}'"), |e| e.to_string());
            return Err(InputError::new(
                src.at(line).with_column(col + 1).with_column_name(name),
                format!("header: {e}"),
            )
            .expected("a unit such as s, m, m s^-1, deg, rad/s, N, N m or kg m^2"));
        }
    }
    Ok(head)
}

/// Title lines, `key: value` lines and `[Section]` blocks before the header.
pub(crate) fn preamble_meta(src: &Source, lines: &[usize], delim: Delim) -> Vec<(String, String)> {
    let mut meta = Vec::new();
    let mut section: Option<String> = None;
    for &i in lines {
        let (text, is_comment) = match comment(src.lines[i]) {
            Some(c) => (c.trim(), true),
            None => (src.lines[i].trim(), false),
        };
        if text.is_empty() {
            continue;
        }
        if is_section(text) {
            section = Some(text[1..text.len() - 1].trim().to_string());
            continue;
        }
        if let Some(s) = section.take() {
            meta.push((s, text.to_string()));
            continue;
        }
        let delim = if is_comment { Delim::Whitespace } else { delim };
        if let Some(kv) = key_value(text, delim) {
            meta.push(kv);
        } else {
            let key = if is_comment { "comment" } else { "title" };
            meta.push((key.to_string(), text.trim_matches('"').to_string()));
        }
    }
    meta
}

/// `key: value`, `key = value` or `key<delim>value`.
pub(crate) fn key_value(text: &str, delim: Delim) -> Option<(String, String)> {
    let split = text
        .find([':', '='])
        .map(|p| (&text[..p], &text[p + 1..]))
        .filter(|(k, _)| !matches!(delim, Delim::Char(d) if k.contains(d as char)));
    let split = split.or_else(|| match delim {
        Delim::Char(d) => {
            let f = split_fields(text, Delim::Char(d));
            (f.len() == 2).then(|| {
                let p = text.find(d as char).unwrap_or(text.len());
                (&text[..p], text.get(p + 1..).unwrap_or(""))
            })
        }
        Delim::Whitespace => None,
    })?;
    let key = split.0.trim().trim_matches('"').trim();
    let value = split.1.trim().trim_matches('"').trim();
    let plausible = !key.is_empty()
        && key.chars().count() <= 40
        && key.starts_with(|c: char| c.is_alphabetic())
        && !value.is_empty();
    plausible.then(|| (key.to_string(), value.to_string()))
}

/// Widest table handed to polars. polars keeps a schema entry and a series per column, which
/// for a table of 300,000 columns costs more time and memory than the numbers; the line by
/// line reader is linear in the cells whatever the shape.
const POLARS_MAX_COLUMNS: usize = 1024;

/// Parses the data lines with polars; on any failure, reads them line by line instead,
/// which either succeeds or names the offending cell. Very wide tables are read line by line.
fn polars_rows(src: &Source, layout: &Layout, d: u8, names: &[String]) -> Result<Rows, InputError> {
    if names.len() > POLARS_MAX_COLUMNS {
        return hand_rows(src, layout, Delim::Char(d), names);
    }
    match polars_parse(src, layout, d, names)? {
        Some(rows) => Ok(rows),
        None => hand_rows(src, layout, Delim::Char(d), names),
    }
}

/// The polars pass: the rows, or `None` when polars rejects the data (a cell that is not a
/// number, a stray quote) or a value is not finite. Rows with the wrong number of cells are
/// found while the lines are collected, and are an error at once.
fn polars_parse(
    src: &Source,
    layout: &Layout,
    d: u8,
    names: &[String],
) -> Result<Option<Rows>, InputError> {
    let n = names.len();
    let delim = Delim::Char(d);
    let mut buf: Vec<u8> = Vec::with_capacity(layout.data.len() * (n * 12 + 1));
    for &i in &layout.data {
        let mut line = src.lines[i].trim_end_matches(|c| c == ' ' || (c == '\t' && d != b'\t'));
        if layout.trailing_delim {
            line = line.strip_suffix(d as char).unwrap_or(line);
        }
        // One pass over the bytes: count delimiters, look for quotes and padding.
        let mut count = 1;
        let mut needs_split = false;
        for &b in line.as_bytes() {
            if b == d {
                count += 1;
            } else if b == b'"' || b == b' ' || b == b'\t' {
                needs_split = true;
            }
        }
        if needs_split {
            let f = split_fields(line, delim);
            if f.len() != n {
                return Err(count_error(src, i, f.len(), names, delim));
            }
            for (j, c) in f.iter().enumerate() {
                if j > 0 {
                    buf.push(d);
                }
                buf.extend_from_slice(c.text.as_bytes());
            }
        } else {
            if count != n {
                return Err(count_error(src, i, count, names, delim));
            }
            buf.extend_from_slice(line.as_bytes());
        }
        buf.push(b'\n');
    }
    if layout.data.is_empty() {
        return Ok(Some(Rows::new(n)));
    }
    let mut schema = Schema::default();
    for j in 0..n {
        schema.with_column(format!("c{j}").into(), DataType::Float64);
    }
    let dc = layout.decimal_comma;
    let parsed = CsvReadOptions::default()
        .with_has_header(false)
        .with_schema(Some(Arc::new(schema)))
        .map_parse_options(|p| p.with_separator(d).with_decimal_comma(dc))
        .into_reader_with_file_handle(Cursor::new(buf))
        .finish();
    let df = match parsed {
        Ok(df) if df.height() == layout.data.len() => df,
        _ => return Ok(None),
    };
    let mut rows = Rows::new(n);
    rows.lines = layout.data.iter().map(|i| i + 1).collect();
    // exactly the room the empty cells need: a file of empty cells is the densest there is
    rows.missing
        .reserve_exact(df.columns().iter().map(|c| c.null_count()).sum());
    // each polars column is freed once copied
    for (j, col) in df.into_columns().into_iter().enumerate() {
        let Ok(ca) = col.f64() else {
            return Ok(None);
        };
        let out = &mut rows.columns[j];
        out.reserve_exact(layout.data.len());
        if ca.null_count() == 0 {
            for arr in ca.downcast_iter() {
                out.extend_from_slice(arr.values());
            }
            if out.iter().any(|v| !v.is_finite()) {
                return Ok(None);
            }
            continue;
        }
        for (r, v) in ca.iter().enumerate() {
            match v {
                Some(v) if v.is_finite() => out.push(v),
                Some(_) => return Ok(None),
                None => {
                    out.push(f64::NAN);
                    rows.missing.push((r, j));
                }
            }
        }
    }
    rows.missing.sort_unstable();
    Ok(Some(rows))
}

/// Reads the data lines cell by cell: the exact error, or the rows.
fn hand_rows(
    src: &Source,
    layout: &Layout,
    delim: Delim,
    names: &[String],
) -> Result<Rows, InputError> {
    let n = names.len();
    let mut rows = Rows::new(n);
    for &i in &layout.data {
        let mut f = split_fields(src.lines[i], delim);
        if layout.trailing_delim && f.len() == n + 1 && f.last().is_some_and(|c| c.text.is_empty())
        {
            f.pop();
        }
        if f.len() != n {
            return Err(count_error(src, i, f.len(), names, delim));
        }
        let r = rows.lines.len();
        for (j, cell) in f.iter().enumerate() {
            if cell.text.is_empty() {
                rows.columns[j].push(f64::NAN);
                rows.missing.push((r, j));
                continue;
            }
            match number(&cell.text, layout.decimal_comma) {
                Some(v) if v.is_finite() => rows.columns[j].push(v),
                _ => {
                    return Err(super::text::cell_error(src, i, j, &names[j], &cell.text));
                }
            }
        }
        rows.lines.push(i + 1);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// polars does the parsing for every ordinary single-character-delimited layout; only
    /// bad cells and non-finite values fall back to the line-by-line reader.
    #[test]
    fn polars_parses_ordinary_layouts() {
        let parse = |text: &str| {
            let src = Source::new(Path::new("t.csv"), text);
            let l = scan(&src).unwrap();
            let Delim::Char(d) = l.delim else {
                panic!("not single-character delimited: {text}")
            };
            let names: Vec<String> = (0..l.ncols).map(|j| format!("c{j}")).collect();
            polars_parse(&src, &l, d, &names).unwrap()
        };
        for text in [
            "a,b\n1,2\n3,4\n",
            "a, b\n 1 , 2\n3 ,4 \n",
            "\"a\",\"b\"\n\"1\",2\n3,4\n",
            "a;b\n1,5;2\n3;4,25\n",
            "a\tb\n1\t\n\t4\n",
            "a,b,\n1,2,\n3,4,\n",
            "a,b\r\n1e-3,-2.5E+02\r\n+3.,.4\r\n",
        ] {
            let rows = parse(text).unwrap_or_else(|| panic!("polars rejected {text:?}"));
            assert_eq!(rows.lines, [2, 3], "{text:?}");
        }
        let rows = parse("a\tb\n1\t\n\t4\n").unwrap();
        assert_eq!(rows.missing, [(0, 1), (1, 0)]);
        assert_eq!(
            parse("a;b\n1,5;2\n3;4,25\n").unwrap().columns[1],
            [2.0, 4.25]
        );
        assert!(parse("a,b\n1,2\n3,x\n4,5\n").is_none());
        assert!(parse("a,b\n1,2\n3,nan\n4,5\n").is_none());
    }
}
