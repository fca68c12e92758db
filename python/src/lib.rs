//! `hydroid._hydroid`, the compiled part of the `hydroid` Python package (python/python/hydroid
//! holds the rest): thin wrappers over hydroid's library (src/lib.rs), never over the command
//! line. Each function hands its result to Python as JSON text (serde_json writes every f64 in
//! the shortest form that reads back to the same double, so nothing is rounded on the way);
//! the Python side builds the polars DataFrames. Errors raise `hydroid.HydroidError` with
//! hydroid's message and its problems in the form of `hydroid check --json`.

mod simulate;

use hydroid::app::{catalogue, check, pipeline, report};
use hydroid::base::progress::Silent;
use hydroid::io::formats::{Format, FormatChoice};
use hydroid::Error;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::path::PathBuf;

create_exception!(
    hydroid._hydroid,
    HydroidError,
    PyException,
    "An error of hydroid: the message names the file, line, column or configuration key; \
     `problems` lists each problem as a dict {file, line, column, column_name, key, message} \
     and `exit_code` is the command line's exit code for it."
);

/// hydroid's error as a `HydroidError`, its problems attached.
pub(crate) fn py_err(e: Error) -> PyErr {
    let problems: Vec<serde_json::Value> = match &e {
        Error::Config(list) => list.iter().map(check::config_problem).collect(),
        other => vec![check::input_problem_at(None, other)],
    };
    Python::attach(|py| {
        let err = HydroidError::new_err(e.to_string());
        let value = err.value(py);
        // attaching the details cannot fail on an exception instance; the message is there
        let _ = json_value(py, &problems).and_then(|p| value.setattr("problems", p));
        let _ = value.setattr("exit_code", e.exit_code());
        err
    })
}

/// `value` as a Python object (through the json module).
fn json_value(py: Python<'_>, value: &impl serde::Serialize) -> PyResult<Py<PyAny>> {
    let text = json_text(value)?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// `value` as JSON text.
fn json_text(value: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(value)
        .map_err(|e| py_err(Error::Usage(format!("cannot write JSON: {e}"))))
}

/// Runs the configuration `config` with the overrides `overrides` (`KEY=VALUE`) and writes
/// the output folder as `hydroid run` does (written whole or not at all; a folder hydroid did
/// not write is refused, one changed since hydroid wrote it is replaced only with `force`).
/// Returns the folder written and results.json's text.
#[pyfunction]
#[pyo3(signature = (config, out=None, overrides=Vec::new(), force=false))]
fn run(
    py: Python<'_>,
    config: PathBuf,
    out: Option<PathBuf>,
    overrides: Vec<String>,
    force: bool,
) -> PyResult<(PathBuf, String)> {
    py.detach(|| {
        let loaded = hydroid::load(&config, &overrides)?;
        // before any stage runs: a refusal does not come after the work
        let staging = report::staging(&loaded, out.as_deref(), force)?;
        let output = pipeline::run(&loaded, &mut Silent)?;
        report::write(&staging, &loaded, &output)?;
        let dir = staging.commit()?;
        let results = hydroid::io::output::to_json(&output.result)?;
        Ok((dir, String::from_utf8_lossy(&results).into_owned()))
    })
    .map_err(py_err)
}

/// What `hydroid check --json` prints for `config`, as JSON text.
#[pyfunction]
#[pyo3(signature = (config, overrides=Vec::new(), out=None))]
fn check_config(
    py: Python<'_>,
    config: PathBuf,
    overrides: Vec<String>,
    out: Option<PathBuf>,
) -> PyResult<String> {
    let report = py
        .detach(|| {
            let mut text = Vec::new();
            let (loaded, found) = check::check(&config, &overrides, out.as_deref(), &mut text)?;
            Ok(check::json_report(&config, loaded.as_ref(), found))
        })
        .map_err(py_err)?;
    json_text(&report)
}

/// One export read as `hydroid inspect` reads it (`format` a `--format` name, default
/// detected): JSON text {file, format, columns: [{name, header, unit, si_unit, quantity,
/// values}], time, warnings}, the values in SI (null for a missing cell).
#[pyfunction]
#[pyo3(signature = (file, format=None))]
fn read(py: Python<'_>, file: PathBuf, format: Option<String>) -> PyResult<String> {
    let choice = format_choice(format.as_deref().unwrap_or("auto")).map_err(py_err)?;
    let (table, report) = py
        .detach(|| hydroid::app::inspect::read(&file, choice))
        .map_err(|e| py_err(e.into()))?;
    let columns: Vec<serde_json::Value> = report
        .columns
        .iter()
        .zip(&table.columns)
        .map(|(r, c)| {
            serde_json::json!({
                "name": r.name,
                "header": r.header,
                "unit": r.unit,
                "si_unit": r.si_unit,
                "quantity": r.quantity,
                "values": c.values,
            })
        })
        .collect();
    json_text(&serde_json::json!({
        "file": report.file,
        "format": report.format,
        "columns": columns,
        "time": table.time.map(|t| table.columns[t].name.clone()),
        "warnings": report.warnings,
    }))
}

/// The format a `--format` name names, or a usage error listing them.
fn format_choice(name: &str) -> Result<FormatChoice, Error> {
    FormatChoice::parse(name).ok_or_else(|| {
        let names: Vec<&str> = std::iter::once("auto")
            .chain(Format::ALL.iter().map(|f| f.name()))
            .collect();
        Error::Usage(format!(
            "unknown format '{name}'; expected one of {}",
            names.join(", ")
        ))
    })
}

/// Every model of the catalogue (`hydroid coefficients MODEL --json` for each), JSON text.
#[pyfunction]
fn models() -> PyResult<String> {
    let all: Vec<catalogue::ModelEntry> = hydroid::ModelName::ALL
        .iter()
        .map(|m| catalogue::model(*m))
        .collect();
    json_text(&all)
}

/// The catalogue of coefficients (`hydroid coefficients --json`), or one model's entry when
/// `model` is given, JSON text.
#[pyfunction]
#[pyo3(signature = (model=None))]
fn coefficients(model: Option<&str>) -> PyResult<String> {
    match model {
        Some(name) => json_text(&catalogue::model(
            catalogue::model_named(name).map_err(py_err)?,
        )),
        None => json_text(&catalogue::entries()),
    }
}

/// The module.
#[pymodule]
fn _hydroid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("HydroidError", m.py().get_type::<HydroidError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("COEFFICIENT_COLUMNS", report::COEFFICIENT_COLUMNS.to_vec())?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(check_config, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(models, m)?)?;
    m.add_function(wrap_pyfunction!(coefficients, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    Ok(())
}
