//! Free-running manoeuvring logs as model basins and CFD free-running runs write them
//! (tests/fixtures/freerunning/): title lines, headerless whitespace or tab columns, degrees,
//! rpm, repeated time stamps of each kind, earth-frame velocities, Froude scaling.

use hydroid::base::quantity::Quantity;
use hydroid::config::InputSpec;
use hydroid::io::record::{self, Needs, Record};
use std::path::Path;

fn base() -> &'static Path {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/freerunning"
    ))
}

const MOTION: Needs = Needs {
    required: &[Quantity::Time, Quantity::Yaw],
    optional: &[
        Quantity::X,
        Quantity::Y,
        Quantity::U,
        Quantity::V,
        Quantity::R,
        Quantity::Rudder,
        Quantity::Rpm,
    ],
    min_rows: 2,
};

fn spec(toml_text: &str) -> InputSpec {
    toml::from_str(toml_text).unwrap_or_else(|e| panic!("{e}\n{toml_text}"))
}

fn load(toml_text: &str, needs: &Needs) -> Result<Record, String> {
    record::load(&spec(toml_text), base(), needs).map_err(|e| e.to_string())
}

/// The MARIN layout, as a user writes it from docs/config.md.
const MARIN: &str = r#"
file = "marin_turn_3digits.dat"
skip_lines = 3
names = ["time", "x0", "y0", "phi", "psi", "dxdt", "dydt", "p", "r", "delta", "rev"]
velocity_frame = "earth"
rate_frame = "body"
[columns]
time = { column = "time", unit = "s" }
x = { column = "x0", unit = "m" }
y = { column = "y0", unit = "m" }
roll = { column = "phi", unit = "deg" }
yaw = { column = "psi", unit = "deg" }
u = { column = "dxdt", unit = "m/s" }
v = { column = "dydt", unit = "m/s" }
r = { column = "r", unit = "deg/s" }
rudder = { column = "delta", unit = "deg" }
rpm = { column = "rev", unit = "rpm" }
"#;

#[test]
fn marin_turn_reads_to_si_with_its_time_base_rebuilt() {
    let r = load(MARIN, &MOTION).unwrap();
    assert_eq!(r.rows(), 800);
    assert_eq!(r.lines[0], 4, "data start after the three skipped lines");
    let t = r.time().unwrap();
    // printed with three significant digits: rebuilt on the 0.1353 s sampling
    assert!((t[799] - 799.0 * 0.1353).abs() < 0.05, "{}", t[799]);
    assert!(t.windows(2).all(|w| w[1] > w[0]));
    assert!(
        r.warnings.iter().any(|w| w.contains("too few digits")),
        "{:?}",
        r.warnings
    );
    // degrees, rpm, earth-frame velocities rotated by the heading into u and v
    let rudder = r.channel(Quantity::Rudder).unwrap();
    assert!((rudder[799] - 35f64.to_radians()).abs() < 1e-12);
    let rpm = r.channel(Quantity::Rpm).unwrap();
    assert!((rpm[0] - 91.7 / 60.0).abs() < 1e-12, "rev/s");
    let (u, v) = (
        r.channel(Quantity::U).unwrap(),
        r.channel(Quantity::V).unwrap(),
    );
    for i in [0, 400, 799] {
        assert!(
            (u[i] - 7.93).abs() < 0.02 && v[i].abs() < 0.02,
            "{i}: {} {}",
            u[i],
            v[i]
        );
    }
    let rate = r.channel(Quantity::R).unwrap();
    assert!(
        (rate[799] + 0.3f64.to_radians()).abs() < 1e-12,
        "a body rate, not rotated"
    );
    assert!(r
        .meta
        .iter()
        .any(|(k, v)| k == "title" && v.contains("KVLCC2")));
}

/// Without `skip_lines` the title lines are found too (they open with words).
#[test]
fn marin_titles_are_detected_without_skip_lines() {
    let text = MARIN.replace("skip_lines = 3\n", "");
    let r = load(&text, &MOTION).unwrap();
    assert_eq!((r.rows(), r.lines[0]), (800, 4));
}

const HSVA: &str = r#"
file = "hsva_zigzag_model_scale.dat"
skip_lines = 4
names = ["time", "x0", "y0", "psi", "u", "v", "p", "r", "delta", "rev", "thrust", "torque"]
[columns]
rudder = { column = "delta", unit = "deg", scale = -1 }   # positive to port in this log
rpm = { column = "rev", unit = "Hz" }
time = { column = "time", unit = "s" }
yaw = { column = "psi", unit = "deg" }
u = { column = "u", unit = "m/s" }
v = { column = "v", unit = "m/s" }
r = { column = "r", unit = "deg/s" }
"#;

