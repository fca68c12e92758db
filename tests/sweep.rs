//! `hydroid simulate` with `[sweep]`: turning circles over rudder angle and approach speed
//! (configs/simulate/kvlcc2_sweep.toml, the KVLCC2 model with mmg3).

use crate::common;

use common::{hydroid, root, text};
use std::path::Path;

const SWEEP: &str = "configs/simulate/kvlcc2_sweep.toml";

fn run_into(out: &Path) -> std::process::Output {
    hydroid(&["simulate", SWEEP, "--out", out.to_str().unwrap()])
}

fn rows(csv: &str) -> Vec<Vec<String>> {
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn the_diameter_falls_as_the_rudder_rises_and_reruns_are_identical() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let o = run_into(&out);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("14 turning circles"),
        "{}",
        text(&o.stdout)
    );
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows = rows(&csv);
    // tactical diameter (L) is column 9: by rudder, each side
    for side in ["starboard", "port"] {
        let d: Vec<f64> = rows
            .iter()
            .filter(|r| r[0] == "rudder" && r[3] == side)
            .map(|r| r[9].parse().unwrap())
            .collect();
        assert_eq!(d.len(), 4, "{side}");
        assert!(d.windows(2).all(|w| w[1] < w[0]), "{side}: {d:?}");
        // the 35 deg turn as the KVLCC2 free-running tests (about 3.2 L, tests/ships.rs)
        assert!((d[3] - 3.2).abs() < 0.35, "{side}: {}", d[3]);
    }
    for f in [
        "sweep.md",
        "tracks_rudder.svg",
        "tracks_speed.svg",
        "diameter_vs_rudder.svg",
        "diameter_vs_speed.svg",
        "diameter_vs_speed.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // a rerun replaces its own output with the same bytes
    let first: Vec<Vec<u8>> = ["sweep.csv", "sweep.md", "tracks_rudder.svg"]
        .iter()
        .map(|f| std::fs::read(out.join(f)).unwrap())
        .collect();
    let o = run_into(&out);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    for (f, bytes) in ["sweep.csv", "sweep.md", "tracks_rudder.svg"]
        .iter()
        .zip(first)
    {
        assert_eq!(std::fs::read(out.join(f)).unwrap(), bytes, "{f}");
    }
}

#[test]
fn each_speed_case_holds_its_approach_speed_with_the_balanced_propeller() {
    // the paper's own study on the KCS (configs/simulate/kcs_sweep.toml), at its speeds
    let loaded =
        hydroid::app::simulate::config::load(&root().join("configs/simulate/kcs_sweep.toml"))
            .unwrap();
    let result = hydroid::app::simulate::sweep::simulate_sweep(&loaded).unwrap();
    let speed_cases: Vec<_> = result
        .cases
        .iter()
        .filter(|c| c.varies == hydroid::app::simulate::sweep::Varies::Speed)
        .collect();
    assert_eq!(speed_cases.len(), 6);
    for c in speed_cases {
        let approach = c.turn.approach_speed.value().unwrap();
        assert!(
            ((approach - c.speed) / c.speed).abs() < 1e-3,
            "{} m/s held as {approach}",
            c.speed
        );
        let (_, rps) = c.propeller.unwrap();
        assert!(rps > 5.0 && rps < 25.0, "{rps} rev/s");
    }
}

#[test]
fn a_folder_hydroid_did_not_write_is_never_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let mine = dir.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "keep").unwrap();
    let o = run_into(&mine);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert_eq!(
        std::fs::read_to_string(mine.join("notes.txt")).unwrap(),
        "keep"
    );
}

#[test]
fn bad_sweeps_name_their_keys() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(root().join(SWEEP)).unwrap();
    for (from, to, key) in [
        (
            "rudder = [\"10 deg\", \"15 deg\", \"25 deg\", \"35 deg\"]",
            "rudder = [\"10 deg\", \"90 deg\"]",
            "sweep.rudder[1]",
        ),
        ("sides = \"both\"", "sides = \"all\"", "sides"),
        (
            "rudder = [\"10 deg\", \"15 deg\", \"25 deg\", \"35 deg\"]",
            "rudder = [\"10 m/s\"]",
            "rudder",
        ),
        (
            "kind = \"turn\"",
            "kind = \"zigzag\"\nheading = \"20 deg\"",
            "sweep",
        ),
    ] {
        assert!(src.contains(from), "{from}");
        let cfg = dir.path().join("bad.toml");
        std::fs::write(&cfg, src.replace(from, to)).unwrap();
        let o = hydroid(&[
            "simulate",
            cfg.to_str().unwrap(),
            "--out",
            dir.path().join("o").to_str().unwrap(),
        ]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{to}: {err}");
        assert!(err.contains(key), "{to}: {err}");
        assert!(err.contains("bad.toml"), "{err}");
    }
}

