//! `hydroid manoeuvre CONFIG`: the measures of every HEKF run of a configuration, read as the
//! run reads it, with the reason for each measure a run cannot give.

use crate::common;

use common::{hydroid, text};

const LOGS: &str = "tests/fixtures/freerunning/manoeuvres.toml";

#[test]
fn measures_every_run_and_says_what_a_short_log_cannot_give() {
    let o = hydroid(&["manoeuvre", LOGS, "--scale", "45.7"]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(out.contains("turning circle 35 deg ("), "{out}");
    assert!(out.contains("zig-zag ("), "{out}");
    // these logs are short: every measure they cannot give says why, none is a number made up
    assert!(
        out.contains("advance (measured): the heading changes by"),
        "{out}"
    );
    assert!(out.contains("this needs 90 deg"), "{out}");
    assert!(!out.contains("NaN"), "{out}");
    // the IMO limits in ship lengths, on the run's scale: 4.5 L and 5 L with L = 7 m
    assert!(out.contains("<= 31.50 (MSC.137(76) 5.3.1)"), "{out}");
    assert!(out.contains("<= 35.00 (MSC.137(76) 5.3.1)"), "{out}");
    let o = hydroid(&["manoeuvre", LOGS, "--json"]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    let runs = v.as_array().unwrap();
    assert_eq!(runs.len(), 2);
    assert!(
        runs[0]["turning_circle"]["advance"]["missing"].is_string(),
        "{v}"
    );
    // without the scale ratio only the Froude-invariant criteria (in ship lengths) are judged
    let checks = runs[0]["checks"].as_array().unwrap();
    assert!(
        !checks.is_empty()
            && checks
                .iter()
                .all(|c| c["criterion"] == "advance" || c["criterion"] == "tactical_diameter"),
        "{checks:?}"
    );
}

#[test]
fn a_run_without_rudder_or_a_bad_scale_is_refused_with_the_reason() {
    let o = hydroid(&["manoeuvre", "configs/spheroid.toml"]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(err.contains("cfd_exports/turn_paper.csv"), "{err}");
    assert!(
        err.contains("needs the rudder angle (or an execute time)"),
        "{err}"
    );
    // below full scale, absurdly large, not finite: refused with the range expected
    for bad in ["0.5", "1e300", "1001", "inf", "NaN"] {
        let o = hydroid(&["manoeuvre", LOGS, "--scale", bad]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {e}");
        assert!(
            e.contains("--scale") && e.contains("expected a number from 1 (full scale) to 1000"),
            "{bad}: {e}"
        );
    }
}

/// The chain for a ship: `hydroid simulate` steers the KVLCC2 model (mmg3) through a 35 deg
/// turning circle and a 20/20 zig-zag with its helmsman, `hydroid manoeuvre` measures them.
/// Yasukawa & Yoshimura (2015) report advance about 3.1 L and tactical diameter about 3.2 L
/// for the 35 deg turn of their free-running model; the tolerance (0.35 L) covers the rudder
/// rate, the propeller held at the approach balance and basin scatter (tests/ships.rs).
#[test]
fn ship_manoeuvres_steered_by_the_helm_are_measured() {
    let o = hydroid(&[
        "manoeuvre",
        "tests/fixtures/ships/manoeuvres.toml",
        "--scale",
        "45.7",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    let l = 7.0;
    let turn = &v[0]["turning_circle"];
    let advance = turn["advance"]["value"].as_f64().unwrap() / l;
    let tactical = turn["tactical_diameter"]["value"].as_f64().unwrap() / l;
    assert!((advance - 3.1).abs() < 0.35, "advance {advance} L");
    assert!(
        (tactical - 3.2).abs() < 0.35,
        "tactical diameter {tactical} L"
    );
    // README.md: "advance 3.08 L, tactical diameter 3.12 L", at its printed digits
    assert_eq!(
        format!("advance {advance:.2} L, tactical diameter {tactical:.2} L"),
        "advance 3.08 L, tactical diameter 3.12 L"
    );
    assert_eq!(
        turn["side"], "starboard",
        "a positive rudder turns mmg3 to starboard"
    );
    // the IMO turning criteria pass, judged in ship lengths
    let checks = v[0]["checks"].as_array().unwrap();
    assert!(
        checks.len() >= 2 && checks.iter().all(|c| c["verdict"] == "pass"),
        "{checks:?}"
    );
    // the zig-zag: the helm reversed the rudder at 20 deg of heading change each time
    let z = &v[1]["zigzag"];
    let first = z["first_overshoot"]["value"].as_f64().unwrap().to_degrees();
    let second = z["second_overshoot"]["value"]
        .as_f64()
        .unwrap()
        .to_degrees();
    assert!(first > 2.0 && first < 25.0, "first overshoot {first} deg");
    assert!(second > first, "second overshoot {second} deg");
    assert!(z["period"]["value"].as_f64().unwrap() > 0.0);
}

/// The measures of `hydroid manoeuvre ARGS --json`.
fn measures(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["manoeuvre"];
    all.extend_from_slice(args);
    all.push("--json");
    let o = hydroid(&all);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("stdout is JSON")
}

/// Nominal angles given per run in the configuration, or for every run on the command line
/// (over the configuration), are those the measures are taken at; the results and the table
/// say where each comes from, and a test no IMO criterion applies to says so.
#[test]
fn nominal_angles_are_given_per_run_or_on_the_command_line() {
    let cfg = "tests/fixtures/ships/manoeuvres.toml";
    let per_run = "hekf.validation[0].manoeuvre.check=\"20 deg\"";
    let inferred = measures(&[cfg]);
    let given = measures(&[cfg, "--set", per_run]);
    let overridden = measures(&[cfg, "--set", per_run, "--check", "10"]);
    let z = |v: &serde_json::Value| v[1]["zigzag"].clone();
    let deg = |v: &serde_json::Value, key: &str| v[key]["value"].as_f64().unwrap().to_degrees();
    // the helm of `hydroid simulate` reversed the rudder at 20 deg: inferred as 20 deg
    assert_eq!(z(&inferred)["heading_angle_from"]["from"], "inferred");
    assert_eq!(z(&given)["heading_angle_from"]["from"], "given");
    assert_eq!(
        z(&given)["first_overshoot"],
        z(&inferred)["first_overshoot"]
    );
    // read as a 20/10 the first swing's peak is 10 deg further beyond the check angle
    let (a, b) = (
        deg(&z(&overridden), "first_overshoot"),
        deg(&z(&given), "first_overshoot"),
    );
    assert!((a - b - 10.0).abs() < 1e-9, "{a} {b}");
    let reasons = overridden[1]["not_judged"].as_array().unwrap();
    assert!(
        reasons[0]
            .as_str()
            .unwrap()
            .starts_with("no IMO criterion applies to a 20/10 zig-zag"),
        "{reasons:?}"
    );
    assert_eq!(
        inferred[0]["turning_circle"]["nominal_rudder_from"]["from"],
        "inferred"
    );
    // the table says where the angles come from and why no criterion is judged
    let o = hydroid(&["manoeuvre", cfg, "--rudder", "20", "--check", "10"]);
    let out = text(&o.stdout);
    assert!(
        out.contains(
            "nominal angles (measured): rudder angle nominal 20 deg, given; check angle \
             nominal 10 deg, given"
        ),
        "{out}"
    );
    assert!(
        out.contains("IMO criteria (measured): no IMO criterion applies to a 20/10 zig-zag"),
        "{out}"
    );
    // an angle out of range is refused, naming the option
    let o = hydroid(&["manoeuvre", cfg, "--rudder", "120"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("--rudder must be an angle in degrees above 0 and at most 90"));
}

/// `hydroid check` names a bad `manoeuvre` value with its file, line and key.
#[test]
fn check_reports_a_bad_nominal_angle_with_its_line() {
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/errors/manoeuvre_angles.toml",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(
        err.contains("manoeuvre_angles.toml:33: hekf.runs[0].manoeuvre.check: must be an angle"),
        "{err}"
    );
}
