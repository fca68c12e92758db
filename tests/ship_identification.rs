//! Twin experiment of the bundled ship example (configs/ship_kvlcc2.toml): the KVLCC2 model's
//! MMG hull derivatives (Yasukawa & Yoshimura 2015) identified from +-35 deg turning circles
//! made by `hydroid simulate` with sensor noise, and the identified model sailing the turns
//! and the validation 20/20 zig-zag against the truth model sailing them without noise.

use crate::common;

use common::accuracy::Accuracy;
use common::{hydroid, json, root, text};
use hydroid::dynamics::course_stability::sway_yaw;
use hydroid::model::models::mmg3::{KVLCC2, KVLCC2_RPS};
use hydroid::model::models::{Mmg3, Model};
use std::path::Path;

/// The truth: Y&Y 2015 Table 2, as configs/vehicles/kvlcc2_mmg.toml holds it.
const TRUTH: [(&str, f64); 12] = [
    ("Yv_p", -0.315),
    ("Yr_p", 0.083),
    ("Yvvv_p", -1.607),
    ("Yvvr_p", 0.379),
    ("Yvrr_p", -0.391),
    ("Yrrr_p", 0.008),
    ("Nv_p", -0.137),
    ("Nr_p", -0.049),
    ("Nvvv_p", -0.030),
    ("Nvvr_p", -0.294),
    ("Nvrr_p", 0.055),
    ("Nrrr_p", -0.013),
];

/// The hull derivatives the +-35 deg turns leave undetermined (sigma above half the value):
/// Y'vvr, Y'rrr and N'vvv, each with a sigma about as large as its value.
const UNDETERMINED: [&str; 3] = ["Yvvr_p", "Yrrr_p", "Nvvv_p"];

/// The twelve hull derivatives of a results.json against the truth, printed: the determined
/// ones within 2 sigma, the others ([`UNDETERMINED`]) flagged by hydroid's identifiability
/// advice (issue 28: a 2-sigma check of a coefficient whose sigma is its size is vacuous).
fn assert_hull(r: &serde_json::Value, title: &str) -> Accuracy {
    let hull = Accuracy::of_hekf(title, r, &TRUTH);
    println!("{}", hull.table());
    hull.assert_determined_within(&UNDETERMINED, 2.0);
    // docs/validation.md: "all within 2 sigma (1.8 at most)"
    assert!(hull.worst_z() < 1.8, "{}", hull.table());
    hull
}

