//! The layout pre-scan of delimited files: which delimiter, where the header is, which lines
//! are preamble, comments and data, and whether lines end in an extra delimiter.
//!
//! The first line that is all numbers (confirmed by the next two) fixes the delimiter and the
//! number of columns; the header is the nearest line above it whose cells are all names.

use super::text::{
    comment, decimal_commas_likely, parse_number, split_fields, Delim, Field, Source,
    DECIMAL_COMMA_HINT,
};
use crate::base::error::InputError;

/// Where things are in a delimited file.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// The cell separator.
    pub delim: Delim,
    /// Numbers use a decimal comma (`1,5;2,25`).
    pub decimal_comma: bool,
    /// Number of columns.
    pub ncols: usize,
    /// Every line ends with one extra delimiter, which is dropped.
    pub trailing_delim: bool,
    /// The header line, when there is one.
    pub header: Option<HeaderLine>,
    /// Lines before the header (or the data), comments included (0-based).
    pub preamble: Vec<usize>,
    /// Data lines (0-based), comments, blank lines and repeated headers excluded.
    pub data: Vec<usize>,
    /// Lines that repeat the header further down (a concatenated file).
    pub repeated_headers: Vec<usize>,
    /// One name over rows of two integers split by a comma: perhaps `0,5` with a decimal
    /// comma, perhaps a title over two columns. Read as two columns, with a warning.
    pub decimal_comma_suspect: bool,
    /// A line right above the data that reads like a header (names with units, or one name
    /// more than the rows have values) but does not fit the rows: kept as a title, with a
    /// warning. (0-based line, its number of names.)
    pub unfit_header: Option<(usize, usize)>,
}

/// The header line of a delimited file.
#[derive(Debug, Clone)]
pub(crate) struct HeaderLine {
    /// 0-based line index.
    pub index: usize,
    /// Its cells.
    pub fields: Vec<Field>,
    /// True when the header is written as a comment (`# time u v`).
    pub commented: bool,
}

const CANDIDATES: [(Delim, bool); 6] = [
    (Delim::Char(b','), false),
    (Delim::Char(b';'), false),
    (Delim::Char(b'\t'), false),
    (Delim::Whitespace, false),
    (Delim::Char(b';'), true),
    (Delim::Char(b'\t'), true),
];

/// A cell as a number, reading a decimal comma when the layout has them.
pub(crate) fn number(text: &str, decimal_comma: bool) -> Option<f64> {
    if decimal_comma && text.contains(',') {
        parse_number(&text.replace(',', "."))
    } else {
        parse_number(text)
    }
}

/// Cells of `line` if every cell is a number or empty and at least one is a number.
fn numeric_cells(line: &str, delim: Delim, dc: bool) -> Option<usize> {
    let f = split_fields(line, delim);
    let ok = f
        .iter()
        .all(|c| c.text.is_empty() || number(&c.text, dc).is_some())
        && f.iter().any(|c| !c.text.is_empty());
    ok.then_some(f.len())
}

fn is_header_like(fields: &[Field], dc: bool) -> bool {
    !fields.is_empty()
        && fields
            .iter()
            .all(|c| !c.text.is_empty() && number(&c.text, dc).is_none())
}

/// A line that may be a data row with a problem: it opens with a number. A title line
/// (`Zig-zag 10/10 run 3`, `KVLCC2 : 35 (deg)`) opens with a word, even if it holds numbers.
fn opens_with_number(fields: &[Field], dc: bool) -> bool {
    fields
        .first()
        .is_some_and(|c| number(&c.text, dc).is_some())
}

/// The cells of a blank-separated header line with the units that blanks split off joined
/// back to their names: `time (s) u (m/s)` and `u [ m s^-1 ]` are two names and one, each
/// with its unit. A cell that opens a bracket takes the cells up to the one that closes it.
fn join_units(fields: Vec<Field>) -> Vec<Field> {
    let mut out: Vec<Field> = Vec::with_capacity(fields.len());
    let mut depth = 0i32;
    for f in fields {
        let opens = !f.quoted && f.text.starts_with(['(', '[']);
        let joined = depth > 0 || opens;
        depth += f.text.matches(['(', '[']).count() as i32;
        depth -= f.text.matches([')', ']']).count() as i32;
        depth = depth.max(0);
        match out.last_mut() {
            Some(last) if joined => {
                last.text.push(' ');
                last.text.push_str(&f.text);
            }
            _ => out.push(f),
        }
    }
    out
}

