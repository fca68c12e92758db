//! Independent physical properties of the `npsauv` model (NPS AUV II, Healey & Lienard 1993,
//! docs/models/npsauv.md): energy conservation of the rigid body with its added mass, the
//! straight-line speed the propulsion law settles at, the turn and pitch directions of the
//! control surfaces, and the paper's helix.

use crate::common;

use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::npsauv::{nps_auv_vehicle, NpsAuv, ADDED_MASS, PUBLISHED};
use hydroid::model::models::{Model, Vehicle};

/// The published vehicle and coefficient set.
fn published() -> (NpsAuv, Vec<f64>) {
    let m = NpsAuv::build(&nps_auv_vehicle()).expect("the published vehicle");
    let c = m.coefficient_vector(PUBLISHED);
    (m, c)
}

/// Simulates `duration` s from `x0` with constant `inputs` [delta_r, delta_s, delta_b, n
/// (rev/s)], sampled every `dt` s (RK4 steps of 0.01 s).
fn run(m: &NpsAuv, c: &[f64], x0: &[f64], inputs: &[f64], duration: f64, dt: f64) -> Vec<Vec<f64>> {
    let steps = (duration / dt).round() as usize;
    let times: Vec<f64> = (0..=steps).map(|k| k as f64 * dt).collect();
    let substeps = (dt / 0.01).round().max(1.0) as usize;
    simulate(m, c, x0, &InputSeries::constant(inputs), &times, substeps).expect("simulates")
}

/// A state moving straight ahead at `u`.
fn ahead(u: f64) -> Vec<f64> {
    let mut x = vec![0.0; 12];
    x[0] = u;
    x
}

/// rpm to the model's rev/s.
fn rps(rpm: f64) -> f64 {
    rpm / 60.0
}

/// (a) With every damping, lift, control and propulsion term zero (only the added-mass
/// coefficients, no cross-flow drag, no hull resistance C_d0, propeller stopped), the
/// kinetic energy 0.5 nu^T M nu (added mass included) plus the potential energy of weight
/// and buoyancy stays constant: M nu_dot = -C_RB(nu) nu - g(eta) with a skew-symmetric
/// C_RB. This catches the two sign errors of the 2024 MSS npsauv.m (heave rigid-body term
/// and the (I_z - I_x) p r pitch term), which gain about 30 % in 30 s. Checked: flipping the
/// sign of the heave rigid-body term in `NpsAuv::rigid_body_coriolis` gives a relative drift
/// of 9.2e-1, flipping the (I_z - I_x) p r pitch term 1.9e-2; as built the drift is 2.0e-12.
#[test]
fn energy_is_conserved_without_damping() {
    let mut v: Vehicle = nps_auv_vehicle();
    for key in ["cdy", "cdz", "cd0"] {
        v.particulars.insert(key.into(), toml::Value::Float(0.0));
    }
    let m = NpsAuv::build(&v).unwrap();
    let added: Vec<(&str, f64)> = PUBLISHED
        .iter()
        .copied()
        .filter(|(n, _)| ADDED_MASS.contains(n))
        .collect();
    assert_eq!(added.len(), ADDED_MASS.len());
    let c = m.coefficient_vector(&added);
    // every velocity non-zero, and a heel and trim so that the restoring forces work
    let x0 = [
        1.2, 0.3, -0.25, 0.15, -0.1, 0.12, 0.0, 0.0, 0.0, 0.1, -0.05, 0.3,
    ];
    let energy = |x: &[f64]| m.kinetic_energy(x, &c) + m.potential_energy(x);
    let e0 = energy(&x0);
    let xs = run(&m, &c, &x0, &[0.0; 4], 30.0, 0.01);
    let worst = xs
        .iter()
        .map(|x| ((energy(x) - e0) / e0).abs())
        .fold(0.0, f64::max);
    // the motion is not trivial: the rates change
    let last = xs.last().unwrap();
    assert!((last[3] - x0[3]).abs() > 1e-3, "{last:?}");
    println!("energy: E0 = {e0:.3} J, worst relative drift {worst:.3e} over 30 s");
    assert!(
        worst < 1e-6,
        "relative energy drift {worst:.3e} (E0 = {e0:.1} J)"
    );
}

