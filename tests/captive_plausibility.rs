//! Captive and PMM plausibility (issue 22, item 7): each bad input a tester fed the captive
//! stage silently (a yaw rate in rad/s under a deg/s label, a flipped Fy, forces in kN
//! labelled N, u = 0, a PMM force record of pure noise, a PMM amplitude twice too large, a
//! model that misses the table) ends as a warning or error naming the cause; the clean
//! table and runs give none. The data come from the independent KVLCC2 generator
//! (tests/independent/mmg.rs: Yasukawa & Yoshimura 2015 equations, not src/model/models), the
//! forces on the hull held in the motion, with noise from a fixed seed.
//!
//!   cargo test --test suite captive_plausibility::

use crate::common;
use crate::independent;

use independent::mmg::{approach_speed, Kvlcc2};
use independent::{Noise, Series};
use std::path::Path;

/// The hull derivatives captive runs give (Y&Y 2015 Table 2).
const HULL: [&str; 12] = [
    "Yv_p", "Yr_p", "Yvvv_p", "Yvvr_p", "Yvrr_p", "Yrrr_p", "Nv_p", "Nr_p", "Nvvv_p", "Nvvr_p",
    "Nvrr_p", "Nrrr_p",
];

/// A mistake made in a table before hydroid reads it.
#[derive(Clone, Copy, PartialEq)]
enum Mistake {
    None,
    /// The yaw rate written in rad/s under a deg/s label.
    RadAsDeg,
    /// The sway force's sign flipped.
    FlippedFy,
    /// Forces and moment in kN and kN m under N labels.
    KiloAsUnit,
    /// The u column all zeros.
    NoSpeed,
    /// A PMM force record (fy, mz) of noise only.
    NoiseOnly,
    /// The PMM sway velocity written twice too large.
    DoubleAmplitude,
}

/// The generator's added masses m_x, m_y (kg) and moment of inertia J_z (kg m^2), from its
/// prime values on 0.5 rho L^2 d (and L^2 for J_z).
fn added_masses(ship: &Kvlcc2) -> (f64, f64, f64) {
    let half = 0.5 * ship.rho * ship.lpp * ship.lpp * ship.draught;
    (
        ship.p["m_x_dash"] * half,
        ship.p["m_y_dash"] * half,
        ship.p["J_z_dash"] * half * ship.lpp * ship.lpp,
    )
}

/// The ITTC steady programme at the approach speed and the self-propulsion point: static
/// drift -20..20 deg, rudder -35..35 deg, drift 10 deg with rudder +-20 deg, circular motion
/// at r' 0.2, 0.4, 0.6 with drift -12..12 deg; the forces on the hull held in the motion
/// with 1 % noise of their RMS.
fn steady_table(dir: &Path, mistake: Mistake, seed: u64) -> std::path::PathBuf {
    let ship = Kvlcc2::model();
    let speed = approach_speed();
    let n = ship.self_propulsion(speed);
    let (mx, my, _) = added_masses(&ship);
    let points = common::ittc_programme();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 7];
    for &(beta, rp, delta) in &points {
        let beta: f64 = f64::to_radians(beta);
        let (u, v, r) = (
            speed * beta.cos(),
            -speed * beta.sin(),
            rp * speed / ship.lpp,
        );
        let f = ship.forces(&[u, v, r, 0.0, 0.0, 0.0, delta.to_radians()], n);
        // the added-mass terms of Y&Y 2015 eq. 4 on the force side: X + m_y v r, Y - m_x u r
        let (fx, fy) = (f[0] + my * v * r, f[1] - mx * u * r);
        for (c, x) in cols.iter_mut().zip([u, v, r, delta, fx, fy, f[2]]) {
            c.push(x);
        }
    }
    let mut noise = Noise::new(seed);
    for c in &mut cols[4..] {
        let rms = (c.iter().map(|x| x * x).sum::<f64>() / c.len() as f64).sqrt();
        *c = noise.add(c, 0.01 * rms);
    }
    let mut s = Series::new("KVLCC2 captive programme, independent MMG generator");
    let u = if mistake == Mistake::NoSpeed {
        vec![0.0; points.len()]
    } else {
        cols[0].clone()
    };
    s.push("u", "m/s", u);
    s.push("v", "m/s", cols[1].clone());
    let r_deg: Vec<f64> = if mistake == Mistake::RadAsDeg {
        cols[2].clone()
    } else {
        cols[2].iter().map(|r| r.to_degrees()).collect()
    };
    s.push("yaw rate", "deg/s", r_deg);
    s.push("rudder", "deg", cols[3].clone());
    s.push("propeller", "rps", vec![n; points.len()]);
    let force = |k: usize| -> Vec<f64> {
        let sign = if k == 5 && mistake == Mistake::FlippedFy {
            -1.0
        } else {
            1.0
        };
        let unit = if mistake == Mistake::KiloAsUnit {
            1e-3
        } else {
            1.0
        };
        cols[k].iter().map(|f| sign * unit * f).collect()
    };
    s.push("Fx", "N", force(4));
    s.push("Fy", "N", force(5));
    s.push("Mz", "N m", force(6));
    s.write_csv(dir, "captive.csv")
}