/// True when a cell ends in a bracket that parses as a unit (`time (s)`, `u [ m/s ]`).
fn has_unit(fields: &[Field]) -> bool {
    use super::columns::{interpret_unit, split_unit_suffix, HeaderUnit};
    fields.iter().any(|f| {
        let split = split_unit_suffix(&f.text, '(', ')', true)
            .or_else(|| split_unit_suffix(&f.text, '[', ']', true));
        split.is_some_and(|(_, u)| matches!(interpret_unit(u), HeaderUnit::Known(_)))
    })
}

/// A `[Section]` line (CFX-Post preamble).
pub(crate) fn is_section(line: &str) -> bool {
    let t = line.trim();
    t.starts_with('[') && t.ends_with(']') && !t[1..].contains('[')
}

/// Finds the layout of a delimited file.
pub(crate) fn scan(src: &Source) -> Result<Layout, InputError> {
    let cand: Vec<usize> = src
        .content()
        .filter(|(_, l)| comment(l).is_none())
        .map(|(i, _)| i)
        .collect();
    let Some((k0, delim, dc, mut ncols)) = first_data(src, &cand) else {
        return Err(no_data(src, &cand));
    };
    let found = find_header(src, cand[k0], delim, dc, ncols);
    let mut header = found.header.or(found.commented);
    let mut unfit_header = found.unfit_header;
    let mut data_start = found.data_start;
    // a header found after all (a commented one): the line above is no header
    if header.is_some() {
        unfit_header = None;
    }
    let decimal_comma_suspect =
        split_by_decimal_commas(src, &cand[k0..], delim, ncols, &header, found.names_above)?;
    if let Some(h) = &header {
        data_start = h.index + 1;
    }
    let trailing_delim = trailing_delimiter(src.lines[cand[k0]], delim, ncols, &header);
    if trailing_delim {
        ncols -= 1;
    }
    if let Some(h) = &mut header {
        if h.fields.len() > ncols {
            h.fields.truncate(ncols);
        }
    }
    let (data, repeated_headers) = data_rows(src, &cand, data_start, &header);
    // In semicolon- or tab-separated numbers a comma can only be a decimal comma, even when
    // the first rows happen to have none.
    let dc = dc
        || (matches!(delim, Delim::Char(b';' | b'\t'))
            && data.iter().any(|&i| src.lines[i].contains(',')));
    let preamble_end = header.as_ref().map_or(data_start, |h| h.index);
    let preamble = (0..preamble_end)
        .filter(|&i| !src.lines[i].trim().is_empty())
        .collect();
    Ok(Layout {
        delim,
        decimal_comma: dc,
        ncols,
        trailing_delim,
        header,
        preamble,
        data,
        repeated_headers,
        decimal_comma_suspect,
        unfit_header,
    })
}

/// The first line that is all numbers, confirmed by the next two, with the delimiter that
/// gives the most cells (a tab-separated row with an empty cell is still two cells): its
/// index in `cand`, the delimiter, whether commas are decimal and the cell count.
fn first_data(src: &Source, cand: &[usize]) -> Option<(usize, Delim, bool, usize)> {
    for (k, &i) in cand.iter().enumerate() {
        let mut best: Option<(Delim, bool, usize)> = None;
        for (delim, dc) in CANDIDATES {
            let Some(n) = numeric_cells(src.lines[i], delim, dc) else {
                continue;
            };
            let confirmed = cand[k + 1..]
                .iter()
                .take(2)
                .all(|&j| numeric_cells(src.lines[j], delim, dc) == Some(n));
            if confirmed && best.is_none_or(|b| n > b.2) {
                best = Some((delim, dc, n));
            }
        }
        if let Some((delim, dc, n)) = best {
            return Some((k, delim, dc, n));
        }
    }
    None
}

/// What the lines above the first confirmed data row say.
struct HeaderSearch {
    /// The nearest bare line above the data whose cells are names fitting the data.
    header: Option<HeaderLine>,
    /// A header written as a comment (`# time u v`) right above the data.
    commented: Option<HeaderLine>,
    /// The line right above the data when it is all names (line, cell count).
    names_above: Option<(usize, usize)>,
    /// That line when it looks like a header that does not fit the data (line, cell count).
    unfit_header: Option<(usize, usize)>,
    /// The first data row, counting rows opening with a number above the confirmed ones.
    data_start: usize,
}

