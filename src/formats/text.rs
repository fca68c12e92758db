//! Shared pieces of every reader: decoding the file, lines, fields, numbers, units in
//! headers, and the errors that name the place.
//!
//! Nothing here knows a particular CFD code; the readers combine these helpers.

use crate::error::{InputError, Place};
use crate::table::{Column, Table};
use crate::units::Unit;
use std::path::{Path, PathBuf};

/// A decoded text file split into lines (without line terminators).
#[derive(Debug)]
pub(crate) struct Source<'a> {
    /// The file.
    pub path: &'a Path,
    /// Lines; index `i` is file line `i + 1`.
    pub lines: Vec<&'a str>,
    /// True when the last line has no line terminator (the file may have been cut off).
    pub unterminated: bool,
}

impl<'a> Source<'a> {
    /// Splits decoded text into lines; `\r\n`, `\n` and lone `\r` all end a line.
    pub fn new(path: &'a Path, text: &'a str) -> Self {
        let sep = if text.contains('\n') { '\n' } else { '\r' };
        let mut lines: Vec<&str> = text
            .split(sep)
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .collect();
        let unterminated = !text.is_empty() && !text.ends_with(sep);
        if !unterminated {
            // `split` yields an empty piece after the final terminator.
            lines.pop();
        }
        Source {
            path,
            lines,
            unterminated,
        }
    }

    /// The whole file.
    pub fn file(&self) -> Place {
        Place::file(self.path)
    }

    /// Line `index` (0-based) as a place (1-based).
    pub fn at(&self, index: usize) -> Place {
        Place::line(self.path, index + 1)
    }

    /// Non-blank lines with their 0-based index.
    pub fn content(&self) -> impl Iterator<Item = (usize, &'a str)> + '_ {
        self.lines
            .iter()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
            .map(|(i, l)| (i, *l))
    }

    /// A hint to append to errors on line `index` when the file may have been cut off.
    pub fn truncation_hint(&self, index: usize) -> &'static str {
        if self.unterminated && index + 1 == self.lines.len() {
            "; this is the last line and it has no line end: was the file cut off while \
             being written?"
        } else {
            ""
        }
    }
}

/// Decodes file bytes to text: UTF-8 (with or without BOM), else Latin-1 as older Windows
/// tools write it. Binary files, UTF-16 and empty files are errors.
pub(crate) fn decode(path: &Path, mut bytes: Vec<u8>) -> Result<String, InputError> {
    let place = || Place::file(path);
    let expected = "a text export (CSV, .dat, .out), UTF-8 or Latin-1";
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(InputError::new(place(), "the file is empty")
            .expected("a header line and rows of numbers"));
    }
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(InputError::new(
            place(),
            "the file is UTF-16 text, which hydroid does not read",
        )
        .expected(format!("{expected}; save it again as UTF-8")));
    }
    if let Some(pos) = bytes.iter().position(|&b| b == 0) {
        let line = 1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count();
        return Err(InputError::new(
            Place::line(path, line),
            format!("not a text file: a zero byte at byte offset {pos}"),
        )
        .expected(expected));
    }
    // Binary data without zero bytes: many control characters near the start.
    let head = &bytes[..bytes.len().min(65536)];
    let control = head
        .iter()
        .filter(|&&b| b < 0x20 && !matches!(b, b'\n' | b'\r' | b'\t' | 0x0c))
        .count();
    if control * 20 > head.len() {
        return Err(InputError::new(
            place(),
            format!(
                "not a text file: {control} control characters in the first {} bytes",
                head.len()
            ),
        )
        .expected(expected));
    }
    if bytes.starts_with(&[0xEF, 0xBB, 0xBF]) {
        bytes.drain(..3);
    }
    Ok(match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => e.into_bytes().iter().map(|&b| b as char).collect(),
    })
}

/// The text after a comment marker (`#`, `%`, `//`), or `None` for other lines.
pub(crate) fn comment(line: &str) -> Option<&str> {
    let t = line.trim_start();
    t.strip_prefix("//")
        .or_else(|| t.strip_prefix('#'))
        .or_else(|| t.strip_prefix('%'))
}

