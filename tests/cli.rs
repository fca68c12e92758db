//! The command line as a user meets it: the bundled example end to end, exit codes, every
//! problem of a bad configuration listed with its place, reruns and comparisons.

use crate::common;

use common::{
    copy_example, hydroid, hydroid_in, json, named, root, run_example, text, ExampleRun,
    ANALYTIC_PAPER_SPHEROID,
};
use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

/// One run of the bundled example into a temporary folder, shared by the tests that read it.
fn example_run() -> &'static ExampleRun {
    static RUN: OnceLock<ExampleRun> = OnceLock::new();
    RUN.get_or_init(|| run_example(&[]))
}

fn example_out() -> PathBuf {
    example_run().out.clone()
}

#[test]
fn help_and_usage_errors() {
    let o = hydroid(&["--help"]);
    assert_eq!(o.status.code(), Some(0));
    for cmd in [
        "run",
        "check",
        "inspect",
        "simulate",
        "analytic",
        "rerun",
        "compare",
        "calibrate",
    ] {
        assert!(text(&o.stdout).contains(cmd), "--help lists {cmd}");
        let h = hydroid(&[cmd, "--help"]);
        assert_eq!(h.status.code(), Some(0), "{cmd} --help");
    }
    // the texts that name the models name every registered one
    for args in [
        &["--help"][..],
        &["coefficients", "--help"],
        &["init", "--help"],
    ] {
        let o = hydroid(args);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        let help = text(&o.stdout);
        for model in hydroid::model::models::ModelName::NAMES {
            assert!(
                help.contains(model),
                "{args:?} does not name {model}:\n{help}"
            );
        }
    }
    let help = text(&hydroid(&["--help"]).stdout);
    for kind in [
        "Surface ships",
        "Course keeping in waves",
        "six degrees of freedom",
    ] {
        assert!(help.contains(kind), "--help says nothing of {kind}");
    }
    let o = hydroid(&["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
}

#[test]
fn bundled_example_runs_end_to_end() {
    let o = &example_run().output;
    assert_eq!(o.status.code(), Some(0), "stderr: {}", text(&o.stderr));
    let stdout = text(&o.stdout);
    // the comparison table goes to stdout, progress to stderr
    assert!(
        stdout.contains("coefficient") && stdout.contains("Yvd"),
        "{stdout}"
    );
    assert!(text(&o.stderr).contains("hekf:"), "{}", text(&o.stderr));
    let out = example_out();
    for f in [
        "results.json",
        "coefficients.csv",
        "inputs.json",
        "config.toml",
        "rerun.json",
    ] {
        let p = out.join(f);
        assert!(
            p.is_file() && std::fs::metadata(&p).unwrap().len() > 0,
            "{f}"
        );
    }
    let r = json(&out.join("results.json"));
    assert_eq!(r["schema"], "hydroid-results/2");
    let get = |n: &str| named(&r["coefficients"], n);
    // every stage contributed, with a sigma
    for (n, src) in [
        ("Xuu", "polar"),
        ("Xud", "surge"),
        ("Yvd", "hekf"),
        ("Xvr", "symmetry"),
    ] {
        assert_eq!(get(n)["source"], src, "{n}");
        assert!(get(n)["sigma"].as_f64().unwrap() > 0.0, "{n}");
    }
    // the sigma of an HEKF estimate includes the uncertainty of the fixed coefficients
    let hekf = &r["stages"]["hekf"];
    let i = hekf["estimated"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n == "Nrd")
        .unwrap();
    let filter_only = hekf["sigma_filter"][i].as_f64().unwrap();
    assert!(get("Nrd")["sigma"].as_f64().unwrap() > 10.0 * filter_only);
    // inputs are recorded with their hashes, relative to the configuration
    let inputs = r["inputs"].as_array().unwrap();
    assert_eq!(inputs.len(), 4);
    assert!(inputs
        .iter()
        .all(|i| i["sha256"].as_str().unwrap().len() == 64));
    assert!(inputs
        .iter()
        .any(|i| i["file"] == "../cfd_exports/turn_paper.csv"));
    // the validation run is re-simulated
    let resim = r["resimulation"].as_array().unwrap();
    assert!(resim.iter().any(|m| m["used_for_fit"] == false));
    assert!(!std::fs::read_to_string(out.join("results.json"))
        .unwrap()
        .contains("NaN"));
}

#[test]
fn identical_inputs_give_byte_identical_results() {
    let first = example_out();
    let again = run_example(&[]);
    let (second, o) = (&again.out, &again.output);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    for f in ["results.json", "coefficients.csv"] {
        let a = std::fs::read(first.join(f)).unwrap();
        let b = std::fs::read(second.join(f)).unwrap();
        assert!(a == b, "{f} differs between two runs");
    }
}

#[test]
fn check_prints_a_clean_summary_of_the_bundled_config() {
    let o = hydroid(&["check", "configs/spheroid.toml"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    assert!(s.contains("stages: polar -> surge -> hekf"), "{s}");
    assert!(s.contains("turn_paper.csv (cfx, 2001 rows"), "{s}");
    assert!(s.contains("ok:"), "{s}");
}

#[test]
fn check_lists_all_three_mistakes_with_their_lines() {
    let o = hydroid(&["check", "tests/fixtures/configs/three_mistakes.toml"]);
    assert_eq!(o.status.code(), Some(2));
    let e = text(&o.stderr);
    assert!(e.contains("3 problems"), "{e}");
    assert!(
        e.contains("three_mistakes.toml:4") && e.contains("did you mean `length`"),
        "{e}"
    );
    assert!(
        e.contains("three_mistakes.toml:3: vehicle.mass") && e.contains("-50"),
        "{e}"
    );
    assert!(
        e.contains(":16: surge.runs[0].file") && e.contains("no_such_file.csv"),
        "{e}"
    );
}

/// A broken configuration, the exit code of `check` and fragments its message must contain.
struct Bad {
    file: &'static str,
    code: i32,
    says: &'static [&'static str],
}

const BAD: &[Bad] = &[
    Bad {
        file: "syntax.toml",
        code: 2,
        says: &["syntax.toml:3"],
    },
    Bad {
        file: "unknown_section.toml",
        code: 2,
        says: &[":10", "`fluidd`", "did you mean `fluid`"],
    },
    Bad {
        file: "wrong_type.toml",
        code: 2,
        says: &[":3", "vehicle.mass", "\"fifty\" is not a number"],
    },
    Bad {
        file: "missing_mass.toml",
        code: 2,
        says: &["vehicle.mass", "required key `mass` is missing"],
    },
    Bad {
        file: "zero_area.toml",
        code: 2,
        says: &[":7: vehicle.reference_area", "positive"],
    },
    Bad {
        file: "negative_rho.toml",
        code: 2,
        says: &[":11: fluid.rho", "-1025"],
    },
    Bad {
        file: "unknown_quantity.toml",
        code: 2,
        says: &[":34", "`yawn`", "did you mean `yaw`"],
    },
    Bad {
        file: "unknown_format.toml",
        code: 2,
        says: &[":29", "`cfx5`", "did you mean `cfx`"],
    },
    Bad {
        file: "unknown_coefficient.toml",
        code: 2,
        says: &[":25: hekf.estimate[0]", "'Yvdd'", "did you mean 'Yvd'"],
    },
    Bad {
        file: "bad_constant.toml",
        code: 2,
        says: &[":29", "'furlongs'"],
    },
    Bad {
        file: "prior_not_estimated.toml",
        code: 2,
        says: &[":27: hekf.prior.Xuu", "not in hekf.estimate"],
    },
    Bad {
        file: "spheroid6_without_inertia.toml",
        code: 2,
        says: &["vehicle.ixx", "vehicle.iyy", "spheroid6"],
    },
    Bad {
        file: "diameter_too_large.toml",
        code: 2,
        says: &[":5: vehicle.diameter", "not smaller than the length"],
    },
    Bad {
        file: "derived_estimate.toml",
        code: 2,
        says: &["'Xvr'", "symmetry relation"],
    },
    Bad {
        file: "coefficient_missing.toml",
        code: 2,
        says: &["no value for Xuv", "[coefficients]"],
    },
    Bad {
        file: "missing_thrust.toml",
        code: 2,
        says: &["gives no thrust", "constants"],
    },
    Bad {
        file: "bad_unit.toml",
        code: 2,
        says: &[":34: hekf.runs[0].columns.yaw.unit", "'degs'"],
    },
    Bad {
        file: "missing_column.toml",
        code: 1,
        says: &["turn_paper.csv", "no column for u", "closest: 'Velocity u'"],
    },
];

#[test]
fn every_bad_configuration_is_named_and_placed() {
    for b in BAD {
        let path = format!("tests/fixtures/configs/bad/{}", b.file);
        let o = hydroid(&["check", &path]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(b.code), "{}: {e}", b.file);
        assert!(!e.contains("panicked"), "{}: {e}", b.file);
        assert!(
            e.contains(b.file) || e.contains("turn_paper.csv"),
            "{}: {e}",
            b.file
        );
        for s in b.says {
            assert!(e.contains(s), "{}: expected '{s}' in\n{e}", b.file);
        }
        // `run` refuses the same configuration without writing anything
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let r = hydroid(&["run", &path, "--out", out.to_str().unwrap()]);
        assert_eq!(
            r.status.code(),
            Some(b.code),
            "run {}: {}",
            b.file,
            text(&r.stderr)
        );
        assert!(!out.exists(), "run {} left an output folder", b.file);
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "{} left files",
            b.file
        );
    }
}

#[test]
fn set_overrides_keys_and_suggests_for_unknown_ones() {
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/base.toml",
        "--set",
        "hekf.passs=3",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("did you mean `passes`"),
        "{}",
        text(&o.stderr)
    );
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/base.toml",
        "--set",
        "vehicle.mass=-1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("vehicle.mass"),
        "{}",
        text(&o.stderr)
    );
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/base.toml",
        "--set",
        "hekf.passes=5",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
}