/// The header: the nearest line above the data whose cells are all names. Lines opening
/// with a number between it and the confirmed data are data rows (with a problem to
/// report); lines opening with a word are titles.
fn find_header(src: &Source, first: usize, delim: Delim, dc: bool, ncols: usize) -> HeaderSearch {
    let fits = |f: &[Field]| {
        let named =
            f.len() - usize::from(f.len() > ncols && f.last().is_some_and(|c| c.text.is_empty()));
        (named == ncols || (named + 1 == ncols && ncols > 1)) && is_header_like(&f[..named], dc)
    };
    // A header written as a comment (`# time u v`) right above the data is used only when
    // no bare header line is found above it.
    let mut header = None;
    let mut commented = None;
    // The line right above the data when it is all names but does not fit the data (for the
    // decimal-comma check).
    let mut names_above: Option<(usize, usize)> = None;
    let mut unfit_header: Option<(usize, usize)> = None;
    let mut nearest = true;
    let mut data_start = first;
    let mut absorbing = true;
    for i in (0..first).rev() {
        let line = src.lines[i];
        if line.trim().is_empty() {
            continue;
        }
        if let Some(text) = comment(line) {
            if absorbing && commented.is_none() {
                commented = [delim, Delim::Whitespace].into_iter().find_map(|d| {
                    let mut f = split_fields(text, d);
                    if d == Delim::Whitespace && f.len() != ncols {
                        f = join_units(f);
                    }
                    (f.len() == ncols && is_header_like(&f, dc)).then_some(HeaderLine {
                        index: i,
                        fields: f,
                        commented: true,
                    })
                });
            }
            continue;
        }
        if is_section(line) {
            absorbing = false;
            continue;
        }
        let mut f = split_fields(line, delim);
        if delim == Delim::Whitespace && !fits(&f) {
            f = join_units(f);
        }
        if fits(&f) {
            header = Some(HeaderLine {
                index: i,
                fields: f,
                commented: false,
            });
            break;
        }
        if std::mem::take(&mut nearest) && is_header_like(&f, dc) {
            names_above = Some((i, f.len()));
            if f.len() == ncols + 1 || has_unit(&f) {
                unfit_header = Some((i, f.len()));
            }
        }
        if absorbing && commented.is_none() && opens_with_number(&f, dc) {
            data_start = i;
        } else {
            absorbing = false;
        }
    }
    HeaderSearch {
        header,
        commented,
        names_above,
        unfit_header,
        data_start,
    }
}

/// `time,u` over `0,5,1,25`: every number split in two by a comma separator. An error when
/// several names head twice as many values; true (a suspicion to report) for one name over
/// two integers, as likely a title over a table without header.
fn split_by_decimal_commas(
    src: &Source,
    rows: &[usize],
    delim: Delim,
    ncols: usize,
    header: &Option<HeaderLine>,
    names_above: Option<(usize, usize)>,
) -> Result<bool, InputError> {
    let names = match header {
        Some(h) => Some((
            h.index,
            h.fields.iter().filter(|f| !f.text.is_empty()).count(),
        )),
        None => names_above,
    };
    let mut decimal_comma_suspect = false;
    if let Some((i, m)) = names.filter(|&(_, m)| delim == Delim::Char(b',') && 2 * m == ncols) {
        let split = rows
            .iter()
            .take(3)
            .all(|&j| decimal_commas_likely(src.lines[j]));
        // One name over two integers is as likely a title over a table without header.
        decimal_comma_suspect = split && m == 1;
        if split && m > 1 {
            return Err(InputError::new(
                src.at(i),
                format!(
                    "the header has {m} name{} but the rows below have {ncols} values; \
                     {DECIMAL_COMMA_HINT}",
                    if m == 1 { "" } else { "s" }
                ),
            )
            .expected(format!("{m} values per row separated by commas")));
        }
    }
    Ok(decimal_comma_suspect)
}

/// Whether a delimiter at the end of every line makes an extra empty column (judged on the
/// first data line and the header's cell count).
fn trailing_delimiter(
    first_line: &str,
    delim: Delim,
    ncols: usize,
    header: &Option<HeaderLine>,
) -> bool {
    let first_fields = split_fields(first_line, delim);
    if let (Delim::Char(_), Some(last)) = (delim, first_fields.last()) {
        if last.text.is_empty() && !last.quoted && ncols > 1 {
            let hn = header.as_ref().map(|h| {
                let f = &h.fields;
                f.len() - usize::from(f.last().is_some_and(|c| c.text.is_empty()))
            });
            if hn.is_none_or(|n| n == ncols - 1) {
                return true;
            }
        }
    }
    false
}

