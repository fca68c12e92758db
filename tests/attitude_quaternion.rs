//! 6-DOF exports that give the attitude as a quaternion (scalar first), as solvers that track
//! the orientation as a quaternion write it: read into roll, pitch and yaw, checked against
//! nalgebra's own Euler-angle conversion, with earth-frame velocities rotated through them.

use hydroid::base::quantity::Quantity;
use hydroid::config::InputSpec;
use hydroid::io::record::{self, Needs, Record};
use nalgebra::{UnitQuaternion, Vector3};
use std::f64::consts::PI;
use std::fmt::Write as _;

const NEEDS: Needs = Needs {
    required: &[Quantity::Time, Quantity::Yaw],
    optional: &[
        Quantity::Roll,
        Quantity::Pitch,
        Quantity::U,
        Quantity::V,
        Quantity::W,
    ],
    min_rows: 2,
};

/// A slow roll and pitch oscillation while the heading turns through more than a full circle.
fn attitude(t: f64) -> (f64, f64, f64) {
    (0.3 * (0.5 * t).sin(), -0.2 * (0.3 * t).cos(), -PI + 0.9 * t)
}

/// Body velocity of the run.
const BODY: [f64; 3] = [2.0, 0.3, -0.1];

/// A STAR-CCM+ table: time, the quaternion (nalgebra's, from the Euler angles), and the
/// velocity in the earth frame.
fn table(corrupt_row: Option<usize>) -> String {
    let mut s = String::from(
        "\"Time (s)\",\"Qw\",\"Qx\",\"Qy\",\"Qz\",\"Vx (m/s)\",\"Vy (m/s)\",\"Vz (m/s)\"\n",
    );
    for k in 0..80 {
        let t = 0.1 * k as f64;
        let (phi, th, psi) = attitude(t);
        let q = UnitQuaternion::from_euler_angles(phi, th, psi);
        let e = q * Vector3::new(BODY[0], BODY[1], BODY[2]);
        let mut w = q.w;
        if corrupt_row == Some(k) {
            w *= 1.1;
        }
        writeln!(
            s,
            "{t},{w},{},{},{},{},{},{}",
            q.i, q.j, q.k, e[0], e[1], e[2]
        )
        .unwrap();
    }
    s
}

const SPEC: &str = r#"
file = "quat.csv"
velocity_frame = "earth"
[columns]
time = { column = "Time" }
quat_w = { column = "Qw", unit = "-" }
quat_x = { column = "Qx", unit = "-" }
quat_y = { column = "Qy", unit = "-" }
quat_z = { column = "Qz", unit = "-" }
u = { column = "Vx" }
v = { column = "Vy" }
w = { column = "Vz" }
"#;

fn load(text: &str, spec_text: &str) -> Result<Record, String> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quat.csv"), text).unwrap();
    let spec: InputSpec = toml::from_str(spec_text).unwrap();
    record::load(&spec, dir.path(), &NEEDS).map_err(|e| e.to_string())
}

#[test]
fn a_quaternion_attitude_reads_as_unwrapped_euler_angles() {
    let r = load(&table(None), SPEC).unwrap();
    let (roll, pitch, yaw) = (
        r.channel(Quantity::Roll).unwrap(),
        r.channel(Quantity::Pitch).unwrap(),
        r.channel(Quantity::Yaw).unwrap(),
    );
    let mut max_err: f64 = 0.0;
    for (k, t) in r.time().unwrap().iter().enumerate() {
        let (phi, th, psi) = attitude(*t);
        // the heading starts at -180 deg: the read one may start at +180 and stay 2 pi
        // away, but must be continuous
        let dpsi = (yaw[k] - psi) - 2.0 * PI * ((yaw[k] - psi) / (2.0 * PI)).round();
        max_err = max_err
            .max((roll[k] - phi).abs())
            .max((pitch[k] - th).abs())
            .max(dpsi.abs());
    }
    assert!(max_err < 1e-9, "largest angle error {max_err}");
    assert!(
        yaw.windows(2).all(|w| (w[1] - w[0]).abs() < 0.2),
        "yaw is unwrapped through +-180 deg"
    );
    assert!(
        (yaw.last().unwrap() - yaw[0] - 0.9 * 7.9).abs() < 1e-9,
        "a turn of 7.1 rad"
    );
    // the earth-frame velocity is rotated back to the body frame through those angles
    for (q, want) in [
        (Quantity::U, BODY[0]),
        (Quantity::V, BODY[1]),
        (Quantity::W, BODY[2]),
    ] {
        let v = r.channel(q).unwrap();
        assert!(v.iter().all(|x| (x - want).abs() < 1e-9), "{q}: {v:?}");
    }
}

