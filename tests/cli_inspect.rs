//! `hydroid inspect` as a user runs it: text, JSON, --format, and a closed pipe.

use crate::common;

use common::{hydroid, named, root};
use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Command, Stdio};

fn fixture(name: &str) -> PathBuf {
    root().join("tests/fixtures/formats").join(name)
}

/// Exit code, stdout and stderr (both UTF-8) of `hydroid inspect args`.
fn inspect(args: &[&str]) -> (Option<i32>, String, String) {
    let out = hydroid(&[&["inspect"], args].concat());
    (
        out.status.code(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn text_report_of_a_cfx_monitor_export() {
    let f = fixture("cfx_monitor.csv");
    let (code, out, err) = inspect(&[f.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
    assert!(out.contains("format    cfx"), "{out}");
    assert!(out.contains("rows      5 (lines 5-9)"), "{out}");
    assert!(
        out.contains("time      'Time' from 0 s to 2 s (span 2 s)"),
        "{out}"
    );
    assert!(out.contains("dt mean 0.5 s, min 0.5 s, max 0.5 s"), "{out}");
    // the column table: one line per column, aligned, with unit, SI unit and quantity
    let heading = out
        .lines()
        .find(|l| l.trim_start().starts_with("4  Heading"))
        .unwrap_or_else(|| panic!("no Heading row in\n{out}"));
    let cells: Vec<&str> = heading.split_whitespace().collect();
    assert!(cells.contains(&"degree") && cells.contains(&"rad") && cells.contains(&"yaw"));
    let header = out.lines().find(|l| l.contains("quantity")).unwrap();
    let col = header.find("quantity").unwrap();
    assert_eq!(heading.get(col..col + 3), Some("yaw"), "aligned:\n{out}");
}

#[test]
fn json_report_of_an_openfoam_restart() {
    let f = fixture("openfoam_forceCoeffs_restart.dat");
    let (code, out, err) = inspect(&[f.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["format"], "openfoam-forcecoeffs");
    assert_eq!(v["rows"], 4);
    assert_eq!(v["data_lines"], serde_json::json!([6, 11]));
    let cols = v["columns"].as_array().unwrap();
    assert_eq!(cols.len(), 6);
    assert_eq!(cols[0]["quantity"], "time");
    assert_eq!(cols[0]["unit"], "s");
    assert_eq!(cols[2]["name"], "Cd");
    assert_eq!(cols[2]["quantity"], "cd");
    assert_eq!(cols[2]["si_unit"], "1");
    assert_eq!(cols[2]["min"], 0.5);
    assert_eq!(cols[2]["max"], 0.63);
    assert_eq!(cols[2]["missing"], 0);
    assert_eq!(v["time"]["repeated"], 2);
    assert_eq!(v["time"]["start"], 0.1);
    assert_eq!(v["time"]["end"], 0.4);
    let meta = v["meta"].as_array().unwrap();
    assert!(meta
        .iter()
        .any(|m| m["key"] == "magUInf" && m["value"] == "2.0"));
    let warnings = v["warnings"].as_array().unwrap();
    assert!(warnings[0]
        .as_str()
        .unwrap()
        .contains("repeated time stamps"));
    // the warnings also go to stderr, for the person running the command
    assert!(err.contains("warning: 2 repeated time stamps"), "{err}");
}

#[test]
fn json_report_of_sixdof_angles_in_si() {
    let f = fixture("sixDoFRigidBodyState_degrees.dat");
    let (code, out, _) = inspect(&[f.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let yaw = named(&v["columns"], "yaw");
    assert_eq!(yaw["unit"], "deg");
    assert_eq!(yaw["si_unit"], "rad");
    assert_eq!(yaw["quantity"], "yaw");
    let max = yaw["max"].as_f64().unwrap();
    assert!((max.to_degrees() - 186.0).abs() < 1e-9, "{max}");
}

#[test]
fn json_counts_missing_cells() {
    let f = fixture("generic_missing.csv");
    let (code, out, _) = inspect(&[f.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let missing: Vec<i64> = v["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["missing"].as_i64().unwrap())
        .collect();
    assert_eq!(missing, [0, 1, 1]);
}

#[test]
fn format_option_overrides_detection_and_is_checked() {
    let f = fixture("cfx_monitor.csv");
    let (code, out, _) = inspect(&[f.to_str().unwrap(), "--format", "delimited", "--json"]);
    assert_eq!(code, Some(0));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["format"], "delimited");
    let (code, out, err) = inspect(&[f.to_str().unwrap(), "--format", "cvs"]);
    assert_eq!(code, Some(2));
    assert!(out.is_empty());
    assert!(
        err.contains("unknown format 'cvs'") && err.contains("did you mean 'cfx'"),
        "{err}"
    );
}

#[test]
fn closed_pipe_stops_quietly() {
    // Enough columns that the report overflows the pipe buffer.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.csv");
    let mut f = std::fs::File::create(&path).unwrap();
    let n = 3000;
    let names: Vec<String> = (0..n).map(|j| format!("column_{j}")).collect();
    writeln!(f, "{}", names.join(",")).unwrap();
    for r in 0..3 {
        let row: Vec<String> = (0..n).map(|j| format!("{}", r * n + j)).collect();
        writeln!(f, "{}", row.join(",")).unwrap();
    }
    drop(f);
    let mut child = Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .arg("inspect")
        .arg(&path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let mut first = String::new();
    BufReader::new(stdout).read_line(&mut first).unwrap();
    assert!(first.starts_with("file"), "{first}");
    // the reader is dropped here: the pipe is closed while hydroid still writes
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
}
