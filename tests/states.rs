//! The state series of each HEKF run (issue 29, item 1; docs/results.md, "State series"):
//! `states/NAME.csv`, listed in results.json, read back with the csv crate from a run of the
//! bundled example (configs/spheroid.toml: one fit run, smoother on).

use crate::common;

use common::{json, named, run_example, text, ExampleRun};
use std::path::Path;

/// The table: its header and rows, every field parsed as a number.
fn read(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| {
            rec.unwrap()
                .iter()
                .map(|f| f.parse::<f64>().unwrap_or_else(|_| panic!("'{f}'")))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The column named `name`.
fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column '{name}' in {header:?}"))
}

/// A run of the bundled example that succeeded.
fn example(extra: &[&str]) -> ExampleRun {
    let run = run_example(extra);
    assert_eq!(
        run.output.status.code(),
        Some(0),
        "{}",
        text(&run.output.stderr)
    );
    run
}

/// The spheroid model's columns, in order: time, then per state the filtered value and sigma,
/// the smoothed ones, each measured state's measurement, innovation and innovation sigma, the
/// NIS, each estimated coefficient with its sigma, every unit SI.
fn expected_header(smoothed: bool) -> Vec<String> {
    let states = [
        ("u", "m/s"),
        ("v", "m/s"),
        ("r", "rad/s"),
        ("x", "m"),
        ("y", "m"),
        ("psi", "rad"),
    ];
    let mut h = vec!["time [s]".to_string()];
    let kinds: &[&str] = if smoothed {
        &["filtered", "smoothed"]
    } else {
        &["filtered"]
    };
    for kind in kinds {
        for (s, u) in states {
            h.push(format!("{s}_{kind} [{u}]"));
            h.push(format!("{s}_{kind}_sigma [{u}]"));
        }
    }
    for (s, u) in states {
        for what in ["measured", "innovation", "innovation_sigma"] {
            h.push(format!("{s}_{what} [{u}]"));
        }
    }
    h.push("nis [-]".into());
    for (c, u) in [
        ("Yvd", "kg"),
        ("Yrd", "kg m"),
        ("Nrd", "kg m^2"),
        ("Nvv", "kg"),
        ("Nrr", "kg m^2"),
        ("Yrr", "kg m"),
    ] {
        h.push(format!("{c} [{u}]"));
        h.push(format!("{c}_sigma [{u}]"));
    }
    h
}

#[test]
fn the_state_series_ends_at_the_estimate_and_the_smoother_narrows_every_sigma() {
    let run = example(&[]);
    let r = json(&run.out.join("results.json"));
    let h = &r["stages"]["hekf"];
    let listed = h["runs"][0]["states"].as_str().unwrap();
    assert_eq!(
        listed, "states/paper_manoeuvre_u0_3_v0_1_m_s_22_N.csv",
        "the run's name made file-safe"
    );
    let (header, rows) = read(&run.out.join(listed));
    // (b) columns and units
    assert_eq!(header, expected_header(true));
    // about 1.1 kB a sample as CSV (docs/performance.md)
    let bytes = std::fs::metadata(run.out.join(listed)).unwrap().len() as f64;
    let per_row = bytes / rows.len() as f64;
    assert!((1050.0..1150.0).contains(&per_row), "{per_row} bytes a row");
    assert_eq!(rows.len() as u64, h["runs"][0]["samples"].as_u64().unwrap());
    assert!(rows.iter().all(|row| row.len() == header.len()));
    assert_eq!(rows[0][0], 0.0);
    // (a) the last row's coefficients are the HEKF's estimates, and their sigmas the
    // filter's (results.json's sigma_filter; the reported sigma adds the upstream
    // stages'), to the last printed digit: both are written in Rust's shortest form
    let last = rows.last().unwrap();
    let estimated = h["estimated"].as_array().unwrap();
    assert_eq!(estimated.len(), 6);
    for (j, name) in estimated.iter().enumerate() {
        let name = name.as_str().unwrap();
        let value_col = header
            .iter()
            .position(|c| c.starts_with(&format!("{name} [")))
            .unwrap();
        let c = named(&h["coefficients"], name);
        assert_eq!(last[value_col], c["value"].as_f64().unwrap(), "{name}");
        assert_eq!(
            last[value_col + 1],
            h["sigma_filter"][j].as_f64().unwrap(),
            "{name} sigma"
        );
        assert!(c["sigma"].as_f64().unwrap() >= last[value_col + 1]);
    }
    // (c) the smoother's sigma never exceeds the filter's (Simon 2006, sec. 9.4.2), equals
    // it at the last sample, and is smaller where later samples inform the state
    let mut narrower = 0;
    for (k, row) in rows.iter().enumerate() {
        for s in ["u", "v", "r", "x", "y", "psi"] {
            let f = row[col(&header, &format!("{s}_filtered_sigma [{}]", unit_of(s)))];
            let sm = row[col(&header, &format!("{s}_smoothed_sigma [{}]", unit_of(s)))];
            assert!(
                sm <= f * (1.0 + 1e-9),
                "sample {k}, {s}: smoothed sigma {sm} > filtered {f}"
            );
            if k + 1 == rows.len() {
                assert_eq!(sm, f, "{s} at the last sample");
            }
            narrower += usize::from(sm < 0.9 * f);
        }
    }
    assert!(narrower > rows.len(), "{narrower} narrower samples");
    // innovations and their sigmas: the NIS is the sum of the squared normalised
    // innovations of the sequential updates, so it is at least each one's, and the
    // innovation sigma covers the measurement noise
    let nis = col(&header, "nis [-]");
    let (u_nu, u_s) = (
        col(&header, "u_innovation [m/s]"),
        col(&header, "u_innovation_sigma [m/s]"),
    );
    let noise = h["runs"][0]["noise"][0]["sigma"].as_f64().unwrap();
    for row in rows.iter().skip(1) {
        assert!(row[u_s] >= noise * (1.0 - 1e-12), "{} < {noise}", row[u_s]);
        assert!(row[nis].is_finite() && row[nis] >= 0.0);
    }
    let mean_nis = rows.iter().map(|r| r[nis]).sum::<f64>() / rows.len() as f64;
    let nis_json = h["runs"][0]["nis"]["mean"].as_f64().unwrap();
    assert!(
        (mean_nis - nis_json).abs() <= 1e-9 * nis_json.abs().max(1.0),
        "{mean_nis} against results.json's {nis_json}"
    );
    assert!(rows.iter().any(|r| r[u_nu] != 0.0));
    // (d) the same run gives the same bytes
    let again = example(&[]);
    assert_eq!(
        std::fs::read(run.out.join(listed)).unwrap(),
        std::fs::read(again.out.join(listed)).unwrap(),
        "a second run wrote different bytes"
    );
}

/// The SI unit of a spheroid state.
fn unit_of(state: &str) -> &'static str {
    match state {
        "u" | "v" => "m/s",
        "r" => "rad/s",
        "psi" => "rad",
        _ => "m",
    }
}

