//! Collects every problem found in a configuration, each with its key path and line.

use super::paths::Seg;
use crate::base::error::ConfigProblem;
use crate::base::numfmt::short;
use std::path::{Path, PathBuf};

/// The problems found so far, and what is needed to place them in the file.
pub struct Problems {
    file: PathBuf,
    base_dir: PathBuf,
    doc: Option<toml_edit::Document<String>>,
    /// Key paths whose values were unusable and were removed or replaced while reading:
    /// problems at or under them are already reported and are not added again.
    poisoned: Vec<String>,
    /// Key paths set by `--set`, with the override as given.
    overridden: Vec<(String, String)>,
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
            poisoned: Vec::new(),
            overridden: Vec::new(),
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

    /// Adds a problem at `key` (a dotted path such as `hekf.runs[0].file`), with the line
    /// of the key in the file, or the `--set` that gave its value.
    pub fn add(&mut self, key: &str, message: impl Into<String>) {
        if self.is_poisoned(key) {
            return;
        }
        let mut message = message.into();
        let mut line = self.line_of(key);
        if let Some((_, spec)) = self.overridden.iter().rev().find(|(k, _)| under(key, k)) {
            message = format!("(from --set {spec}) {message}");
            line = None;
        }
        let problem = ConfigProblem {
            file: self.file.clone(),
            line,
            key: Some(key.to_string()),
            message,
        };
        // two stages of one model find the same problem with the vehicle: said once
        if !self.list.contains(&problem) {
            self.list.push(problem);
        }
    }

    /// Adds a problem that belongs to no key (TOML syntax, a malformed `--set`).
    pub fn add_unplaced(&mut self, line: Option<usize>, message: impl Into<String>) {
        self.list.push(ConfigProblem {
            file: self.file.clone(),
            line,
            key: None,
            message: message.into(),
        });
    }

    /// Records that the value at `key` was unusable and has been reported.
    pub fn poison(&mut self, key: &str) {
        if !self.is_poisoned(key) {
            self.poisoned.push(key.to_string());
        }
    }

    /// True when `key`, or a table or list it is in, was unusable and has been reported.
    pub fn is_poisoned(&self, key: &str) -> bool {
        self.poisoned.iter().any(|p| under(key, p))
    }

    /// The unusable keys found while reading.
    pub fn poisoned(&self) -> &[String] {
        &self.poisoned
    }

    /// Records that `--set spec` gave the value at `key`.
    pub fn overridden(&mut self, key: &str, spec: &str) {
        self.overridden.push((key.to_string(), spec.to_string()));
    }