#[test]
fn a_quaternion_that_is_not_a_rotation_names_its_line() {
    let e = load(&table(Some(12)), SPEC).unwrap_err();
    // header on line 1, row 12 (from 0) on line 14
    assert!(e.contains("quat.csv:14:"), "{e}");
    assert!(e.contains("norm"), "{e}");
}

#[test]
fn a_partial_quaternion_or_both_attitudes_is_refused() {
    let partial = SPEC.replace("quat_z = { column = \"Qz\", unit = \"-\" }\n", "");
    let e = load(&table(None), &partial).unwrap_err();
    assert!(e.contains("missing: quat_z"), "{e}");
    let both = format!("{SPEC}yaw = {{ column = \"Qz\", unit = \"rad\" }}\n");
    let e = load(&table(None), &both).unwrap_err();
    assert!(
        e.contains("both as a column and through the attitude quaternion"),
        "{e}"
    );
}

use crate::common;

/// A 6-DOF spheroid run (roll, pitch and a turn through 180 deg) written by `hydroid simulate` as a
/// STAR-CCM+ table with both the Euler angles and the quaternion.
const SIMULATION: &str = r#"
title = "quaternion export"
model = "spheroid6"
[vehicle]
mass = 50.0
length = 1.2
diameter = 0.2
ixx = 0.2
iyy = 3.7
izz = 3.7
reference_area = 0.0314159265
reference_length = 1.0
bg = 0.01
[fluid]
rho = 1025.0
mu = 0.0009
[coefficients]
Xud = -1.164
Yvd = -23.626
Nrd = -1.4532
Kpd = -0.01
Xuu = -1.33
Yuvl = -16.31
Nuvl = 13.43
Nrr = -5.0
Kpp = -0.05
Yrd = 0.0
Xuv = 0.44
Xvv = -5.38
Yvv = -0.44
Yrr = 0.5
Yuvd = 1.33
Nvv = 10.0
[manoeuvre]
kind = "time_history"
duration = 20.0
dt = 0.1
initial = { u = 2.0, v = 0.3, w = -0.2, p = 0.3, q = 0.1, r = 0.5, yaw = 3.0 }
inputs = { thrust = "15 N" }
[export]
file = "sixdof.csv"
layout = "starccm"
digits = 12
columns = [
  { quantity = "time", name = "Time", unit = "s" },
  { quantity = "roll", name = "Roll", unit = "deg" },
  { quantity = "pitch", name = "Pitch", unit = "deg" },
  { quantity = "yaw", name = "Yaw", unit = "deg" },
  { quantity = "quat_w", name = "Orientation W", unit = "-" },
  { quantity = "quat_x", name = "Orientation X", unit = "-" },
  { quantity = "quat_y", name = "Orientation Y", unit = "-" },
  { quantity = "quat_z", name = "Orientation Z", unit = "-" },
]
"#;

#[test]
fn simulate_writes_a_quaternion_that_reads_back_as_its_euler_angles() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sim.toml"), SIMULATION).unwrap();
    let out = common::hydroid_in(dir.path(), &["simulate", "sim.toml"]);
    assert!(out.status.success(), "{}", common::text(&out.stderr));
    let read = |map: &str| -> Record {
        let spec: InputSpec = toml::from_str(&format!(
            "file = \"sixdof.csv\"\n[columns]\ntime = {{ column = \"Time\" }}\n{map}"
        ))
        .unwrap();
        record::load(&spec, dir.path(), &NEEDS).unwrap()
    };
    let euler = read(
        "roll = { column = \"Roll\" }\npitch = { column = \"Pitch\" }\nyaw = { column = \"Yaw\" }",
    );
    let quat = read(
        "quat_w = { column = \"Orientation W\" }\nquat_x = { column = \"Orientation X\" }\n\
         quat_y = { column = \"Orientation Y\" }\nquat_z = { column = \"Orientation Z\" }",
    );
    let yaw = euler.channel(Quantity::Yaw).unwrap();
    assert!(
        yaw[0] < PI && *yaw.last().unwrap() > PI + 0.5,
        "the run turns through 180 deg: {} .. {}",
        yaw[0],
        yaw.last().unwrap()
    );
    assert!(euler
        .channel(Quantity::Roll)
        .unwrap()
        .iter()
        .any(|v| v.abs() > 0.05));
    for q in [Quantity::Roll, Quantity::Pitch, Quantity::Yaw] {
        let (a, b) = (euler.channel(q).unwrap(), quat.channel(q).unwrap());
        let worst = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-8, "{q}: worst difference {worst} rad");
    }
}
