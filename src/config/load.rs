//! Reading a configuration: TOML syntax, schema (unknown keys with suggestions), `--set`
//! overrides, then validation; every problem is collected, not only the first.

use super::{Config, Problems};
use crate::error::{ConfigProblem, Error, Result};
use std::path::{Path, PathBuf};

/// A configuration that parsed and validated.
#[derive(Debug, Clone)]
pub struct LoadedConfig {
    /// The configuration.
    pub config: Config,
    /// The file it came from.
    pub path: PathBuf,
    /// The folder paths in it are relative to.
    pub base_dir: PathBuf,
    /// The `--set` overrides applied, as given.
    pub overrides: Vec<String>,
}

impl LoadedConfig {
    /// Resolves a path from the configuration against its folder.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.base_dir.join(p)
    }

    /// The effective configuration (after defaults and overrides) as TOML.
    pub fn effective_toml(&self) -> String {
        toml::to_string_pretty(&self.config)
            .unwrap_or_else(|e| format!("# could not serialise the configuration: {e}\n"))
    }
}

/// Reads and validates the configuration at `path`, applying `overrides` (`KEY=VALUE`).
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedConfig> {
    load_str(path, &read(path)?, overrides)
}

/// The text of a configuration file, or the problem reading it. The file is read like every
/// input (`formats::input`): a regular file, within the size and line limits, UTF-8.
pub fn read(path: &Path) -> Result<String> {
    use crate::formats::input::{read_bytes, Limits};
    let problem = |line: Option<usize>, message: String| {
        Error::Config(vec![ConfigProblem {
            file: path.to_path_buf(),
            line,
            key: None,
            message,
        }])
    };
    let bytes = Limits::for_file(path)
        .and_then(|limits| read_bytes(path, &limits))
        .map_err(|e| {
            let expected = e
                .expected
                .map(|x| format!(" (expected {x})"))
                .unwrap_or_default();
            problem(
                e.place.line,
                format!("cannot read the configuration: {}{expected}", e.message),
            )
        })?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
        problem(
            Some(line),
            format!("the configuration is not UTF-8 text (byte offset {at}); save it as UTF-8"),
        )
    })
}

/// Like [`load`], from text already read (`path` places messages and resolves relative paths).
pub fn load_str(path: &Path, text: &str, overrides: &[String]) -> Result<LoadedConfig> {
    match load_lenient(path, text, overrides) {
        (Some(c), p) if p.is_empty() => Ok(c),
        (_, p) => Err(Error::Config(p)),
    }
}

/// Reads the configuration and returns it whenever it could be deserialised, together with
/// every problem found (so that `hydroid check` can go on to check the input files).
pub fn load_lenient(
    path: &Path,
    text: &str,
    overrides: &[String],
) -> (Option<LoadedConfig>, Vec<ConfigProblem>) {
    let (config, mut problems) = deserialize_collecting(path, text);
    let Some(mut config) = config else {
        return (None, problems);
    };
    if !overrides.is_empty() && problems.is_empty() {
        match apply_overrides(path, text, overrides) {
            Ok(c) => config = c,
            Err(mut p) => problems.append(&mut p),
        }
    }
    let mut checks = Problems::new(path, text);
    config.validate(&mut checks);
    problems.extend(checks.list);
    let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    (
        Some(LoadedConfig {
            config,
            path: path.to_path_buf(),
            base_dir,
            overrides: overrides.to_vec(),
        }),
        problems,
    )
}