/// The bundled manoeuvre `name` simulated again without its sensor noise into `dir`.
fn noise_free(dir: &Path, name: &str) -> String {
    let src =
        std::fs::read_to_string(root().join(format!("configs/simulate/{name}.toml"))).unwrap();
    let (head, rest) = src.split_once("[noise]").expect("a [noise] section");
    let (_, export) = rest.split_once("[export]").expect("an [export] section");
    let vehicle = root().join("configs/vehicles").display().to_string();
    let text = format!("{head}[export]{export}")
        .replace("../../cfd_exports/", "")
        .replace("../vehicles/", &format!("{vehicle}/"));
    let cfg = dir.join(format!("{name}.toml"));
    std::fs::write(&cfg, text).unwrap();
    let o = hydroid(&["simulate", cfg.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    cfg.display().to_string()
}

fn text_of(o: &std::process::Output) -> String {
    format!("{}{}", text(&o.stdout), text(&o.stderr))
}

#[test]
fn turning_circles_identify_the_hull_and_the_model_sails_the_zigzag_as_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = hydroid(&[
        "run",
        "configs/ship_kvlcc2.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    let console = text(&o.stdout);
    assert!(
        console.contains("20/20 zig-zag (validation): zig-zag, the identified model steered"),
        "the manoeuvre tables are on the console: {console}"
    );
    let r = json(&out.join("results.json"));
    // the manoeuvre tables follow the results schema
    let schema = json(&root().join("docs/results.schema.json"));
    let validator = jsonschema::draft202012::new(&schema).expect("the schema is valid");
    let errors: Vec<String> = validator
        .iter_errors(&r)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    let mut broken = r.clone();
    broken["resimulation"][2]["manoeuvre"]["steering"]["rate"] = serde_json::json!(-1.0);
    assert!(!validator.is_valid(&broken), "the schema checks the helm");

    // the determined hull derivatives within 2 sigma, the others flagged; the linear ones
    // within 0.8 % (README.md, docs/validation.md)
    let hull = assert_hull(&r, "configs/ship_kvlcc2.toml");
    for name in ["Yv_p", "Yr_p", "Nv_p", "Nr_p"] {
        let e = hull.row(name).error_percent();
        assert!(e.abs() < 0.8, "{name}: {e:+.3} %\n{}", hull.table());
    }
    // docs/validation.md's table at its digits
    hull.assert_printed(&[
        ("Yv_p", "-0.3165 ± 0.0033 | -0.5"),
        ("Yr_p", "0.0824 ± 0.0012 | -0.5"),
        ("Yvvv_p", "-1.68 ± 0.22 | -0.3"),
        ("Yvvr_p", "0.27 ± 0.20 | -0.6"),
        ("Yvrr_p", "-0.446 ± 0.069 | -0.8"),
        ("Yrrr_p", "-0.0006 ± 0.0091 | -0.9"),
        ("Nv_p", "-0.13686 ± 0.00060 | +0.2"),
        ("Nr_p", "-0.04899 ± 0.00023 | +0.0"),
        ("Nvvv_p", "-0.007 ± 0.028 | +0.8"),
        ("Nvvr_p", "-0.248 ± 0.035 | +1.3"),
        ("Nvrr_p", "0.080 ± 0.016 | +1.6"),
        ("Nrrr_p", "-0.0088 ± 0.0023 | +1.8"),
    ]);
    assert_correlations(&r);
    assert_manoeuvres(&r, dir.path());
    // the only warning: the cubic hull terms trade off against each other in turning
    // circles (each loose, together exact: the model sails the zig-zag as the truth)
    let warnings = r["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().all(|w| {
            let m = w["message"].as_str().unwrap();
            m.starts_with("not determined by these runs: ")
                && m.split("), ").all(|part| {
                    part.contains("vvv_p")
                        || part.contains("vvr_p")
                        || part.contains("vrr_p")
                        || part.contains("rrr_p")
                })
        }),
        "{}",
        r["warnings"]
    );

    assert_steering(&r);
}

/// docs/validation.md and docs/models/ships.md: from turns each linear pair (Y'v, Y'r) and
/// (N'v, N'r) is correlated above 0.99 (measured 0.996, 0.993), and each cubic term at 0.91
/// to 0.98 (its largest correlation with another cubic term of its equation; measured
/// 0.912 to 0.984).
fn assert_correlations(r: &serde_json::Value) {
    let c = &r["correlation"];
    let names: Vec<&str> = c["names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    let at = |a: &str, b: &str| {
        let (i, j) = (
            names.iter().position(|x| *x == a).unwrap(),
            names.iter().position(|x| *x == b).unwrap(),
        );
        c["matrix"][i][j].as_f64().unwrap().abs()
    };
    for (a, b) in [("Yv_p", "Yr_p"), ("Nv_p", "Nr_p")] {
        let rho = at(a, b);
        assert!(rho > 0.99, "{a} {b} {rho:.3}");
    }
    for eq in ["Y", "N"] {
        let cubic: Vec<String> = ["vvv", "vvr", "vrr", "rrr"]
            .iter()
            .map(|t| format!("{eq}{t}_p"))
            .collect();
        for a in &cubic {
            let most = cubic
                .iter()
                .filter(|b| *b != a)
                .map(|b| at(a, b))
                .fold(0.0, f64::max);
            assert!((0.905..0.985).contains(&most), "{a} {most:.3}");
        }
    }
}

/// The identified model steered through each run's manoeuvre (results.json `resimulation`)
/// against the truth model steered the same way without noise: docs/validation.md's table at
/// its digits, tactical diameters within 0.1 %, overshoots within 0.2 deg (README.md,
/// docs/validation.md, docs/manoeuvres.md).
fn assert_manoeuvres(r: &serde_json::Value, dir: &Path) {
    // the truth model sailing the same manoeuvres without noise
    let truth_dir = tempfile::tempdir().unwrap();
    let mut truth = Vec::new();
    for name in ["kvlcc2_turn35", "kvlcc2_turn35_port", "kvlcc2_zigzag20"] {
        noise_free(truth_dir.path(), name);
        truth.push(truth_dir.path().join(format!("{name}.csv")));
    }
    let measured = measure(&truth, dir);
    let resim = r["resimulation"].as_array().unwrap();
    assert_eq!(resim.len(), 3);
    // docs/validation.md's table at its digits: tactical diameters within 0.1 %, overshoots
    // within 0.2 deg (README.md, docs/validation.md, docs/manoeuvres.md)
    let mut rows = Vec::new();
    for (i, m) in resim.iter().enumerate() {
        let (model, truth) = (&m["manoeuvre"]["model"], &measured[i]);
        if i < 2 {
            let diameter = |v: &serde_json::Value| {
                v["turning_circle"]["tactical_diameter"]["value"]
                    .as_f64()
                    .unwrap()
            };
            let (got, want) = (diameter(model), diameter(truth));
            rows.push(format!(
                "{want:.3} m | {got:.3} m ({:+.2} %)",
                100.0 * (got / want - 1.0)
            ));
            assert!(((got - want) / want).abs() < 0.001, "{rows:?}");
            assert_eq!(
                model["turning_circle"]["side"],
                truth["turning_circle"]["side"]
            );
        } else {
            for key in ["first_overshoot", "second_overshoot"] {
                let angle = |v: &serde_json::Value| {
                    v["zigzag"][key]["value"].as_f64().unwrap().to_degrees()
                };
                let (got, want) = (angle(model), angle(truth));
                rows.push(format!("{want:.2} deg | {got:.2} deg"));
                assert!((got - want).abs() < 0.2, "{rows:?}");
            }
        }
    }
    println!("{rows:#?}");
    assert_eq!(
        rows,
        [
            "21.828 m | 21.821 m (-0.03 %)",
            "21.734 m | 21.751 m (+0.08 %)",
            "10.60 deg | 10.71 deg",
            "15.81 deg | 15.65 deg",
        ]
    );
}

/// Nomoto's indices of the identified model against the truth model's, linearised at the
/// same approach (KVLCC2 is course-unstable: K and T negative): within 2 sigma, and the
/// numbers of docs/models/ships.md at their digits.
fn assert_steering(r: &serde_json::Value) {
    let s = &r["steering"];
    let m = Mmg3::build(&Mmg3::example_vehicle()).unwrap();
    let truth = sway_yaw(
        &m,
        &m.coefficient_vector(KVLCC2),
        &[s["speed"].as_f64().unwrap(), 0.0, 0.0, 0.0, 0.0, 0.0],
        &[0.0, KVLCC2_RPS],
    )
    .unwrap()
    .nomoto()
    .unwrap();
    let got = |key: &str| {
        (
            s[key].as_f64().unwrap(),
            s[&format!("{key}_sigma")].as_f64().unwrap(),
        )
    };
    let ((k, k_sigma), (t, t_sigma)) = (got("k"), got("t"));
    let said = format!(
        "truth model K = {:.3} 1/s, T = {:.1} s; identified {k:.3} +- {k_sigma:.3} 1/s and \
         {t:.1} +- {t_sigma:.1} s",
        truth.k, truth.t
    );
    println!("{said}");
    assert!((k - truth.k).abs() <= 2.0 * k_sigma, "{said}");
    assert!((t - truth.t).abs() <= 2.0 * t_sigma, "{said}");
    assert_eq!(
        said,
        "truth model K = -1.087 1/s, T = -85.4 s; identified -1.109 +- 0.038 1/s and \
         -86.9 +- 2.5 s"
    );
    assert_eq!(s["course_stable"], false);
    assert!(!truth.course_stable);
}

/// `hydroid manoeuvre --json` of the noise-free exports, through a configuration that reads
/// them as configs/ship_kvlcc2.toml reads its runs.
fn measure(exports: &[std::path::PathBuf], dir: &Path) -> Vec<serde_json::Value> {
    let base = std::fs::read_to_string(root().join("configs/ship_kvlcc2.toml")).unwrap();
    let mut cfg = base.replace(
        "\"../cfd_exports/kvlcc2_turn35.csv\"",
        &format!("{:?}", exports[0].display().to_string()),
    );
    cfg = cfg.replace(
        "\"../cfd_exports/kvlcc2_turn35_port.csv\"",
        &format!("{:?}", exports[1].display().to_string()),
    );
    cfg = cfg.replace(
        "\"../cfd_exports/kvlcc2_zigzag20.csv\"",
        &format!("{:?}", exports[2].display().to_string()),
    );
    let path = dir.join("truth.toml");
    std::fs::write(&path, cfg).unwrap();
    let o = hydroid(&["manoeuvre", path.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    serde_json::from_slice::<serde_json::Value>(&o.stdout)
        .unwrap()
        .as_array()
        .unwrap()
        .clone()
}

/// A validation log whose rudder sign convention is the opposite of the model's: the
/// plausibility checks stop the run before the filter (the model's yaw response to the
/// rudder against the run's); run anyway (`hekf.checks = "warn"`), the model, steered with
/// the log's rudder, turns the other way, and the run says both on the console and in
/// results.json instead of printing a table that looks like a poor fit.
#[test]
fn a_model_turning_the_other_way_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let flipped = "hekf.validation[0].columns.rudder={column=\"rudder\",scale=-1}";
    let before = "turns the other way from the mmg3 model for the same rudder angle";
    let o = hydroid(&["check", "configs/ship_kvlcc2.toml", "--set", flipped]);
    assert_eq!(o.status.code(), Some(2), "{}", text_of(&o));
    assert!(text(&o.stderr).contains(before), "{}", text_of(&o));
    let o = hydroid(&[
        "run",
        "configs/ship_kvlcc2.toml",
        "--out",
        out.to_str().unwrap(),
        "--set",
        flipped,
        "--set",
        "hekf.passes=1",
        "--set",
        "hekf.checks=\"warn\"",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    let said = "the identified model turns to port where the run turns to starboard";
    assert!(text(&o.stderr).contains(said), "{}", text_of(&o));
    let r = json(&out.join("results.json"));
    let w = r["warnings"].as_array().unwrap();
    for what in [said, before] {
        assert!(
            w.iter().any(|w| w["run"] == "20/20 zig-zag"
                && (w["message"].as_str().unwrap().contains(what)
                    || w["meaning"].as_str().unwrap().contains(what))),
            "{what}: {w:?}"
        );
    }
}

/// The same turns as a model basin logs them (tests/fixtures/ships/README.md: headerless,
/// title lines, time stamps that repeat past 100 s, earth-frame velocities, degrees, rpm,
/// the rudder positive to port), read by a configuration written from docs/config.md:
/// the same estimates as from the CSV exports.
#[test]
fn basin_logs_are_read_and_identified_as_the_exports() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = hydroid(&[
        "run",
        "tests/fixtures/ships/marin_logs.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    let err = text(&o.stderr);
    assert!(err.contains("rebuilt the time base"), "{err}");
    assert!(
        err.contains("velocities rotated from the earth frame"),
        "{err}"
    );
    let r = json(&out.join("results.json"));
    let hull = assert_hull(&r, "tests/fixtures/ships/marin_logs.toml");
    for name in ["Yv_p", "Yr_p", "Nv_p", "Nr_p"] {
        let e = hull.row(name).error_percent();
        assert!(e.abs() < 0.8, "{name}: {e:+.3} %\n{}", hull.table());
    }
    // the identified model turns the way the logs do, the rudder sign read through the map
    for m in r["resimulation"].as_array().unwrap() {
        let cmp = &m["manoeuvre"];
        assert_eq!(
            cmp["model"]["turning_circle"]["side"],
            cmp["measured"]["turning_circle"]["side"]
        );
    }
}

/// Model mismatch (configs/ship_paper.toml): the paper's linear model identified on the MMG
/// model's turns fits them to a few percent but predicts the validation zig-zag poorly, and
/// the run says so (innovation test, manoeuvre comparison, re-simulation) instead of
/// presenting its tiny filter sigmas as the truth.
#[test]
fn the_papers_linear_model_on_mmg_runs_is_reported_as_a_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = hydroid(&[
        "run",
        "configs/ship_paper.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text_of(&o));
    let r = json(&out.join("results.json"));
    let said = |what: &str, run: &str| {
        r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["run"] == run && w["message"].as_str().unwrap().contains(what))
    };
    for run in ["35 deg starboard turn", "35 deg port turn"] {
        assert!(said("inconsistent with the noise model", run), "{run}");
    }
    assert!(said("predicts the zig-zag poorly", "20/20 zig-zag"));
    // the numbers docs/models/ships.md and docs/validation.md give: the filter holds the runs
    // (mean NIS 4.3 and 4.4, conservative) ...
    let runs = r["stages"]["hekf"]["runs"].as_array().unwrap();
    let mut means: Vec<String> = runs
        .iter()
        .map(|run| format!("{:.1}", run["nis"]["mean"].as_f64().unwrap()))
        .collect();
    means.sort();
    assert_eq!(means, ["4.3", "4.4"], "mean NIS of the runs");
    // ... the model misses the turns it was fitted to (tactical diameter 25.6 m against
    // 21.8 m, +17 %) and the zig-zag's second overshoot (9.8 deg against 15.8 deg)
    let resim = r["resimulation"].as_array().unwrap();
    let measure = |i: usize, which: &str, kind: &str, key: &str| {
        resim[i]["manoeuvre"][which][kind][key]["value"]
            .as_f64()
            .unwrap()
    };
    let (got, want) = (
        measure(0, "model", "turning_circle", "tactical_diameter"),
        measure(0, "measured", "turning_circle", "tactical_diameter"),
    );
    assert!(
        (25.55..25.65).contains(&got) && (21.75..21.85).contains(&want),
        "{got} against {want}"
    );
    assert_eq!(
        (100.0 * (got / want - 1.0)).round(),
        17.0,
        "{got} against {want}"
    );
    assert!(said(
        "predicts the turning circle poorly",
        "35 deg starboard turn"
    ));
    let (got, want) = (
        measure(2, "model", "zigzag", "second_overshoot").to_degrees(),
        measure(2, "measured", "zigzag", "second_overshoot").to_degrees(),
    );
    assert!(
        (9.75..9.85).contains(&got) && (15.75..15.85).contains(&want),
        "{got} against {want}"
    );
    // halving or doubling the noise model moves c2 by 17 sigma; 12 of 16 not determined
    let warned = |what: &str| {
        r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .find(|w| w["message"].as_str().unwrap().contains(what))
            .map(|w| w["message"].as_str().unwrap().to_string())
            .unwrap_or_default()
    };
    assert!(
        warned("halving or doubling").contains("c2 17."),
        "{}",
        r["warnings"]
    );
    let undetermined = warned("not determined by these runs");
    assert_eq!(
        undetermined.matches(" (sigma is").count(),
        12,
        "{undetermined}"
    );
    // Nomoto's indices: course-stable (K = 0.110 1/s, T = 5.4 s)
    let s = &r["steering"];
    let (k, t) = (s["k"].as_f64().unwrap(), s["t"].as_f64().unwrap());
    assert!(
        (0.1095..0.1105).contains(&k) && (5.35..5.45).contains(&t),
        "{s}"
    );
    assert_eq!(s["course_stable"], true);
}

/// The bundled vehicle files load with their model: each, with a fluid and a run of the
/// bundled turn, passes `hydroid check` (every key read, every particular known). The
/// paper's KCS set turns to port for a positive rudder and 70 times less than the KVLCC2 run
/// does (configs/vehicles/kcs_linear_paper.toml: kept for comparison, not as a usable
/// model): the plausibility checks say so, as a warning with `hekf.checks = "warn"`.
#[test]
fn vehicle_files_load_with_their_model() {
    let dir = tempfile::tempdir().unwrap();
    let export = root().join("cfd_exports/kvlcc2_turn35.csv");
    for (file, model, estimate, checks) in [
        ("kvlcc2_mmg.toml", "mmg3", "Yv_p", "error"),
        ("kcs_linear_paper.toml", "ship_linear", "b1", "warn"),
        ("kcs_mmg.toml", "mmg3", "Yv_p", "error"),
    ] {
        let mut text = std::fs::read_to_string(root().join("configs/vehicles").join(file)).unwrap();
        if !text.contains("[fluid]") {
            text.push_str("\n[fluid]\nrho = 1000.0\nmu = 0.001\n");
        }
        text.push_str(&format!(
            "\n[hekf]\nmodel = \"{model}\"\nestimate = [\"{estimate}\"]\nchecks = \"{checks}\"\n\
             [[hekf.runs]]\n\
             file = {:?}\n[hekf.runs.columns]\ntime = \"time\"\nx = \"x\"\ny = \"y\"\n\
             yaw = \"heading\"\nu = \"u\"\nv = \"v\"\nr = \"yaw rate\"\nrudder = \"rudder\"\n\
             rpm = \"propeller\"\n",
            export.display().to_string()
        ));
        let cfg = dir.path().join(file);
        std::fs::write(&cfg, text).unwrap();
        let o = hydroid(&["check", cfg.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{file}: {}", text_of(&o));
        let warned = String::from_utf8_lossy(&o.stdout)
            .contains("turns the other way from the ship_linear model");
        assert_eq!(warned, checks == "warn", "{file}: {}", text_of(&o));
    }
}