/// The vehicle and published set of configs/ship_captive.toml (everything above its
/// `[captive]`), with `hull` of the twelve hull derivatives added at their published values
/// (ship_captive.toml's `[reference]`; those in `zero` at 0 instead) and `drop` removed
/// from `[coefficients]`.
fn head(hull: &[&str], zero: &[&str], drop: &[&str]) -> String {
    let ship = std::fs::read_to_string(common::root().join("configs/ship_captive.toml")).unwrap();
    let reference = ship.lines().find(|l| l.starts_with("values = {")).unwrap();
    let mut head = String::new();
    for line in ship[..ship.find("[captive]").unwrap()].lines() {
        if drop.iter().any(|d| line.starts_with(&format!("{d} ="))) {
            continue;
        }
        head.push_str(line);
        head.push('\n');
        if line.starts_with("[coefficients]") {
            for item in reference["values = {".len()..]
                .trim_end_matches('}')
                .split(',')
            {
                let (k, v) = item.split_once('=').unwrap();
                let (k, v) = (k.trim(), v.trim());
                if zero.contains(&k) {
                    head.push_str(&format!("{k} = 0\n"));
                } else if hull.contains(&k) {
                    head.push_str(&format!("{k} = {v}\n"));
                }
            }
        }
    }
    head
}

/// The hull derivatives not in `estimate` (held at their published values).
fn held_except(estimate: &[&str]) -> Vec<&'static str> {
    HULL.iter()
        .copied()
        .filter(|h| !estimate.contains(h))
        .collect()
}

/// `hydroid run` on the configuration `text` written in `dir`: the exit status,
/// results.json when written and the console.
fn run_text(dir: &Path, text: &str) -> (Option<i32>, Option<serde_json::Value>, String) {
    let config = dir.join("captive.toml");
    std::fs::write(&config, text).unwrap();
    let out = dir.join("out");
    let o = common::run_config(&config, &out, &[]);
    let results = out.join("results.json");
    let json = results.exists().then(|| common::json(&results));
    (o.status.code(), json, common::text(&o.stderr))
}

/// The captive stage on the steady table of `mistake`, estimating `estimate` (the other hull
/// derivatives held at their published values, those in `zero` at 0), with
/// `captive.checks = "warn"` (a clear mistake is named and the fit runs anyway): the exit
/// status, results.json when written and the console.
fn steady(
    mistake: Mistake,
    estimate: &[&str],
    zero: &[&str],
) -> (Option<i32>, Option<serde_json::Value>, String) {
    steady_checked(mistake, estimate, zero, "warn")
}

/// [`steady`] with `captive.checks = checks`.
fn steady_checked(
    mistake: Mistake,
    estimate: &[&str],
    zero: &[&str],
    checks: &str,
) -> (Option<i32>, Option<serde_json::Value>, String) {
    let dir = tempfile::tempdir().unwrap();
    let file = steady_table(dir.path(), mistake, 11);
    let list: Vec<String> = estimate.iter().map(|e| format!("\"{e}\"")).collect();
    let text = format!(
        "{}[captive]\nmodel = \"mmg3\"\nchecks = \"{checks}\"\nestimate = [{}]\n\
         [[captive.runs]]\nname = \"programme\"\n\
         file = \"{}\"\nsource = \"measured\"\n[captive.runs.columns]\nu = \"u\"\nv = \"v\"\n\
         r = \"yaw rate\"\nrudder = \"rudder\"\nrpm = \"propeller\"\nfx = \"Fx\"\nfy = \"Fy\"\n\
         mz = \"Mz\"\n",
        head(&held_except(estimate), zero, &[]),
        list.join(", "),
        file.display()
    );
    run_text(dir.path(), &text)
}

