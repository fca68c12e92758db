//! The autopilot's recorded sea (`autopilot.disturbance_file`): a recording in degrees read
//! as radians, a unit of another quantity, a magnitude no sea gives; each refused naming the
//! file, the column, the unit it was read in and the fix, before anything runs (a yaw moment,
//! which needs the plant to be judged, stops the autopilot with the cause).

use super::{autopilot, autopilot_case, write};
use crate::hostile::{refused, run_table, warned, Case, Expect};

/// A recording of 0 to 200 s every 0.5 s: `header`, then `time, value(t)` rows.
fn recording(header: &str, value: impl Fn(f64) -> f64) -> String {
    let mut s = format!("{header}\n");
    for i in 0..=400 {
        let t = i as f64 * 0.5;
        s += &format!("{t},{}\n", value(t));
    }
    s
}

/// A wave yaw of amplitude `a` at 8 s.
fn waves(a: f64) -> impl Fn(f64) -> f64 {
    move |t| a * (2.0 * std::f64::consts::PI * t / 8.0).sin()
}

/// The run with `extra` in `[autopilot]` naming cfd_exports/sea.csv, which holds `file`.
fn sea(name: &str, extra: &str, file: String, expect: Expect) -> Case {
    let extra = format!("disturbance_file = \"../cfd_exports/sea.csv\"\n{extra}");
    Case::new(name, "run configs/ap.toml --out out/ap", expect).setup(move |d| {
        autopilot(d, &extra);
        write(d, "cfd_exports/sea.csv", &file);
    })
}

/// The fix a recording in degrees read as radians is told.
const DEG_HINT: &str = "disturbance_unit = \"deg\"";

/// Refused before anything runs: a wave yaw's magnitude and the units of its header.
fn wave_yaw_refusals() -> Vec<Case> {
    vec![
        sea(
            "degrees read as radians",
            "",
            recording("t,psi", waves(1.5)),
            refused(&[
                "sea.csv",
                "wave_yaw column `psi`",
                "read in rad",
                "1.059 rad (60.70 deg)",
                DEG_HINT,
            ]),
        ),
        sea(
            "100 rad RMS",
            "",
            recording("t,psi", waves(141.0)),
            refused(&[
                "sea.csv",
                "RMS of 99.58 rad",
                "implausible for a heading disturbance",
            ]),
        ),
        sea(
            "100 deg RMS in deg",
            "disturbance_unit = \"deg\"",
            recording("t,psi", waves(141.0)),
            refused(&["read in deg", "implausible"]),
        ),
        sea(
            "header deg, 100 deg",
            "",
            recording("t,psi [deg]", waves(141.0)),
            refused(&["read in deg (its header)", "implausible"]),
        ),
        sea(
            "header in m/s",
            "",
            recording("t,psi [m/s]", waves(0.01)),
            refused(&["`psi` is in m/s", "not an angle"]),
        ),
        sea(
            "header in N",
            "",
            recording("t,psi [N]", waves(0.01)),
            refused(&["`psi` is in N", "not an angle"]),
        ),
        sea(
            "header in N m",
            "",
            recording("t,psi [N m]", waves(0.01)),
            refused(&["`psi` is in N m", "not an angle"]),
        ),
        sea(
            "time in m/s",
            "",
            recording("t [m/s],psi", waves(0.01)),
            refused(&["time column `t`", "not a time"]),
        ),
        sea(
            "time in ms",
            "",
            recording("t [ms],psi", waves(0.01)),
            refused(&["sea.csv", "covers"]),
        ),
    ]
}

