//! The module paths one Rust source file names, read lexically (no parser, no name
//! resolution), the same way as the project's hand tool `layers.py` reads them:
//!
//! * block comments `/* ... */` go first, then every line from the first one that starts
//!   with `#[cfg(test)]` (a file's test module sits at its end), then `//` line comments;
//! * every `use ...;` statement, whitespace removed, its groups expanded
//!   (`a::{b, c::{d, e}}` -> `a::b`, `a::c::d`, `a::c::e`; `a::{self}` -> `a`);
//! * every path anywhere in the code that starts with `crate::`, `super::` or `self::`
//!   (a path used inline, `crate::units::Unit::Metre` in an expression).
//!
//! Each path comes with the 1-based line it was written on, for the failure messages.

/// One module path named in a file: as written (whitespace removed, groups expanded) and
/// the line it starts on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mention {
    /// 1-based line of the `use` keyword or of the inline path.
    pub line: usize,
    /// The path, e.g. `crate::units::Unit` or `super::x::*`.
    pub path: String,
}

/// Source text with comments and test modules removed; each character keeps the 1-based
/// line of the original file it came from.
struct Stripped {
    chars: Vec<char>,
    lines: Vec<usize>,
}

/// Every module path the file's text names, `use` statements first, then inline paths.
pub fn mentions(text: &str) -> Vec<Mention> {
    let s = strip(text);
    let mut out = Vec::new();
    for (start, body) in use_statements(&s.chars) {
        let path: String = body.iter().filter(|c| !c.is_whitespace()).collect();
        for p in expand(&path) {
            out.push(Mention {
                line: s.lines[start],
                path: p,
            });
        }
    }
    for (start, end) in inline_paths(&s.chars) {
        out.push(Mention {
            line: s.lines[start],
            path: s.chars[start..end].iter().collect(),
        });
    }
    out
}

