//! Harmonic captive runs (issue: "Captive CFD runs and one joint estimate"): the spheroid's
//! PMM pure sway and pure yaw runs reduced to Fourier parts and fitted, alone and as the prior
//! of the joint HEKF estimate, against the truth they were simulated with; and the runs that
//! must be refused (too few whole periods, a motion that is not one sine).

use crate::common;

use common::accuracy::Accuracy;
use std::path::Path;

fn run_ok(config: &Path, out: &Path, set: &[&str]) -> (serde_json::Value, String) {
    let o = common::run_config(config, out, set);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    (
        common::json(&out.join("results.json")),
        common::text(&o.stderr),
    )
}

fn value_sigma(list: &serde_json::Value, name: &str) -> (f64, f64) {
    let c = common::named(list, name);
    (c["value"].as_f64().unwrap(), c["sigma"].as_f64().unwrap())
}

/// The issue's spheroid twin: polar, surge run, one PMM pure sway and one pure yaw run and
/// the paper's manoeuvre; joint mode gives Xud, Yvd, Nrd, Nvv, Nrr within 0.2 % with the
/// truth inside 2 sigma, a consistent innovation test, and no sigma larger than consider
/// mode's.
#[test]
fn spheroid_joint_example_meets_the_targets() {
    let dir = tempfile::tempdir().unwrap();
    let config = common::root().join("configs/spheroid_joint.toml");
    let (joint, console) = run_ok(&config, &dir.path().join("joint"), &[]);
    assert!(
        console.contains("captive: 13 coefficients from 2 harmonic runs"),
        "{console}"
    );
    let hekf = &joint["stages"]["hekf"];
    assert_joint_estimates(&joint);
    assert_innovations(hekf);
    let captive = &joint["stages"]["captive"];
    let periods = &captive["runs"][0]["periods"];
    assert_eq!(periods["periods"], 5, "{periods}");
    assert!((periods["frequency"].as_f64().unwrap() - 0.5).abs() < 1e-6);
    // docs/stages.md: the captive Y_uv,l's sigma, 0.092 kg/m with the polar's part
    let yuvl = captive["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "Yuvl")
        .unwrap();
    assert_eq!(format!("{:.3}", yuvl["sigma"].as_f64().unwrap()), "0.092");
    assert_modes(&hekf["modes"]["rows"]);
    let schema = common::json(&common::root().join("docs/results.schema.json"));
    let validator = jsonschema::draft202012::new(&schema).unwrap();
    assert!(
        validator.is_valid(&joint),
        "results.json does not follow its schema"
    );
    let report = std::fs::read_to_string(dir.path().join("joint/report.md")).unwrap();
    assert!(
        report.contains("| pure sway | v 0.2500 | 0.5000 | 5 |"),
        "{report}"
    );
}

/// The joint estimates of configs/spheroid_joint.toml against the truth: Xud, Yvd, Nrd, Nvv,
/// Nrr within 0.2 % (README.md) and 2 sigma; all 13 determined, 12 within 2 sigma, and the
/// table of docs/hekf.md, "Joint estimate", at its printed digits.
fn assert_joint_estimates(joint: &serde_json::Value) {
    let estimates = Accuracy::from_json(
        "joint estimate",
        &joint["stages"]["hekf"]["coefficients"],
        &common::spheroid_joint_truth(),
        &common::accuracy::hekf_flagged(joint),
    );
    println!("{}", estimates.table());
    for name in ["Xud", "Yvd", "Nrd", "Nvv", "Nrr"] {
        let row = estimates.row(name);
        assert!(
            row.error_percent().abs() < 0.2,
            "{name} is more than 0.2 % from its truth\n{}",
            estimates.table()
        );
        assert!(row.z.abs() < 2.0, "{name}\n{}", estimates.table());
    }
    estimates.assert_determined_within(&[], 2.5);
    assert_eq!(
        estimates.within_two_sigma(),
        (12, 13),
        "{}",
        estimates.table()
    );
    // docs/hekf.md, "The noise model's share of the uncertainty": on the bundled seed the
    // noise-model direction moves Yrr beyond chance, so it enters the budget (and no tuning
    // note says it stayed within chance)
    let yrr = &common::named(&joint["comparison"], "Yrr")["budget"];
    assert!(yrr["noise"].as_f64().unwrap() > 0.0, "{yrr}");
    let tuning = joint["stages"]["hekf"]["tuning"].to_string();
    assert!(
        !tuning.contains("within what a right noise model"),
        "{tuning}"
    );
    // Yuvl and Yvv, which the runs see only together, at -2.3 and +1.9 sigma
    estimates.assert_printed(&[
        ("Xud", "-1.1623 ± 0.0021 | 0.14 %"),
        ("Yvd", "-23.630 ± 0.005 | 0.02 %"),
        ("Nrd", "-1.4516 ± 0.0021 | 0.11 %"),
        ("Nvv", "9.997 ± 0.004 | 0.03 %"),
        ("Nrr", "-4.999 ± 0.003 | 0.03 %"),
        ("Yuvl", "-16.330 ± 0.008 | -2.3"),
        ("Yvv", "-0.423 ± 0.009 | +1.9"),
    ]);
}

/// The innovation tests of the joint run (docs/hekf.md): the paper's manoeuvre consistent,
/// mean NIS 6.04 (5.71-6.30); the surge run's 0.932 (0.882-1.122, consistent: the bounds allow
/// for its noise, estimated 1.4 % above the simulated 1 mm/s), and v, r, y and the heading held at 0 by the run, measured at
/// those values and not counted by the test.
fn assert_innovations(hekf: &serde_json::Value) {
    let nis = &hekf["runs"][0]["nis"];
    assert_eq!(nis["consistent"], true, "{nis}");
    let surge = &hekf["runs"][1];
    let u = common::named_by(&surge["noise"], "quantity", "u");
    let said = format!(
        "{:.2} ({:.2}-{:.2}); {:.3} ({:.3}-{:.3}); u noise {:+.1} %",
        nis["mean"].as_f64().unwrap(),
        nis["mean_bounds"][0].as_f64().unwrap(),
        nis["mean_bounds"][1].as_f64().unwrap(),
        surge["nis"]["mean"].as_f64().unwrap(),
        surge["nis"]["mean_bounds"][0].as_f64().unwrap(),
        surge["nis"]["mean_bounds"][1].as_f64().unwrap(),
        100.0 * (u["sigma"].as_f64().unwrap() / 1e-3 - 1.0)
    );
    assert_eq!(
        said,
        "6.04 (5.71-6.30); 0.932 (0.882-1.122); u noise +1.4 %"
    );
    assert_eq!(surge["nis"]["dof"], 1, "{surge}");
    // docs/hekf.md: "the chi-square bounds alone, 0.939-1.063": the widening undone
    // (half-widths scaled by sqrt(1 + extra k / (2 dof)) about dof)
    let s = &surge["nis"];
    let k = s["samples"].as_f64().unwrap();
    let extra = s["noise_estimate_variance"].as_f64().unwrap();
    let widen = (1.0 + extra * k / 2.0).sqrt();
    let chi = |b: f64| 1.0 + (b - 1.0) / widen;
    assert_eq!(
        format!(
            "{:.3}-{:.3}",
            chi(s["mean_bounds"][0].as_f64().unwrap()),
            chi(s["mean_bounds"][1].as_f64().unwrap())
        ),
        "0.939-1.063"
    );
    let v = common::named_by(&surge["noise"], "quantity", "v");
    assert_eq!(v["source"], "held constant by the run (constants)", "{v}");
}

/// Consider mode, run beside joint mode (`stages.hekf.modes.rows`): no joint sigma above
/// it; its column of docs/hekf.md's table; the yaw scale pinned by the captive stage alone.
fn assert_modes(rows: &serde_json::Value) {
    for (name, _) in common::spheroid_joint_truth() {
        let row = common::named(rows, name);
        let (sj, sc) = (
            row["joint"][1].as_f64().unwrap(),
            row["consider"][1].as_f64().unwrap(),
        );
        assert!(
            sj <= sc * 1.0001,
            "{name}: joint sigma {sj} > consider sigma {sc}"
        );
    }
    let consider: Vec<String> = ["Xud", "Yvd", "Nrd", "Nvv", "Nrr"]
        .iter()
        .map(|n| {
            let row = common::named(rows, n);
            if row["undetermined_by_runs"] == true {
                "not determined".to_string()
            } else {
                let c = &row["consider"];
                format!(
                    "{:.4} +- {:.4}",
                    c[0].as_f64().unwrap(),
                    c[1].as_f64().unwrap()
                )
            }
        })
        .collect();
    assert_eq!(
        consider,
        [
            "-1.1608 +- 0.0023",
            "-23.6282 +- 0.0057",
            "not determined",
            "not determined",
            "not determined"
        ]
    );
    let nrd = common::named(rows, "Nrd");
    assert!(
        nrd["pinned_by"]
            .as_str()
            .unwrap()
            .starts_with("captive stage: free-running data alone do not determine it"),
        "{nrd}"
    );
}

/// The captive stage alone (configs/spheroid_joint.toml without its HEKF stage): the 11
/// coefficients the two harmonic runs determine within 2.1 sigma of the truth (9 within 2:
/// Xud and Nuvl at -2.04, one seed of sigmas that cover 95 % at 2), and the two they leave
/// undetermined, Yrr (360 % off, sigma 0.77 kg m against 0.5) and Yvv (sigma 0.85 kg/m
/// against 0.44), flagged in the comparison table (docs/stages.md).
#[test]
fn the_captive_stage_alone_flags_what_it_leaves_undetermined() {
    let dir = tempfile::tempdir().unwrap();
    let config = common::root().join("configs/spheroid_joint.toml");
    let (r, _) = run_ok(&config, &dir.path().join("out"), &["hekf.enabled=false"]);
    let alone = Accuracy::from_json(
        "captive stage alone",
        &r["coefficients"],
        &common::spheroid_joint_truth(),
        &common::accuracy::comparison_flagged(&r),
    );
    println!("{}", alone.table());
    alone.assert_determined_within(&["Yrr", "Yvv"], 2.1);
    alone.assert_printed(&[
        ("Yvd", "-23.639 ± 0.011 | -1.1"),
        ("Nrd", "-1.4519 ± 0.0027 | +0.5"),
        ("Xud", "-1.34 ± 0.09 | -2.0"),
        ("Nvv", "10.22 ± 0.23 | +1.0"),
        ("Yrr", "2.30 ± 0.77 | 360 %"),
        ("Yvv", "-0.49 ± 0.85 | -0.1"),
    ]);
}

/// Writes a force history with the given v(t) (u = 2 m/s) and forces of the truth-free
/// shape: enough for the reduction's checks, which come before any fit.
fn history(path: &Path, duration: f64, v: impl Fn(f64) -> f64, transient: impl Fn(f64) -> f64) {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let noise = Normal::new(0.0, 0.05).unwrap();
    let mut s = String::from("time [s],u [m/s],v [m/s],r [rad/s],fx [N],fy [N],mz [N m]\n");
    for k in 0..=(duration * 100.0).round() as usize {
        let t = k as f64 / 100.0;
        let vv = v(t);
        let mut n = || noise.sample(&mut rng);
        s.push_str(&format!(
            "{t},2,{vv},0,{},{},{}\n",
            -5.3 + 0.1 * vv + n(),
            -15.0 * vv + transient(t) + n(),
            9.0 * vv + n()
        ));
    }
    std::fs::write(path, s).unwrap();
}

fn config(dir: &Path, file: &Path) -> std::path::PathBuf {
    let text = format!(
        r#"
[vehicle]
name = "spheroid"
mass = 50.0
length = 1.2
izz = 3.7
reference_area = 0.0314159265
reference_length = 1.0
[fluid]
rho = 1025.0
mu = 0.0009
[coefficients]
Xud = -1.164
Xuu = -1.33
Xuv = 0.44
Xvv = -5.38
Yvv = -0.44
Yuvd = 1.33
Yuvl = -16.31
Nuvl = 13.43
Yrd = 0.0
Nrd = -1.45
Yrr = 0.5
Nrr = -5.0
[captive]
model = "spheroid3"
estimate = ["Yvd", "Nvv"]
average_after = 0
[[captive.runs]]
name = "sway"
file = "{}"
constants = {{ thrust = 0 }}
columns = {{ time = "time [s]", u = "u [m/s]", v = "v [m/s]", r = "r [rad/s]", fx = "fx [N]", fy = "fy [N]", mz = "mz [N m]" }}
"#,
        file.display()
    );
    let path = dir.join("c.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn refused(v: impl Fn(f64) -> f64, duration: f64) -> String {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sway.csv");
    history(&file, duration, v, |_| 0.0);
    let cfg = config(dir.path(), &file);
    let out = dir.path().join("out");
    let o = common::run_config(&cfg, &out, &[]);
    assert_ne!(o.status.code(), Some(0));
    assert!(!out.join("results.json").exists(), "no output on an error");
    common::text(&o.stderr)
}

#[test]
fn a_run_with_fewer_than_two_whole_periods_is_refused() {
    let e = refused(|t| 0.25 * (std::f64::consts::PI * t).sin(), 3.5);
    assert!(e.contains("run 'sway'"), "{e}");
    assert!(e.contains("at least 2 whole periods"), "{e}");
}

#[test]
fn a_motion_that_is_not_one_sine_is_refused() {
    // a square-ish wave: strong third harmonic
    let e = refused(
        |t| {
            let p = std::f64::consts::PI * t;
            0.25 * (p.sin() + 0.3 * (3.0 * p).sin())
        },
        10.0,
    );
    assert!(e.contains("the motion is not harmonic"), "{e}");
    assert!(e.contains("v has a first harmonic"), "{e}");
}

/// A start-up transient left in the periods used is said (the first and second half of the
/// periods disagree); starting after it, it is not.
#[test]
fn a_transient_in_the_periods_used_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sway.csv");
    history(
        &file,
        16.0,
        |t| 0.25 * (std::f64::consts::PI * t).sin(),
        |t| 3.0 * (-t / 0.5).exp(),
    );
    let cfg = config(dir.path(), &file);
    let (_, said) = run_ok(&cfg, &dir.path().join("early"), &[]);
    assert!(said.contains("the force harmonics change"), "{said}");
    assert!(said.contains("run 'sway'"), "{said}");
    let (r, said) = run_ok(&cfg, &dir.path().join("late"), &["captive.average_after=8"]);
    assert!(!said.contains("the force harmonics change"), "{said}");
    let periods = &r["stages"]["captive"]["runs"][0]["periods"];
    assert_eq!(periods["periods"], 4, "{periods}");
    assert_eq!(periods["from"], 8.0, "{periods}");
}

