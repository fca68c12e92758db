//! `--set KEY=VALUE`: a dotted key path with list indices, and a TOML value (or a bare word,
//! taken as text).

use super::paths::Seg;
use toml_edit::{DocumentMut, Item, TableLike, Value};

/// Applies one `KEY=VALUE` to the document; returns the key path it set.
pub fn apply(doc: &mut DocumentMut, spec: &str) -> Result<String, String> {
    let (key, value) = spec
        .split_once('=')
        .ok_or("expected KEY=VALUE, e.g. hekf.passes=3")?;
    let key = key.trim();
    let value = value.trim();
    // A value that is not TOML (a bare word) is taken as text.
    let parsed: Value = value.parse().unwrap_or_else(|_| Value::from(value));
    let mut segs: Vec<(String, Option<usize>)> = Vec::new();
    for part in key.split('.') {
        let (name, idx) = match part.find('[') {
            Some(i) => {
                let n: usize = part[i + 1..].trim_end_matches(']').parse().map_err(|_| {
                    format!("bad list position in '{part}' (expected e.g. runs[0])")
                })?;
                (part[..i].to_string(), Some(n))
            }
            None => (part.to_string(), None),
        };
        if name.is_empty() {
            return Err(format!("empty key segment in '{key}'"));
        }
        segs.push((name, idx));
    }
    set_path(doc.as_table_mut(), &segs, parsed)?;
    let path: Vec<Seg> = segs
        .into_iter()
        .flat_map(|(k, i)| std::iter::once(Seg::Key(k)).chain(i.map(Seg::Index)))
        .collect();
    Ok(Seg::join(&path))
}

fn set_path(
    table: &mut dyn TableLike,
    segs: &[(String, Option<usize>)],
    value: Value,
) -> Result<(), String> {
    let ((name, idx), rest) = segs.split_first().ok_or("empty key")?;
    if rest.is_empty() && idx.is_none() {
        table.insert(name, Item::Value(value));
        return Ok(());
    }
    if table.get(name).is_none() {
        if idx.is_some() {
            return Err(format!("there is no list '{name}' to index"));
        }
        table.insert(name, Item::Table(toml_edit::Table::new()));
    }
    let Some(child) = table.get_mut(name) else {
        return Err(format!("'{name}' cannot be set"));
    };
    match (idx, child) {
        (None, item) => {
            let t = item
                .as_table_like_mut()
                .ok_or_else(|| format!("'{name}' is a value, not a table"))?;
            set_path(t, rest, value)
        }
        (Some(i), Item::ArrayOfTables(a)) => {
            let n = a.len();
            let t = a
                .get_mut(*i)
                .ok_or_else(|| format!("'{name}' has {n} entries, so [{i}] does not exist"))?;
            if rest.is_empty() {
                return Err(format!("cannot replace the whole table {name}[{i}]"));
            }
            set_path(t, rest, value)
        }
        (Some(i), Item::Value(Value::Array(arr))) if rest.is_empty() => {
            let n = arr.len();
            if *i >= n {
                return Err(format!("'{name}' has {n} entries, so [{i}] does not exist"));
            }
            arr.replace(*i, value);
            Ok(())
        }
        (Some(i), _) => Err(format!("'{name}' is not a list that [{i}] can index")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_nested_keys() {
        let mut doc: DocumentMut = "[hekf]\npasses = 1\n[[hekf.runs]]\nfile = \"a\"\n"
            .parse()
            .unwrap();
        assert_eq!(apply(&mut doc, "hekf.passes=3").unwrap(), "hekf.passes");
        assert_eq!(
            apply(&mut doc, "hekf.runs[0].file=b.csv").unwrap(),
            "hekf.runs[0].file"
        );
        apply(&mut doc, "output.dir=\"x\"").unwrap();
        let s = doc.to_string();
        assert!(s.contains("passes = 3"), "{s}");
        assert!(s.contains("file = \"b.csv\""), "{s}");
        assert!(s.contains("dir = \"x\""), "{s}");
        assert!(apply(&mut doc, "hekf.runs[4].file=c").is_err());
        assert!(apply(&mut doc, "nonsense").is_err());
        let e = apply(&mut doc, "hekf.passes[0]=1").unwrap_err();
        assert_eq!(e, "'passes' is not a list that [0] can index");
    }
}