/// The data rows from `data_start` on, and the lines repeating a bare header among them.
fn data_rows(
    src: &Source,
    cand: &[usize],
    data_start: usize,
    header: &Option<HeaderLine>,
) -> (Vec<usize>, Vec<usize>) {
    let header_text = header.as_ref().map(|h| src.lines[h.index].trim());
    let mut data = Vec::new();
    let mut repeated_headers = Vec::new();
    for &i in cand.iter().filter(|&&i| i >= data_start) {
        if !header.as_ref().is_some_and(|h| h.commented) && Some(src.lines[i].trim()) == header_text
        {
            repeated_headers.push(i);
        } else {
            data.push(i);
        }
    }
    (data, repeated_headers)
}

fn no_data(src: &Source, cand: &[usize]) -> InputError {
    let expected = "rows of numbers separated by commas, semicolons, tabs or spaces, under an \
                    optional header line (or name the format with --format)";
    // Rows of decimal-comma numbers split by commas have varying cell counts: no rows fit.
    let decimal: Vec<usize> = cand
        .iter()
        .take(10)
        .copied()
        .filter(|&i| decimal_commas_likely(src.lines[i]))
        .collect();
    if decimal.len() >= 3 {
        return InputError::new(
            src.at(decimal[0]),
            format!("no rows of numbers with the same number of cells; {DECIMAL_COMMA_HINT}"),
        )
        .expected(expected);
    }
    if let Some(e) = text_columns(src, cand) {
        return e.expected(expected);
    }
    match cand.first() {
        Some(&i) if cand.len() <= 3 => InputError::new(
            src.at(i),
            format!(
                "no rows of numbers: the file has only {} line{} of text ('{}'), like a \
                 header without data",
                cand.len(),
                if cand.len() == 1 { "" } else { "s" },
                shorten(src.lines[i].trim(), 60)
            ),
        )
        .expected(expected),
        Some(&i) => InputError::new(
            src.at(i),
            format!(
                "no rows of numbers anywhere in the file; it starts with '{}'",
                shorten(src.lines[i].trim(), 60)
            ),
        )
        .expected(expected),
        None => InputError::new(src.file(), "the file holds only comment lines").expected(expected),
    }
}

/// Rows of numbers with one or more columns of text (a published table's `test type`): the
/// error naming those columns, when at least three rows have the same cells, every one a
/// number except those columns, text on every row.
fn text_columns(src: &Source, cand: &[usize]) -> Option<InputError> {
    for (delim, dc) in CANDIDATES {
        let rows: Vec<(usize, Vec<Field>)> = cand
            .iter()
            .map(|&i| (i, split_fields(src.lines[i], delim)))
            .filter(|(_, f)| f.len() > 1 && opens_with_number(f, dc))
            .collect();
        let Some(n) = rows.first().map(|r| r.1.len()) else {
            continue;
        };
        let text = |f: &Field| !f.text.is_empty() && number(&f.text, dc).is_none();
        let same: Vec<&(usize, Vec<Field>)> = rows.iter().filter(|r| r.1.len() == n).collect();
        let columns: Vec<usize> = (0..n)
            .filter(|&j| same.iter().all(|r| text(&r.1[j])))
            .collect();
        let numeric = |r: &&(usize, Vec<Field>)| {
            r.1.iter()
                .enumerate()
                .all(|(j, f)| columns.contains(&j) || !text(f))
        };
        if same.len() < 3 || columns.is_empty() || columns.len() == n || !same.iter().all(numeric) {
            continue;
        }
        let header = cand
            .iter()
            .take_while(|&&i| i < same[0].0)
            .map(|&i| split_fields(src.lines[i], delim))
            .filter(|f| f.len() == n && is_header_like(f, dc))
            .last();
        let named: Vec<String> = columns
            .iter()
            .map(|&j| {
                let name = header
                    .as_ref()
                    .map(|h| format!(" '{}'", h[j].text))
                    .unwrap_or_default();
                let mut values: Vec<&str> = same.iter().map(|r| r.1[j].text.as_str()).collect();
                values.sort_unstable();
                values.dedup();
                let shown: Vec<String> = values
                    .iter()
                    .take(3)
                    .map(|v| format!("'{}'", shorten(v, 30)))
                    .collect();
                format!(
                    "column {}{name} ({}{})",
                    j + 1,
                    shown.join(", "),
                    if values.len() > 3 { ", ..." } else { "" }
                )
            })
            .collect();
        return Some(InputError::new(
            src.at(same[0].0),
            format!(
                "no rows of numbers: {} rows (from line {}) are numbers except {} of text: {}; \
                 hydroid reads columns of numbers only: delete the text column{} from the file \
                 (or export the table without {}), then map the numeric columns in the run's \
                 `columns`",
                same.len(),
                same[0].0 + 1,
                if columns.len() == 1 {
                    "one column"
                } else {
                    "columns"
                },
                named.join(", "),
                if columns.len() == 1 { "" } else { "s" },
                if columns.len() == 1 { "it" } else { "them" }
            ),
        ));
    }
    None
}