/// Deserializes, and after each schema error comments out the offending line (or table) and
/// tries again, so that one pass reports every unknown key and wrong type.
fn deserialize_collecting(path: &Path, text: &str) -> (Option<Config>, Vec<ConfigProblem>) {
    let mut text = text.to_string();
    let mut problems = Vec::new();
    let mut neutralised_keys: Vec<String> = Vec::new();
    for _ in 0..64 {
        match toml::from_str::<Config>(&text) {
            // With the faulty lines commented out the rest still deserialises: return it so
            // that validation can report the remaining problems too.
            Ok(c) => return (Some(c), problems),
            Err(e) => {
                let line = e.span().map(|s| line_of_offset(&text, s.start));
                let syntax = is_syntax_error(&e);
                // "missing field `mass`" after commenting out a bad `mass = ...` line says
                // nothing new: stop there.
                if let Some(k) = e.message().strip_prefix("missing field `") {
                    let k = k.trim_end_matches('`');
                    if neutralised_keys.iter().any(|n| n == k) {
                        return (None, problems);
                    }
                }
                if let Some(l) = line {
                    if let Some(k) = text
                        .lines()
                        .nth(l - 1)
                        .and_then(|s| s.split_once('='))
                        .map(|(k, _)| k.trim().to_string())
                    {
                        neutralised_keys.push(k);
                    }
                }
                problems.push(ConfigProblem {
                    file: path.to_path_buf(),
                    line,
                    key: None,
                    message: improve_message(e.message()),
                });
                let Some(l) = line.filter(|_| !syntax) else {
                    return (None, problems);
                };
                if !neutralise(&mut text, l) {
                    return (None, problems);
                }
            }
        }
    }
    (None, problems)
}

fn is_syntax_error(e: &toml::de::Error) -> bool {
    // Schema errors come from serde and read like "unknown field", "invalid type",
    // "missing field"; anything else is TOML syntax, after which recovery is guesswork.
    let m = e.message();
    !(m.contains("unknown field")
        || m.contains("unknown variant")
        || m.contains("invalid type")
        || m.contains("invalid value")
        || m.contains("unknown format")
        || m.contains("is not a number")
        || m.contains("unknown unit"))
}

