//! `--json` output: one pretty JSON document on stdout, and problems in the form every
//! command uses ({file, line, column, key, message}).

use super::CmdResult;
use crate::base::error::{ConfigProblem, Error};
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
    input_problem_at(Some(key), e)
}

/// A problem with an input file, or any error, in the form of [`config_problem`]; `key` the
/// configuration key naming the input, if any.
fn input_problem_at(key: Option<&str>, e: &Error) -> Value {
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
        Error::Io { path, source } | Error::Write { path, source } => (
            Some(path.clone()),
            None,
            None,
            None,
            crate::base::error::io_reason(source),
        ),
        Error::Numerical { message, .. } => (None, None, None, None, message.clone()),
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

/// The JSON error object a `--json` command prints on stdout when it fails (the human
/// message still goes to stderr): `{"error": {kind, message, file, line, column,
/// column_name, key, stage, problems}, "exit_code"}`. `kind` is `config`, `input`,
/// `numerical`, `io` or `usage`; `problems` lists every problem in the form of `check
/// --json` (several for a configuration, one otherwise); a field that does not apply is
/// null.
pub fn error(e: &Error) -> Value {
    let problems: Vec<Value> = match e {
        Error::Config(list) => list.iter().map(config_problem).collect(),
        other => vec![input_problem_at(None, other)],
    };
    // the place of the error: its one problem's (every field of a configuration's list
    // shares only the file)
    let single = problems.len() == 1;
    let field = |name: &str| {
        if single {
            problems[0][name].clone()
        } else {
            Value::Null
        }
    };
    let file = match e {
        Error::Config(list) => list.first().map(|p| json!(p.file)).unwrap_or(Value::Null),
        _ => field("file"),
    };
    let (kind, stage) = match e {
        Error::Config(_) => ("config", None),
        Error::Input(_) => ("input", None),
        Error::Numerical { stage, .. } => ("numerical", Some(stage.as_str())),
        Error::Io { .. } | Error::Write { .. } => ("io", None),
        Error::Usage(_) => ("usage", None),
    };
    json!({
        "error": {
            "kind": kind,
            "message": e.to_string(),
            "file": file,
            "line": field("line"),
            "column": field("column"),
            "column_name": field("column_name"),
            "key": field("key"),
            "stage": stage,
            "problems": problems,
        },
        "exit_code": e.exit_code(),
    })
}

/// A usage error clap found on the command line (exit code 2), as [`error`] gives it.
pub fn usage_error(message: &str) -> Value {
    error(&Error::Usage(message.to_string()))
}