/// Sign constraints (clarabel steps): an inactive one changes nothing; one the data push
/// against holds its coefficient at 0, says so, and leaves the others fitted.
#[test]
fn sign_constraints_hold_a_coefficient_at_its_bound() {
    let dir = tempfile::tempdir().unwrap();
    let config = common::root().join("configs/spheroid_joint.toml");
    let only_captive = ["hekf.enabled=false"];
    let (free, _) = run_ok(&config, &dir.path().join("free"), &only_captive);
    let (inactive, _) = run_ok(
        &config,
        &dir.path().join("inactive"),
        &[
            only_captive[0],
            "captive.signs.Yvd=\"negative\"",
            "captive.signs.Nrd=\"negative\"",
        ],
    );
    let free_c = &free["stages"]["captive"]["coefficients"];
    let yvd = value_sigma(free_c, "Yvd");
    let yvd_inactive = value_sigma(&inactive["stages"]["captive"]["coefficients"], "Yvd");
    assert!(
        (yvd.0 - yvd_inactive.0).abs() < 1e-6 * yvd.0.abs(),
        "{yvd:?} {yvd_inactive:?}"
    );
    assert!(
        (yvd.1 - yvd_inactive.1).abs() < 1e-6 * yvd.1,
        "{yvd:?} {yvd_inactive:?}"
    );
    // Yrd (truth 0) comes out negative here: asked to be positive, it is held at 0
    let yrd_free = value_sigma(free_c, "Yrd").0;
    assert!(yrd_free < 0.0, "{yrd_free}");
    let (held, said) = run_ok(
        &config,
        &dir.path().join("held"),
        &[only_captive[0], "captive.signs.Yrd=\"positive\""],
    );
    assert!(
        said.contains("held at their sign bound 0 (captive.signs): Yrd"),
        "{said}"
    );
    let c = common::named(&held["stages"]["captive"]["coefficients"], "Yrd");
    assert_eq!(c["value"].as_f64().unwrap(), 0.0);
    // held by the constraint: no sigma (shown "0 (held)", never "0 ± 0")
    assert!(c["sigma"].is_null(), "{c}");
    let (v, s) = value_sigma(&held["stages"]["captive"]["coefficients"], "Nrd");
    assert!((v + 1.4532).abs() < 3.0 * s, "Nrd {v} ± {s}");
}