/// Speed after `duration` s straight ahead at `rpm` from 1 m/s, and its change over the
/// last 50 s.
fn straight_speed(rpm: f64, duration: f64) -> (f64, f64) {
    let (m, c) = published();
    let xs = run(
        &m,
        &c,
        &ahead(1.0),
        &[0.0, 0.0, 0.0, rps(rpm)],
        duration,
        0.5,
    );
    let u_end = xs.last().unwrap()[0];
    let u_before = xs[xs.len() - 101][0];
    // straight: nothing else moves (but for the trace of the surge-pitch coupling m z_G of
    // the mass matrix while the speed changes, and the products of inertia)
    let last = xs.last().unwrap();
    for i in [1, 2, 3, 4, 5, 9, 10, 11] {
        assert!(last[i].abs() < 1e-6, "state {i} = {}", last[i]);
    }
    (u_end, (u_end - u_before).abs())
}

/// (b) Straight ahead at 500 rpm with the control surfaces at zero the speed settles where
/// the propulsion law's thrust balances the hull resistance, eta = k n / u = 1 (MSS
/// npsauv.m: prop = 0.012 n / u, n in rad/s): u = 0.012 * 500 * 2 pi / 60 = 0.628 m/s.
/// Measured: 0.62833 m/s after 900 s from 1 m/s at 500 rpm (still changing by 6.8e-6 m/s
/// over the last 50 s), 1.25664 m/s at 1000 rpm, 1.88496 m/s at 1500 rpm (the MSS file's
/// limit): the balance to five digits. The source says no more than that balance; 0.63 m/s at
/// 500 rpm is below the 1-3 m/s one might expect of a 5.3 m vehicle, because the MSS file
/// converts rpm to rad/s before applying Healey & Lienard's 0.012 (with n in rpm the same law
/// would give 6 m/s).
#[test]
fn straight_line_speed_settles_and_grows_with_rpm() {
    let (u500, change500) = straight_speed(500.0, 900.0);
    let want = 0.012 * 500.0 * 2.0 * std::f64::consts::PI / 60.0;
    assert!(
        change500 < 1e-3,
        "still changing by {change500:.2e} m/s in 50 s"
    );
    assert!(
        (u500 - want).abs() < 0.01 * want,
        "{u500} m/s, balance {want} m/s"
    );
    assert!((0.3..3.0).contains(&u500), "{u500} m/s");
    let (u1000, change1000) = straight_speed(1000.0, 900.0);
    assert!(change1000 < 1e-3, "{change1000}");
    assert!(u1000 > u500 * 1.5, "{u1000} vs {u500}");
    let (u1500, _) = straight_speed(1500.0, 900.0);
    println!(
        "straight: {u500:.5} m/s at 500 rpm (changing {change500:.1e} m/s in the last 50 s), \
         {u1000:.5} at 1000 rpm ({change1000:.1e}), {u1500:.5} at 1500 rpm"
    );
    assert!(u1500 > u1000 && (0.3..3.0).contains(&u1500), "{u1500}");
    // docs/models/npsauv.md, "Straight line", at its printed digits
    assert_eq!(
        format!("{u500:.5} ({change500:.1e}), {u1000:.5}, {u1500:.5}"),
        "0.62833 (6.8e-6), 1.25664, 1.88496"
    );
}

