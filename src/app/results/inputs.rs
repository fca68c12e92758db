//! The input files a run read: each loaded record with its configuration key and hash, and
//! the summary results.json keeps of it.

use crate::io::record::Record;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A loaded input with its key path and hash.
#[derive(Debug, Clone)]
pub struct LoadedInput {
    /// Configuration key of the input (`hekf.runs[0]`): a label for messages and
    /// results.json, never parsed.
    pub key: String,
    /// The record.
    pub record: Record,
    /// SHA-256 of the file, hex.
    pub sha256: String,
    /// Where the data come from (the input's `source`, or the default of its layout).
    pub source: crate::config::DataSource,
}

/// One input file.
#[derive(Debug, Clone, Serialize)]
pub struct InputSummary {
    /// Configuration key.
    pub key: String,
    /// Name for reports.
    pub name: String,
    /// Path relative to the configuration file.
    pub file: String,
    /// Layout it was read as.
    pub format: String,
    /// Data rows.
    pub rows: usize,
    /// SHA-256 of the file.
    pub sha256: String,
    /// First and last time, s.
    pub time_span: Option<[f64; 2]>,
    /// Quantities read and the unit each was read in.
    pub quantities: BTreeMap<String, String>,
    /// Constants from the configuration (SI).
    pub constants: BTreeMap<String, f64>,
    /// Where the data come from: `measured` or `cfd`.
    pub source: crate::config::DataSource,
}

impl InputSummary {
    /// Summary of a loaded input; the file path is written relative to `base`.
    pub fn from_loaded(i: &LoadedInput, base: &Path) -> Self {
        let r = &i.record;
        let file = crate::io::record::report_path(&r.source, base);
        InputSummary {
            key: i.key.clone(),
            name: r.name.clone(),
            file,
            format: r.format.name().to_string(),
            rows: r.rows(),
            sha256: i.sha256.clone(),
            time_span: r.time().and_then(|t| Some([*t.first()?, *t.last()?])),
            quantities: r
                .units
                .iter()
                .map(|(q, u)| (q.key().to_string(), u.clone()))
                .collect(),
            constants: r
                .constants
                .iter()
                .map(|(q, v)| (q.key().to_string(), *v))
                .collect(),
            source: i.source,
        }
    }
}

/// What the report calls the data of the inputs whose configuration key starts with
/// `prefix` (`hekf.`, `polar.`; empty for all): "measured", "CFD", or "measured and CFD" when
/// they differ; None without such inputs.
pub fn data_word(inputs: &[InputSummary], prefix: &str) -> Option<&'static str> {
    let mut all: Vec<crate::config::DataSource> = inputs
        .iter()
        .filter(|i| i.key.starts_with(prefix))
        .map(|i| i.source)
        .collect();
    all.sort();
    all.dedup();
    match all.as_slice() {
        [] => None,
        [one] => Some(one.word()),
        _ => Some("measured and CFD"),
    }
}