/// The captive warnings of a run, as text.
fn captive_warnings(r: &serde_json::Value) -> Vec<String> {
    r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["stage"] == "captive")
        .map(|w| format!("{} / {}", w["message"], w["meaning"]))
        .collect()
}

/// Asserts a warning naming `needles` (each somewhere in one warning's text).
fn warned(mistake: Mistake, estimate: &[&str], needles: &[&str]) -> Vec<String> {
    let (code, r, err) = steady(mistake, estimate, &[]);
    assert_eq!(code, Some(0), "{err}");
    let w = captive_warnings(&r.unwrap());
    assert_named(&w, needles);
    w
}

/// Asserts that one of the warnings `w` holds every one of `needles`.
fn assert_named(w: &[String], needles: &[&str]) {
    println!("{w:#?}");
    assert!(
        w.iter().any(|w| needles.iter().all(|n| w.contains(n))),
        "no warning with {needles:?}: {w:#?}"
    );
}

#[test]
fn a_clean_captive_table_gives_no_warning() {
    let (code, r, err) = steady(Mistake::None, &HULL, &[]);
    assert_eq!(code, Some(0), "{err}");
    let w = captive_warnings(&r.unwrap());
    assert!(w.is_empty(), "{w:#?}");
}

#[test]
fn a_yaw_rate_in_rad_per_s_under_a_deg_per_s_label_is_named() {
    warned(Mistake::RadAsDeg, &HULL, &["yaw", "rad/s read as deg/s"]);
}

#[test]
fn a_flipped_sway_force_is_named() {
    warned(
        Mistake::FlippedFy,
        &HULL,
        &["fy has the opposite sign convention", "scale = -1"],
    );
}

#[test]
fn forces_in_kilonewton_labelled_newton_are_named() {
    warned(
        Mistake::KiloAsUnit,
        &HULL,
        &["kN read as N", "columns.fy", "kN m read as N m"],
    );
}

/// A clear mistake stops the run before any stage by default (`captive.checks = "error"`),
/// with the fix and the way to run anyway; nothing is written.
#[test]
fn a_clear_mistake_stops_the_run_unless_checks_warn() {
    let (code, r, err) = steady_checked(Mistake::FlippedFy, &HULL, &[], "error");
    assert_eq!(code, Some(2), "{err}");
    assert!(r.is_none(), "results written");
    for words in [
        "run 'programme'",
        "fy has the opposite sign convention",
        "captive.runs[0].columns.fy",
        "captive.checks = \"warn\" runs anyway",
    ] {
        assert!(err.contains(words), "{words}: {err}");
    }
}

#[test]
fn a_table_without_forward_speed_is_refused() {
    let (code, _, err) = steady(Mistake::NoSpeed, &HULL, &[]);
    assert_ne!(code, Some(0), "{err}");
    assert!(err.contains("forward speed u is 0 on every row"), "{err}");
    assert!(err.contains("programme"), "{err}");
}

/// The cubic drift terms held at 0: the model misses the table at large drift, the residuals
/// vary smoothly with the condition, the lack-of-fit test says so and the sigmas grow.
#[test]
fn a_model_that_misses_the_steady_table_warns_and_widens_its_sigmas() {
    let estimate = [
        "Yv_p", "Yr_p", "Yvvr_p", "Yvrr_p", "Yrrr_p", "Nv_p", "Nr_p", "Nvvr_p", "Nvrr_p", "Nrrr_p",
    ];
    let sigma = |r: &serde_json::Value, name: &str| {
        common::named(&r["stages"]["captive"]["coefficients"], name)["sigma"]
            .as_f64()
            .unwrap()
    };
    let (code, clean, err) = steady(Mistake::None, &estimate, &[]);
    assert_eq!(code, Some(0), "{err}");
    let clean = clean.unwrap();
    assert!(captive_warnings(&clean).is_empty(), "{err}");
    let (code, missed, err) = steady(Mistake::None, &estimate, &["Yvvv_p", "Nvvv_p"]);
    assert_eq!(code, Some(0), "{err}");
    let missed = missed.unwrap();
    assert_named(&captive_warnings(&missed), &["lack of fit", "fy"]);
    let grown = sigma(&missed, "Yv_p") / sigma(&clean, "Yv_p");
    assert!(grown > 2.0, "Yv_p's sigma grew {grown} times");
}