fn line_of_offset(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Comments out line `l` (1-based); a table header takes its whole table with it.
fn neutralise(text: &mut String, l: usize) -> bool {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let Some(line) = lines.get(l - 1) else {
        return false;
    };
    if line.trim_start().starts_with('#') {
        return false;
    }
    let is_header = line.trim_start().starts_with('[');
    lines[l - 1] = format!("# {line}");
    if is_header {
        for next in lines.iter_mut().skip(l) {
            if next.trim_start().starts_with('[') {
                break;
            }
            *next = format!("# {next}");
        }
    }
    *text = lines.join("\n");
    text.push('\n');
    true
}

/// Adds "did you mean" to serde's unknown field and variant messages.
fn improve_message(message: &str) -> String {
    let msg = message.trim().to_string();
    let Some(word) = between(&msg, '`', '`') else {
        return msg;
    };
    let Some(idx) = msg.find("expected") else {
        return msg;
    };
    let expected: Vec<&str> = msg[idx..].split('`').skip(1).step_by(2).collect();
    if msg.starts_with("unknown") {
        if let Some(s) = crate::suggest::nearest(word, expected.iter().copied()) {
            return format!("{msg}; did you mean `{s}`?");
        }
    }
    msg
}

fn between(s: &str, open: char, close: char) -> Option<&str> {
    let a = s.find(open)? + open.len_utf8();
    let b = a + s[a..].find(close)?;
    Some(&s[a..b])
}

/// Applies `KEY=VALUE` overrides to the document and deserializes the result.
fn apply_overrides(
    path: &Path,
    text: &str,
    overrides: &[String],
) -> std::result::Result<Config, Vec<ConfigProblem>> {
    let problem = |msg: String| ConfigProblem {
        file: path.to_path_buf(),
        line: None,
        key: None,
        message: msg,
    };
    let mut doc: toml_edit::DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| vec![problem(e.to_string())])?;
    let mut problems = Vec::new();
    for o in overrides {
        if let Err(m) = set_one(&mut doc, o) {
            problems.push(problem(format!("--set {o}: {m}")));
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    toml::from_str::<Config>(&doc.to_string()).map_err(|e| {
        vec![problem(format!(
            "--set {}: {}",
            overrides.join(" --set "),
            improve_message(e.message())
        ))]
    })
}

fn set_one(doc: &mut toml_edit::DocumentMut, spec: &str) -> std::result::Result<(), String> {
    let (key, value) = spec
        .split_once('=')
        .ok_or("expected KEY=VALUE, e.g. hekf.passes=3")?;
    let key = key.trim();
    let value = value.trim();
    // A value that is not TOML (a bare word) is taken as a string.
    let parsed: toml_edit::Value = value
        .parse()
        .unwrap_or_else(|_| toml_edit::Value::from(value));
    let mut segs: Vec<(String, Option<usize>)> = Vec::new();
    for part in key.split('.') {
        let (name, idx) = match part.find('[') {
            Some(i) => {
                let n: usize = part[i + 1..]
                    .trim_end_matches(']')
                    .parse()
                    .map_err(|_| format!("bad index in '{part}'"))?;
                (part[..i].to_string(), Some(n))
            }
            None => (part.to_string(), None),
        };
        if name.is_empty() {
            return Err(format!("empty key segment in '{key}'"));
        }
        segs.push((name, idx));
    }
    set_path(doc.as_table_mut(), &segs, parsed)
}

fn set_path(
    table: &mut dyn toml_edit::TableLike,
    segs: &[(String, Option<usize>)],
    value: toml_edit::Value,
) -> std::result::Result<(), String> {
    let ((name, idx), rest) = segs.split_first().ok_or("empty key")?;
    if rest.is_empty() && idx.is_none() {
        table.insert(name, toml_edit::Item::Value(value));
        return Ok(());
    }
    if table.get(name).is_none() {
        if idx.is_some() {
            return Err(format!("there is no list '{name}' to index"));
        }
        table.insert(name, toml_edit::Item::Table(toml_edit::Table::new()));
    }
    let child = table.get_mut(name).expect("present or just inserted");
    match (idx, child) {
        (None, item) => {
            let t = item
                .as_table_like_mut()
                .ok_or_else(|| format!("'{name}' is a value, not a table"))?;
            set_path(t, rest, value)
        }
        (Some(i), toml_edit::Item::ArrayOfTables(a)) => {
            let n = a.len();
            let t = a
                .get_mut(*i)
                .ok_or_else(|| format!("'{name}' has {n} entries, so [{i}] does not exist"))?;
            if rest.is_empty() {
                return Err(format!("cannot replace the whole table {name}[{i}]"));
            }
            set_path(t, rest, value)
        }
        (Some(i), toml_edit::Item::Value(toml_edit::Value::Array(arr))) if rest.is_empty() => {
            let n = arr.len();
            if *i >= n {
                return Err(format!("'{name}' has {n} entries, so [{i}] does not exist"));
            }
            arr.replace(*i, value);
            Ok(())
        }
        _ => Err(format!("'{name}' is not a list that [{idx:?}] can index")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn improves_unknown_field_messages() {
        let m = improve_message("unknown field `masss`, expected one of `name`, `mass`, `length`");
        assert!(m.ends_with("did you mean `mass`?"), "{m}");
    }

    #[test]
    fn sets_nested_keys() {
        let mut doc: toml_edit::DocumentMut = "[hekf]\npasses = 1\n[[hekf.runs]]\nfile = \"a\"\n"
            .parse()
            .unwrap();
        set_one(&mut doc, "hekf.passes=3").unwrap();
        set_one(&mut doc, "hekf.runs[0].file=b.csv").unwrap();
        set_one(&mut doc, "output.dir=\"x\"").unwrap();
        let s = doc.to_string();
        assert!(s.contains("passes = 3"), "{s}");
        assert!(s.contains("file = \"b.csv\""), "{s}");
        assert!(s.contains("dir = \"x\""), "{s}");
        assert!(set_one(&mut doc, "hekf.runs[4].file=c").is_err());
        assert!(set_one(&mut doc, "nonsense").is_err());
    }
}
