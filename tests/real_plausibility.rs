//! The plausibility checks on real basin logs: the KVLCC2 free-running tests of MARIN (full
//! scale, read at model scale) and HSVA (model scale), read from ../shared/data/real (their
//! licence is not stated: they are never copied into the repository). Each configuration is
//! written as a user writes it from docs/config.md ("Free-running model-test logs"), for the
//! 7 m model of configs/ship_kvlcc2.toml; the correct mapping gives no plausibility finding,
//! and each mistake a user makes with these logs is named by `hydroid check`.
//!
//!   cargo test --test suite -- --ignored --nocapture real_plausibility::

use crate::common;

use common::{root, text};
use std::path::PathBuf;
use std::process::{Command, Output};

/// The folder of the real logs: `HYDROID_REAL_DATA`, else ../shared/data/real.
fn data() -> PathBuf {
    let dir = std::env::var_os("HYDROID_REAL_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("../shared/data/real"));
    assert!(
        dir.join("marin").is_dir() && dir.join("hsva").is_dir(),
        "the real KVLCC2 logs are not at {} (set HYDROID_REAL_DATA to the folder holding \
         marin/ and hsva/)",
        dir.display()
    );
    dir
}

/// The vehicle, its particulars and the published coefficients of configs/ship_kvlcc2.toml
/// (everything above its `[output]`), with the HEKF of the MMG model over one run.
fn config(run: &str) -> String {
    let bundled = std::fs::read_to_string(root().join("configs/ship_kvlcc2.toml")).unwrap();
    let head = &bundled[..bundled.find("[output]").expect("an [output] section")];
    format!("{head}\n[hekf]\nmodel = \"mmg3\"\nestimate = [\"Nv_p\", \"Nr_p\"]\n\n{run}",)
}

/// A MARIN log: three title lines, tab-separated columns without a header, full scale (L =
/// 320 m) read at the scale of the 7 m model, earth-frame u and v with body rates, angles in
/// degrees, rates in deg/s, the propeller in rpm, the rudder positive to port.
fn marin(file: &str) -> String {
    let path = data().join("marin").join(file);
    format!(
        r#"[[hekf.runs]]
name = "{file}"
file = "{}"
skip_lines = 3
names = ["time", "x0", "y0", "phi", "psi", "u", "v", "p", "r", "delta", "rev"]
velocity_frame = "earth"
rate_frame = "body"
froude = {{ lambda = 45.7, to = "model" }}
[hekf.runs.columns]
time = {{ column = "time", unit = "s" }}
x = {{ column = "x0", unit = "m" }}
y = {{ column = "y0", unit = "m" }}
roll = {{ column = "phi", unit = "deg" }}
yaw = {{ column = "psi", unit = "deg" }}
u = {{ column = "u", unit = "m/s" }}
v = {{ column = "v", unit = "m/s" }}
p = {{ column = "p", unit = "deg/s" }}
r = {{ column = "r", unit = "deg/s" }}
rudder = {{ column = "delta", unit = "deg", scale = -1 }}
rpm = {{ column = "rev", unit = "rpm" }}
"#,
        path.display()
    )
}

/// An HSVA log: four title lines (cp1252), fixed-width columns without a header, model
/// scale, earth-frame u and v, the yaw rate in deg/s in column 7 (column 8 is not the yaw
/// rate), the rudder positive to port, the propeller in rps.
fn hsva(file: &str) -> String {
    let path = data().join("hsva").join(file);
    format!(
        r#"[[hekf.runs]]
name = "{file}"
file = "{}"
skip_lines = 4
names = ["time", "x0", "y0", "psi", "u", "v", "r", "col8", "delta", "rev", "thrust", "torque"]
velocity_frame = "earth"
rate_frame = "body"
[hekf.runs.columns]
time = {{ column = "time", unit = "s" }}
x = {{ column = "x0", unit = "m" }}
y = {{ column = "y0", unit = "m" }}
yaw = {{ column = "psi", unit = "deg" }}
u = {{ column = "u", unit = "m/s" }}
v = {{ column = "v", unit = "m/s" }}
r = {{ column = "r", unit = "deg/s" }}
rudder = {{ column = "delta", unit = "deg", scale = -1 }}
rpm = {{ column = "rev", unit = "rps" }}
"#,
        path.display()
    )
}

const MARIN: [&str; 3] = [
    "MARIN_FREE_KVLCC2_tc_35_m.dat",
    "MARIN_FREE_KVLCC2_tc_-35_m.dat",
    "MARIN_FREE_KVLCC2_zz_20_m.dat",
];
const HSVA: [&str; 3] = [
    "HSVA_CPMC_KVLCC2_Z_10_10_P.dat",
    "HSVA_CPMC_KVLCC2_Z_20_10_P.dat",
    "HSVA_CPMC_KVLCC2_Z_20_10_S.dat",
];

/// `hydroid check` of a configuration written to a temporary folder.
fn check(config: &str) -> Output {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("real.toml");
    std::fs::write(&path, config).unwrap();
    Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(["check", path.to_str().unwrap()])
        .output()
        .expect("the hydroid binary runs")
}

/// `run` with `from` replaced by `to` (which must occur), checked: a configuration error
/// (exit code 2) whose message holds every one of `says`.
fn named_in_check(run: &str, from: &str, to: &str, says: &[&str]) {
    assert!(run.contains(from), "{from} is not in\n{run}");
    let o = check(&config(&run.replace(from, to)));
    let e = text(&o.stderr);
    eprintln!("--- {from} -> {to}\n{e}");
    assert_eq!(o.status.code(), Some(2), "{to}: {e}\n{}", text(&o.stdout));
    for s in says {
        assert!(e.contains(s), "{to}: expected '{s}' in\n{e}");
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn the_correct_mapping_of_every_log_has_no_plausibility_finding() {
    for run in MARIN.map(marin).into_iter().chain(HSVA.map(hsva)) {
        let o = check(&config(&run));
        let (out, err) = (text(&o.stdout), text(&o.stderr));
        assert_eq!(o.status.code(), Some(0), "{run}\n{out}\n{err}");
        assert!(!out.contains("warnings:"), "{run}\n{out}");
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn hsva_column_8_is_not_the_yaw_rate() {
    for file in HSVA {
        named_in_check(
            &hsva(file),
            r#"r = { column = "r", unit = "deg/s" }"#,
            r#"r = { column = "col8", unit = "deg/s" }"#,
            &["is not the yaw rate", "column 'col8' (8)", file],
        );
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn a_rudder_positive_to_port_without_the_sign_flip_is_named() {
    for run in MARIN.map(marin).into_iter().chain(HSVA.map(hsva)) {
        named_in_check(
            &run,
            r#"rudder = { column = "delta", unit = "deg", scale = -1 }"#,
            r#"rudder = { column = "delta", unit = "deg" }"#,
            &[
                "turns the other way from the mmg3 model",
                "`scale = -1`",
                "column 'delta'",
            ],
        );
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn a_rudder_in_degrees_labelled_radians_is_named() {
    for run in MARIN.map(marin).into_iter().chain(HSVA.map(hsva)) {
        named_in_check(
            &run,
            r#"rudder = { column = "delta", unit = "deg", scale = -1 }"#,
            r#"rudder = { column = "delta", unit = "rad", scale = -1 }"#,
            &["degrees read as radians", "`unit = \"deg\"`"],
        );
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn marin_rpm_read_as_rps_is_named() {
    for file in MARIN {
        named_in_check(
            &marin(file),
            r#"rpm = { column = "rev", unit = "rpm" }"#,
            r#"rpm = { column = "rev", unit = "rps" }"#,
            &["rpm read as rev/s", "advance ratio", "`unit = \"rpm\"`"],
        );
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn positions_under_the_wrong_length_unit_are_named() {
    for run in MARIN.map(marin).into_iter().chain(HSVA.map(hsva)) {
        let km = run
            .replace(
                r#"x = { column = "x0", unit = "m" }"#,
                r#"x = { column = "x0", unit = "km" }"#,
            )
            .replace(
                r#"y = { column = "y0", unit = "m" }"#,
                r#"y = { column = "y0", unit = "km" }"#,
            );
        let o = check(&config(&km));
        let e = text(&o.stderr);
        eprintln!("--- km\n{e}");
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains("metres read as kilometres"), "{e}");
        assert!(e.contains("`unit = \"m\"`"), "{e}");
    }
}

#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn swapped_u_and_v_are_named() {
    for run in MARIN.map(marin).into_iter().chain(HSVA.map(hsva)) {
        named_in_check(
            &run,
            "u = { column = \"u\", unit = \"m/s\" }\nv = { column = \"v\", unit = \"m/s\" }",
            "u = { column = \"v\", unit = \"m/s\" }\nv = { column = \"u\", unit = \"m/s\" }",
            &["u and v look swapped"],
        );
    }
}

/// A full-scale MARIN log without its Froude scaling is a full-scale test for the model (not
/// "rev/s read as rpm": that advice leaves the speeds at full scale), also after the rpm
/// column was read as rev/s.
#[test]
#[ignore = "reads ../shared/data/real; run by .ci/run"]
fn marin_without_its_froude_scaling_is_named_a_full_scale_log() {
    let scaling = "froude = { lambda = 45.7, to = \"model\" }\n";
    // the Froude number over the model's and the scale the speeds give (docs/hekf.md: 7.2
    // to 7.4, 52 to 54 for the true 45.7)
    let found = [("7.247", 53), ("7.220", 52), ("7.365", 54)];
    for (file, (ratio, lambda)) in MARIN.into_iter().zip(found) {
        let scale = format!("froude = {{ lambda = {lambda}, to = \"model\" }}");
        let times = format!("{ratio} times that of the model's example (0.1329)");
        let says = [
            "full-scale test read for the model-scale vehicle",
            &scale,
            &times,
        ];
        named_in_check(&marin(file), scaling, "", &says);
        let rps = marin(file).replace(
            r#"rpm = { column = "rev", unit = "rpm" }"#,
            r#"rpm = { column = "rev", unit = "rps" }"#,
        );
        named_in_check(&rps, scaling, "", &says);
    }
}
