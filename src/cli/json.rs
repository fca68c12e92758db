//! `--json` output: one pretty JSON document on stdout, and problems in the form every
//! command uses ({file, line, column, key, message}).

use super::CmdResult;
use hydroid::error::{ConfigProblem, Error};
use serde_json::{json, Value};
use std::io::Write;

/// Writes `value` as pretty JSON and a newline.
pub fn write(out: &mut dyn Write, value: &impl serde::Serialize) -> CmdResult {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::Usage(format!("cannot format JSON: {e}")))?;
    writeln!(out, "{text}")?;
    Ok(0)
}

/// A configuration problem (placed by line and key; no column).
pub fn config_problem(p: &ConfigProblem) -> Value {
    json!({
        "file": p.file,
        "line": p.line,
        "column": null,
        "column_name": null,
        "key": p.key,
        "message": p.message,
    })
}

/// A problem with the input file that the configuration key `key` names.
pub fn input_problem(key: &str, e: &Error) -> Value {
    let (file, line, column, column_name, message) = match e {
        Error::Input(i) => (
            Some(i.place.file.clone()),
            i.place.line,
            i.place.column,
            i.place.column_name.clone(),
            match &i.expected {
                Some(x) => format!("{} (expected {x})", i.message),
                None => i.message.clone(),
            },
        ),
        Error::Io { path, source } => (Some(path.clone()), None, None, None, source.to_string()),
        other => (None, None, None, None, other.to_string()),
    };
    json!({
        "file": file,
        "line": line,
        "column": column,
        "column_name": column_name,
        "key": key,
        "message": message,
    })
}
