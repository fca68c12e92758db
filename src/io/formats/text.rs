//! Shared pieces of every reader: decoding the file, lines, fields, numbers, units in
//! headers, and the errors that name the place.
//!
//! Nothing here knows a particular CFD code; the readers combine these helpers.

use super::columns::Rows;
use crate::base::error::{InputError, Place};
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

    /// Blanks the first `n` lines, which then read as empty lines (line numbers stay those of
    /// the file), and returns their non-blank text as `title` metadata. More lines than the
    /// file has is an error.
    pub fn skip_lines(&mut self, n: usize) -> Result<Vec<(String, String)>, InputError> {
        if n >= self.lines.len() && n > 0 {
            return Err(InputError::new(
                self.file(),
                format!(
                    "skip_lines = {n}, but the file has only {} line{}",
                    self.lines.len(),
                    if self.lines.len() == 1 { "" } else { "s" }
                ),
            )
            .expected("skip_lines smaller than the number of lines: the title lines only"));
        }
        let mut titles = Vec::new();
        for line in &mut self.lines[..n] {
            let t = line.trim();
            if !t.is_empty() {
                titles.push(("title".to_string(), t.to_string()));
            }
            *line = "";
        }
        Ok(titles)
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

/// The cells of `line` under the delimiter that splits it into the most: commas, semicolons,
/// tabs, or runs of blanks (quotes are not honoured: an upper bound). Returns the count and
/// the delimiter.
fn widest_split(line: &str) -> (usize, Delim) {
    let (mut comma, mut semi, mut tab, mut words) = (0usize, 0usize, 0usize, 0usize);
    let mut blank = true;
    for b in line.bytes() {
        match b {
            b',' => comma += 1,
            b';' => semi += 1,
            b'\t' => tab += 1,
            _ => {}
        }
        let is_blank = b == b' ' || b == b'\t';
        if blank && !is_blank {
            words += 1;
        }
        blank = is_blank;
    }
    // the last of equal counts wins: a single-character delimiter over blanks
    [
        (words, Delim::Whitespace),
        (comma + 1, Delim::Char(b',')),
        (semi + 1, Delim::Char(b';')),
        (tab + 1, Delim::Char(b'\t')),
    ]
    .into_iter()
    .max_by_key(|(n, _)| *n)
    .unwrap_or((0, Delim::Whitespace))
}

/// Refuses a file with a line of more than `max_columns` cells, before any line is split:
/// the structures kept per column would take far more memory than the numbers (an absurdly
/// wide table, or a binary stream that happens to be text). One pass over the bytes.
pub(crate) fn check_width(src: &Source, max_columns: u64) -> Result<(), InputError> {
    let max = usize::try_from(max_columns).unwrap_or(usize::MAX);
    for (i, line) in src.lines.iter().enumerate() {
        // a line of fewer bytes cannot hold more cells
        if line.len() < max {
            continue;
        }
        let (n, delim) = widest_split(line);
        if n > max {
            use super::input::{Limits, MAX_COLUMNS_ENV};
            let most = Limits::MOST_COLUMNS;
            // advice that reads the file, where any value may
            let advice = if n as u64 <= most {
                format!(
                    "set the environment variable {MAX_COLUMNS_ENV} to read a wider one \
                     ({MAX_COLUMNS_ENV}={} reads this line)",
                    (n.next_power_of_two() as u64).min(most)
                )
            } else {
                format!(
                    "hydroid reads no table of more than {most} columns (the most \
                     {MAX_COLUMNS_ENV} may be): a table has one row per line, and this line is \
                     not one (binary data, or text without line ends?)"
                )
            };
            return Err(InputError::new(
                src.at(i),
                format!(
                    "this line has {n} cells separated by {}, more than the {max} columns \
                     hydroid reads in a table; {advice}",
                    delim.describe(),
                ),
            )
            .expected(format!(
                "a table of at most {max} columns (rows of numbers, one line each)"
            )));
        }
    }
    Ok(())
}

/// Decodes file bytes to text: UTF-8 (with or without BOM), else Windows-1252 as older
/// Windows tools write it (a superset of Latin-1 for printable text: 0x96 is an en dash, 0xB0
/// a degree sign). Binary files, UTF-16 and empty files are errors.
pub(crate) fn decode(path: &Path, mut bytes: Vec<u8>) -> Result<String, InputError> {
    let place = || Place::file(path);
    let expected = "a text export (CSV, .dat, .out), UTF-8 or Windows-1252";
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
        Err(e) => e.into_bytes().iter().map(|&b| windows_1252(b)).collect(),
    })
}

