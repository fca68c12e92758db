//! Shared pieces of every reader: decoding the file, lines, fields, numbers, units in
//! headers, and the errors that name the place.
//!
//! Nothing here knows a particular CFD code; the readers combine these helpers.

use super::columns::Rows;
use crate::error::{InputError, Place};
use std::path::Path;

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