/// (c) Turn and pitch directions. Fossen's and SNAME's convention, with the published signs
/// Y_delta_r = +0.027 and N_delta_r = -0.013: a positive rudder angle pushes the stern to
/// starboard and turns the bow to port, r < 0 and psi decreasing (Fossen 1994: a positive
/// rudder angle gives a negative yaw moment). M_delta_s = -0.041: a positive stern-plane
/// angle pitches the nose down (q < 0, theta < 0) and the vehicle goes deeper (z grows, z
/// down). Measured from 0.628 m/s at 500 rpm, 60 s after the step: rudder 10 deg gives
/// r = -0.0202 rad/s, psi = -1.079 rad, y = -13.4 m; stern planes 10 deg give theta =
/// -0.0997 rad and z = +1.87 m.
#[test]
fn rudder_turns_to_port_and_stern_planes_pitch_nose_down() {
    let (m, c) = published();
    let u0 = 0.012 * 500.0 * 2.0 * std::f64::consts::PI / 60.0;
    let n = rps(500.0);
    let ten = 10f64.to_radians();
    let xs = run(&m, &c, &ahead(u0), &[ten, 0.0, 0.0, n], 60.0, 0.5);
    let x = xs.last().unwrap();
    println!(
        "rudder +10 deg, 60 s: r = {:.4} rad/s, psi = {:.3} rad, y = {:.2} m",
        x[5], x[11], x[7]
    );
    assert!(x[5] < 0.0 && x[11] < -0.1, "r = {}, psi = {}", x[5], x[11]);
    // docs/models/npsauv.md, "Turn and pitch direction", at its printed digits
    assert_eq!(
        format!("r = {:.4}, psi = {:.3}, y = {:.1}", x[5], x[11], x[7]),
        "r = -0.0202, psi = -1.079, y = -13.4"
    );
    // the other way round for a negative rudder angle
    let xs = run(&m, &c, &ahead(u0), &[-ten, 0.0, 0.0, n], 60.0, 0.5);
    let y = xs.last().unwrap();
    assert!(y[5] > 0.0 && y[11] > 0.1, "r = {}, psi = {}", y[5], y[11]);
    // stern planes
    let xs = run(&m, &c, &ahead(u0), &[0.0, ten, 0.0, n], 60.0, 0.5);
    let x = xs.last().unwrap();
    println!(
        "stern planes +10 deg, 60 s: theta = {:.4} rad, z = {:.3} m, q = {:.5}",
        x[10], x[8], x[4]
    );
    assert!(x[10] < -0.01, "theta = {}", x[10]);
    assert!(x[8] > 0.1, "z = {}", x[8]);
    assert_eq!(
        format!("theta = {:.4}, z = {:+.2}", x[10], x[8]),
        "theta = -0.0997, z = +1.87"
    );
    // the stern planes alone hardly touch the horizontal plane (only through the products
    // of inertia, 13.58 kg m^2)
    assert!(x[5].abs() < 1e-6 && x[9].abs() < 1e-6, "{x:?}");
}

