//! serde's and the TOML reader's messages in words a user of hydroid reads: no Rust type
//! names (`f64`, `usize`, `struct HekfConfig`), no `Some(..)`, no "variant".

/// The whole message, translated. `is_key` says that the fault is in a key (an unknown name)
/// rather than in a value.
pub fn translate(message: &str, is_key: bool) -> String {
    let m = message.trim();
    if let Some(rest) = m.strip_prefix("invalid type: ") {
        return got_expected(rest);
    }
    if let Some(rest) = m.strip_prefix("invalid value: ") {
        return got_expected(rest);
    }
    if let Some(rest) = m.strip_prefix("invalid length ") {
        let (n, exp) = rest.split_once(", expected ").unwrap_or((rest, ""));
        return format!("has {n} entries; expected {}", expected(exp));
    }
    if let Some(rest) = m.strip_prefix("unknown field ") {
        return unknown(if is_key { "key" } else { "value" }, rest);
    }
    if let Some(rest) = m.strip_prefix("unknown variant ") {
        return unknown(if is_key { "name" } else { "value" }, rest);
    }
    if let Some(rest) = m.strip_prefix("unknown ") {
        // our own "unknown format `x`, expected one of ..." messages
        if let Some((noun, rest)) = rest.split_once(' ') {
            if rest.starts_with('`') && rest.contains("expected") {
                return unknown(noun, rest);
            }
        }
    }
    if let Some(rest) = m.strip_prefix("duplicate field ") {
        return format!("the key {rest} is given twice");
    }
    scrub(m)
}

/// `X, expected Y` as `expected Y', got X'`.
fn got_expected(rest: &str) -> String {
    match rest.split_once(", expected ") {
        Some((got, exp)) => format!("expected {}, got {}", expected(exp), found(got)),
        None => scrub(rest),
    }
}

/// `` `word`, expected one of `a`, `b` `` with a suggestion.
fn unknown(what: &str, rest: &str) -> String {
    let word = between(rest, '`', '`').unwrap_or(rest);
    let valid: Vec<&str> = match rest.find("expected") {
        Some(i) => rest[i..].split('`').skip(1).step_by(2).collect(),
        None => Vec::new(),
    };
    let mut s = format!("unknown {what} `{word}`");
    if let Some(n) = crate::base::suggest::nearest(word, valid.iter().copied()) {
        s.push_str(&format!("; did you mean `{n}`?"));
    }
    if valid.is_empty() {
        s.push_str(" (nothing can be given here)");
    } else {
        let list: Vec<String> = valid.iter().map(|v| format!("`{v}`")).collect();
        s.push_str(&format!(" (expected one of {})", list.join(", ")));
    }
    s
}

/// What serde says it expected, in words.
fn expected(exp: &str) -> String {
    let e = exp.trim();
    let words = match e {
        "f64" | "f32" => "a number",
        "usize" | "u64" | "u32" | "u16" | "u8" | "u128" => "a whole number, 0 or more",
        "isize" | "i64" | "i32" | "i16" | "i8" | "i128" => "a whole number",
        "a boolean" | "bool" => "true or false",
        "a string" | "a borrowed string" | "path string" | "a string or bytes" => "text in quotes",
        "a character" | "char" => "one character in quotes",
        "a sequence" => "a list, like [1, 2]",
        "a map" => "a table",
        _ if e.starts_with("struct ") || e.starts_with("enum ") => "a table",
        _ if e.starts_with("a sequence of ") || e.starts_with("an array of ") => {
            "a list, like [1, 2]"
        }
        _ if e.starts_with("one of ") || e.starts_with('`') => return format!("one of {e}"),
        _ => return scrub(e),
    };
    words.to_string()
}

/// What serde says it found, in words.
fn found(got: &str) -> String {
    let g = got.trim();
    let value = between(g, '`', '`');
    if let Some(s) = g.strip_prefix("string ") {
        return format!("the text {s}");
    }
    if g.starts_with("integer") {
        return format!("the whole number {}", value.unwrap_or(""));
    }
    if g.starts_with("floating point") {
        return format!("the number {}", value.unwrap_or(""));
    }
    if g.starts_with("boolean") {
        return value.unwrap_or("true or false").to_string();
    }
    match g {
        "sequence" => "a list".into(),
        "map" => "a table".into(),
        "unit value" | "unit" => "nothing".into(),
        "char" => "a character".into(),
        _ => scrub(g),
    }
}

/// Removes what is left of Rust's vocabulary from a message that was not recognised.
fn scrub(m: &str) -> String {
    let mut s = m.to_string();
    for (from, to) in [
        ("f64", "number"),
        ("usize", "whole number"),
        ("u64", "whole number"),
        ("u32", "whole number"),
        ("i64", "whole number"),
        ("variant", "value"),
        ("a borrowed string", "text"),
        ("::", " "),
    ] {
        s = s.replace(from, to);
    }
    s
}

fn between(s: &str, open: char, close: char) -> Option<&str> {
    let a = s.find(open)? + open.len_utf8();
    let b = a + s[a..].find(close)?;
    Some(&s[a..b])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serde_messages_in_words() {
        assert_eq!(
            translate("invalid type: string \"heavy\", expected f64", false),
            "expected a number, got the text \"heavy\""
        );
        assert_eq!(
            translate("invalid value: integer `-1`, expected usize", false),
            "expected a whole number, 0 or more, got the whole number -1"
        );
        assert_eq!(
            translate(
                "invalid type: integer `3`, expected struct HekfConfig",
                false
            ),
            "expected a table, got the whole number 3"
        );
        let m = translate(
            "unknown field `masss`, expected one of `mass`, `length`",
            true,
        );
        assert!(
            m.starts_with("unknown key `masss`; did you mean `mass`?"),
            "{m}"
        );
        let m = translate("unknown variant `cfx5`, expected `cfx` or `starccm`", false);
        assert!(
            m.contains("unknown value `cfx5`; did you mean `cfx`?"),
            "{m}"
        );
        let m = translate(
            "unknown format `cfx5`, expected one of `auto`, `cfx`",
            false,
        );
        assert!(
            m.starts_with("unknown format `cfx5`; did you mean `cfx`?"),
            "{m}"
        );
        assert!(
            !translate("invalid type: map, expected a borrowed string", false).contains("borrowed")
        );
    }
}
