//! Reading a TOML configuration so that one bad key does not hide the others.
//!
//! The text is parsed once for its syntax. Then it is deserialized; each schema error
//! (unknown key, wrong type, bad unit, missing key) is placed on its key path from the span
//! the TOML reader gives, reported, and repaired in the document: an unknown or unusable key
//! is removed, a missing or unusable required value is replaced by a placeholder of a type
//! that deserializes. Deserialization is then tried again, until it succeeds. The repaired
//! keys are recorded in [`Problems`] as *poisoned*, so that validation does not also
//! complain about the placeholders, and `check` does not read an input named by one.

use super::paths::{entries, locate, remove, set, Seg};
use super::{overrides, words, Problems};
use serde::de::DeserializeOwned;
use toml_edit::{DocumentMut, Value};

/// At most this many repairs (each re-reads the document); a file with more problems gets
/// the first ones and a note.
const MAX_ROUNDS: usize = 500;

/// Applies each `--set` to the document, recording where it put its value (and the first key
/// it added, whose problems are the override's too), or why it could not.
fn apply_overrides(p: &mut Problems, doc: &mut DocumentMut, list: &[String]) {
    for o in list {
        match overrides::apply(doc, o) {
            Ok(applied) => {
                p.overridden(&applied.path, o);
                if let Some(created) = applied.created {
                    p.overridden(&created, o);
                }
            }
            Err(m) => p.add_unplaced(None, format!("--set '{o}': {m}")),
        }
    }
}

/// Deserializes `text` (with `--set` `overrides` applied) into `T`, adding every problem to
/// `p`. Returns a value whenever the repairs let it deserialize; it is only fit for
/// validation and `check` when `p` records poisoned keys.
pub fn read_collecting<T: DeserializeOwned>(
    p: &mut Problems,
    text: &str,
    overrides: &[String],
) -> Option<T> {
    let mut doc: DocumentMut = match text.parse() {
        Ok(d) => d,
        Err(e) => {
            let e: toml_edit::TomlError = e;
            let line = e.span().map(|s| line_of_offset(text, s.start));
            let message = e.message().trim().replace('\n', "; ");
            p.add_unplaced(line, format!("TOML syntax: {message}"));
            return None;
        }
    };
    apply_overrides(p, &mut doc, overrides);
    repair_unusable_values(p, &mut doc);
    let mut placeholders: Vec<(String, usize)> = Vec::new();
    let mut guessed_names: Vec<String> = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let current = doc.to_string();
        let err = match toml::from_str::<T>(&current) {
            Ok(v) => return Some(v),
            Err(e) => e,
        };
        let message = err.message().to_string();
        let list = entries(&current);
        let Some((path, is_key)) = locate(&list, err.span()) else {
            p.add_unplaced(None, words::translate(&message, false));
            return None;
        };
        let key = Seg::join(&path);
        if let Some(field) = missing_field(&message) {
            let mut target = path.clone();
            target.push(Seg::Key(field.to_string()));
            let tkey = Seg::join(&target);
            if !p.is_poisoned(&tkey) && !guessed_names.contains(&tkey) {
                p.add(&tkey, format!("the required key `{field}` is missing"));
            }
            p.poison(&tkey);
            placeholders.push((tkey, 0));
            if !set(&mut doc, &target, placeholder(0)) {
                return None;
            }
            continue;
        }
        if let Some(i) = placeholders.iter().rposition(|(k, _)| *k == key) {
            // a placeholder of the wrong type (or an unknown name): try the next one
            let next = match first_expected(&message) {
                Some(name) if message.starts_with("unknown variant") => {
                    placeholders[i].1 = NAMED;
                    if !set(&mut doc, &path, Value::from(name)) {
                        return None;
                    }
                    continue;
                }
                _ => placeholders[i].1 + 1,
            };
            placeholders[i].1 = next;
            if next >= NAMED || !set(&mut doc, &path, placeholder(next)) {
                return None;
            }
            continue;
        }
        if p.is_poisoned(&key) {
            // inside a placeholder: nothing more to say, and nothing more to repair
            return None;
        }
        let translated = words::translate(&message, is_key);
        if let Some(s) = suggestion(&translated) {
            let mut guess = path.clone();
            guess.pop();
            guess.push(Seg::Key(s.to_string()));
            guessed_names.push(Seg::join(&guess));
        }
        p.add(&key, translated);
        p.poison(&key);
        let repaired = match path.last() {
            Some(Seg::Key(_)) => remove(&mut doc, &path),
            Some(Seg::Index(_)) => {
                placeholders.push((key, 0));
                set(&mut doc, &path, placeholder(0))
            }
            None => false,
        };
        if !repaired {
            return None;
        }
    }
    p.add_unplaced(
        None,
        "too many problems to list them all; correct these first",
    );
    None
}

