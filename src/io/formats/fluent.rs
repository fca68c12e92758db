//! ANSYS Fluent report files (`.out`) and older convergence histories.
//!
//! A report file starts with three header lines: a quoted title, the quoted column names,
//! and the names again in parentheses; the parenthesised list is the complete one (the second
//! line may be shortened). Older histories have only the title and the names, and often CRLF
//! line ends. Rows are whitespace-separated numbers. The time column is `flow-time` or
//! `Flow Time`, in seconds; iteration and time-step counters have no unit.

use super::columns::{apply_names, assemble, normalise, Head};
use super::text::{split_fields, whitespace_rows, Delim, Source};
use super::{Format, ReadOptions};
use crate::base::error::InputError;
use crate::io::table::Table;

/// True when the first line is one quoted string and the next is a line of quoted names.
pub(crate) fn looks_like(src: &Source) -> bool {
    let mut lines = src.content().map(|(_, l)| l.trim());
    let (Some(title), Some(names)) = (lines.next(), lines.next()) else {
        return false;
    };
    let t = split_fields(title, Delim::Whitespace);
    let n = split_fields(names, Delim::Whitespace);
    t.len() == 1 && t[0].quoted && !n.is_empty() && n.iter().all(|f| f.quoted)
}

/// Reads a Fluent report file or history.
pub(crate) fn read(src: &Source, options: &ReadOptions) -> Result<Table, InputError> {
    let content: Vec<usize> = src.content().map(|(i, _)| i).collect();
    let mut k = 0;
    let mut meta = Vec::new();
    if let Some(&i) = content.first() {
        let f = split_fields(src.lines[i], Delim::Whitespace);
        if f.len() == 1 && f[0].quoted {
            meta.push(("title".to_string(), f[0].text.clone()));
            k = 1;
        }
    }
    let mut names: Vec<String> = Vec::new();
    let mut header_line = None;
    while let Some(&i) = content.get(k) {
        let line = src.lines[i].trim();
        if let Some(inner) = line.strip_prefix('(') {
            let Some(inner) = inner.strip_suffix(')') else {
                return Err(InputError::new(
                    src.at(i),
                    "the list of column names opens '(' but does not close it",
                )
                .expected("(\"name 1\" \"name 2\" ...) on one line"));
            };
            names = fields(inner);
        } else if line.starts_with('"') {
            names = fields(line);
        } else {
            break;
        }
        header_line = Some(i);
        k += 1;
    }
    let Some(header_line) = header_line.filter(|_| !names.is_empty()) else {
        let at = content.get(k).map_or(src.file(), |&i| src.at(i));
        return Err(InputError::new(at, "no line of quoted column names")
            .expected("a Fluent report file: a quoted title, then \"Iteration\" \"name\" ..."));
    };
    let mut heads: Vec<Head> = names
        .iter()
        .map(|n| {
            let norm = normalise(n);
            if norm == "flowtime" {
                Head::si(n.clone(), "s")
            } else {
                Head::plain(n.clone())
            }
        })
        .collect();
    apply_names(&mut heads, options, src.at(header_line))?;
    let names: Vec<String> = heads.iter().map(|h| h.name.clone()).collect();
    let rows = whitespace_rows(src, content[k..].iter().copied(), &names)?;
    Ok(assemble(
        src.path,
        Format::Fluent,
        heads,
        rows,
        meta,
        Vec::new(),
    ))
}

fn fields(s: &str) -> Vec<String> {
    split_fields(s, Delim::Whitespace)
        .into_iter()
        .map(|f| f.text)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn parenthesised_names_win() {
        let text = "\"r\"\r\n\"Time Step\" \"m etc..\"\r\n(\"Time Step\" \"m\" \"flow-time\")\r\n\
                    0 0.5 0\r\n1 0.25 0.1\r\n";
        let src = Source::new(Path::new("r.out"), text);
        assert!(looks_like(&src));
        let t = read(&src, &ReadOptions::default()).unwrap();
        assert_eq!(t.names(), ["Time Step", "m", "flow-time"]);
        assert_eq!(t.time, Some(2));
        assert_eq!(t.lines, [4, 5]);
        assert_eq!(t.meta("title"), Some("r"));
    }

    #[test]
    fn unclosed_name_list_is_an_error() {
        let src = Source::new(
            Path::new("r.out"),
            "\"r\"\n\"a\" \"b\"\n(\"a\" \"b\"\n1 2\n",
        );
        let e = read(&src, &ReadOptions::default()).unwrap_err();
        assert_eq!(e.place.line, Some(3));
    }
}
