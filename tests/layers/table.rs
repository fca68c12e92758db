//! The layer table (docs/layers.txt): one line per layer, lowest first,
//! `name: path-prefix path-prefix ...`, e.g. `base: src/error.rs src/units.rs src/base/`;
//! `#` starts a comment. A file belongs to the layer of its longest matching prefix (a
//! prefix matches the file itself or any file in the folder it names).

/// One layer: its name, the prefixes of the files it holds, and its line in the table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layer {
    /// The layer's name, e.g. `io`.
    pub name: String,
    /// Files (`src/table.rs`) and folders (`src/formats`, `src/formats/`) in the layer.
    pub prefixes: Vec<String>,
    /// 1-based line of the table the layer is on.
    pub line: usize,
}

/// The layers, lowest first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Table {
    /// Where the table was read from, for messages (`docs/layers.txt`).
    pub file: String,
    /// The layers in the table's order, lowest first.
    pub layers: Vec<Layer>,
}

impl Table {
    /// Reads a table; every line that is not `name: prefix ...` is an error naming the
    /// file, the line and what was expected, and so is a prefix listed twice.
    pub fn parse(text: &str, file: &str) -> Result<Table, Vec<String>> {
        let mut layers: Vec<Layer> = Vec::new();
        let mut errors = Vec::new();
        for (k, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let expected = "expected `name: path-prefix path-prefix ...`";
            let Some((name, prefixes)) = line.split_once(':') else {
                errors.push(format!("{file} line {}: {expected}, found `{line}`", k + 1));
                continue;
            };
            let layer = Layer {
                name: name.trim().to_string(),
                prefixes: prefixes.split_whitespace().map(String::from).collect(),
                line: k + 1,
            };
            if layer.name.is_empty() || layer.prefixes.is_empty() {
                errors.push(format!(
                    "{file} line {}: {expected} (a name and at least one prefix), found `{line}`",
                    k + 1
                ));
            }
            for p in &layer.prefixes {
                if let Some(first) = layers.iter().find(|l| l.prefixes.contains(p)) {
                    errors.push(format!(
                        "{file} line {}: `{p}` is already in layer {} (line {}); a file or \
                         folder belongs to one layer",
                        k + 1,
                        first.name,
                        first.line
                    ));
                }
            }
            layers.push(layer);
        }
        if errors.is_empty() {
            Ok(Table {
                file: file.to_string(),
                layers,
            })
        } else {
            Err(errors)
        }
    }

    /// The layer of `file` (`src/...`): its position in the table (0 = lowest) and name; the
    /// layer of the longest prefix matching the file, None when no prefix matches.
    pub fn layer_of(&self, file: &str) -> Option<(usize, &str)> {
        let mut best: Option<(&str, usize, &str)> = None;
        for (i, layer) in self.layers.iter().enumerate() {
            for p in layer.prefixes.iter().filter(|p| matches(p, file)) {
                if best.is_none_or(|(b, _, _)| p.len() > b.len()) {
                    best = Some((p, i, &layer.name));
                }
            }
        }
        best.map(|(_, i, name)| (i, name))
    }

    /// The prefixes that match none of `files`, with their line: a name misspelt or a file
    /// moved since the table was written.
    pub fn unmatched<'a>(&'a self, files: &[&str]) -> Vec<(usize, &'a str)> {
        let mut out = Vec::new();
        for layer in &self.layers {
            for p in &layer.prefixes {
                if !files.iter().any(|f| matches(p, f)) {
                    out.push((layer.line, p.as_str()));
                }
            }
        }
        out
    }
}

/// Whether prefix `p` holds `file`: the file itself, or a folder the file is in.
fn matches(p: &str, file: &str) -> bool {
    file == p
        || file
            .strip_prefix(p.trim_end_matches('/'))
            .is_some_and(|rest| rest.starts_with('/'))
}