/// One past the last placeholder: the candidates are exhausted (or a name was chosen).
const NAMED: usize = 6;

/// The placeholders tried in turn for a value whose type is not known.
fn placeholder(i: usize) -> Value {
    match i {
        0 => Value::from(1.0),
        1 => Value::from(1i64),
        2 => Value::from("placeholder"),
        3 => Value::from(true),
        4 => Value::Array(toml_edit::Array::new()),
        _ => Value::InlineTable(toml_edit::InlineTable::new()),
    }
}

/// Non-finite numbers and dates are never meaningful in a configuration: each is reported
/// and removed (or, in a list, replaced) before deserializing.
fn repair_unusable_values(p: &mut Problems, doc: &mut DocumentMut) {
    let text = doc.to_string();
    let bad: Vec<(Vec<Seg>, String)> = entries(&text)
        .into_iter()
        .filter_map(|e| e.unusable.map(|m| (e.path, m)))
        .collect();
    for (path, message) in bad {
        let key = Seg::join(&path);
        p.add(&key, message);
        p.poison(&key);
        match path.last() {
            Some(Seg::Key(_)) => {
                remove(doc, &path);
            }
            _ => {
                set(doc, &path, Value::from(0.0));
            }
        }
    }
}

fn missing_field(message: &str) -> Option<&str> {
    message
        .strip_prefix("missing field `")
        .map(|r| r.trim_end_matches('`'))
}

/// The first name in "expected `a` or `b`" / "expected one of `a`, `b`".
fn first_expected(message: &str) -> Option<String> {
    let i = message.find("expected")?;
    message[i..].split('`').nth(1).map(str::to_string)
}

/// The name a translated message suggests ("did you mean `mass`?").
fn suggestion(message: &str) -> Option<&str> {
    let rest = message.split_once("did you mean `")?.1;
    rest.split('`').next()
}

/// 1-based line of a byte offset.
fn line_of_offset(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    let end = (0..=end)
        .rev()
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    text[..end].matches('\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;
    use std::path::Path;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct C {
        v: V,
        #[serde(default)]
        runs: Vec<R>,
    }
    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct V {
        mass: f64,
        length: f64,
        #[serde(default)]
        n: Option<usize>,
    }
    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct R {
        file: String,
        #[serde(default)]
        list: Vec<String>,
    }

    fn read(text: &str) -> (Option<C>, Vec<String>) {
        let mut p = Problems::new(Path::new("c.toml"), text);
        let c = read_collecting::<C>(&mut p, text, &[]);
        (c, p.list.iter().map(|x| x.to_string()).collect())
    }

    #[test]
    fn every_schema_problem_is_listed() {
        let text = "[v]\nmass = \"heavy\"\nlenght = 1\nn = -2\n\n[[runs]]\nfile = 3\n\
                    list = [\"a\", 4, \"b\", true]\n[[runs]]\nfile = \"b\"\nx = nan\n";
        let (c, list) = read(text);
        let all = list.join("\n");
        assert!(c.is_some(), "{all}");
        assert!(all.contains("c.toml:2: v.mass: expected a number"), "{all}");
        assert!(
            all.contains("c.toml:3: v.lenght: unknown key `lenght`"),
            "{all}"
        );
        assert!(all.contains("did you mean `length`"), "{all}");
        // the misspelt key is not reported a second time as a missing one
        assert!(!all.contains("`length` is missing"), "{all}");
        assert!(
            all.contains("c.toml:4: v.n: expected a whole number"),
            "{all}"
        );
        assert!(all.contains("c.toml:7: runs[0].file"), "{all}");
        assert!(
            all.contains("runs[0].list[1]") && all.contains("runs[0].list[3]"),
            "{all}"
        );
        assert!(all.contains("c.toml:11: runs[1].x"), "{all}");
        assert_eq!(list.len(), 7, "{all}");
    }

    #[test]
    fn missing_keys_and_sections() {
        let (c, list) = read("");
        assert!(c.is_some());
        assert_eq!(list, ["c.toml: v: the required key `v` is missing"]);
        let (_, list) = read("[v]\n[[runs]]\n");
        let all = list.join("\n");
        assert!(
            all.contains("v.mass: the required key `mass` is missing"),
            "{all}"
        );
        assert!(all.contains("v.length: the required key"), "{all}");
        assert!(all.contains(":2: runs[0].file: the required key"), "{all}");
        let (_, list) = read("v = 3\n");
        assert_eq!(list.len(), 1, "{list:?}");
        let (c, list) = read("[v\nmass = 1\n");
        assert!(c.is_none() && list[0].contains("c.toml:1") && list[0].contains("TOML"));
    }
}
