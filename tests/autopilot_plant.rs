//! Plants of the autopilot (issue 29, item 3): the autopilot tuned and filtered on a Nomoto
//! model closes its loop around another registered model, here the course-stable 150 m ship
//! of configs/vehicles/ship150_clarke.toml as a ship_linear model with its propeller held at
//! the 8 m/s balance, and around the same ship slowed to 5 m/s mid-run.
//!
//! The reference, written from the equations alone: tests/common/ship150_loop.rs (the linear
//! sway-yaw model of the ship, Fossen 2011, 7.1-7.2, and the PID loop fed the true heading).

use crate::common;

use common::ship150_loop::{self, nomoto, rms_from, SwayYaw, OMEGA_N, U0, ZETA};
use hydroid::config::autopilot::AutopilotConfig;
use hydroid::dynamics::autopilot::seas::Seas;
use hydroid::dynamics::autopilot::{AutopilotResult, Feed};
use std::f64::consts::PI;

const DURATION: f64 = 1200.0;
const COURSE: f64 = 10.0 * PI / 180.0;
const CHANGE_AT: f64 = 50.0;

/// The sway-yaw system at `U0` scaled by `s` (the reference's, tests/common/ship150_loop.rs).
fn sway_yaw(u: f64, s: f64) -> SwayYaw {
    assert!((u / U0 - s).abs() < 1e-12);
    ship150_loop::sway_yaw(u)
}

/// Heading error and rudder RMS of the reference loop at 8 m/s, fed the true heading.
fn reference_loop(plant: SwayYaw, _: (f64, f64)) -> (f64, f64) {
    assert_eq!(plant, ship150_loop::sway_yaw(U0));
    let (e, d) = ship150_loop::run(&ship150_loop::Run {
        plant: ship150_loop::sway_yaw,
        slow: None,
        retune: false,
        orders: vec![(CHANGE_AT, COURSE)],
        duration: DURATION,
    });
    (rms_from(&e, 0.0), rms_from(&d, 0.0))
}

/// The `[autopilot]` section with the plant `plant` (TOML lines).
fn config(plant: &str) -> AutopilotConfig {
    toml::from_str(&format!(
        "omega_n = {OMEGA_N}\nzeta = {ZETA}\ncompass_noise = \"0.1 deg\"\nduration = {DURATION}\n\
         feeds = [\"true\"]\n[plant]\n{plant}"
    ))
    .unwrap()
}

/// hydroid's loop: the identified model nomoto_wave with K and T `(k, t)`, the plant of `cfg`.
fn hydroid_loop(cfg: &AutopilotConfig, kt: (f64, f64)) -> AutopilotResult {
    ship150_loop::hydroid_autopilot(cfg, kt, &Seas::Generated)
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
    let change = ship150_loop::slow_down_toml(600.0, 5.0);
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
    let r = ship150_loop::hydroid_autopilot(&cfg, (k, t), &seas);
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