/// (d) The paper's helix: rudder and stern planes at 10 deg (0.175 rad), 500 rpm, from the
/// straight-line speed. After the transient the turn rate, the speed and the rate of depth
/// change settle: a helix. Measured (last 200 s of 800 s): r = -0.01697 rad/s (a turn to
/// port, period 370 s, radius u / |r| = 31.3 m), u = 0.5316 m/s, dz/dt = +0.0195 m/s
/// (descending 7.2 m per turn), theta = -0.0839 rad, phi = +0.0106 rad; the turn rate varies
/// by 6.8e-7 rad/s over those 200 s.
#[test]
fn the_papers_helix_turns_and_descends_steadily() {
    let (m, c) = published();
    let u0 = 0.012 * 500.0 * 2.0 * std::f64::consts::PI / 60.0;
    let xs = run(
        &m,
        &c,
        &ahead(u0),
        &[0.175, 0.175, 0.0, rps(500.0)],
        800.0,
        0.5,
    );
    let tail = &xs[xs.len() - 401..];
    let mean = |i: usize| tail.iter().map(|x| x[i]).sum::<f64>() / tail.len() as f64;
    let spread = |i: usize| {
        let mu = mean(i);
        tail.iter().map(|x| (x[i] - mu).abs()).fold(0.0, f64::max)
    };
    let (r, u, theta, phi) = (mean(5), mean(0), mean(10), mean(9));
    let first = tail.first().unwrap();
    let last = tail.last().unwrap();
    let z_rate = (last[8] - first[8]) / 200.0;
    // the depth rate over the first and the second half of the tail
    let mid = &tail[200];
    let z_rate_1 = (mid[8] - first[8]) / 100.0;
    let z_rate_2 = (last[8] - mid[8]) / 100.0;
    println!(
        "helix: r = {r:.5} rad/s (spread {:.1e}), u = {u:.4} m/s, theta = {theta:.4} rad, \
         phi = {phi:.5} rad, dz/dt = {z_rate:.4} m/s ({z_rate_1:.4}, {z_rate_2:.4}), \
         radius {:.1} m",
        spread(5),
        u / r.abs()
    );
    // a turn to port (positive rudder), steady
    assert!(r < -1e-3, "r = {r}");
    assert!(
        spread(5) < 0.01 * r.abs(),
        "turn rate not steady: {}",
        spread(5)
    );
    assert!(spread(0) < 0.01 * u, "speed not steady: {}", spread(0));
    // a steady change of depth
    assert!(z_rate.abs() > 1e-3, "dz/dt = {z_rate}");
    assert!(
        (z_rate_1 - z_rate_2).abs() < 0.02 * z_rate.abs(),
        "depth rate not steady: {z_rate_1} vs {z_rate_2}"
    );
    // docs/models/npsauv.md, "The paper's helix", at its printed digits
    let period = 2.0 * std::f64::consts::PI / r.abs();
    assert_eq!(
        format!(
            "r = {r:.5} (period {period:.0} s, radius {:.1} m), u = {u:.4}, dz/dt = {z_rate:+.4} \
             ({:.1} m per turn), theta = {theta:.4}, phi = {phi:+.4}; r varies by {:.1e}",
            u / r.abs(),
            z_rate * period,
            spread(5)
        ),
        "r = -0.01697 (period 370 s, radius 31.3 m), u = 0.5316, dz/dt = +0.0195 (7.2 m per \
         turn), theta = -0.0839, phi = +0.0106; r varies by 6.8e-7"
    );
}

/// configs/vehicles/npsauv.toml holds the published set and the published vehicle: its
/// coefficients are the model's `PUBLISHED` values and its particulars the defaults.
#[test]
fn the_vehicle_file_holds_the_published_set() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("configs/vehicles/npsauv.toml")).unwrap();
    let file: toml::Table = toml::from_str(&text).unwrap();
    let coefficients = file["coefficients"].as_table().unwrap();
    assert_eq!(coefficients.len(), PUBLISHED.len());
    for (name, value) in PUBLISHED {
        let v = &coefficients[*name];
        let v = v.as_float().or(v.as_integer().map(|i| i as f64)).unwrap();
        assert_eq!(v, *value, "{name}");
    }
    let vehicle = file["vehicle"].as_table().unwrap();
    let published = nps_auv_vehicle();
    let with_file = Vehicle {
        particulars: vehicle["particulars"].as_table().unwrap().clone(),
        ..published.clone()
    };
    let a = NpsAuv::build(&with_file).unwrap();
    let b = NpsAuv::build(&published).unwrap();
    assert_eq!(a.particulars, b.particulars);
    assert_eq!(a.inertia, b.inertia);
    let mass = vehicle["mass"].as_float().unwrap();
    assert!((mass - published.mass).abs() < 0.01, "{mass}");
    assert_eq!(vehicle["bg"].as_float(), published.bg);
    assert_eq!(vehicle["buoyancy"].as_float(), published.buoyancy);
}