#[test]
fn hsva_zigzag_drops_identical_rows_and_flips_the_rudder() {
    let r = load(HSVA, &MOTION).unwrap();
    assert_eq!(r.rows(), 120, "three rows written twice are dropped");
    let w: Vec<&String> = r
        .warnings
        .iter()
        .filter(|w| w.contains("exactly"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", r.warnings);
    assert!(w[0].starts_with("3 rows repeat"), "{}", w[0]);
    let t = r.time().unwrap();
    assert!((t[119] - 119.0 * 0.05).abs() < 1e-9);
    let rudder = r.channel(Quantity::Rudder).unwrap();
    assert!((rudder[119] + 10f64.to_radians()).abs() < 1e-12);
    assert!((r.channel(Quantity::Rpm).unwrap()[0] - 10.2295).abs() < 1e-12);
    assert!(r.meta.iter().any(|(_, v)| v.contains("Z10\u{b0}/10\u{b0}")));
}

#[test]
fn froude_scaling_to_full_scale() {
    let scaled = format!("froude = {{ lambda = 45.7, to = \"full\" }}\n{HSVA}");
    let model = load(HSVA, &MOTION).unwrap();
    let full = load(&scaled, &MOTION).unwrap();
    let s = 45.7f64.sqrt();
    let at = |r: &Record, q, i: usize| r.channel(q).unwrap()[i];
    assert!((at(&full, Quantity::Time, 119) - s * at(&model, Quantity::Time, 119)).abs() < 1e-9);
    assert!((at(&full, Quantity::U, 5) - s * at(&model, Quantity::U, 5)).abs() < 1e-9);
    assert!((at(&full, Quantity::R, 100) - at(&model, Quantity::R, 100) / s).abs() < 1e-12);
    assert!((at(&full, Quantity::Rpm, 0) - at(&model, Quantity::Rpm, 0) / s).abs() < 1e-12);
    assert_eq!(
        at(&full, Quantity::Rudder, 119),
        at(&model, Quantity::Rudder, 119)
    );
    assert!(full
        .warnings
        .iter()
        .any(|w| w.contains("Froude-scaled from model scale")));
}

#[test]
fn position_and_heading_only_is_usable() {
    let text = r#"
file = "marin_turn_3digits.dat"
names = ["time", "x0", "y0", "phi", "psi", "dxdt", "dydt", "roll rate", "yaw rate", "delta", "rev"]
[columns]
time = { column = "time", unit = "s" }
x = { column = "x0", unit = "m" }
y = { column = "y0", unit = "m" }
yaw = { column = "psi", unit = "deg" }
"#;
    let r = load(text, &MOTION).unwrap();
    assert!(r.has(Quantity::X) && r.has(Quantity::Yaw));
    assert!(
        !r.has(Quantity::U) && !r.has(Quantity::R),
        "velocities are not measured"
    );
}

#[test]
fn a_required_rudder_column_that_is_missing_names_the_file() {
    let needs = Needs {
        required: &[Quantity::Time, Quantity::Yaw, Quantity::Rudder],
        ..MOTION
    };
    let text = HSVA.replace(
        "rudder = { column = \"delta\", unit = \"deg\", scale = -1 }",
        "",
    );
    let e = load(&text, &needs).unwrap_err();
    assert!(
        e.contains("hsva_zigzag_model_scale.dat") && e.contains("no column for rudder"),
        "{e}"
    );
}

#[test]
fn an_rpm_in_a_unit_that_does_not_convert_names_file_column_and_unit() {
    let text = HSVA.replace("unit = \"Hz\"", "unit = \"m/s\"");
    let e = load(&text, &MOTION).unwrap_err();
    assert!(
        e.contains("hsva_zigzag_model_scale.dat")
            && e.contains("'rev'")
            && e.contains("'m/s'")
            && e.contains("does not fit rpm"),
        "{e}"
    );
    let mut p = hydroid::config::Problems::new(Path::new("run.toml"), &text);
    spec(&text).validate("hekf.runs[0]", &mut p);
    let m: Vec<&str> = p.list.iter().map(|c| c.message.as_str()).collect();
    assert!(
        m.iter().any(|m| m.contains("rpm") && m.contains("'m/s'")),
        "{m:?}"
    );
}

#[test]
fn repeated_stamps_that_are_neither_case_name_both_lines() {
    let text = r#"
file = "bad_repeated_stamps.dat"
names = ["time", "u", "rudder", "rev"]
[columns]
time = { column = "time", unit = "s" }
u = { column = "u", unit = "m/s" }
"#;
    let needs = Needs {
        required: &[Quantity::Time, Quantity::U],
        optional: &[],
        min_rows: 2,
    };
    let e = load(text, &needs).unwrap_err();
    assert!(
        e.contains("bad_repeated_stamps.dat:6") && e.contains("lines 5 and 6"),
        "{e}"
    );
}