/// How the cells of a line are separated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Delim {
    /// One character: `,`, `;` or tab; empty cells are possible.
    Char(u8),
    /// Runs of spaces and tabs.
    Whitespace,
}

impl Delim {
    /// Name for messages and reports.
    pub fn describe(self) -> &'static str {
        match self {
            Delim::Char(b',') => "commas",
            Delim::Char(b';') => "semicolons",
            Delim::Char(b'\t') => "tabs",
            Delim::Char(_) => "a delimiter",
            Delim::Whitespace => "spaces or tabs",
        }
    }
}

/// One cell of a split line.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Field {
    /// Trimmed text, quotes removed (`""` inside quotes is one `"`).
    pub text: String,
    /// True when the cell was quoted.
    pub quoted: bool,
}

/// Splits a line into cells, honouring double quotes. Spaces around cells are dropped.
pub(crate) fn split_fields(line: &str, delim: Delim) -> Vec<Field> {
    let is_sep = |c: char| match delim {
        Delim::Char(d) => c == d as char,
        Delim::Whitespace => c == ' ' || c == '\t',
    };
    let pad = |c: char| (c == ' ' || c == '\t') && !is_sep(c);
    let s = match delim {
        Delim::Whitespace => line.trim(),
        Delim::Char(_) => line.trim_matches(|c: char| pad(c) || c == '\r' || c == '\n'),
    };
    if s.is_empty() && delim == Delim::Whitespace {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut chars = s.chars().peekable();
    loop {
        while chars.peek().is_some_and(|&c| pad(c)) {
            chars.next();
        }
        let mut text = String::new();
        let mut quoted = false;
        if chars.peek() == Some(&'"') {
            quoted = true;
            chars.next();
            while let Some(c) = chars.next() {
                if c != '"' {
                    text.push(c);
                } else if chars.peek() == Some(&'"') {
                    chars.next();
                    text.push('"');
                } else {
                    break;
                }
            }
        }
        let mut more = false;
        for c in chars.by_ref() {
            if is_sep(c) {
                more = true;
                break;
            }
            text.push(c);
        }
        out.push(Field {
            text: text.trim().to_string(),
            quoted,
        });
        if !more {
            break;
        }
        if delim == Delim::Whitespace {
            while chars.peek().is_some_and(|&c| is_sep(c)) {
                chars.next();
            }
        }
    }
    out
}

/// Parses one cell as a number (surrounding spaces and one pair of quotes allowed).
/// `nan` and `inf` parse; callers reject non-finite values with [`cell_error`].
pub(crate) fn parse_number(cell: &str) -> Option<f64> {
    let t = cell.trim();
    let t = t
        .strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(t)
        .trim();
    t.parse::<f64>().ok()
}

/// The error for a cell that is not a finite number.
pub(crate) fn cell_error(
    src: &Source,
    index: usize,
    column: usize,
    name: &str,
    text: &str,
) -> InputError {
    let place = src.at(index).with_column(column + 1).with_column_name(name);
    let shown = if text.chars().count() > 40 {
        format!("{}...", text.chars().take(40).collect::<String>())
    } else {
        text.to_string()
    };
    let message = match parse_number(text) {
        Some(v) if v.is_nan() => format!("'{shown}' is not a number (NaN)"),
        Some(_) => format!("'{shown}' is infinite"),
        None if text.contains(',') && text.replace(',', ".").parse::<f64>().is_ok() => {
            format!("'{shown}' is not a number (a decimal comma?)")
        }
        None => format!("'{shown}' is not a number"),
    };
    InputError::new(place, format!("{message}{}", src.truncation_hint(index)))
        .expected("a finite number such as 0.25 or -1.5e-3 (a diverged solver writes NaN: cut the file before it)")
}

/// The error for a row with the wrong number of cells.
pub(crate) fn count_error(
    src: &Source,
    index: usize,
    found: usize,
    names: &[String],
    delim: Delim,
) -> InputError {
    let n = names.len();
    let quote = if src.lines[index].matches('"').count() % 2 == 1 {
        "; a '\"' on this line opens a quote that never closes"
    } else {
        ""
    };
    InputError::new(
        src.at(index)
            .with_column(found.min(n) + 1 - usize::from(found > n)),
        format!(
            "{found} value{} on this line, but the table has {n} column{}{quote}{}",
            if found == 1 { "" } else { "s" },
            if n == 1 { "" } else { "s" },
            src.truncation_hint(index)
        ),
    )
    .expected(format!(
        "{n} values separated by {} ({})",
        delim.describe(),
        abbreviate(names)
    ))
}

/// `a, b, c ... (12 columns)` for messages.
pub(crate) fn abbreviate(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(6).map(String::as_str).collect();
    if names.len() > 6 {
        format!("{} ... ({} columns)", shown.join(", "), names.len())
    } else {
        shown.join(", ")
    }
}

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
    "K", "kelvin", "degC", "C", "A", "mA", "ampere", "V", "mV", "kV", "volt", "ohm", "Ohm", "S",
    "mol", "kmol", "cd", "lm", "lx", "T", "Wb", "H", "F", "Bq", "Gy", "Sv",
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
    options: &crate::formats::ReadOptions,
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

/// Reads whitespace-separated rows of plain numbers (`lines` are 0-based indices).
pub(crate) fn whitespace_rows(
    src: &Source,
    lines: impl IntoIterator<Item = usize>,
    names: &[String],
) -> Result<Rows, InputError> {
    let mut rows = Rows::new(names.len());
    let mut cells: Vec<f64> = Vec::with_capacity(names.len());
    for index in lines {
        let line = src.lines[index];
        cells.clear();
        let mut count = 0;
        for (j, tok) in line.split_ascii_whitespace().enumerate() {
            count += 1;
            if j >= names.len() {
                continue;
            }
            match parse_number(tok) {
                Some(v) if v.is_finite() => cells.push(v),
                _ => return Err(cell_error(src, index, j, &names[j], tok)),
            }
        }
        if count != names.len() {
            return Err(count_error(src, index, count, names, Delim::Whitespace));
        }
        for (col, v) in rows.columns.iter_mut().zip(&cells) {
            col.push(*v);
        }
        rows.lines.push(index + 1);
    }
    Ok(rows)
}

/// A token or a bracketed list in an OpenFOAM row such as `t ((a b c) (d e f))`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Node<'a> {
    /// A bare token and its 1-based character position.
    Atom(&'a str, usize),
    /// `( ... )` and the 1-based character position of its `(`.
    List(Vec<Node<'a>>, usize),
}

impl Node<'_> {
    /// 1-based character position where the node starts.
    pub fn pos(&self) -> usize {
        match self {
            Node::Atom(_, p) | Node::List(_, p) => *p,
        }
    }
}

/// Splits a line into tokens and bracketed lists. Unbalanced brackets are an error:
/// (1-based character position, what is wrong).
pub(crate) fn parse_brackets(line: &str) -> Result<Vec<Node<'_>>, (usize, String)> {
    type Stack<'a> = Vec<(Vec<Node<'a>>, usize)>;
    fn flush<'a>(
        line: &'a str,
        stack: &mut Stack<'a>,
        start: &mut Option<(usize, usize)>,
        end: usize,
    ) {
        if let Some((b, p)) = start.take() {
            if let Some(top) = stack.last_mut() {
                top.0.push(Node::Atom(&line[b..end], p));
            }
        }
    }
    let mut stack: Stack = vec![(Vec::new(), 0)];
    // (byte, character position) where the current token started
    let mut start: Option<(usize, usize)> = None;
    for (pos, (b, c)) in line.char_indices().enumerate() {
        let pos = pos + 1;
        match c {
            '(' => {
                flush(line, &mut stack, &mut start, b);
                stack.push((Vec::new(), pos));
            }
            ')' => {
                flush(line, &mut stack, &mut start, b);
                if stack.len() == 1 {
                    return Err((
                        pos,
                        format!("')' at character {pos} closes a bracket that was never opened"),
                    ));
                }
                if let Some((items, open)) = stack.pop() {
                    if let Some(top) = stack.last_mut() {
                        top.0.push(Node::List(items, open));
                    }
                }
            }
            c if c.is_whitespace() => flush(line, &mut stack, &mut start, b),
            _ => {
                if start.is_none() {
                    start = Some((b, pos));
                }
            }
        }
    }
    flush(line, &mut stack, &mut start, line.len());
    if stack.len() > 1 {
        let open = stack.last().map_or(0, |s| s.1);
        return Err((open, format!("'(' at character {open} is never closed")));
    }
    Ok(stack.pop().map(|s| s.0).unwrap_or_default())
}

