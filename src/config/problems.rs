//! Collects every problem found in a configuration, each with its key path and line.

use crate::error::ConfigProblem;
use std::path::{Path, PathBuf};

/// The problems found so far, and what is needed to place them in the file.
pub struct Problems {
    file: PathBuf,
    base_dir: PathBuf,
    doc: Option<toml_edit::Document<String>>,
    /// Every problem, in the order found.
    pub list: Vec<ConfigProblem>,
}

impl Problems {
    /// A collector for the configuration `file` whose text is `text`.
    pub fn new(file: &Path, text: &str) -> Self {
        Problems {
            file: file.to_path_buf(),
            base_dir: file.parent().map(Path::to_path_buf).unwrap_or_default(),
            doc: toml_edit::Document::parse(text.to_string()).ok(),
            list: Vec::new(),
        }
    }

    /// The folder relative paths are resolved against.
    pub fn base_dir(&self) -> &Path {
        &self.base_dir
    }

    /// Resolves a path from the configuration against its folder.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.base_dir.join(p)
    }

    /// Adds a problem at `key` (a dotted path such as `hekf.runs[0].file`).
    pub fn add(&mut self, key: &str, message: impl Into<String>) {
        let line = self.line_of(key);
        self.list.push(ConfigProblem {
            file: self.file.clone(),
            line,
            key: Some(key.to_string()),
            message: message.into(),
        });
    }

    /// True when nothing was found.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Requires a finite value greater than zero.
    pub fn positive(&mut self, key: &str, value: f64, unit: &str) {
        if !(value.is_finite() && value > 0.0) {
            self.add(
                key,
                format!("must be a positive number ({unit}), got {value}"),
            );
        }
    }

    /// Requires a finite value.
    pub fn finite(&mut self, key: &str, value: f64) {
        if !value.is_finite() {
            self.add(key, format!("must be a finite number, got {value}"));
        }
    }

    /// Requires a value within [lo, hi].
    pub fn within(&mut self, key: &str, value: f64, lo: f64, hi: f64) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            self.add(key, format!("must be between {lo} and {hi}, got {value}"));
        }
    }

    /// Requires a coefficient name from the catalogue.
    pub fn known_coefficient(&mut self, key: &str, name: &str) {
        if let Err(m) = super::check_coefficient_name(name) {
            self.add(key, m);
        }
    }

    /// Requires an existing input file.
    pub fn existing_file(&mut self, key: &str, path: &Path) {
        let full = self.resolve(path);
        if !full.is_file() {
            self.add(
                key,
                format!(
                    "input file {} does not exist (paths are relative to the configuration file)",
                    full.display()
                ),
            );
        }
    }

    /// The 1-based line of a dotted key path, if it is in the file.
    pub fn line_of(&self, key: &str) -> Option<usize> {
        let doc = self.doc.as_ref()?;
        let mut item: &toml_edit::Item = doc.as_item();
        let mut last_span = None;
        for seg in split_key(key) {
            let next = match seg {
                Seg::Key(k) => item.get(k),
                Seg::Index(i) => item.get(i),
            };
            match next {
                Some(n) => {
                    item = n;
                    if let Some(s) = span_of(n) {
                        last_span = Some(s);
                    }
                }
                None => break,
            }
        }
        let start = last_span?.start;
        Some(doc.raw()[..start].matches('\n').count() + 1)
    }
}

fn span_of(item: &toml_edit::Item) -> Option<std::ops::Range<usize>> {
    match item {
        toml_edit::Item::ArrayOfTables(a) => a.span(),
        toml_edit::Item::Table(t) => t.span(),
        other => other.span(),
    }
}

enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn split_key(key: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in key.split('.') {
        let (name, rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !name.is_empty() {
            out.push(Seg::Key(name));
        }
        for idx in rest.split('[').filter(|s| !s.is_empty()) {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(Seg::Index(i));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_of_keys() {
        let text =
            "[vehicle]\nmass = 50\n\n[[hekf.runs]]\nfile = \"a\"\n[[hekf.runs]]\nfile = \"b\"\n";
        let p = Problems::new(Path::new("c.toml"), text);
        assert_eq!(p.line_of("vehicle.mass"), Some(2));
        assert_eq!(p.line_of("hekf.runs[1].file"), Some(7));
        assert_eq!(p.line_of("hekf.runs[0]"), Some(4));
        assert_eq!(p.line_of("nothing.here"), None);
    }
}
