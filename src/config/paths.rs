//! Key paths in a TOML document (`hekf.runs[0].constants.thrust`): finding the key at a
//! byte span the TOML reader reports, and removing or replacing the value at a path.

use std::ops::Range;
use toml_edit::{DocumentMut, Item, Table, TableLike, Value};

/// One step of a key path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    /// A key in a table.
    Key(String),
    /// A 0-based position in a list or an array of tables.
    Index(usize),
}

impl Seg {
    /// The dotted form, `a.b[0].c`, with a key that is not a bare TOML key quoted
    /// (`captive.oscillations."pure sway".amplitude`), so that [`parse_path`] reads it back.
    pub fn join(path: &[Seg]) -> String {
        let mut s = String::new();
        for seg in path {
            match seg {
                Seg::Key(k) => {
                    if !s.is_empty() {
                        s.push('.');
                    }
                    s.push_str(&key_text(k));
                }
                Seg::Index(i) => s.push_str(&format!("[{i}]")),
            }
        }
        s
    }
}

/// A key as TOML writes it in a dotted key: bare when it may be (letters, digits, `_`, `-`),
/// else a basic string in double quotes.
pub fn key_text(key: &str) -> String {
    if is_bare(key) {
        return key.to_string();
    }
    let mut s = String::from("\"");
    for c in key.chars() {
        match c {
            '"' => s.push_str("\\\""),
            '\\' => s.push_str("\\\\"),
            c if c.is_control() => s.push_str(&format!("\\u{:04X}", c as u32)),
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

/// A bare TOML key: one or more ASCII letters, digits, `_` or `-`.
fn is_bare(key: &str) -> bool {
    !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The most steps (keys and list positions) a key path may have: the deepest key of a
/// configuration has 6 (`hekf.runs[0].columns.rudder.scale`). It bounds the work of setting
/// a key and of every later walk of the document (each nested table is a level of it).
pub const MAX_PATH_STEPS: usize = 32;
/// The longest key path, in bytes (quoted keys included).
pub const MAX_PATH_BYTES: usize = 1024;
/// The highest list position a key path may name: far more runs than any configuration has.
pub const MAX_POSITION: usize = 99_999;

/// Reads a key path as `--set` and messages write it: TOML's dotted keys (bare keys,
/// "basic" keys with escapes, 'literal' keys, whitespace around the dots), each followed by
/// any number of list positions `[N]` (0-based). Returns the segments and the text after
/// the path (after `KEY` in `KEY=VALUE`: the `=` and the value). The error says what was
/// expected where the path stops making sense. A path of more than [`MAX_PATH_STEPS`] steps
/// or [`MAX_PATH_BYTES`] bytes, or a position above [`MAX_POSITION`], is refused with the
/// limit: the reading stops there, so a path of any length costs no more than the limits.
pub fn parse_path(text: &str) -> Result<(Vec<Seg>, &str), String> {
    let mut segs = Vec::new();
    let start = text.trim_start();
    let mut s = start;
    loop {
        let (key, rest) = one_key(s)?;
        segs.push(Seg::Key(key));
        s = rest.trim_start();
        while let Some(inner) = s.strip_prefix('[') {
            let close = inner.find(']').ok_or_else(|| {
                let shown: String = inner.chars().take(20).collect();
                format!("'[{shown}': a list position ends with ']', e.g. runs[0]")
            })?;
            segs.push(Seg::Index(position(inner[..close].trim())?));
            s = inner[close + 1..].trim_start();
        }
        path_within_limits(segs.len(), start.len() - s.len())?;
        match s.strip_prefix('.') {
            Some(rest) => s = rest.trim_start(),
            None => return Ok((segs, s)),
        }
    }
}

/// A list position `[N]`: a whole number from 0 to [`MAX_POSITION`].
fn position(n: &str) -> Result<usize, String> {
    let shown: String = n.chars().take(20).collect();
    if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) {
        if let Some(i) = n.parse::<usize>().ok().filter(|&i| i <= MAX_POSITION) {
            return Ok(i);
        }
        return Err(format!(
            "'[{shown}]' is past the highest list position hydroid reads ([{MAX_POSITION}]); \
             a list of a configuration has a few entries, from [0]"
        ));
    }
    Err(format!(
        "'[{shown}]' is not a list position: expected a whole number from 0, e.g. runs[0]"
    ))
}

/// Refuses a key path past [`MAX_PATH_STEPS`] steps or [`MAX_PATH_BYTES`] bytes.
fn path_within_limits(steps: usize, bytes: usize) -> Result<(), String> {
    if steps > MAX_PATH_STEPS {
        return Err(format!(
            "the key has more than {MAX_PATH_STEPS} steps (keys and list positions), the most \
             a key path may have (the deepest key of a configuration has 6, e.g. \
             hekf.runs[0].columns.rudder.scale)"
        ));
    }
    if bytes > MAX_PATH_BYTES {
        return Err(format!(
            "the key is longer than {MAX_PATH_BYTES} bytes, the longest key path hydroid reads"
        ));
    }
    Ok(())
}

/// One key at the start of `s` (bare, "basic" or 'literal'), and the text after it.
fn one_key(s: &str) -> Result<(String, &str), String> {
    let stop = |what: &str| {
        let shown: String = s.chars().take(20).collect();
        Err(format!(
            "{what} at '{shown}': a key is a bare word (letters, digits, _ and -) or a quoted \
             string (\"pure sway\" or 'pure sway')"
        ))
    };
    if let Some(inner) = s.strip_prefix('\'') {
        return match inner.find('\'') {
            Some(end) => Ok((inner[..end].to_string(), &inner[end + 1..])),
            None => stop("an unclosed quote"),
        };
    }
    if let Some(inner) = s.strip_prefix('"') {
        // the closing quote is the first one not escaped by a backslash
        let mut escaped = false;
        let end = inner.char_indices().find_map(|(i, c)| {
            let close = c == '"' && !escaped;
            escaped = c == '\\' && !escaped;
            close.then_some(i)
        });
        let Some(end) = end else {
            return stop("an unclosed quote");
        };
        let quoted = &s[..end + 2];
        // TOML's own reading of the escapes
        let key = format!("{quoted} = 0")
            .parse::<toml_edit::DocumentMut>()
            .ok()
            .and_then(|d| d.iter().next().map(|(k, _)| k.to_string()));
        return match key {
            Some(k) => Ok((k, &inner[end + 1..])),
            None => stop("a quoted key with a bad escape"),
        };
    }
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
        .unwrap_or(s.len());
    if end == 0 {
        return stop("no key");
    }
    Ok((s[..end].to_string(), &s[end..]))
}

/// A node of the document with its place.
pub struct Entry {
    /// Where it is.
    pub path: Vec<Seg>,
    /// Its span (a table's header, a value's text).
    pub span: Option<Range<usize>>,
    /// The span of the key that names it, if any.
    pub key_span: Option<Range<usize>>,
    /// Why the value cannot be used in any configuration (not finite, a date), if so.
    pub unusable: Option<String>,
}

/// Every table and value of `text` with its path; empty when `text` is not TOML.
pub fn entries(text: &str) -> Vec<Entry> {
    let Ok(doc) = toml_edit::Document::parse(text.to_string()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    walk_table(doc.as_table(), &mut Vec::new(), &mut out);
    out
}

fn walk_table(t: &dyn TableLike, path: &mut Vec<Seg>, out: &mut Vec<Entry>) {
    for (k, item) in t.iter() {
        let key_span = t.key(k).and_then(|key| key.span());
        path.push(Seg::Key(k.to_string()));
        walk_item(item, key_span, path, out);
        path.pop();
    }
}

fn walk_item(
    item: &Item,
    key_span: Option<Range<usize>>,
    path: &mut Vec<Seg>,
    out: &mut Vec<Entry>,
) {
    match item {
        Item::None => {}
        Item::Table(t) => {
            out.push(Entry {
                path: path.clone(),
                span: t.span(),
                key_span,
                unusable: None,
            });
            walk_table(t, path, out);
        }
        Item::ArrayOfTables(a) => {
            out.push(Entry {
                path: path.clone(),
                span: a.span(),
                key_span,
                unusable: None,
            });
            for (i, t) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                out.push(Entry {
                    path: path.clone(),
                    span: t.span(),
                    key_span: None,
                    unusable: None,
                });
                walk_table(t, path, out);
                path.pop();
            }
        }
        Item::Value(v) => walk_value(v, key_span, path, out),
    }
}

fn walk_value(
    v: &Value,
    key_span: Option<Range<usize>>,
    path: &mut Vec<Seg>,
    out: &mut Vec<Entry>,
) {
    let unusable = match v {
        Value::Float(f) if !f.value().is_finite() => Some(format!(
            "{} is not a finite number; give a value (SI, or a string with a unit)",
            f.display_repr()
        )),
        Value::Datetime(_) => Some("a date or time is not a value hydroid uses here".to_string()),
        _ => None,
    };
    out.push(Entry {
        path: path.clone(),
        span: v.span(),
        key_span,
        unusable,
    });
    match v {
        Value::Array(a) => {
            for (i, e) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                walk_value(e, None, path, out);
                path.pop();
            }
        }
        Value::InlineTable(t) => walk_table(t, path, out),
        _ => {}
    }
}

/// The path at `span`, and whether the span is a key (rather than a value or a table).
/// An empty span at the start is the whole document (a key missing at the top level).
pub fn locate(entries: &[Entry], span: Option<Range<usize>>) -> Option<(Vec<Seg>, bool)> {
    let span = span?;
    if span.is_empty() && span.start == 0 {
        return Some((Vec::new(), false));
    }
    if let Some(e) = entries.iter().find(|e| e.key_span.as_ref() == Some(&span)) {
        return Some((e.path.clone(), true));
    }
    let mut best: Option<(usize, &Entry)> = None;
    for e in entries {
        let Some(s) = &e.span else { continue };
        if s.start <= span.start && span.end <= s.end {
            let len = s.end - s.start;
            // the smallest enclosing node; on a tie the deeper one (found later)
            if best.is_none_or(|(b, _)| len <= b) {
                best = Some((len, e));
            }
        }
    }
    best.map(|(_, e)| (e.path.clone(), false))
}

enum Node<'a> {
    Item(&'a mut Item),
    Table(&'a mut Table),
    Value(&'a mut Value),
}

fn child<'a>(node: Node<'a>, seg: &Seg) -> Option<Node<'a>> {
    match (node, seg) {
        (Node::Item(Item::Table(t)) | Node::Table(t), Seg::Key(k)) => t.get_mut(k).map(Node::Item),
        (Node::Item(Item::ArrayOfTables(a)), Seg::Index(i)) => a.get_mut(*i).map(Node::Table),
        (Node::Item(Item::Value(v)) | Node::Value(v), seg) => match (v, seg) {
            (Value::Array(a), Seg::Index(i)) => a.get_mut(*i).map(Node::Value),
            (Value::InlineTable(t), Seg::Key(k)) => t.get_mut(k).map(Node::Value),
            _ => None,
        },
        _ => None,
    }
}

fn parent<'a>(doc: &'a mut DocumentMut, path: &[Seg]) -> Option<Node<'a>> {
    let mut node = Node::Item(doc.as_item_mut());
    for seg in path {
        node = child(node, seg)?;
    }
    Some(node)
}

