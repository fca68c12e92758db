//! The plausibility checks before the filter, as a user meets them: each common mistake with a
//! ship log (the wrong column for the yaw rate, the rudder in the wrong unit or sign, rpm and
//! rps confused, positions in km, the time in minutes, u and v swapped) injected into the
//! bundled KVLCC2 example (configs/ship_kvlcc2.toml, synthetic turns of `hydroid simulate`),
//! named by `hydroid check` and by `hydroid run` with the column and the fix (exit code 2, a
//! configuration problem; nothing written); the unchanged example and every bundled
//! configuration have no finding; other models (the NPS AUV, Nomoto) are judged alike.

use crate::common;

use common::{example_copy, hydroid_in, text};
use std::path::Path;
use std::process::Output;

const CONFIG: &str = "configs/ship_kvlcc2.toml";
const TURN: &str = "cfd_exports/kvlcc2_turn35.csv";

/// Columns of the KVLCC2 exports: time, x, y, heading, u, v, yaw rate, rudder, propeller.
const TIME: usize = 0;
const X: usize = 1;
const Y: usize = 2;
const HEADING: usize = 3;
const RUDDER: usize = 7;
const PROPELLER: usize = 8;

/// Rewrites the export at `path`: `header` changes the header's cells, `row` each data row's.
fn edit(path: &Path, header: impl Fn(&mut Vec<String>), row: impl Fn(&mut Vec<String>)) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    header(&mut head);
    let mut out = vec![head.join(",")];
    for line in lines {
        let mut cells: Vec<String> = line.split(',').map(String::from).collect();
        row(&mut cells);
        out.push(cells.join(","));
    }
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

/// Multiplies the cells `columns` of every row by `factor`.
fn scale(columns: &'static [usize], factor: f64) -> impl Fn(&mut Vec<String>) {
    move |c| {
        for &k in columns {
            let v: f64 = c[k].trim().parse().unwrap();
            c[k] = format!("{:.12e}", v * factor);
        }
    }
}

fn args<'a>(cmd: &'a str, set: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![cmd, CONFIG];
    if cmd == "run" {
        a.extend(["--out", "out", "--set", "output.plots=false"]);
    }
    for s in set {
        a.extend(["--set", s]);
    }
    a
}

/// `check` and `run` of the example in `dir` with `set`: both refuse the configuration (exit
/// code 2, nothing written) with a message holding every one of `says`.
fn named_by_check_and_run(dir: &Path, set: &[&str], says: &[&str]) {
    for cmd in ["check", "run"] {
        let o: Output = hydroid_in(dir, &args(cmd, set));
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{cmd} {set:?}: {e}");
        for s in says {
            assert!(e.contains(s), "{cmd} {set:?}: expected '{s}' in\n{e}");
        }
        assert!(e.contains("hekf.checks = \"warn\" runs anyway"), "{e}");
        assert!(!dir.join("out").exists(), "{cmd} wrote its output");
    }
}

/// A copy of the example with the turn's export changed by `header` and `row`.
fn with_turn(
    header: impl Fn(&mut Vec<String>),
    row: impl Fn(&mut Vec<String>),
) -> tempfile::TempDir {
    let dir = example_copy();
    edit(&dir.path().join(TURN), header, row);
    dir
}

#[test]
fn the_example_and_every_bundled_configuration_have_no_finding() {
    let dir = example_copy();
    for e in std::fs::read_dir(dir.path().join("configs")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "toml") {
            let o = hydroid_in(dir.path(), &["check", path.to_str().unwrap()]);
            let out = text(&o.stdout);
            assert_eq!(
                o.status.code(),
                Some(0),
                "{}: {}",
                path.display(),
                text(&o.stderr)
            );
            assert!(!out.contains("warnings:"), "{}: {out}", path.display());
        }
    }
}

#[test]
fn a_rate_column_that_is_not_the_yaw_rate_is_named() {
    // a heel column (in deg, its header without a unit) follows the turn: mapped to r as a
    // user who took it for the yaw rate would, its integral is not the heading
    let dir = with_turn(
        |h| h.push("\"heel\"".into()),
        |c| {
            let psi: f64 = c[HEADING].trim().parse().unwrap();
            c.push(format!("{:.9}", 0.05 * psi));
        },
    );
    named_by_check_and_run(
        dir.path(),
        &["hekf.runs[0].columns.r={column=\"heel\",unit=\"deg/s\"}"],
        &[
            "is not the yaw rate",
            "column 'heel' (10)",
            "kvlcc2_turn35.csv",
            "Map r to the column that holds the yaw rate",
        ],
    );
}