/// One byte of Windows-1252 text as a character. 0x80 to 0x9F are typographic characters
/// (Unicode's mapping table MAPPINGS/VENDORS/MICSFT/WINDOWS/CP1252.TXT); the five bytes it
/// leaves undefined keep their Latin-1 control code, as the WHATWG Encoding Standard does.
fn windows_1252(b: u8) -> char {
    const HIGH: [char; 32] = [
        '\u{20AC}', '\u{81}', '\u{201A}', '\u{192}', '\u{201E}', '\u{2026}', '\u{2020}',
        '\u{2021}', '\u{2C6}', '\u{2030}', '\u{160}', '\u{2039}', '\u{152}', '\u{8D}', '\u{17D}',
        '\u{8F}', '\u{90}', '\u{2018}', '\u{2019}', '\u{201C}', '\u{201D}', '\u{2022}', '\u{2013}',
        '\u{2014}', '\u{2DC}', '\u{2122}', '\u{161}', '\u{203A}', '\u{153}', '\u{9D}', '\u{17E}',
        '\u{178}',
    ];
    match b {
        0x80..=0x9F => HIGH[usize::from(b - 0x80)],
        _ => char::from(b),
    }
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
///
/// Works on bytes: separators, quotes and padding are ASCII, which never occur inside a
/// multi-byte UTF-8 character, so every slice boundary is a character boundary. One pass over
/// the line, one allocation per cell.
pub(crate) fn split_fields(line: &str, delim: Delim) -> Vec<Field> {
    let is_sep = |b: u8| match delim {
        Delim::Char(d) => b == d,
        Delim::Whitespace => b == b' ' || b == b'\t',
    };
    let pad = |b: u8| (b == b' ' || b == b'\t') && !is_sep(b);
    let s = match delim {
        Delim::Whitespace => line.trim(),
        Delim::Char(_) => {
            line.trim_matches(|c: char| c.is_ascii() && (pad(c as u8) || c == '\r' || c == '\n'))
        }
    };
    if s.is_empty() && delim == Delim::Whitespace {
        return Vec::new();
    }
    let bytes = s.as_bytes();
    let len = bytes.len();
    let mut out = Vec::new();
    let mut i = 0;
    loop {
        while i < len && pad(bytes[i]) {
            i += 1;
        }
        let mut text = String::new();
        let mut quoted = false;
        if i < len && bytes[i] == b'"' {
            quoted = true;
            i += 1;
            loop {
                match bytes[i..].iter().position(|&b| b == b'"') {
                    None => {
                        // A quote that never closes takes the rest of the line.
                        text.push_str(&s[i..]);
                        i = len;
                        break;
                    }
                    Some(k) => {
                        text.push_str(&s[i..i + k]);
                        i += k + 1;
                        if i < len && bytes[i] == b'"' {
                            text.push('"');
                            i += 1;
                        } else {
                            break;
                        }
                    }
                }
            }
        }
        let end = bytes[i..]
            .iter()
            .position(|&b| is_sep(b))
            .map_or(len, |k| i + k);
        text.push_str(&s[i..end]);
        let more = end < len;
        i = if more { end + 1 } else { len };
        let trimmed = text.trim();
        let text = if trimmed.len() == text.len() {
            text
        } else {
            trimmed.to_string()
        };
        out.push(Field { text, quoted });
        if !more {
            break;
        }
        if delim == Delim::Whitespace {
            while i < len && is_sep(bytes[i]) {
                i += 1;
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
    let line = src.lines[index];
    let quote = if line.matches('"').count() % 2 == 1 {
        "; a '\"' on this line opens a quote that never closes"
    } else if delim == Delim::Char(b',') && found > n && decimal_commas_likely(line) {
        DECIMAL_COMMA_HINT_SEP
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

/// What to do about decimal commas in a comma-separated file.
pub(crate) const DECIMAL_COMMA_HINT: &str = "this file seems to use decimal commas with a comma \
     separator; export with a semicolon or point decimals";
/// [`DECIMAL_COMMA_HINT`] appended to a message.
const DECIMAL_COMMA_HINT_SEP: &str = "; this file seems to use decimal commas with a comma \
     separator; export with a semicolon or point decimals";

/// True when a comma-separated line reads as numbers written with decimal commas: no decimal
/// point anywhere and every cell an optionally signed run of digits, perhaps with an exponent
/// (`-0,5,1,25e-3` splits into `-0`, `5`, `1`, `25e-3`).
pub(crate) fn decimal_commas_likely(line: &str) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let cell = |c: &str| {
        let c = c.trim().trim_matches('"');
        let c = c.strip_prefix(['-', '+']).unwrap_or(c);
        match c.split_once(['e', 'E']) {
            Some((m, e)) => digits(m) && digits(e.strip_prefix(['-', '+']).unwrap_or(e)),
            None => digits(c),
        }
    };
    !line.contains('.') && line.contains(',') && line.split(',').all(cell)
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
    // Deeper than any OpenFOAM row (forces.dat nests two levels); the bound keeps a
    // malformed line from building an unbounded tree.
    const MAX_DEPTH: usize = 16;
    let mut stack: Stack = vec![(Vec::new(), 0)];
    // (byte, character position) where the current token started
    let mut start: Option<(usize, usize)> = None;
    for (pos, (b, c)) in line.char_indices().enumerate() {
        let pos = pos + 1;
        match c {
            '(' => {
                flush(line, &mut stack, &mut start, b);
                if stack.len() > MAX_DEPTH {
                    return Err((
                        pos,
                        format!("'(' at character {pos} nests brackets more than {MAX_DEPTH} deep"),
                    ));
                }
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
        assert_eq!(texts("\"a,b", Delim::Char(b',')), ["a,b"]);
        assert_eq!(
            texts("\"a\"x ,°y;\u{2013}", Delim::Char(b',')),
            ["ax", "°y;\u{2013}"]
        );
        assert_eq!(texts("x,", Delim::Char(b',')), ["x", ""]);
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