/// Puts `value` at `path` (replacing what is there); false if the place does not exist.
pub fn set(doc: &mut DocumentMut, path: &[Seg], value: Value) -> bool {
    let Some((last, head)) = path.split_last() else {
        return false;
    };
    let Some(node) = parent(doc, head) else {
        return false;
    };
    match (node, last) {
        (Node::Item(Item::Table(t)) | Node::Table(t), Seg::Key(k)) => {
            t.insert(k, Item::Value(value));
            true
        }
        (Node::Item(Item::ArrayOfTables(a)), Seg::Index(i)) => match a.get_mut(*i) {
            Some(t) => {
                *t = Table::new();
                true
            }
            None => false,
        },
        (Node::Item(Item::Value(v)) | Node::Value(v), seg) => match (v, seg) {
            (Value::Array(a), Seg::Index(i)) if *i < a.len() => {
                a.replace(*i, value);
                true
            }
            (Value::InlineTable(t), Seg::Key(k)) => {
                t.insert(k, value);
                true
            }
            _ => false,
        },
        _ => false,
    }
}

/// Removes the key at `path`; false if there is none.
pub fn remove(doc: &mut DocumentMut, path: &[Seg]) -> bool {
    let Some((Seg::Key(k), head)) = path.split_last() else {
        return false;
    };
    match parent(doc, head) {
        Some(Node::Item(Item::Table(t)) | Node::Table(t)) => t.remove(k).is_some(),
        Some(Node::Item(Item::Value(Value::InlineTable(t))))
        | Some(Node::Value(Value::InlineTable(t))) => t.remove(k).is_some(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_to_paths_and_back() {
        let text = "[a]\nx = 1\n[[r]]\nf = \"u\"\nc = { t = [1, 2] }\n";
        let list = entries(text);
        let at = |s: &str| {
            let i = text.find(s).unwrap();
            locate(&list, Some(i..i + s.len())).map(|(p, k)| (Seg::join(&p), k))
        };
        assert_eq!(at("x"), Some(("a.x".into(), true)));
        assert_eq!(at("\"u\""), Some(("r[0].f".into(), false)));
        assert_eq!(at("2"), Some(("r[0].c.t[1]".into(), false)));
        assert_eq!(at("[[r]]"), Some(("r[0]".into(), false)));
        let mut doc: DocumentMut = text.parse().unwrap();
        let path = |s: &str| -> Vec<Seg> {
            s.split('.')
                .flat_map(|p| match p.parse::<usize>() {
                    Ok(i) => vec![Seg::Index(i)],
                    Err(_) => vec![Seg::Key(p.to_string())],
                })
                .collect()
        };
        assert!(set(&mut doc, &path("r.0.c.t.1"), Value::from(7)));
        assert!(remove(&mut doc, &path("a.x")));
        assert!(set(&mut doc, &path("a.y"), Value::from("z")));
        assert!(!remove(&mut doc, &path("a.nothing")));
        let s = doc.to_string();
        assert!(
            s.contains("t = [1, 7]") && s.contains("y = \"z\"") && !s.contains("x = 1"),
            "{s}"
        );
    }
}