/// The paper's helix of [`the_papers_helix_identifies_its_17_coefficients`], the truth
/// model's nine outputs at 10 Hz for 60 s with white noise of variance 1e-3 (seed 2015).
fn papers_helix_record(m: &NpsAuv, truth: &[f64]) -> hydroid::io::record::Record {
    use hydroid::base::quantity::Quantity;
    use hydroid::io::record::Record;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};
    use std::collections::BTreeMap;

    let inputs = [0.175, 0.175, 0.0, rps(500.0)];
    let x0 = [
        2.0, 0.1, 0.1, 0.05, 0.05, 0.05, 11.0, 11.0, 11.0, 0.1, 0.1, 0.1,
    ];
    let dt = 0.1;
    let xs = run(m, truth, &x0, &inputs, 60.0, dt);
    let times: Vec<f64> = (0..xs.len()).map(|k| k as f64 * dt).collect();
    let measured = [
        (0, Quantity::U),
        (1, Quantity::V),
        (2, Quantity::W),
        (3, Quantity::P),
        (4, Quantity::Q),
        (5, Quantity::R),
        (9, Quantity::Roll),
        (10, Quantity::Pitch),
        (11, Quantity::Yaw),
    ];
    let noise = Normal::new(0.0, 1e-3f64.sqrt()).unwrap();
    let mut rng = StdRng::seed_from_u64(2015);
    let mut channels = BTreeMap::new();
    for (i, q) in measured {
        let column = xs.iter().map(|x| x[i] + noise.sample(&mut rng)).collect();
        channels.insert(q, column);
    }
    let n = times.len();
    for (q, v) in [
        (Quantity::Rudder, inputs[0]),
        (Quantity::SternPlanes, inputs[1]),
        (Quantity::BowPlanes, inputs[2]),
        (Quantity::Rpm, inputs[3]),
    ] {
        channels.insert(q, vec![v; n]);
    }
    channels.insert(Quantity::Time, times);
    let record = Record {
        units: channels
            .keys()
            .map(|q| (*q, q.si_symbol().to_string()))
            .collect(),
        ..Record::from_channels("helix", "synthetic", channels)
    };
    record
}

/// The paper's identification (Mousavian et al. 2015, section 4-5) as a twin experiment: the
/// helix (rudder and stern planes at 0.175 rad, 500 rpm) from 2 m/s with every other velocity
/// and the attitude disturbed (the paper's initial state, every velocity 1 m/s or 1 rad/s,
/// drives u through zero within 0.4 s, where the propulsion law eta = k n / u is singular, in
/// MSS npsauv.m as here), the nine outputs u, v, w, p, q, r, phi,
/// theta, psi measured at 10 Hz for 60 s with white noise of variance 1e-3 (the paper's R),
/// the 17 coefficients estimated with hydroid's hybrid EKF at its default tuning, the other
/// 76 known.
#[test]
fn the_papers_helix_identifies_its_17_coefficients() {
    use hydroid::config::{FluidConfig, VehicleConfig};
    use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source};
    use hydroid::model::models::npsauv::PAPER_17;
    use hydroid::stages::hekf::{self, HekfConfig};

    let (m, truth) = published();
    let record = papers_helix_record(&m, &truth);
    let v = nps_auv_vehicle();
    let vehicle = VehicleConfig {
        name: "NPS AUV II".into(),
        mass: v.mass,
        length: v.length,
        diameter: None,
        ixx: v.ixx,
        iyy: v.iyy,
        izz: v.izz,
        reference_area: v.reference_area,
        reference_length: v.length,
        buoyancy: v.buoyancy,
        bg: v.bg,
        scale: None,
        particulars: v.particulars.clone(),
        yaw_moment: Default::default(),
    };
    let fluid = FluidConfig {
        rho: v.rho,
        mu: 1.08e-3,
    };
    let mut known = CoefficientSet::new();
    for (name, value) in PUBLISHED {
        if !PAPER_17.contains(name) {
            known.insert(Coefficient::new(name, *value, None, Source::Config));
        }
    }
    let cfg: HekfConfig = toml::from_str(&format!(
        "model = \"npsauv\"\nestimate = {PAPER_17:?}\nsmoother = false\nruns = []\n"
    ))
    .unwrap();
    let r = hekf::run(
        &cfg,
        &hekf::StageInputs {
            vehicle: &vehicle.for_model(&fluid),
            known: &known,
            runs: std::slice::from_ref(&record),
            base_dir: std::path::Path::new(""),
        },
        &mut hydroid::base::progress::Silent,
    )
    .expect("the identification runs");
    let a = common::accuracy::Accuracy::of_hekf_result("the paper's helix, seed 2015", &r, |n| {
        truth[m.coefficient_index(n).unwrap()]
    });
    println!("{}", a.table());
    assert_eq!(r.coefficients.len(), 17);
    // docs/models/npsauv.md: the 13 determined (sigma below half the value) within 1.8
    // sigma, the four with a sigma comparable to the value flagged by the identifiability
    // advice; the errors of the well-determined ones at their printed digits
    a.assert_determined_within(&["Np", "Yp", "Kr", "Yr"], 1.8);
    for (name, error) in [
        ("Zq", "+3.8"),
        ("Ndr", "+3.8"),
        ("Kp", "-6.3"),
        ("Zw", "+7.7"),
        ("Zds", "+7.8"),
        ("Ydr", "+0.6"),
        ("Mq", "+11"),
        ("Mds", "+11"),
    ] {
        // the docs' sign: of the magnitude (Fossen's negative derivatives grow more negative)
        let r = a.row(name);
        let e = 100.0 * (r.estimate.abs() - r.truth.abs()) / r.truth.abs();
        let d = error.split_once('.').map_or(0, |(_, f)| f.len());
        assert_eq!(format!("{e:+.d$}"), error, "{name}\n{}", a.table());
    }
}