/// Splits at whitespace outside brackets: `Time forces(pressure viscous) Cl(f)` is three
/// tokens.
pub(crate) fn bracketed_tokens(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut start = None;
    for (b, c) in s.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ => {}
        }
        if c.is_whitespace() && depth <= 0 {
            if let Some(a) = start.take() {
                out.push(&s[a..b]);
            }
        } else if start.is_none() {
            start = Some(b);
        }
    }
    if let Some(a) = start {
        out.push(&s[a..]);
    }
    out
}

/// Puts heads and rows together into a table and finds the time column.
pub(crate) fn assemble(
    path: &Path,
    format: crate::formats::Format,
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

fn warn_duplicates(table: &mut Table) {
    for i in 0..table.columns.len() {
        let name = &table.columns[i].name;
        if let Some(j) = table.columns[..i].iter().position(|c| &c.name == name) {
            let w = format!(
                "column name '{name}' appears twice (columns {} and {}); a configuration that \
                 names it gets column {}, use `index = {}` for the other",
                j + 1,
                i + 1,
                j + 1,
                i + 1
            );
            table.warnings.push(w);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &str, d: Delim) -> Vec<String> {
        split_fields(line, d).into_iter().map(|f| f.text).collect()
    }

    #[test]
    fn fields() {
        assert_eq!(texts(" a , \"b,c\" ,", Delim::Char(b',')), ["a", "b,c", ""]);
        assert_eq!(
            texts("\"Flow Time\" \"cd\"", Delim::Whitespace),
            ["Flow Time", "cd"]
        );
        assert_eq!(texts("1\t\t2", Delim::Char(b'\t')), ["1", "", "2"]);
        assert_eq!(texts("  1   2\t3 ", Delim::Whitespace), ["1", "2", "3"]);
        assert!(texts("   ", Delim::Whitespace).is_empty());
        assert_eq!(texts("\"a \"\"q\"\"\"", Delim::Char(b',')), ["a \"q\""]);
    }

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

    #[test]
    fn brackets() {
        let n = parse_brackets("1 ((2 3) (4)) 5").unwrap();
        assert_eq!(n.len(), 3);
        assert!(matches!(&n[1], Node::List(v, 3) if v.len() == 2));
        assert_eq!(parse_brackets("1 ((2 3) (4) 5").unwrap_err().0, 3);
        assert_eq!(parse_brackets("1 (2 3))").unwrap_err().0, 8);
        assert_eq!(
            bracketed_tokens("# Time forces(pressure viscous) Cl(f)"),
            ["#", "Time", "forces(pressure viscous)", "Cl(f)"]
        );
    }

    #[test]
    fn lines_and_terminators() {
        let p = Path::new("x");
        let s = Source::new(p, "a\r\nb\r\n");
        assert_eq!(s.lines, ["a", "b"]);
        assert!(!s.unterminated);
        let s = Source::new(p, "a\nb");
        assert_eq!(s.lines, ["a", "b"]);
        assert!(s.unterminated);
        let s = Source::new(p, "a\rb\r");
        assert_eq!(s.lines, ["a", "b"]);
    }
}
