//! `--set KEY=VALUE`: a TOML key path (dotted keys, bare or quoted, with list positions
//! `[N]`: `captive.oscillations."pure sway".amplitude.v`, `hekf.runs[0].columns.rudder.scale`)
//! and a TOML value (`3`, `true`, `"text"`, `[1, 2]`, `{ column = "x", scale = -1 }`); a bare
//! word (`other.csv`, `50 kg`) is taken as text, which the key then accepts only where it
//! expects text.

use super::paths::{parse_path, Seg};
use toml_edit::{DocumentMut, Item, TableLike, Value};

/// What the syntax of an override is, for its errors.
const SYNTAX: &str = "expected KEY=VALUE with a TOML key (a.b.\"quoted key\", runs[0].file) and \
                      a TOML value (3, true, \"text\", [1, 2], { a = 1 }; a bare word is text)";

/// What one `--set` did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Applied {
    /// The key path it set, in the form messages use.
    pub path: String,
    /// The first key it added that was not in the configuration (a table or key of its
    /// path), if any: a problem found there comes from the override too.
    pub created: Option<String>,
}

/// Applies one `KEY=VALUE` to the document. The error says what was expected.
pub fn apply(doc: &mut DocumentMut, spec: &str) -> Result<Applied, String> {
    let (segs, rest) = parse_path(spec).map_err(|m| format!("{m}; {SYNTAX}"))?;
    let rest = rest.trim_start();
    let Some(value) = rest.strip_prefix('=') else {
        if rest.is_empty() {
            return Err(SYNTAX.to_string());
        }
        // where the key stops making sense: a character a bare key cannot hold
        let shown: String = rest.chars().take(20).collect();
        return Err(format!(
            "the key stops at '{}': a bare key holds ASCII letters, digits, _ and - only \
             (quote any other: \"hékf\", 'pure sway'); {SYNTAX}",
            shown.escape_debug()
        ));
    };
    let value = parse_value(value)?;
    let mut place = Place {
        done: Vec::new(),
        created: None,
    };
    set_in_table(doc.as_table_mut(), &segs, value, &mut place)?;
    Ok(Applied {
        path: Seg::join(&segs),
        created: place.created.map(|p| Seg::join(&p)),
    })
}

/// The value of an override: TOML, or a bare word taken as text.
fn parse_value(text: &str) -> Result<Value, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err(format!("no value after '='; {SYNTAX}"));
    }
    match t.parse::<Value>() {
        Ok(v) => Ok(v),
        Err(_) if bare_word(t) => Ok(Value::from(t)),
        Err(e) => Err(format!(
            "`{t}` is not a TOML value ({}); {SYNTAX}",
            e.message().trim().replace('\n', "; ")
        )),
    }
}

/// Text that is meant as text: nothing TOML would read as the start of a string, list or
/// table (a file name, `50 kg`, `3 deg/s`), and no stray quote or bracket.
fn bare_word(t: &str) -> bool {
    !t.contains(['"', '\'', '[', ']', '{', '}', '=', '\n'])
}

/// Where the walk along the path is: the segments passed, and the first one it added.
struct Place {
    done: Vec<Seg>,
    created: Option<Vec<Seg>>,
}

impl Place {
    /// The path so far, for messages.
    fn shown(&self) -> String {
        Seg::join(&self.done)
    }

    fn enter(&mut self, seg: &Seg) {
        self.done.push(seg.clone());
    }

    fn created_here(&mut self) {
        if self.created.is_none() {
            self.created = Some(self.done.clone());
        }
    }
}

/// Sets `segs` (starting with a key) under the table `table`.
fn set_in_table(
    table: &mut dyn TableLike,
    segs: &[Seg],
    value: Value,
    place: &mut Place,
) -> Result<(), String> {
    let (first, rest) = segs.split_first().ok_or("no key")?;
    let Seg::Key(name) = first else {
        return Err(format!(
            "{} is a table, not a list: a position [N] cannot follow it",
            place.shown()
        ));
    };
    place.enter(first);
    if rest.is_empty() {
        if table.get(name).is_none() {
            place.created_here();
        }
        table.insert(name, Item::Value(value));
        return Ok(());
    }
    if table.get(name).is_none() {
        if let Some(Seg::Index(i)) = rest.first() {
            return Err(format!(
                "{} is not in the configuration, so [{i}] does not exist: add the list to the \
                 file first",
                place.shown()
            ));
        }
        place.created_here();
        table.insert(name, Item::Table(toml_edit::Table::new()));
    }
    let child = table
        .get_mut(name)
        .ok_or_else(|| format!("{} cannot be set", place.shown()))?;
    set_in_item(child, rest, value, place)
}