#[test]
fn without_the_smoother_and_decimated_the_table_has_the_filtered_samples_only() {
    let run = example(&["--set", "hekf.smoother=false", "--set", "hekf.decimate=4"]);
    let r = json(&run.out.join("results.json"));
    let h = &r["stages"]["hekf"];
    let listed = h["runs"][0]["states"].as_str().unwrap();
    let (header, rows) = read(&run.out.join(listed));
    assert_eq!(header, expected_header(false));
    // one sample in 4 of 2001, from the first: the samples the filter used
    assert_eq!(rows.len(), 501);
    assert!((rows[1][0] - 0.04).abs() < 1e-12, "{}", rows[1][0]);
    let last = rows.last().unwrap();
    let yvd = col(&header, "Yvd [kg]");
    assert_eq!(
        last[yvd],
        named(&h["coefficients"], "Yvd")["value"].as_f64().unwrap()
    );
    // the schema lists the field
    let schema = json(&common::root().join("docs/results.schema.json"));
    let validator = jsonschema::draft202012::new(&schema).expect("the schema is valid");
    let errors: Vec<String> = validator.iter_errors(&r).map(|e| e.to_string()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    assert!(
        schema
            .to_string()
            .contains("the run's state series in the output folder"),
        "docs/results.schema.json describes runs[].states"
    );
}

#[test]
fn a_temporary_folder_it_cannot_spool_to_stops_the_run_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args([
            "run",
            "configs/spheroid.toml",
            "--out",
            out.to_str().unwrap(),
        ])
        .current_dir(common::root())
        .env("TMPDIR", dir.path().join("no such folder"))
        .output()
        .unwrap();
    let err = text(&o.stderr);
    assert_ne!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("states/paper_manoeuvre_u0_3_v0_1_m_s_22_N.csv")
            && err.contains("could not be spooled to a temporary file")
            && err.contains("TMPDIR"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}