/// A PMM run of the independent generator: pure sway (v = 0.06 m/s sin(2 pi 0.05 t)) or
/// pure yaw (r = 3 deg/s sin(...)) at the approach speed for 80 s at 20 Hz, the forces on
/// the hull held in the motion: the MMG forces with the added-mass terms of Y&Y 2015 eq. 4
/// on the force side (X + m_y v r, Y - m_y v_dot - m_x u r, N - J_z r_dot), noise 1 N, 2 N,
/// 5 N m.
fn pmm_run(dir: &Path, yaw: bool, mistake: Mistake, seed: u64) -> std::path::PathBuf {
    let ship = Kvlcc2::model();
    let speed = approach_speed();
    let n = ship.self_propulsion(speed);
    let (mx, my, jz) = added_masses(&ship);
    let w = 2.0 * std::f64::consts::PI * 0.05;
    let amplitude = if yaw { 3f64.to_radians() } else { 0.06 };
    let t: Vec<f64> = (0..1600).map(|k| k as f64 * 0.05).collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 6];
    for &t in &t {
        let (x, dx) = (amplitude * (w * t).sin(), amplitude * w * (w * t).cos());
        let (v, r, vd, rd) = if yaw {
            (0.0, x, 0.0, dx)
        } else {
            (x, 0.0, dx, 0.0)
        };
        let f = ship.forces(&[speed, v, r, 0.0, 0.0, 0.0, 0.0], n);
        let forces = [
            f[0] + my * v * r,
            f[1] - my * vd - mx * speed * r,
            f[2] - jz * rd,
        ];
        for (c, x) in cols.iter_mut().zip([v, r, forces[0], forces[1], forces[2]]) {
            c.push(x);
        }
    }
    let mut noise = Noise::new(seed);
    for (c, sigma) in cols[2..5].iter_mut().zip([1.0, 2.0, 5.0]) {
        if mistake == Mistake::NoiseOnly && sigma > 1.0 {
            c.iter_mut().for_each(|x| *x = 0.0);
        }
        *c = noise.add(c, sigma);
    }
    if mistake == Mistake::DoubleAmplitude {
        cols[0].iter_mut().for_each(|v| *v *= 2.0);
    }
    let mut s = Series::new("KVLCC2 PMM run, independent MMG generator");
    s.push("time", "s", t.clone());
    s.push("u", "m/s", vec![speed; t.len()]);
    s.push("v", "m/s", cols[0].clone());
    s.push(
        "r",
        "deg/s",
        cols[1].iter().map(|r| r.to_degrees()).collect(),
    );
    s.push("Fx", "N", cols[2].clone());
    s.push("Fy", "N", cols[3].clone());
    s.push("Mz", "N m", cols[4].clone());
    s.write_csv(dir, if yaw { "yaw.csv" } else { "sway.csv" })
}

/// The captive stage on a pure sway run with `mistake` and a clean pure yaw run, estimating
/// the added masses and linear derivatives: results.json (the run must succeed).
fn pmm(mistake: Mistake) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let n = Kvlcc2::model().self_propulsion(approach_speed());
    let estimate = ["my_p", "Jz_p", "Yv_p", "Yr_p", "Nv_p", "Nr_p"];
    let mut text = format!(
        "{}[captive]\nmodel = \"mmg3\"\naverage_after = 0\nestimate = [{}]\n",
        head(&held_except(&estimate), &[], &["my_p", "Jz_p"]),
        estimate.map(|e| format!("\"{e}\"")).join(", ")
    );
    for (name, yaw, seed) in [("pure sway", false, 5), ("pure yaw", true, 6)] {
        let file = pmm_run(
            dir.path(),
            yaw,
            if yaw { Mistake::None } else { mistake },
            seed,
        );
        text.push_str(&format!(
            "[[captive.runs]]\nname = \"{name}\"\nfile = \"{}\"\nsource = \"measured\"\n\
             constants = {{ rudder = 0, rpm = \"{n} rps\" }}\n",
            file.display()
        ));
    }
    let (code, json, err) = run_text(dir.path(), &text);
    assert_eq!(code, Some(0), "{err}");
    json.unwrap()
}