/// Sets `segs` (not empty) below the item `item` at `place`.
fn set_in_item(
    item: &mut Item,
    segs: &[Seg],
    value: Value,
    place: &mut Place,
) -> Result<(), String> {
    match item {
        Item::Value(v) => set_in_value(v, segs, value, place),
        Item::Table(t) => set_in_table(t, segs, value, place),
        Item::ArrayOfTables(a) => {
            let n = a.len();
            let Some(Seg::Index(i)) = segs.first() else {
                return Err(format!(
                    "{} is a list of {}: give a position, e.g. {}[0]{}",
                    place.shown(),
                    entries(n),
                    place.shown(),
                    rest_text(segs)
                ));
            };
            place.enter(&segs[0]);
            let shown = place.shown();
            let t = a.get_mut(*i).ok_or_else(|| out_of_range(&shown, *i, n))?;
            if segs.len() == 1 {
                return Err(format!(
                    "{shown} is a table of the list: set one of its keys, {shown}.KEY=VALUE"
                ));
            }
            set_in_table(t, &segs[1..], value, place)
        }
        Item::None => Err(format!("{} cannot be set", place.shown())),
    }
}

/// Sets `segs` (not empty) below the value `v` at `place`: in an inline table, in a list, or
/// in a column given by name (`yaw = "Heading"` becomes `yaw = { column = "Heading" }`, so
/// that `columns.yaw.scale=-1` works).
fn set_in_value(
    v: &mut Value,
    segs: &[Seg],
    value: Value,
    place: &mut Place,
) -> Result<(), String> {
    let in_columns = place.done.len() >= 2
        && matches!(&place.done[place.done.len() - 2], Seg::Key(k) if k == "columns");
    if let (Value::String(s), Some(Seg::Key(_)), true) = (&*v, segs.first(), in_columns) {
        let mut t = toml_edit::InlineTable::new();
        t.insert("column", Value::from(s.value().as_str()));
        *v = Value::InlineTable(t);
    }
    match (v, &segs[0]) {
        (Value::InlineTable(t), Seg::Key(_)) => set_in_table(t, segs, value, place),
        (Value::Array(arr), Seg::Index(i)) => {
            let n = arr.len();
            place.enter(&segs[0]);
            let shown = place.shown();
            if *i >= n {
                return Err(out_of_range(&shown, *i, n));
            }
            if segs.len() == 1 {
                arr.replace(*i, value);
                return Ok(());
            }
            let Some(element) = arr.get_mut(*i) else {
                return Err(out_of_range(&shown, *i, n));
            };
            set_in_value(element, &segs[1..], value, place)
        }
        (Value::Array(arr), Seg::Key(_)) => Err(format!(
            "{} is a list of {}: give a position, e.g. {}[0]{}",
            place.shown(),
            entries(arr.len()),
            place.shown(),
            rest_text(segs)
        )),
        (other, seg) => Err(format!(
            "{} is the value {}, not a {}: {} cannot follow it; set it whole, {}=VALUE",
            place.shown(),
            other.to_string().trim(),
            if matches!(seg, Seg::Index(_)) {
                "list"
            } else {
                "table"
            },
            match seg {
                Seg::Index(i) => format!("[{i}]"),
                Seg::Key(k) => format!("'.{k}'"),
            },
            place.shown()
        )),
    }
}

/// "1 entry", "3 entries".
fn entries(n: usize) -> String {
    if n == 1 {
        "1 entry".into()
    } else {
        format!("{n} entries")
    }
}

/// A list position past the end, with how many there are.
fn out_of_range(shown: &str, i: usize, n: usize) -> String {
    let list = shown.rsplit_once('[').map_or(shown, |(l, _)| l);
    let valid = match n {
        0 => "it is empty".to_string(),
        1 => "the only position is [0]".to_string(),
        n => format!("positions are [0] to [{}]", n - 1),
    };
    format!(
        "{list} has {}, so [{i}] does not exist ({valid})",
        entries(n)
    )
}