/// `s` cut to `n` characters with `...`.
pub(crate) fn shorten(s: &str, n: usize) -> String {
    if s.chars().count() > n {
        format!("{}...", s.chars().take(n).collect::<String>())
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn layout(text: &str) -> Layout {
        scan(&Source::new(Path::new("t.csv"), text)).unwrap()
    }

    #[test]
    fn a_text_column_is_named_with_its_values() {
        let text = "run,beta(deg),X',test type\n1,0,0.1,rudder angle\n2,5,0.2,drift angle\n\
                    3,10,0.3,drift angle\n";
        let e = scan(&Source::new(Path::new("t.csv"), text))
            .unwrap_err()
            .to_string();
        assert!(e.contains("3 rows (from line 2)"), "{e}");
        assert!(
            e.contains("column 4 'test type' ('drift angle', 'rudder angle')"),
            "{e}"
        );
        assert!(e.contains("delete the text column"), "{e}");
    }

    #[test]
    fn finds_header_preamble_and_delimiter() {
        let l = layout("Run 12\n# comment\ntime;u\n0;1\n1;2\n");
        assert_eq!(l.delim, Delim::Char(b';'));
        assert_eq!(l.header.as_ref().map(|h| h.index), Some(2));
        assert_eq!(l.preamble, vec![0, 1]);
        assert_eq!(l.data, vec![3, 4]);
    }

    #[test]
    fn decimal_comma_and_trailing_delimiter() {
        let l = layout("a;b\n1,5;2\n3;4,25\n");
        assert!(l.decimal_comma);
        let l = layout("a;b\n1;2\n3;4\n5;6\n7,5;8\n");
        assert!(l.decimal_comma, "a decimal comma further down");
        let l = layout("a,b\n1,2,\n3,4,\n");
        assert!(l.trailing_delim);
        assert_eq!(l.ncols, 2);
    }

    #[test]
    fn bad_first_row_is_data_not_header() {
        let l = layout("t,u\n1,x\n2,3\n3,4\n4,5\n");
        assert_eq!(l.header.as_ref().map(|h| h.index), Some(0));
        assert_eq!(l.data, vec![1, 2, 3, 4]);
    }

    #[test]
    fn decimal_commas_split_by_the_separator() {
        let scan_err = |text: &str| {
            scan(&Source::new(Path::new("t.csv"), text))
                .err()
                .map(|e| e.to_string())
        };
        let e = scan_err("time,u\n0,5,1,25\n1,0,1,5\n1,5,1,75\n").unwrap();
        assert!(e.contains("t.csv:1") && e.contains("decimal commas"), "{e}");
        // Integers under a header that fits are no decimal commas; under a title line they
        // may be: read, with a warning.
        assert!(layout("Towing tank\n1,2\n3,4\n5,6\n").decimal_comma_suspect);
        assert!(!layout("Towing tank\n1,2.5\n3,4\n5,6\n").decimal_comma_suspect);
        assert_eq!(scan_err("a,b\nrun 3\n1,2\n3,4\n5,6\n"), None);
        assert_eq!(scan_err("a,b,c,d\n1,2,3,4\n3,4,5,6\n5,6,7,8\n"), None);
    }

    /// Title lines of model-test logs open with a word, whatever numbers they hold; they are
    /// preamble, not rows. A line opening with a number right above the data is a row.
    #[test]
    fn title_lines_above_a_headerless_table() {
        let rows = "  .000  2.9  -.007\n  .050  2.99  -.0073\n  .100  3.05  -.0075\n";
        let l = layout(&format!(
            "HSVA, experimental data CPMC\nZigzag 10 / 10 starting to starboard, run 3\n{rows}"
        ));
        assert!(l.header.is_none());
        assert_eq!(l.preamble, [0, 1]);
        assert_eq!(l.data, [2, 3, 4]);
        let l = layout(&format!("KVLCC2\n35 deg turn\n{rows}"));
        assert_eq!(
            l.data,
            [1, 2, 3, 4],
            "a line opening with a number is a row"
        );
    }

    #[test]
    fn commented_header() {
        let l = layout("# time u v\n0 1 2\n1 2 3\n");
        assert!(l.header.as_ref().is_some_and(|h| h.commented));
    }
}