/// A PMM programme's mistakes are said with their keys, and nothing is written.
#[test]
fn a_pmm_programme_with_mistakes_names_every_key() {
    let dir = tempfile::tempdir().unwrap();
    let sim =
        std::fs::read_to_string(common::root().join("configs/simulate/spheroid_pmm_sway.toml"))
            .unwrap()
            .replace(
                "file = \"../../cfd_exports/spheroid_pmm_sway.forces.dat\"",
                &format!("file = \"{}\"", dir.path().join("out.dat").display()),
            );
    let check = |bad: String, keys: &[&str]| {
        let cfg = dir.path().join("bad.toml");
        std::fs::write(&cfg, bad).unwrap();
        let o = common::hydroid(&["simulate", cfg.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", common::text(&o.stderr));
        let e = common::text(&o.stderr);
        for k in keys {
            assert!(e.contains(k), "{k}: {e}");
        }
        assert!(!dir.path().join("out.dat").exists());
    };
    check(
        sim.replace("frequency = \"0.5 Hz\"", "frequency = \"0.5 m\""),
        &["manoeuvre.frequency", "expected a frequency"],
    );
    check(
        sim.replace(
            "amplitude = { v = \"0.25 m/s\" }",
            "amplitude = { x = \"0.25 m\" }",
        )
        .replace("dt = 0.01", "dt = 0.5"),
        &[
            "manoeuvre.amplitude.x: a PMM oscillates a velocity of the model",
            "manoeuvre.dt",
            "fewer than 20 samples",
        ],
    );
    // a model without forces for a prescribed motion
    check(
        sim.replace("model = \"spheroid3\"", "model = \"spheroid6\""),
        &["this model gives no forces for a prescribed motion, so it has no PMM runs"],
    );
    // a key of another kind of manoeuvre
    check(
        sim.replace("kind = \"pmm\"", "kind = \"pmm\"\nspeeds = [2.0]"),
        &["manoeuvre.speeds: is not used by a pmm manoeuvre"],
    );
}

/// Stage conflicts (docs/stages.md): the spheroid's lift-only polar read as the total yaw
/// moment gives a Nuv the PMM runs contradict by hundreds of sigma; the run warns with both
/// values and names `polar.moment.part`, and `--strict` exits with status 3. Read as it is,
/// no conflict is warned.
#[test]
fn a_polar_read_with_the_wrong_moment_part_conflicts_with_the_pmm_runs() {
    let config = common::root().join("configs/spheroid_joint.toml");
    let list = "[\"Xud\", \"Yvd\", \"Yrd\", \"Nrd\", \"Nvv\", \"Nrr\", \"Yrr\", \"Yuvl\", \
                \"Nuv\", \"Xuu\", \"Xuv\", \"Xvv\", \"Yvv\"]";
    let captive = format!("captive.estimate={list}");
    let wrong = [
        captive.as_str(),
        "polar.moment.part=\"total\"",
        "hekf.enabled=false",
    ];
    let dir = tempfile::tempdir().unwrap();
    let (r, console) = run_ok(&config, &dir.path().join("wrong"), &wrong);
    let said = console
        .lines()
        .find(|l| l.contains("disagree on Nuv"))
        .unwrap_or_else(|| panic!("no conflict warned:\n{console}"));
    assert!(said.contains("captive gives -9.053 ± 0.02480"), "{said}");
    assert!(
        said.contains("the polar stage gave 13.39 ± 0.03397"),
        "{said}"
    );
    assert!(said.contains("533.7 sigma apart"), "{said}");
    assert!(
        console.contains("`polar.moment.part` is \"total\""),
        "{console}"
    );
    let conflict = r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["message"].as_str().unwrap().contains("disagree on Nuv"))
        .unwrap_or_else(|| panic!("{}", r["warnings"]));
    assert_eq!(conflict["failed_test"], "stage_conflict");
    // `run --strict` with `set`: its exit status and what it said
    let strict = |out: &str, set: &[&str]| {
        let out = dir.path().join(out);
        let mut args = vec!["run", config.to_str().unwrap(), "--strict", "--out"];
        args.push(out.to_str().unwrap());
        for s in set {
            args.extend(["--set", s]);
        }
        let o = common::hydroid(&args);
        (o.status.code(), common::text(&o.stderr), out)
    };
    // the same run exits with status 3 and names the test, the output written
    let (code, err, out) = strict("strict", &wrong);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("consistency tests failed (stage conflict)"),
        "{err}"
    );
    assert!(out.join("results.json").is_file());
    // the bundled configuration (polar lift-only, captive Nuvl): nothing to warn, and
    // --strict exits with 0
    let (code, err, _) = strict("right", &["hekf.enabled=false"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("disagree"), "{err}");
}