#[test]
fn a_rudder_in_the_wrong_unit_is_named_both_ways() {
    // the log in radians under its degree label: 57.3 times too small
    let dir = with_turn(|_| {}, scale(&[RUDDER], std::f64::consts::PI / 180.0));
    named_by_check_and_run(
        dir.path(),
        &[],
        &[
            "the rudder looks like radians read as degrees",
            "`unit = \"rad\"`",
            "column 'rudder' (8)",
        ],
    );
    // degrees declared radians: 2005 deg, beyond any rudder
    let dir = example_copy();
    named_by_check_and_run(
        dir.path(),
        &["hekf.runs[0].columns.rudder={column=\"rudder\",unit=\"rad\"}"],
        &[
            "the rudder looks like degrees read as radians",
            "`unit = \"deg\"`",
        ],
    );
}

#[test]
fn a_rudder_of_the_other_sign_convention_is_named() {
    let dir = example_copy();
    named_by_check_and_run(
        dir.path(),
        &["hekf.runs[0].columns.rudder={column=\"rudder\",scale=-1}"],
        &[
            "turns the other way from the mmg3 model",
            "a positive rudder turns the model to starboard",
            "remove the `scale = -1`",
        ],
    );
}

#[test]
fn rpm_and_rps_confused_are_named_both_ways() {
    // rpm in the file, declared rev/s: 60 times too fast
    let dir = example_copy();
    named_by_check_and_run(
        dir.path(),
        &["hekf.runs[0].columns.rpm={column=\"propeller\",unit=\"rps\"}"],
        &["rpm read as rev/s", "advance ratio", "`unit = \"rpm\"`"],
    );
    // rev/s in the file under its rpm label: 60 times too slow
    let dir = with_turn(|_| {}, scale(&[PROPELLER], 1.0 / 60.0));
    named_by_check_and_run(
        dir.path(),
        &[],
        &["rev/s (rps) read as rpm", "`unit = \"rps\"`"],
    );
}

#[test]
fn positions_in_km_and_a_time_in_minutes_are_named() {
    let dir = with_turn(|_| {}, scale(&[X, Y], 1e-3));
    named_by_check_and_run(
        dir.path(),
        &[],
        &[
            "kilometres read as metres",
            "`unit = \"km\"`",
            "column 'x' (2)",
        ],
    );
    let dir = with_turn(|_| {}, scale(&[TIME], 1.0 / 60.0));
    named_by_check_and_run(
        dir.path(),
        &[],
        &[
            "the time looks like minutes read as seconds",
            "unit = \"min\"",
        ],
    );
}

#[test]
fn swapped_u_and_v_are_named() {
    let dir = example_copy();
    named_by_check_and_run(
        dir.path(),
        &[
            "hekf.runs[0].columns.u=\"v\"",
            "hekf.runs[0].columns.v=\"u\"",
        ],
        &[
            "u and v look swapped",
            "exchange the columns of the u and v entries",
        ],
    );
}

#[test]
fn body_velocities_declared_earth_frame_are_named() {
    let dir = example_copy();
    named_by_check_and_run(
        dir.path(),
        &["hekf.runs[0].velocity_frame=\"earth\""],
        &[
            "the velocity columns hold body velocities",
            "velocity_frame = \"earth\"",
        ],
    );
}

#[test]
fn warnings_are_printed_by_check_when_checks_only_warn() {
    let dir = example_copy();
    let set = [
        "hekf.runs[0].columns.rudder={column=\"rudder\",scale=-1}",
        "hekf.checks=\"warn\"",
    ];
    let o = hydroid_in(dir.path(), &args("check", &set));
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(out.contains("warnings:"), "{out}");
    assert!(
        out.contains("turns the other way from the mmg3 model"),
        "{out}"
    );
    let mut json_args = args("check", &set);
    json_args.push("--json");
    let o = hydroid_in(dir.path(), &json_args);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w = v["warnings"].as_array().unwrap();
    assert!(
        w.iter().any(|w| w["run"] == "35 deg starboard turn"
            && w["meaning"].as_str().unwrap().contains("`scale = -1`")),
        "{w:?}"
    );
}

#[test]
fn other_models_judge_the_rudder_sign_alike() {
    // the NPS AUV II (a positive rudder turns it to port) and Nomoto's ship (K > 0, only a
    // heading in waves: the yaw rate is the heading's smoothed derivative)
    for (config, key, column) in [
        ("configs/npsauv.toml", "hekf.validation[0]", "Rudder"),
        ("configs/nomoto.toml", "hekf.runs[0]", "rudder"),
    ] {
        let dir = example_copy();
        let set = format!("{key}.columns.rudder={{column=\"{column}\",scale=-1}}");
        let o = hydroid_in(dir.path(), &["check", config, "--set", &set]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{config}: {e}");
        assert!(e.contains("turns the other way from the"), "{config}: {e}");
    }
}