#[test]
fn effective_configuration_is_echoed() {
    let out = example_out();
    let c = std::fs::read_to_string(out.join("config.toml")).unwrap();
    assert!(
        c.contains("preset = \"hydroid\"") && c.contains("mass = 50.0"),
        "{c}"
    );
    // defaults are filled in: the polar constraints are there although the file omits them
    assert!(c.contains("a_nonnegative = true"), "{c}");
}

#[test]
fn rerun_reproduces_and_refuses_changed_inputs() {
    let dir = tempfile::tempdir().unwrap();
    copy_example(dir.path());
    let out = dir.path().join("out");
    // run with a relative path from the example's folder, rerun from elsewhere: the results
    // do not depend on where hydroid was started
    let o = hydroid_in(
        dir.path(),
        &["run", "configs/spheroid.toml", "--out", "out"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let before = std::fs::read(out.join("results.json")).unwrap();
    let o = hydroid(&["rerun", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        std::fs::read(out.join("results.json")).unwrap() == before,
        "rerun changed results.json"
    );
    // change one input: rerun refuses, naming it, unless told otherwise
    let export = dir.path().join("cfd_exports/surge_run.csv");
    let mut t = std::fs::read_to_string(&export).unwrap();
    t = t.replacen("0.01, 0.5", "0.01, 0.6", 1);
    t.push('\n');
    std::fs::write(&export, t).unwrap();
    let o = hydroid(&["rerun", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let e = text(&o.stderr);
    assert!(e.contains("surge_run.csv") && e.contains("changed"), "{e}");
    assert!(
        std::fs::read(out.join("results.json")).unwrap() == before,
        "a refused rerun wrote"
    );
    let o = hydroid(&["rerun", out.to_str().unwrap(), "--allow-changed-inputs"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));

    // an edited config.toml (or rerun.json, inputs.json) of the output folder is refused,
    // naming it, unless --edited accepts it
    let after = std::fs::read(out.join("results.json")).unwrap();
    let cfg = out.join("config.toml");
    let t = std::fs::read_to_string(&cfg).unwrap();
    std::fs::write(&cfg, t.replacen("title = \"", "title = \"edited: ", 1)).unwrap();
    for extra in [&[][..], &["--force"][..], &["--allow-changed-inputs"][..]] {
        let mut args = vec!["rerun", out.to_str().unwrap()];
        args.extend(extra);
        let o = hydroid(&args);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {e}");
        assert!(
            e.contains(&format!("{}", cfg.display())) && e.contains("--edited"),
            "{extra:?}: {e}"
        );
        assert_eq!(std::fs::read(out.join("results.json")).unwrap(), after);
    }
    let o = hydroid(&["rerun", out.to_str().unwrap(), "--edited"]);
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(
        e.contains("config.toml was edited") && e.contains("--edited"),
        "{e}"
    );
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
    assert!(
        r["title"].as_str().unwrap().starts_with("edited: "),
        "the edited configuration ran: {}",
        r["title"]
    );
    // a rerun.json edited by hand is refused the same way
    let rj = out.join("rerun.json");
    let t = std::fs::read_to_string(&rj).unwrap();
    std::fs::write(&rj, t.replacen('{', "{ ", 1)).unwrap();
    let o = hydroid(&["rerun", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("rerun.json"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn compare_prints_differences_between_two_runs() {
    let a = example_out();
    let one_pass = run_example(&["--set", "hekf.passes=1"]);
    let (b, o) = (&one_pass.out, &one_pass.output);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = hydroid(&[
        "compare",
        a.to_str().unwrap(),
        b.join("results.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    assert!(s.contains("(B - A)/sigma"), "{s}");
    let nrd = s.lines().find(|l| l.starts_with("Nrd")).unwrap();
    assert!(nrd.contains("hekf"), "{nrd}");
    let o = hydroid(&["compare", a.to_str().unwrap(), "configs/spheroid.toml"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("not a hydroid results.json"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn closed_stdout_is_not_a_panic() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(ANALYTIC_PAPER_SPHEROID)
        .args(["--rho", "1025"])
        .current_dir(root())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert!(!text(&o.stderr).contains("panicked"), "{}", text(&o.stderr));
}

#[test]
fn bundled_exports_are_what_their_simulate_configs_make() {
    let dir = tempfile::tempdir().unwrap();
    for (cfg, export) in [
        ("polar_sweep", "polar_sweep.csv"),
        ("surge_run", "surge_run.csv"),
        ("turn_paper", "turn_paper.csv"),
        ("turn_validation", "turn_validation.csv"),
        ("kvlcc2_turn35", "kvlcc2_turn35.csv"),
        ("kvlcc2_turn35_port", "kvlcc2_turn35_port.csv"),
        ("nomoto_zigzag_waves", "nomoto_zigzag_waves.csv"),
        ("kvlcc2_zigzag20", "kvlcc2_zigzag20.csv"),
        ("ship150_zigzag20", "ship150_zigzag20.csv"),
        ("ship150_nomoto_waves", "ship150_nomoto_waves.csv"),
        ("npsauv_helix", "npsauv_helix.dat"),
        ("npsauv_zigzag_vertical", "npsauv_zigzag_vertical.csv"),
        ("npsauv_zigzag_horizontal", "npsauv_zigzag_horizontal.csv"),
        ("kvlcc2_captive", "kvlcc2_captive.csv"),
        ("spheroid_pmm_sway", "spheroid_pmm_sway.forces.dat"),
        ("spheroid_pmm_yaw", "spheroid_pmm_yaw.forces.dat"),
    ] {
        let out = dir.path().join(export);
        let o = hydroid(&[
            "simulate",
            &format!("configs/simulate/{cfg}.toml"),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{cfg}: {}", text(&o.stderr));
        let made = std::fs::read(&out).unwrap();
        let bundled = std::fs::read(root().join("cfd_exports").join(export)).unwrap();
        assert!(
            made == bundled,
            "cfd_exports/{export} is stale: rerun hydroid simulate"
        );
    }
}

/// The whole chain on a 6-DOF run: `hydroid simulate` writes OpenFOAM sixDoFRigidBodyState
/// output (earth-frame velocities, angles and rates in degrees), the reader detects it, the
/// velocities are rotated into the body frame, and the 6-DOF model is identified.
#[test]
fn six_dof_export_round_trip_identifies_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    let export = dir.path().join("sixdof.dat");
    let o = hydroid(&[
        "simulate",
        "tests/fixtures/configs/sixdof/sim.toml",
        "--out",
        export.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let inspect = hydroid(&["inspect", export.to_str().unwrap()]);
    assert!(text(&inspect.stdout).contains("openfoam-sixdof"));
    let out = dir.path().join("out");
    let set = format!("hekf.runs[0].file={:?}", export.to_str().unwrap());
    let o = hydroid(&[
        "run",
        "tests/fixtures/configs/sixdof/run.toml",
        "--set",
        &set,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let r = json(&out.join("results.json"));
    let hekf = &r["stages"]["hekf"];
    assert_eq!(hekf["model"], "spheroid6");
    assert_eq!(hekf["runs"][0]["measured"].as_array().unwrap().len(), 12);
    for (name, truth) in [
        ("Yvd", -23.626),
        ("Nrd", -1.4532),
        ("Nvv", 10.0),
        ("Nrr", -5.0),
    ] {
        let c = named(&hekf["coefficients"], name);
        let v = c["value"].as_f64().unwrap();
        assert!(
            (v - truth).abs() < 0.01 * truth.abs(),
            "{name} = {v}, truth {truth}"
        );
    }
}