/// A word character of a regular expression's `\w`: a letter, digit or underscore.
fn is_word(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Whether position `i` of `chars` starts a word (`\b` before a word character).
fn word_starts(chars: &[char], i: usize) -> bool {
    i == 0 || !is_word(chars[i - 1])
}

/// Whether `chars[i..]` starts with `pat`.
fn starts_with(chars: &[char], i: usize, pat: &str) -> bool {
    pat.chars()
        .enumerate()
        .all(|(n, p)| chars.get(i + n) == Some(&p))
}

/// The text without block comments, without everything from the first line that starts
/// with `#[cfg(test)]`, and without `//` comments.
fn strip(text: &str) -> Stripped {
    let (chars, lines) = drop_block_comments(text);
    let mut out = Stripped {
        chars: Vec::new(),
        lines: Vec::new(),
    };
    for (k, (a, b)) in split_lines(&chars).into_iter().enumerate() {
        let line = &chars[a..b];
        let indent = line.iter().take_while(|c| c.is_whitespace()).count();
        if starts_with(line, indent, "#[cfg(test)]") {
            break;
        }
        let end = (0..line.len())
            .find(|&i| starts_with(line, i, "//"))
            .unwrap_or(line.len());
        if k > 0 {
            // The line break joining this line to the previous one.
            out.chars.push('\n');
            out.lines.push(lines[a.saturating_sub(1)]);
        }
        out.chars.extend_from_slice(&line[..end]);
        out.lines.extend_from_slice(&lines[a..a + end]);
    }
    out
}

/// The text's characters with every `/* ... */` removed (shortest match, across lines), and
/// the 1-based original line of each character kept.
fn drop_block_comments(text: &str) -> (Vec<char>, Vec<usize>) {
    let all: Vec<char> = text.chars().collect();
    let mut line = 1;
    let mut numbered = Vec::with_capacity(all.len());
    for &c in &all {
        numbered.push(line);
        if c == '\n' {
            line += 1;
        }
    }
    let (mut chars, mut lines) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < all.len() {
        if starts_with(&all, i, "/*") {
            if let Some(end) = (i + 2..all.len()).find(|&k| starts_with(&all, k, "*/")) {
                i = end + 2;
                continue;
            }
        }
        chars.push(all[i]);
        lines.push(numbered[i]);
        i += 1;
    }
    (chars, lines)
}

/// The lines of `chars` as `[start, end)` ranges, split where Python's `str.splitlines`
/// splits (`\n`, `\r\n`, `\r` and the other Unicode line boundaries); no empty last line.
fn split_lines(chars: &[char]) -> Vec<(usize, usize)> {
    let breaks = [
        '\n', '\r', '\x0b', '\x0c', '\x1c', '\x1d', '\x1e', '\u{85}', '\u{2028}', '\u{2029}',
    ];
    let mut out = Vec::new();
    let (mut start, mut i) = (0, 0);
    while i < chars.len() {
        if breaks.contains(&chars[i]) {
            out.push((start, i));
            let crlf = chars[i] == '\r' && chars.get(i + 1) == Some(&'\n');
            i += if crlf { 2 } else { 1 };
            start = i;
        } else {
            i += 1;
        }
    }
    if start < chars.len() {
        out.push((start, chars.len()));
    }
    out
}

/// Every `use` statement: where its keyword starts, and its body from after the whitespace
/// following `use` up to (not including) the next `;`. Statements do not overlap: a `use`
/// inside an earlier statement's body is part of that body.
fn use_statements(chars: &[char]) -> Vec<(usize, &[char])> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let keyword = starts_with(chars, i, "use")
            && word_starts(chars, i)
            && chars.get(i + 3).is_some_and(|c| c.is_whitespace());
        if keyword {
            let body = i
                + 3
                + chars[i + 3..]
                    .iter()
                    .take_while(|c| c.is_whitespace())
                    .count();
            if let Some(semi) = (i + 3..chars.len()).find(|&k| chars[k] == ';') {
                out.push((i, &chars[body.min(semi)..semi]));
                i = semi + 1;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Every path `crate::a::b`, `super::a` or `self::a` (at least one `::name` after the
/// keyword, the keyword a whole word) as a `[start, end)` range; no overlaps.
fn inline_paths(chars: &[char]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let keyword = ["crate", "super", "self"]
            .into_iter()
            .find(|k| word_starts(chars, i) && starts_with(chars, i, k));
        if let Some(k) = keyword {
            let mut end = i + k.len();
            loop {
                let name = chars[(end + 2).min(chars.len())..]
                    .iter()
                    .take_while(|&&c| is_word(c))
                    .count();
                if !starts_with(chars, end, "::") || name == 0 {
                    break;
                }
                end += 2 + name;
            }
            if end > i + k.len() {
                out.push((i, end));
                i = end;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// A `use` body (whitespace removed) with its groups expanded: `a::{b, c::{d, e}}` ->
/// `a::b`, `a::c::d`, `a::c::e`; `a::{self, b}` -> `a`, `a::b`; a body without a group is
/// itself. Globs stay as written (`a::*`).
pub fn expand(path: &str) -> Vec<String> {
    let chars: Vec<char> = path.chars().collect();
    // The head is the run of name characters and colons before the first `::{`.
    let head_end = chars
        .iter()
        .position(|&c| !(is_word(c) || c == ':'))
        .unwrap_or(chars.len());
    let grouped = head_end >= 2
        && chars.get(head_end) == Some(&'{')
        && starts_with(&chars, head_end - 2, "::")
        && chars.last() == Some(&'}')
        && chars.len() >= head_end + 2;
    if !grouped {
        return vec![path.to_string()];
    }
    let head: String = chars[..head_end - 2].iter().collect();
    let body = &chars[head_end + 1..chars.len() - 1];
    let mut out = Vec::new();
    for part in split_top_level(body) {
        if part == "self" {
            out.push(head.clone());
        } else if !part.is_empty() {
            out.extend(expand(&format!("{head}::{part}")));
        }
    }
    out
}

/// A group's body split at the commas outside nested braces.
fn split_top_level(body: &[char]) -> Vec<String> {
    let mut parts = Vec::new();
    let (mut depth, mut cur) = (0i32, String::new());
    for &c in body {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if c == ',' && depth == 0 {
            parts.push(std::mem::take(&mut cur));
        } else {
            cur.push(c);
        }
    }
    parts.push(cur);
    parts
}