/// The whole way a user takes: configs/vehicles/npsauv.toml as the configuration's vehicle
/// and known coefficients, a helix export with the propeller speed in rpm, `hydroid run`
/// with the hybrid EKF estimating N_delta_r and M_delta_s from the noise-free log: each
/// within 1 % (their published values taken out of the file's [coefficients], so that the
/// truth is nowhere in the configuration).
#[test]
fn the_vehicle_file_runs_an_identification_end_to_end() {
    let (m, truth) = published();
    let inputs = [0.175, 0.175, 0.0, rps(500.0)];
    let dt = 0.05;
    let xs = run(&m, &truth, &ahead(2.0), &inputs, 30.0, dt);
    let mut csv = String::from(
        "time [s],u [m/s],v [m/s],w [m/s],p [rad/s],q [rad/s],r [rad/s],roll [rad],\
         pitch [rad],yaw [rad],rudder [deg],stern_planes [deg],bow_planes [deg],rpm [rpm]\n",
    );
    for (k, x) in xs.iter().enumerate() {
        csv.push_str(&format!("{:.6}", k as f64 * dt));
        for i in [0, 1, 2, 3, 4, 5, 9, 10, 11] {
            csv.push_str(&format!(",{:.17e}", x[i]));
        }
        csv.push_str(&format!(
            ",{:.17e},{:.17e},0,500\n",
            inputs[0].to_degrees(),
            inputs[1].to_degrees()
        ));
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("helix.csv"), csv).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("configs/vehicles/npsauv.toml")).unwrap();
    assert!(text.contains("\nNdr = -1.3e-2\n") && text.contains("\nMds = -4.1e-2\n"));
    let mut text = text
        .replace("\nNdr = -1.3e-2\n", "\nNdr = 0.0\n")
        .replace("\nMds = -4.1e-2\n", "\nMds = 0.0\n");
    text.push_str(
        "\n[hekf]\nmodel = \"npsauv\"\nestimate = [\"Ndr\", \"Mds\"]\n[[hekf.runs]]\n\
         file = \"helix.csv\"\n",
    );
    let cfg = dir.path().join("npsauv.toml");
    std::fs::write(&cfg, text).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(o.status.code(), Some(0), "{said}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    for (name, want) in [("Ndr", -1.3e-2), ("Mds", -4.1e-2)] {
        let c = r["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap_or_else(|| panic!("{name} in {}", r["coefficients"]));
        let v = c["value"].as_f64().unwrap();
        println!("{name}: {v:.6e} (published {want:e})");
        assert!(
            ((v - want) / want).abs() < 0.01,
            "{name} = {v}, published {want}"
        );
    }
}
