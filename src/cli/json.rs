//! `--json` output: one pretty JSON document on stdout, and problems in the form every
//! command uses ({file, line, column, key, message}).

use super::CmdResult;
use crate::app::check::{config_problem, input_problem_at};
use crate::base::error::Error;
use serde_json::{json, Value};
use std::io::Write;

/// Writes `value` as pretty JSON and a newline.
pub fn write(out: &mut dyn Write, value: &impl serde::Serialize) -> CmdResult {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::Usage(format!("cannot format JSON: {e}")))?;
    writeln!(out, "{text}")?;
    Ok(0)
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