#[test]
fn clean_pmm_runs_give_no_warning() {
    let r = pmm(Mistake::None);
    let w = captive_warnings(&r);
    assert!(w.is_empty(), "{w:#?}");
}

#[test]
fn a_pmm_force_record_of_pure_noise_is_named() {
    let w = captive_warnings(&pmm(Mistake::NoiseOnly));
    assert_named(&w, &["no first harmonic above its noise", "fy"]);
}

#[test]
fn a_pmm_amplitude_twice_too_large_is_named() {
    let w = captive_warnings(&pmm(Mistake::DoubleAmplitude));
    assert_named(&w, &["pure sway", "motion amplitude"]);
}

/// The windows of the checks against the published sets they were calibrated on: the
/// KVLCC2 model (Y&Y 2015: L 7 m, d 0.46 m, 3270 kg, fresh water; derivatives on 0.5 rho L d
/// U^2) and the NPS AUV II (Healey & Lienard 1993: L 5.3 m, 5445.29 kg, rho 1025; on 0.5 rho
/// L^k); the ratios of docs/stages.md to 2 digits, inside each window, and the unit mistakes
/// outside.
#[test]
fn the_windows_hold_the_published_sets_and_not_their_unit_mistakes() {
    use hydroid::stages::captive::plausibility::*;
    let inside = |x: f64, w: (f64, f64)| x >= w.0 && x <= w.1;
    let kvlcc2 = independent::published("kvlcc2_mmg_yasukawa2015.csv");
    let k = |n: &str| independent::value(&kvlcc2, n);
    let (rho, l, d, m) = (1000.0, 7.0, 0.46, 3270.0);
    let q = 0.5 * rho * l * d;
    let yv = k("Y_v_dash").abs() * q / (m / l);
    let nr = k("N_r_dash").abs() * q * l * l / (m * l);
    let reference = Reference::new(rho, l, m, Some(d), None);
    let (sway, yaw, _) = reference.added.unwrap();
    let my = k("m_y_dash") * q * l / sway;
    let jz = k("J_z_dash") * q * l.powi(3) / yaw;
    let nps = independent::published("npsauv_healey_lienard1993.csv");
    let n = |x: &str| independent::value(&nps, x);
    let (rho_n, l_n, m_n) = (1025.0, 5.3, 5445.29);
    let yv_n = n("Yv").abs() * 0.5 * rho_n * l_n * l_n / (m_n / l_n);
    let nr_n = n("Nr").abs() * 0.5 * rho_n * l_n.powi(4) / (m_n * l_n);
    let measured = [yv, nr, my, jz, yv_n, nr_n].map(|x| (x * 100.0).round() / 100.0);
    assert_eq!(
        measured,
        [1.09, 0.17, 1.08, 0.64, 1.4, 0.22],
        "{measured:?}"
    );
    for x in [yv, yv_n] {
        assert!(
            inside(x, YV_WINDOW) && !inside(x / 1000.0, YV_WINDOW),
            "{x}"
        );
    }
    for x in [nr, nr_n] {
        let rad_as_deg = x * 180.0 / std::f64::consts::PI;
        assert!(
            inside(x, NR_WINDOW) && !inside(rad_as_deg, NR_WINDOW),
            "{x}"
        );
        assert!(!inside(x / 1000.0, NR_WINDOW), "{x}");
    }
    assert!(inside(my, SWAY_MASS_WINDOW) && !inside(my / 2.0, SWAY_MASS_WINDOW));
    // a pure yaw amplitude twice too large is not caught on the KVLCC2 (0.32 is inside)
    assert!(inside(jz, YAW_MASS_WINDOW) && inside(jz / 2.0, YAW_MASS_WINDOW));
}