    /// The problems in the order of the file (those without a line last, in the order
    /// found).
    pub fn in_file_order(mut self) -> Vec<ConfigProblem> {
        self.list.sort_by_key(|p| p.line.unwrap_or(usize::MAX));
        self.list
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
                format!("must be a positive number ({unit}), got {}", short(value)),
            );
        }
    }

    /// Requires a finite value within `lo ..= hi` (in `unit`); `why` says what the range
    /// stands for.
    pub fn in_range(&mut self, key: &str, value: f64, (lo, hi): (f64, f64), unit: &str, why: &str) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            self.add(
                key,
                format!(
                    "must be from {} to {} {unit} ({why}), got {}",
                    brief(lo),
                    brief(hi),
                    brief(value)
                ),
            );
        }
    }

    /// Requires a finite value.
    pub fn finite(&mut self, key: &str, value: f64) {
        if !value.is_finite() {
            self.add(
                key,
                format!("must be a finite number, got {}", short(value)),
            );
        }
    }

    /// Requires a finite coefficient-sized value: |value| at most `MAX_COEFFICIENT`.
    pub fn coefficient_sized(&mut self, key: &str, value: f64) {
        if !value.is_finite() {
            self.finite(key, value);
        } else if value.abs() > MAX_COEFFICIENT {
            self.add(
                key,
                format!(
                    "{} is larger than any coefficient of a real vehicle (at most {} in SI; \
                     a 300 m ship's N_rdot is about 1e13 kg m^2)",
                    short(value),
                    short(MAX_COEFFICIENT)
                ),
            );
        }
    }

    /// Requires a value within [lo, hi].
    pub fn within(&mut self, key: &str, value: f64, lo: f64, hi: f64) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            self.add(
                key,
                format!(
                    "must be between {} and {}, got {}",
                    short(lo),
                    short(hi),
                    short(value)
                ),
            );
        }
    }

    /// Requires a whole number within [lo, hi], saying why the bound is there.
    pub fn count_within(&mut self, key: &str, value: u64, lo: u64, hi: u64, why: &str) {
        if value < lo || value > hi {
            let range = if hi == u64::MAX {
                format!("a whole number >= {lo}")
            } else {
                format!("a whole number from {lo} to {hi}")
            };
            let why = if why.is_empty() {
                String::new()
            } else {
                format!(" ({why})")
            };
            self.add(key, format!("must be {range}{why}, got {value}"));
        }
    }

    /// Requires a positive value within the plausible range [lo, hi], in `unit`; outside
    /// it the value is almost surely a unit mistake or a typing error (`hint` may say
    /// which). Returns whether the value passed.
    pub fn plausible(
        &mut self,
        key: &str,
        value: f64,
        (lo, hi): (f64, f64),
        unit: &str,
        hint: &str,
    ) -> bool {
        if !(value.is_finite() && value > 0.0) {
            self.positive(key, value, unit);
            return false;
        }
        if value < lo || value > hi {
            let hint = if hint.is_empty() {
                "check the unit (values are SI unless a unit is given)".to_string()
            } else {
                hint.to_string()
            };
            self.add(
                key,
                format!(
                    "{} {unit} is outside the plausible range {} to {} {unit}; {hint}",
                    short(value),
                    short(lo),
                    short(hi)
                ),
            );
            return false;
        }
        true
    }

    /// Reports every name listed more than once in the list at `key`, naming both positions.
    pub fn no_duplicates<'a>(&mut self, key: &str, names: impl IntoIterator<Item = &'a str>) {
        let names: Vec<&str> = names.into_iter().collect();
        for (j, n) in names.iter().enumerate() {
            if let Some(i) = names[..j].iter().position(|m| m == n) {
                self.add(
                    &format!("{key}[{j}]"),
                    format!(
                        "'{n}' is listed twice in {key}: at positions {} and {}",
                        i + 1,
                        j + 1
                    ),
                );
            }
        }
    }

    /// Checks a stage's input files (key path, input): each entry's keys, that its file
    /// exists, and that no file is named twice.
    pub fn inputs(&mut self, inputs: &[(String, &crate::config::InputSpec)]) {
        for (key, r) in inputs {
            r.validate(key, self);
            self.existing_file(&format!("{key}.file"), &r.file);
        }
        self.no_duplicate_files(inputs);
    }

    /// Reports an input file named twice among `inputs` (key path, input): the same export
    /// would count twice, or identify and validate at once.
    pub fn no_duplicate_files(&mut self, inputs: &[(String, &crate::config::InputSpec)]) {
        for (j, (key, spec)) in inputs.iter().enumerate() {
            if let Some((first, _)) = inputs[..j].iter().find(|(_, s)| s.file == spec.file) {
                self.add(
                    &format!("{key}.file"),
                    format!(
                        "{} is already read by {first}; each export may be used once",
                        spec.file.display()
                    ),
                );
            }
        }
    }

    /// Requires a coefficient name from the catalogue.
    pub fn known_coefficient(&mut self, key: &str, name: &str) {
        if let Err(m) = super::check_coefficient_name(name) {
            self.add(key, m.to_string());
        }
    }

    /// Requires an existing input file.
    pub fn existing_file(&mut self, key: &str, path: &Path) {
        let full = self.resolve(path);
        // a folder, FIFO, device or broken link is named as what it is
        if let Err(e) = crate::io::formats::input::check_regular(&full) {
            self.add(
                key,
                format!(
                    "input file {}: {} (paths are relative to the configuration file)",
                    full.display(),
                    e.message
                ),
            );
        }
    }

    /// The 1-based line of a dotted key path, if it is in the file.
    pub fn line_of(&self, key: &str) -> Option<usize> {
        let doc = self.doc.as_ref()?;
        let mut item: &toml_edit::Item = doc.as_item();
        let mut last_span = None;
        let (segs, _) = super::paths::parse_path(key).ok()?;
        for seg in &segs {
            let next = match seg {
                Seg::Key(k) => item.get(k.as_str()),
                Seg::Index(i) => item.get(*i),
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

/// Largest magnitude of a coefficient, prior or process noise value, SI.
pub const MAX_COEFFICIENT: f64 = 1e15;

/// A number written short: `0.5`, `-50`, `2000`, `1e-6`, `1e9`, `NaN`.
/// [`short`] cut to four significant digits when that is shorter (`3.142` for pi).
fn brief(v: f64) -> String {
    let s = short(v);
    let n = crate::base::numfmt::num(v);
    if n.len() < s.len() {
        n
    } else {
        s
    }
}

/// True when `key` is `prefix` or inside it (`a.b` is under `a`, `a[0].c` under `a[0]`).
pub(crate) fn under(key: &str, prefix: &str) -> bool {
    prefix.is_empty()
        || key == prefix
        || key
            .strip_prefix(prefix)
            .is_some_and(|r| r.starts_with('.') || r.starts_with('['))
}

fn span_of(item: &toml_edit::Item) -> Option<std::ops::Range<usize>> {
    match item {
        toml_edit::Item::ArrayOfTables(a) => a.span(),
        toml_edit::Item::Table(t) => t.span(),
        other => other.span(),
    }
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

    #[test]
    fn poisoned_keys_are_not_reported_again() {
        let mut p = Problems::new(Path::new("c.toml"), "[a]\nb = [1]\n");
        p.poison("a.b");
        p.add("a.b[0]", "x");
        p.add("a.bc", "y");
        p.no_duplicates("a.l", ["u", "v", "u"]);
        let all: Vec<String> = p.list.iter().map(|x| x.to_string()).collect();
        assert_eq!(all.len(), 2, "{all:?}");
        assert!(all[0].contains("a.bc: y"), "{all:?}");
        assert!(all[1].contains("a.l[2]: 'u' is listed twice in a.l: at positions 1 and 3"));
    }
}