/// The rest of a path after a list that needs a position, as text (`.file`).
fn rest_text(segs: &[Seg]) -> String {
    let joined = Seg::join(segs);
    if joined.starts_with('[') {
        joined
    } else {
        format!(".{joined}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> DocumentMut {
        "[hekf]\npasses = 1\nestimate = [\"Yvd\", \"Nrd\"]\n[[hekf.runs]]\nfile = \"a\"\n\
         [hekf.runs.columns]\nyaw = \"Heading\"\n[hekf.runs.constants]\nthrust = \"22 N\"\n\
         [captive.oscillations.\"pure sway\"]\nfrequency = 0.5\n\
         amplitude = { v = \"0.25 m/s\" }\n"
            .parse()
            .unwrap()
    }

    #[test]
    fn sets_nested_keys() {
        let mut doc = doc();
        assert_eq!(
            apply(&mut doc, "hekf.passes=3").unwrap().path,
            "hekf.passes"
        );
        let a = apply(&mut doc, "hekf.runs[0].file=b.csv").unwrap();
        assert_eq!(a.path, "hekf.runs[0].file");
        assert_eq!(a.created, None);
        let a = apply(&mut doc, "output.dir=\"x\"").unwrap();
        assert_eq!(a.created.as_deref(), Some("output"));
        let s = doc.to_string();
        assert!(s.contains("passes = 3"), "{s}");
        assert!(s.contains("file = \"b.csv\""), "{s}");
        assert!(s.contains("dir = \"x\""), "{s}");
    }

    #[test]
    fn quoted_keys_lists_and_toml_values() {
        let mut doc = doc();
        for spec in [
            "captive.oscillations.\"pure sway\".amplitude.v=\"0.1 m/s\"",
            "captive . oscillations . 'pure sway' . frequency = 0.25",
            "hekf.runs[0].columns.yaw.scale=-1",
            "hekf.estimate[1]=Yrd",
            "hekf.prior={ Yvd = { initial = -20.0, sigma = 5.0 } }",
            "hekf.measure=[\"u\", \"v\"]",
            "hekf.smoother=false",
            "vehicle.mass=50 kg",
        ] {
            apply(&mut doc, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
        }
        let s = doc.to_string();
        for has in [
            "v = \"0.1 m/s\"",
            "frequency = 0.25",
            "yaw = { column = \"Heading\", scale = -1 }",
            "estimate = [\"Yvd\", \"Yrd\"]",
            "sigma = 5.0",
            "measure = [\"u\", \"v\"]",
            "smoother = false",
            "mass = \"50 kg\"",
        ] {
            assert!(s.contains(has), "{has} in\n{s}");
        }
        let a = apply(&mut doc, "captive.oscillations.\"pure sway\".phase=1").unwrap();
        assert_eq!(a.path, "captive.oscillations.\"pure sway\".phase");
    }

    #[test]
    fn errors_say_what_was_expected() {
        let doc = doc();
        let err = |spec: &str| apply(&mut doc.clone(), spec).unwrap_err();
        assert!(err("a.b").starts_with("expected KEY=VALUE with a TOML key (a.b.\"quoted key\""));
        assert!(
            err("a.\"b=1").contains("an unclosed quote"),
            "{}",
            err("a.\"b=1")
        );
        assert!(
            err("a..b=1").contains("no key at '.b=1'"),
            "{}",
            err("a..b=1")
        );
        assert!(err("hekf.runs[x].file=1").contains("'[x]' is not a list position"));
        assert!(err("hekf.passes=[1,").contains("`[1,` is not a TOML value"));
        assert!(err("hekf.passes=").contains("no value after '='"));
        assert_eq!(
            err("hekf.runs[4].file=c"),
            "hekf.runs has 1 entry, so [4] does not exist (the only position is [0])"
        );
        assert_eq!(
            err("hekf.estimate[2]=Yrd"),
            "hekf.estimate has 2 entries, so [2] does not exist (positions are [0] to [1])"
        );
        assert_eq!(
            err("hekf.runs.file=c"),
            "hekf.runs is a list of 1 entry: give a position, e.g. hekf.runs[0].file"
        );
        assert!(err("hekf.passes[0]=1").starts_with("hekf.passes is the value 1, not a list"));
        assert!(err("hekf.runs[0].constants.thrust.unit=1")
            .starts_with("hekf.runs[0].constants.thrust is the value \"22 N\", not a table"));
        assert!(err("polar.runs[0].file=x").starts_with("polar.runs is not in the configuration"));
        assert!(err("nonsense").starts_with("expected KEY=VALUE"));
        assert!(err("h\u{e9}kf.passes=1").starts_with("the key stops at '\u{e9}kf.passes=1'"));
        assert!(err("hekf.pa\u{1}sses=1").starts_with("the key stops at '\\u{1}sses=1'"));
        assert!(err("hekf.passes 3").starts_with("the key stops at '3'"));
    }

    #[test]
    fn keys_are_bounded_in_steps_bytes_and_positions() {
        use crate::config::paths::{MAX_PATH_BYTES, MAX_PATH_STEPS};
        let doc = doc();
        let err = |spec: &str| apply(&mut doc.clone(), spec).unwrap_err();
        // 20,000 steps overflowed the stack of the setter; refused at the 33rd
        let deep = format!("{}=1", vec!["a"; 20_000].join("."));
        let e = err(&deep);
        assert!(e.starts_with("the key has more than 32 steps"), "{e}");
        let deepest = format!("{}=1", vec!["a"; MAX_PATH_STEPS].join("."));
        let a = apply(&mut doc.clone(), &deepest).unwrap();
        assert_eq!(a.path.matches('.').count(), MAX_PATH_STEPS - 1);
        let lists = format!("hekf.estimate{}=1", "[0]".repeat(MAX_PATH_STEPS));
        assert!(err(&lists).starts_with("the key has more than 32 steps"));
        let long = format!("a.\"{}\"=1", "x".repeat(MAX_PATH_BYTES));
        assert!(err(&long).starts_with("the key is longer than 1024 bytes"));
        assert!(err(&format!("{}=1", "b".repeat(100_000))).contains("longer than 1024 bytes"));
        for big in ["99999999999", "100000", "18446744073709551616"] {
            let e = err(&format!("hekf.runs[{big}].file=x"));
            assert!(
                e.contains("past the highest list position hydroid reads ([99999])"),
                "{e}"
            );
        }
        assert_eq!(
            err("hekf.runs[99999].file=x"),
            "hekf.runs has 1 entry, so [99999] does not exist (the only position is [0])"
        );
        assert!(err("hekf.runs[-1].file=x").contains("'[-1]' is not a list position"));
        assert!(err("hekf.runs[].file=x").contains("'[]' is not a list position"));
    }
}
