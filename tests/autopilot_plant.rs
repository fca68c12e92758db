//! Plants of the autopilot (issue 29, item 3): the autopilot tuned and filtered on a Nomoto
//! model closes its loop around another registered model, here the course-stable 150 m ship
//! of configs/vehicles/ship150_clarke.toml as a ship_linear model with its propeller held at
//! the 8 m/s balance, and around the same ship slowed to 5 m/s mid-run.
//!
//! The reference, written here from the equations alone: the linear sway-yaw model of the
//! ship at speed U (Fossen 2011, 7.1: v_dot = b1 v + (b2 + b4 U) r + b3 delta,
//! r_dot = c1 v + c2 r + c3 delta, the vehicle file's coefficients), its Nomoto indices
//! (Fossen 2011, 7.2: K = (a21 b_v - a11 b_r) / det A, T = T1 + T2 - T3), a PID placed on
//! them (K_p = m w_n^2, K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10, m = T/K, d = 1/K) with
//! anti-windup and a rate- and angle-limited rudder, a third-order reference model (a
//! first-order filter cascaded with a mass-damper-spring, Fossen 2011, 10.2.1), fed the true
//! heading, at 10 Hz with RK4 sub-steps.

mod common;

use common::root;
use hydroid::app::pipeline::autopilot::{load_plant, run, PlantSpec};
use hydroid::config::autopilot::AutopilotConfig;
use hydroid::dynamics::autopilot::seas::Seas;
use hydroid::dynamics::autopilot::{AutopilotResult, Feed};
use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source};
use hydroid::model::models::ModelName;
use std::f64::consts::PI;

/// The vehicle file's sway-yaw coefficients (configs/vehicles/ship150_clarke.toml).
const B: [f64; 4] = [-3.546341e-2, 2.216678, -6.357587e-2, -4.983084e-1];
const C: [f64; 3] = [-1.429146e-3, -1.162988e-1, 2.954610e-3];
const U0: f64 = 8.0;
const DT: f64 = 0.1;
const DURATION: f64 = 1200.0;
const OMEGA_N: f64 = 0.05;
const ZETA: f64 = 0.9;
const COURSE: f64 = 10.0 * PI / 180.0;
const CHANGE_AT: f64 = 50.0;
const REFERENCE: (f64, f64) = (0.03, 1.0);
const RATE_LIMIT: f64 = 2.32 * PI / 180.0;
const ANGLE_LIMIT: f64 = 35.0 * PI / 180.0;

/// The linear sway-yaw system at speed `u` with the coefficients scaled by `s` (U / U0):
/// each hydrodynamic derivative is proportional to U, the rudder's to U^2 (Fossen 2011, 7.1).
fn sway_yaw(u: f64, s: f64) -> ([[f64; 2]; 2], [f64; 2]) {
    (
        [[B[0] * s, B[1] * s + B[3] * u], [C[0] * s, C[1] * s]],
        [B[2] * s * s, C[2] * s * s],
    )
}

/// Nomoto's K and T of the sway-yaw system (Fossen 2011, 7.2).
fn nomoto((a, b): ([[f64; 2]; 2], [f64; 2])) -> (f64, f64) {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let k_num = a[1][0] * b[0] - a[0][0] * b[1];
    let t3 = b[1] / k_num;
    (k_num / det, -(a[0][0] + a[1][1]) / det - t3)
}