/// Refused before anything runs: a rudder disturbance or a yaw moment in the wrong unit.
fn rudder_and_moment_refusals() -> Vec<Case> {
    vec![
        sea(
            "rudder in degrees read as radians",
            "disturbance = \"rudder\"",
            recording("t,delta", |_| 2.0),
            refused(&["rudder column `delta`", "rudder_limit", DEG_HINT]),
        ),
        sea(
            "rudder peak beyond 90 deg",
            "disturbance = \"rudder\"",
            recording("t,delta", |t| if t == 100.0 { 2.0 } else { 0.0 }),
            refused(&["rudder column", "peak"]),
        ),
        sea(
            "rudder in m/s",
            "disturbance = \"rudder\"",
            recording("t,delta [m/s]", |_| 0.01),
            refused(&["`delta` is in m/s", "a rudder angle"]),
        ),
        sea(
            "yaw moment in deg",
            "disturbance = \"yaw_moment\"",
            recording("t,N [deg]", |_| 1.0),
            refused(&["`N` is in deg", "a yaw moment"]),
        ),
        sea(
            "yaw moment with a deg unit key",
            "disturbance = \"yaw_moment\"\ndisturbance_unit = \"deg\"",
            recording("t,N", |_| 1.0),
            refused(&["autopilot.disturbance_unit"]),
        ),
    ]
}

/// Refused before anything runs: the file itself (its values, times, columns, keys, path).
fn file_refusals() -> Vec<Case> {
    vec![
        sea(
            "a value nan",
            "",
            recording("t,psi", |t| if t == 50.0 { f64::NAN } else { 0.01 }),
            refused(&["sea.csv"]),
        ),
        sea(
            "times decreasing",
            "",
            "t,psi\n0,0\n100,0\n50,0\n200,0\n".into(),
            refused(&["sea.csv", "increasing"]),
        ),
        sea(
            "too short",
            "",
            "t,psi\n0,0\n100,0\n".into(),
            refused(&["sea.csv", "covers 0 to 100 s"]),
        ),
        sea(
            "three columns",
            "",
            "t,a,b\n0,0,0\n200,0,0\n".into(),
            refused(&["3 columns", "autopilot.disturbance_columns"]),
        ),
        sea(
            "column named wrong",
            "[autopilot.disturbance_columns]\ntime = \"t\"\ndisturbance = \"yaw\"",
            recording("t,psi", waves(0.01)),
            refused(&[
                "no column `yaw`",
                "autopilot.disturbance_columns.disturbance",
            ]),
        ),
        sea(
            "unit key unknown",
            "disturbance_unit = \"grad\"",
            recording("t,psi", waves(0.01)),
            refused(&["autopilot.disturbance_unit"]),
        ),
        sea(
            "kind unknown",
            "disturbance = \"wave_pitch\"",
            recording("t,psi", waves(0.01)),
            refused(&["autopilot.disturbance"]),
        ),
        autopilot_case(
            "file missing",
            "disturbance_file = \"../cfd_exports/nope.csv\"",
            refused(&["nope.csv"]),
        ),
        autopilot_case(
            "file a folder",
            "disturbance_file = \"../cfd_exports\"",
            refused(&["cfd_exports"]),
        ),
    ]
}

/// What runs: a wave yaw in degrees said so, and a yaw moment no rudder holds (which stops
/// the autopilot with the cause).
fn runs() -> Vec<Case> {
    vec![
        sea(
            "degrees said so",
            "disturbance_unit = \"deg\"",
            recording("t,psi", waves(1.5)),
            warned(&["true low-frequency heading: heading error RMS"]),
        ),
        sea(
            "degrees in the header",
            "",
            recording("t,psi [deg]", waves(1.5)),
            warned(&["true low-frequency heading: heading error RMS"]),
        ),
        sea(
            "yaw moment no rudder holds",
            "disturbance = \"yaw_moment\"",
            recording("t,N", |_| 1e15),
            warned(&[
                "the autopilot was not run",
                "recorded yaw moment",
                "autopilot.rudder_limit",
                "autopilot.yaw_inertia",
            ]),
        ),
    ]
}

#[test]
fn recorded_seas_are_plausible_or_refused() {
    let mut cases = wave_yaw_refusals();
    cases.extend(rudder_and_moment_refusals());
    cases.extend(file_refusals());
    cases.extend(runs());
    let n = run_table("limits (seas)", cases);
    assert!(n >= 25, "{n} cases");
}