/// The sections of configs/vehicles/kcs_mmg.toml from `[vehicle]` on (its vehicle and
/// coefficients), to copy into a configuration.
fn kcs_vehicle_sections() -> String {
    let vehicle = std::fs::read_to_string(root().join("configs/vehicles/kcs_mmg.toml")).unwrap();
    vehicle[vehicle.find("[vehicle]").unwrap()..].to_string()
}

/// The KCS vehicle file (configs/vehicles/kcs_mmg.toml, the SIMMAN 2008 set converted from
/// drift-angle form): its 35 deg turns at the paper's 1.7 m/s, propeller balanced, are a
/// KCS-sized circle (a little over 3 ship lengths) to both sides, and diameters fall as the
/// rudder rises: a sign slip in the conversion would break one of these.
#[test]
fn the_kcs_vehicle_file_turns_like_a_container_ship() {
    let dir = tempfile::tempdir().unwrap();
    let body = kcs_vehicle_sections();
    let cfg = format!(
        "title = \"KCS\"\nmodel = \"mmg3\"\n{body}\n[fluid]\nrho = 1000.0\nmu = 0.001\n\n\
         [manoeuvre]\nkind = \"time_history\"\nduration = 150\ndt = 0.1\nsubsteps = 10\n\
         initial = {{ u = \"1.7 m/s\" }}\ninputs = {{ rpm = \"13.97 rps\" }}\n\
         [manoeuvre.steering]\nkind = \"turn\"\nrudder = \"35 deg\"\nrate = \"16.8 deg/s\"\n\
         execute = \"5 s\"\n\n[sweep]\nrudder = [\"15 deg\", \"35 deg\"]\n\
         speed = [\"1.7 m/s\"]\nspeed_rudder = \"35 deg\"\nsides = \"both\"\ndir = \"out\"\n"
    );
    let path = dir.path().join("kcs.toml");
    std::fs::write(&path, cfg).unwrap();
    let o = hydroid(&["simulate", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let csv = std::fs::read_to_string(dir.path().join("out/sweep.csv")).unwrap();
    let rows = rows(&csv);
    for side in ["starboard", "port"] {
        let d = |varies: &str, rudder: f64| -> (f64, f64) {
            let r = rows
                .iter()
                .find(|r| {
                    r[0] == varies
                        && r[3] == side
                        && (r[1].parse::<f64>().unwrap().abs() - rudder).abs() < 1e-6
                })
                .unwrap();
            (r[6].parse().unwrap(), r[9].parse().unwrap())
        };
        let (advance, tactical) = d("speed", 35.0);
        assert!(
            (3.0..3.6).contains(&tactical),
            "{side}: tactical {tactical} L"
        );
        assert!((2.9..3.5).contains(&advance), "{side}: advance {advance} L");
        assert!(d("rudder", 15.0).1 > d("rudder", 35.0).1, "{side}");
    }
}

/// The columns `(advance, tactical diameter)` in ship lengths of the sweep `config`'s cases
/// that vary `varies` on `side`, in the order of sweep.csv.
fn lengths(config: &str, varies: &str, side: &str) -> Vec<(f64, f64)> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let o = hydroid(&["simulate", config, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    rows(&csv)
        .iter()
        .filter(|r| r[0] == varies && r[3] == side)
        .map(|r| (r[6].parse().unwrap(), r[9].parse().unwrap()))
        .collect()
}

/// docs/simulate.md and docs/models/ships.md at their printed digits: the tactical diameter
/// of the KVLCC2 and of the KCS from 10 to 35 deg of rudder, to either side, and at 15 deg
/// at each speed; the KCS's 35 deg advance and tactical diameter.
#[test]
fn the_sweeps_give_the_diameters_of_the_docs() {
    let said = |config: &str| {
        let (sb, port) = (
            lengths(config, "rudder", "starboard"),
            lengths(config, "rudder", "port"),
        );
        let speeds: Vec<String> = lengths(config, "speed", "starboard")
            .iter()
            .map(|d| format!("{:.2}", d.1))
            .collect();
        format!(
            "starboard {:.1} L at 10 deg to {:.1} L at 35 deg, port {:.1} L to {:.1} L; 35 deg: \
             advance {:.2} L, tactical {:.2} L to starboard, {:.2} L and {:.2} L to port; 15 deg \
             at each speed: {}",
            sb[0].1,
            sb[3].1,
            port[0].1,
            port[3].1,
            sb[3].0,
            sb[3].1,
            port[3].0,
            port[3].1,
            speeds.join(", ")
        )
    };
    assert_eq!(
        said(SWEEP),
        "starboard 6.6 L at 10 deg to 3.1 L at 35 deg, port 5.6 L to 3.1 L; 35 deg: advance \
         3.08 L, tactical 3.12 L to starboard, 3.09 L and 3.10 L to port; 15 deg at each speed: \
         5.17, 5.17, 5.17"
    );
    assert_eq!(
        said("configs/simulate/kcs_sweep.toml"),
        "starboard 6.9 L at 10 deg to 3.2 L at 35 deg, port 6.3 L to 3.3 L; 35 deg: advance \
         3.19 L, tactical 3.21 L to starboard, 3.22 L and 3.29 L to port; 15 deg at each speed: \
         5.45, 5.45, 5.45"
    );
}

/// docs/models/ships.md, "KCS": linearised at the paper's 1.7 m/s with the propeller at the
/// sweep's self-propulsion balance (13.96 rev/s), the KCS is course-stable but nearly neutral: T1 =
/// 149 s, K = 13.1 1/s and T = 148 s, at the digits printed there.
#[test]
fn the_kcs_linearised_at_the_test_speed_is_nearly_neutral() {
    use hydroid::model::models::{Mmg3, Model};
    let loaded =
        hydroid::app::simulate::config::load(&root().join("configs/simulate/kcs_sweep.toml"))
            .unwrap();
    let config = &loaded.config;
    let vehicle = config.vehicle.for_model(&config.fluid).vehicle;
    let m = Mmg3::build(&vehicle).unwrap();
    let values: Vec<(&str, f64)> = config
        .coefficients
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .collect();
    let c = m.coefficient_vector(&values);
    // the balance of the sweep's 1.7 m/s case, not its rounded 13.97
    let sweep = hydroid::app::simulate::sweep::simulate_sweep(&loaded).unwrap();
    let case = sweep
        .cases
        .iter()
        .find(|c| c.varies == hydroid::app::simulate::sweep::Varies::Speed && c.speed == 1.7)
        .unwrap();
    let (_, rps) = case.propeller.unwrap();
    assert_eq!(format!("{rps:.2}"), "13.96");
    let n = hydroid::dynamics::course_stability::sway_yaw(
        &m,
        &c,
        &[1.7, 0.0, 0.0, 0.0, 0.0, 0.0],
        &[0.0, rps],
    )
    .unwrap()
    .nomoto()
    .unwrap();
    assert!(n.course_stable, "{n:?}");
    assert_eq!(
        format!(
            "T1 = {:.0} s, K = {:.1} 1/s, T = {:.0} s",
            n.t1.unwrap(),
            n.k,
            n.t
        ),
        "T1 = 149 s, K = 13.1 1/s, T = 148 s"
    );
}

/// docs/models/ships.md, "KCS": a first-order Nomoto fit (nomoto_wave, configs/nomoto_ship150.toml
/// without waves: wave-yaw forcing 1e-9, compass noise 0.01 deg) to the KCS's 10/10 zig-zag
/// at 1.7 m/s (120 s at 10 Hz, rudder 16.8 deg/s from 5 s, the propeller at 13.96 rev/s)
/// gives K = 0.65 1/s and T = 6.2 s, at the digits printed there.
#[test]
fn a_first_order_fit_of_the_kcs_zigzag_gives_the_indices_of_the_docs() {
    let dir = tempfile::tempdir().unwrap();
    let sim = format!(
        "title = \"KCS 10/10\"\nmodel = \"mmg3\"\n{}\n[fluid]\nrho = 1000.0\nmu = 0.001\n\n\
         [manoeuvre]\nkind = \"time_history\"\nduration = 120\ndt = 0.1\nsubsteps = 10\n\
         initial = {{ u = \"1.7 m/s\" }}\ninputs = {{ rpm = \"13.96 rps\" }}\n\
         [manoeuvre.steering]\nkind = \"zigzag\"\nrudder = \"10 deg\"\nheading = \"10 deg\"\n\
         rate = \"16.8 deg/s\"\nexecute = \"5 s\"\n\n[export]\nfile = \"log.csv\"\n\
         layout = \"starccm\"\nwrap_angles = false\ncolumns = [\n\
         {{ quantity = \"time\", name = \"time\", unit = \"s\" }},\n\
         {{ quantity = \"yaw\", name = \"compass\", unit = \"deg\" }},\n\
         {{ quantity = \"rudder\", name = \"rudder\", unit = \"deg\" }},\n]\n",
        kcs_vehicle_sections()
    );
    std::fs::write(dir.path().join("sim.toml"), sim).unwrap();
    let o = hydroid(&["simulate", dir.path().join("sim.toml").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let nomoto = common::nomoto_ship150_config(true);
    let reference = nomoto.find("[reference]").unwrap()..nomoto.find("[hekf]").unwrap();
    let cfg = format!("{}{}", &nomoto[..reference.start], &nomoto[reference.end..]);
    let path = dir.path().join("nomoto.toml");
    std::fs::write(&path, cfg).unwrap();
    let out = dir.path().join("out");
    let o = hydroid(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let (k, t) = (
        r["steering"]["k"].as_f64().unwrap(),
        r["steering"]["t"].as_f64().unwrap(),
    );
    assert_eq!(
        format!("K = {k:.2} 1/s, T = {t:.1} s"),
        "K = 0.65 1/s, T = 6.2 s"
    );
}