/// Heading error and rudder RMS of the loop around the sway-yaw ship `plant` fed its true
/// heading, the PID placed on (k, t).
fn reference_loop(plant: ([[f64; 2]; 2], [f64; 2]), (k, t): (f64, f64)) -> (f64, f64) {
    let (a, b) = plant;
    let (m, d) = (t / k, 1.0 / k);
    let kp = m * OMEGA_N * OMEGA_N;
    let kd = 2.0 * ZETA * OMEGA_N * m - d;
    let ki = OMEGA_N * kp / 10.0;
    let f = |x: [f64; 3], delta: f64| {
        [
            a[0][0] * x[0] + a[0][1] * x[1] + b[0] * delta,
            a[1][0] * x[0] + a[1][1] * x[1] + b[1] * delta,
            x[1],
        ]
    };
    let add =
        |x: [f64; 3], k: [f64; 3], h: f64| [x[0] + h * k[0], x[1] + h * k[1], x[2] + h * k[2]];
    let (mut x, mut rudder, mut integral) = ([0.0f64; 3], 0.0f64, 0.0f64);
    let (w, z) = REFERENCE;
    let (mut low, mut psi_d, mut r_d) = (0.0f64, 0.0f64, 0.0f64);
    let n = (DURATION / DT).round() as usize + 1;
    let (mut e2, mut d2) = (0.0, 0.0);
    for step in 0..n {
        let time = step as f64 * DT;
        if step > 0 {
            let h = DT / 4.0;
            for _ in 0..4 {
                let k1 = f(x, rudder);
                let k2 = f(add(x, k1, h / 2.0), rudder);
                let k3 = f(add(x, k2, h / 2.0), rudder);
                let k4 = f(add(x, k3, h), rudder);
                for i in 0..3 {
                    x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
            }
            let command = if time >= CHANGE_AT { COURSE } else { 0.0 };
            let h = DT / 50.0;
            for _ in 0..50 {
                let acc = w * w * (low - psi_d) - 2.0 * z * w * r_d;
                low += h * w * (command - low);
                psi_d += h * r_d;
                r_d += h * acc;
            }
        }
        let e = x[2] - psi_d;
        e2 += e * e;
        d2 += rudder * rudder;
        let wanted = -(kp * e + kd * (x[1] - r_d) + ki * integral);
        let held = wanted.clamp(-ANGLE_LIMIT, ANGLE_LIMIT);
        if held == wanted {
            integral += e * DT;
        }
        rudder += (held - rudder).clamp(-RATE_LIMIT * DT, RATE_LIMIT * DT);
    }
    ((e2 / n as f64).sqrt(), (d2 / n as f64).sqrt())
}

/// The `[autopilot]` section with the plant `plant` (TOML lines).
fn config(plant: &str) -> AutopilotConfig {
    toml::from_str(&format!(
        "omega_n = {OMEGA_N}\nzeta = {ZETA}\ncompass_noise = \"0.1 deg\"\nduration = {DURATION}\n\
         feeds = [\"true\"]\n[plant]\n{plant}"
    ))
    .unwrap()
}

/// hydroid's loop: the identified model of configs/nomoto.toml (nomoto_wave) with K and T
/// `(k, t)`, the plant of `cfg`.
fn hydroid_loop(cfg: &AutopilotConfig, (k, t): (f64, f64)) -> AutopilotResult {
    let loaded = hydroid::config::load(&root().join("configs/nomoto.toml"), &[]).unwrap();
    let plant: Option<PlantSpec> = load_plant(cfg, &loaded.config, &loaded.base_dir).unwrap();
    let mut set = CoefficientSet::new();
    for (n, v) in [
        ("K", k),
        ("inv_T", 1.0 / t),
        ("delta0", 0.0),
        ("w0", 0.785398),
        ("zeta_w", 0.1),
    ] {
        set.insert(Coefficient::new(n, v, None, Source::Config));
    }
    run(
        ModelName::NomotoWave,
        &loaded.vehicle,
        &set,
        loaded.config.hekf.as_ref().unwrap(),
        cfg,
        (&Seas::Generated, plant.as_ref()),
    )
    .unwrap()
}

const SHIP150: &str = "model = \"ship_linear\"\n\
    vehicle_file = \"vehicles/ship150_clarke.toml\"\n\
    inputs = { rpm = 1.80101 }\nspeed = \"8 m/s\"\n";

/// The 150 m ship at 8 m/s as the plant: hydroid's plant indices are the linearisation's
/// (K = 0.12265 1/s, T = 80.04 s, the vehicle file's numbers) and its loop, fed the true
/// heading, gives the reference's heading error and rudder within 1 %.
#[test]
fn the_150_m_ship_is_steered_as_its_sway_yaw_equations_say() {
    let plant = sway_yaw(U0, 1.0);
    let (k, t) = nomoto(plant);
    assert!(
        (k - 0.12265).abs() < 1e-4 && (t - 80.04).abs() < 0.01,
        "{k} {t}"
    );
    let r = hydroid_loop(&config(SHIP150), (k, t));
    let before = &r.plant.before;
    assert_eq!(r.plant.model, "ship_linear");
    assert!(
        (before.k / k - 1.0).abs() < 1e-4,
        "{} against {k}",
        before.k
    );
    assert!(
        (before.t / t - 1.0).abs() < 1e-4,
        "{} against {t}",
        before.t
    );
    let (e, d) = reference_loop(plant, (k, t));
    let l = r.feed(Feed::True).unwrap();
    println!(
        "hydroid: heading error {:.4} deg, rudder {:.4} deg; reference {:.4}, {:.4}",
        l.heading_error_rms.to_degrees(),
        l.rudder_rms.to_degrees(),
        e.to_degrees(),
        d.to_degrees()
    );
    assert!((l.heading_error_rms / e - 1.0).abs() < 0.01);
    assert!((l.rudder_rms / d - 1.0).abs() < 0.01);
}

/// The ship slowed to 5 m/s at 600 s (coefficients scaled with U, the propeller at the 5 m/s
/// balance): the plant's indices after the change are the reference's at 5 m/s (K scales
/// with U, T with 1/U), and the loop with the 8 m/s gains follows the reference's.
#[test]
fn a_plant_changed_mid_run_is_reported_and_steered_after_the_change() {
    let s = 5.0 / 8.0;
    let change = format!(
        "[plant.change]\nat = 600.0\nspeed = \"5 m/s\"\ninputs = {{ rpm = 1.32563 }}\n\
         coefficients = {{ b1 = {}, b2 = {}, b3 = {}, c1 = {}, c2 = {}, c3 = {} }}\n",
        B[0] * s,
        B[1] * s,
        B[2] * s * s,
        C[0] * s,
        C[1] * s,
        C[2] * s * s
    );
    let cfg = config(&format!("{SHIP150}{change}"));
    let (k, t) = nomoto(sway_yaw(U0, 1.0));
    let r = hydroid_loop(&cfg, (k, t));
    let after = r.plant.after.expect("indices after the change");
    let (k5, t5) = nomoto(sway_yaw(5.0, s));
    assert!((k5 / k - s).abs() < 1e-9 && (t5 * s / t - 1.0).abs() < 1e-9);
    assert!(
        (after.k / k5 - 1.0).abs() < 1e-4,
        "{} against {k5}",
        after.k
    );
    assert!(
        (after.t / t5 - 1.0).abs() < 1e-4,
        "{} against {t5}",
        after.t
    );
    assert_eq!(r.plant.change_at, Some(600.0));
    assert!(r.lines()[0].contains("from 600 s"), "{}", r.lines()[0]);
}

/// A plant that cannot be one is refused naming the key.
#[test]
fn a_bad_plant_is_refused_naming_the_key() {
    let problems = |plant: &str| {
        let mut p = hydroid::config::Problems::new(std::path::Path::new("c.toml"), "");
        config(plant).validate(&mut p);
        format!("{:?}", p.list)
    };
    let e = problems("model = \"shiplinear\"\n");
    assert!(
        e.contains("autopilot.plant.model") && e.contains("ship_linear"),
        "{e}"
    );
    let e = problems("model = \"ship_linear\"\ninputs = { rudder = 0.1 }\n");
    assert!(
        e.contains("autopilot.plant.inputs.rudder") && e.contains("rpm"),
        "{e}"
    );
    let e = problems("model = \"ship_linear\"\ncoefficients = { K = 0.1 }\n");
    assert!(e.contains("autopilot.plant.coefficients.K"), "{e}");
    let e = problems("model = \"surge1\"\n");
    assert!(e.contains("no rudder input"), "{e}");
    let e = problems("model = \"identified\"\nspeed = 3.0\n");
    assert!(e.contains("identified plant takes no"), "{e}");
    let e = problems("model = \"ship_linear\"\n[plant.change]\nat = 5000.0\n");
    assert!(e.contains("autopilot.plant.change.at"), "{e}");
}

/// A recorded yaw moment, in a file of three columns picked by `disturbance_columns`, enters
/// the plant as the rudder angle that makes it: a steady moment N on the first-order Nomoto
/// frigate (T r_dot + r = K delta + T N / I, Fossen 2011, 7.2) is held by the rudder
/// -N T / (I K), here -1 deg.
#[test]
fn a_recorded_yaw_moment_is_held_by_the_rudder_it_is_worth() {
    let (k, t, inertia) = (0.18, 27.0, 2.0e9);
    let moment = inertia * k / t * 1f64.to_radians();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("moment.csv");
    let mut text = String::from("t,junk,Mz\n");
    for i in 0..=120 {
        text += &format!("{},{},{moment}\n", i as f64 * 10.0, i);
    }
    std::fs::write(&file, text).unwrap();
    let cfg: AutopilotConfig = toml::from_str(&format!(
        "omega_n = {OMEGA_N}\nzeta = {ZETA}\ncompass_noise = \"0.1 deg\"\nduration = 1200.0\n\
         course_change = 0.0\nfeeds = [\"true\"]\ndisturbance_file = {file:?}\n\
         disturbance = \"yaw_moment\"\nyaw_inertia = {inertia}\n\
         [disturbance_columns]\ntime = \"t\"\ndisturbance = \"Mz\"\n"
    ))
    .unwrap();
    let seas = hydroid::app::pipeline::autopilot::load_seas(&cfg, dir.path()).unwrap();
    let loaded = hydroid::config::load(&root().join("configs/nomoto.toml"), &[]).unwrap();
    let mut set = CoefficientSet::new();
    for (n, v) in [
        ("K", k),
        ("inv_T", 1.0 / t),
        ("delta0", 0.0),
        ("w0", 0.785398),
        ("zeta_w", 0.1),
    ] {
        set.insert(Coefficient::new(n, v, None, Source::Config));
    }
    let r = run(
        ModelName::NomotoWave,
        &loaded.vehicle,
        &set,
        loaded.config.hekf.as_ref().unwrap(),
        &cfg,
        (&seas, None),
    )
    .unwrap();
    let rudder = &r.feed(Feed::True).unwrap().rudder;
    let held = rudder[rudder.len() - 1000..].iter().sum::<f64>() / 1000.0;
    assert!(
        (held / -1f64.to_radians() - 1.0).abs() < 0.01,
        "{}",
        held.to_degrees()
    );
    // a column the file does not have: the file and the key named
    let mut cfg = cfg;
    cfg.disturbance_columns.as_mut().unwrap().disturbance = "N".into();
    let e = hydroid::app::pipeline::autopilot::load_seas(&cfg, dir.path())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("moment.csv") && e.contains("autopilot.disturbance_columns.disturbance"),
        "{e}"
    );
}
