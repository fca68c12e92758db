//! What the command line prints and where: `--verbose` and `--quiet`, `--json` on stdout with
//! everything else on stderr, and unchanged exit codes.

use crate::common;

use common::{bundled_config_text, hydroid, named, run_example, text, ExampleRun};

/// The bundled example without the HEKF (well under a second), into a temporary folder, with
/// an input read in the earth frame so that the run has a warning.
fn quick_run(extra: &[&str]) -> ExampleRun {
    let mut args = vec![
        "--set",
        "hekf.enabled=false",
        "--set",
        "surge.runs[0].velocity_frame=\"earth\"",
        "--set",
        "surge.runs[0].constants={yaw=0}",
    ];
    args.extend_from_slice(extra);
    run_example(&args)
}

#[test]
fn quiet_prints_only_warnings_and_keeps_the_table() {
    let run = quick_run(&["--quiet"]);
    let o = &run.output;
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let stderr = text(&o.stderr);
    // warnings (each with its meaning), grouped by kind with the notes on how the inputs
    // were read last, and nothing else
    assert!(
        stderr.trim_end().ends_with(
            "note: input, run 'surge run': velocities rotated from the earth \
                            frame into the body frame"
        ),
        "{stderr}"
    );
    for line in stderr.lines() {
        assert!(
            line.starts_with("warning: ")
                || line.starts_with("  meaning: ")
                || line.starts_with("note: "),
            "{line}"
        );
    }
    // the results table stays on stdout, grouped by stage in pipeline order
    let table = text(&o.stdout);
    let names: Vec<&str> = table
        .lines()
        .skip(1)
        .take_while(|l| !l.is_empty() && !l.starts_with(' '))
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert_eq!(
        names,
        ["Xuu", "Xuv", "Xvv", "Yvv", "Yuvd", "Yuvl", "Nuvl", "Xud", "Yur", "Yuv"],
        "{table}"
    );
    // the same run without --quiet says what each stage did
    let o = quick_run(&[]).output;
    assert!(text(&o.stderr).contains("polar: 7 coefficients"));
    // --quiet is global: it may come before the command, and excludes --verbose
    let o = hydroid(&["-q", "--verbose", "check", "configs/spheroid.toml"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn filter_details_with_verbose() {
    // without --verbose: see run_json_prints_results_json_and_only_that
    let o = run_example(&["--set", "hekf.passes=1", "--verbose"]).output;
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let verbose = text(&o.stderr);
    let priors = verbose
        .lines()
        .filter(|l| l.contains("hekf prior: ") && l.contains(": starts at "))
        .count();
    assert_eq!(priors, 6, "{verbose}");
    // one pass from zero: Nrd swings positive at first and is held at its bound there
    // (docs/hekf.md, "Admissible ranges"), which the tuning notes say
    assert!(
        verbose.contains("Nrd: held at the bound of its admissible range (<= 0 kg m^2)"),
        "{verbose}"
    );
    assert_eq!(verbose.matches("hekf noise of ").count(), 6, "{verbose}");
    assert!(verbose.contains("hekf settings: hydroid preset, 1 passes"));
}

#[test]
fn run_json_prints_results_json_and_only_that() {
    let run = run_example(&["--json"]);
    let (out, o) = (&run.out, &run.output);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["schema"], "hydroid-results/2");
    assert_eq!(o.stdout, std::fs::read(out.join("results.json")).unwrap());
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains(&format!("wrote {}", out.display())),
        "{stderr}"
    );
    // the filter's details are for --verbose only
    assert!(stderr.contains("hekf: 6 coefficients"), "{stderr}");
    for detail in ["hekf settings:", "hekf prior:", "hekf noise of"] {
        assert!(!stderr.contains(detail), "{stderr}");
    }
    // a failed run: the same exit code as without --json, the error as JSON on stdout
    let o = hydroid(&["run", "configs/missing.toml", "--json"]);
    assert_eq!(o.status.code(), Some(2));
    json_error(&o, "config");
}

#[test]
fn coefficients_lists_the_catalogue_and_one_model() {
    let o = hydroid(&["coefficients"]);
    assert_eq!(o.status.code(), Some(0));
    let all = text(&o.stdout);
    assert!(all.contains("Xud") && all.contains("Kpp") && all.contains("kg m^2"));
    assert!(
        all.contains("derived: paper eq. 4: Xvr = -Yvd (spheroid3)"),
        "{all}"
    );
    let o = hydroid(&["coefficients", "spheroid3"]);
    assert_eq!(o.status.code(), Some(0));
    let one = text(&o.stdout);
    assert!(one.contains("states: u [m/s], v [m/s], r [rad/s]"), "{one}");
    assert!(one.contains("psi (column yaw) [rad]"), "{one}");
    assert!(one.contains("inputs: thrust [N]"), "{one}");
    assert!(!one.contains("Kpp"), "{one}");
    // the admissible ranges the filter keeps (docs/hekf.md, "Admissible ranges")
    assert!(
        one.contains("kept in their admissible range by the HEKF: Xud <= 0 kg, Yvd <= 0 kg"),
        "{one}"
    );
    let o = hydroid(&["coefficients", "spheroid6", "--json"]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["model"]["name"], "spheroid6");
    assert_eq!(v["model"]["states"].as_array().unwrap().len(), 12);
    let kpp = named(&v["coefficients"], "Kpp");
    assert_eq!(kpp["unit"], "kg m^2");
    assert_eq!(kpp["given_by"][0]["source"], "hekf");
    assert!(
        kpp.get("range").is_none(),
        "a damping term's sign is not bounded"
    );
    assert_eq!(named(&v["coefficients"], "Yvd")["range"], "<= 0 kg");
    let o = hydroid(&["coefficients", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(
        v["models"].as_array().unwrap().len(),
        hydroid::model::models::ModelName::ALL.len()
    );
    let o = hydroid(&["coefficients", "spheroid7"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("did you mean 'spheroid3'"));
}

/// Fills in every `FILL-IN` file of a template with a small delimited export whose columns
/// are the ones the template maps (units in the headers), as a user would.
fn fill_in(config: &std::path::Path) {
    let text = std::fs::read_to_string(config).unwrap();
    let doc: toml::Table = toml::from_str(&text).unwrap();
    let mut filled = text.clone();
    for stage in ["polar", "surge", "hekf"] {
        let Some(runs) = doc.get(stage).and_then(|s| s.get("runs")) else {
            continue;
        };
        for run in runs.as_array().unwrap() {
            let placeholder = run["file"].as_str().unwrap();
            assert!(placeholder.starts_with("FILL-IN"), "{placeholder}");
            let columns = run["columns"].as_table().unwrap();
            let header: Vec<String> = columns
                .iter()
                .map(|(q, name)| {
                    let unit = hydroid::base::quantity::Quantity::from_key(q)
                        .unwrap()
                        .si_symbol();
                    let name = name.as_str().unwrap();
                    if unit == "-" {
                        name.to_string()
                    } else {
                        format!("{name} [{unit}]")
                    }
                })
                .collect();
            let mut csv = header.join(",") + "\n";
            for i in 0..50 {
                // distinct columns: identical ones would be taken for one column mapped twice
                let row: Vec<String> = columns
                    .keys()
                    .enumerate()
                    .map(|(k, q)| match q.as_str() {
                        "time" => format!("{}", 0.01 * i as f64),
                        "alpha" => format!("{}", 0.01 * (i as f64 - 25.0)),
                        _ => format!("{}", 1.0 + 0.001 * (k + 1) as f64 * i as f64),
                    })
                    .collect();
                csv += &(row.join(",") + "\n");
            }
            let name = format!("{stage}.csv");
            std::fs::write(config.parent().unwrap().join(&name), csv).unwrap();
            filled = filled.replace(placeholder, &name);
        }
    }
    std::fs::write(config, filled).unwrap();
}

/// `hydroid check config`, which must pass.
#[track_caller]
fn check_passes(config: &std::path::Path) -> std::process::Output {
    let o = hydroid(&["check", config.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    o
}

#[test]
fn init_writes_a_template_check_accepts_once_filled_in() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("project");
    let o = hydroid(&["init", project.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let config = project.join("hydroid.toml");
    // the template and nothing else
    assert_eq!(std::fs::read_dir(&project).unwrap().count(), 1);
    let template = std::fs::read(&config).unwrap();
    // as written, check names every file to fill in
    let o = hydroid(&["check", config.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        text(&o.stderr).matches("FILL-IN").count(),
        3,
        "{}",
        text(&o.stderr)
    );
    // never overwritten, not even by a second init
    let o = hydroid(&["init", project.to_str().unwrap(), "--model", "spheroid6"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("already exists"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(std::fs::read(&config).unwrap(), template);
    fill_in(&config);
    check_passes(&config);

    // the 6-DOF model with the filter alone: what no stage gives is asked for
    let config = dir.path().join("six.toml");
    let o = hydroid(&[
        "init",
        config.to_str().unwrap(),
        "--stages",
        "hekf",
        "--model",
        "spheroid6",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    fill_in(&config);
    let o = check_passes(&config);
    assert!(text(&o.stdout).contains("spheroid6 model"));
}

#[test]
fn check_json_lists_what_would_run_and_every_problem() {
    let o = hydroid(&["check", "configs/spheroid.toml", "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["ok"], true);
    assert_eq!(v["problems"], serde_json::json!([]));
    assert_eq!(
        v["would_run"]["stages"],
        serde_json::json!(["polar", "surge", "hekf"])
    );
    assert_eq!(v["would_run"]["hekf"]["model"], "spheroid3");
    let inputs = v["inputs"].as_array().unwrap();
    assert_eq!(inputs.len(), 4);
    assert!(
        inputs.iter().all(|i| i["status"] == "usable"),
        "{inputs:#?}"
    );
    assert_eq!(inputs[1]["rows"], 2001);

    // configuration problems: exit code 2, each with its line and key
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/three_mistakes.toml",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stderr.is_empty(), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["ok"], false);
    let problems = v["problems"].as_array().unwrap();
    assert_eq!(problems.len(), 3, "{problems:#?}");
    let mass = problems
        .iter()
        .find(|p| p["key"] == "vehicle.mass")
        .unwrap();
    assert_eq!(mass["line"], 3);
    assert!(mass["file"]
        .as_str()
        .unwrap()
        .ends_with("three_mistakes.toml"));
    assert!(mass["message"].as_str().unwrap().contains("positive"));

    // a bad input file only: exit code 1, the problem placed in the file
    let o = hydroid(&[
        "check",
        "configs/spheroid.toml",
        "--json",
        "--set",
        "hekf.runs[0].file=\"../tests/fixtures/bad/ragged_row.csv\"",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    let p = &v["problems"][0];
    assert_eq!(p["key"], "hekf.runs[0]");
    assert_eq!(p["line"], 4);
    assert!(p["file"].as_str().unwrap().ends_with("ragged_row.csv"));
    assert_eq!(v["inputs"][2]["status"], "unusable");
}

#[test]
fn compare_json_gives_the_differences() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, coefficients: serde_json::Value| {
        let p = dir.path().join(name);
        std::fs::write(
            &p,
            serde_json::json!({ "schema": "hydroid-results/2", "coefficients": coefficients })
                .to_string(),
        )
        .unwrap();
        p.to_str().unwrap().to_string()
    };
    let coef = |name: &str, value: f64, sigma: f64| serde_json::json!({"name": name, "value": value, "sigma": sigma, "unit": "kg", "source": "hekf"});
    let a = write(
        "a.json",
        serde_json::json!([coef("Yvd", -23.0, 0.3), coef("Nvv", 10.0, 0.5)]),
    );
    let b = write("b.json", serde_json::json!([coef("Yvd", -23.5, 0.4)]));
    let o = hydroid(&["compare", &a, &b, "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    let yvd = named(&v["coefficients"], "Yvd");
    assert_eq!(yvd["difference"], -0.5);
    assert_eq!(yvd["difference_in_sigma"], -1.0);
    assert_eq!(yvd["b"]["sigma"], 0.4);
    let nvv = named(&v["coefficients"], "Nvv");
    assert!(nvv["b"].is_null() && nvv["difference"].is_null());
    // a failure keeps its exit code and gives the error as JSON on stdout
    let missing = dir.path().join("none.json");
    let o = hydroid(&["compare", &a, missing.to_str().unwrap(), "--json"]);
    let plain = hydroid(&["compare", &a, missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), plain.status.code());
    assert_ne!(o.status.code(), Some(0));
    assert!(plain.stdout.is_empty());
    json_error(&o, "config");
}

/// The JSON error object a failed `--json` command printed on stdout (issue 24, item 6):
/// one object, `error.kind` as expected, the exit code the process exited with, the human
/// message on stderr as well.
#[track_caller]
fn json_error(o: &std::process::Output, kind: &str) -> serde_json::Value {
    let out = text(&o.stdout);
    let err = text(&o.stderr);
    let v: serde_json::Value = serde_json::from_str(&out)
        .unwrap_or_else(|e| panic!("stdout is not one JSON object ({e}):\n{out}\nstderr: {err}"));
    let code = o.status.code().expect("an exit code");
    assert_ne!(code, 0, "{err}");
    assert_eq!(v["exit_code"], code, "{out}");
    assert_eq!(v["error"]["kind"], kind, "{out}");
    let message = v["error"]["message"].as_str().expect("a message");
    assert!(!message.is_empty());
    let problems = v["error"]["problems"]
        .as_array()
        .expect("a list of problems");
    assert!(!problems.is_empty(), "{out}");
    for p in problems {
        for field in ["file", "line", "column", "column_name", "key", "message"] {
            assert!(p.get(field).is_some(), "{field} in {p}");
        }
    }
    assert!(
        err.starts_with("error: "),
        "the human message on stderr: {err}"
    );
    let first = message.lines().next().unwrap_or_default();
    assert!(err.contains(first), "{first} on stderr: {err}");
    v
}

/// Every command with `--json` gives a failure as one JSON error object on stdout with the
/// exit code it has without `--json` (issue 24, item 6).
#[test]
fn every_json_command_gives_its_error_as_json_with_the_same_exit_code() {
    let dir = tempfile::tempdir().unwrap();
    let cut = "tests/fixtures/bad/cut_exponent.csv";
    let no_config = dir.path().join("none.toml");
    let no_config = no_config.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["run", no_config], "config"),
        (
            vec!["run", "configs/spheroid.toml", "--set", "hekf.passes=0"],
            "config",
        ),
        (vec!["check", no_config], "config"),
        (vec!["inspect", cut], "input"),
        (vec!["inspect", cut, "--format", "cfxx"], "usage"),
        (vec!["manoeuvre", no_config], "config"),
        (
            vec!["manoeuvre", "configs/spheroid.toml", "--scale", "1e300"],
            "usage",
        ),
        (vec!["compare", cut, cut], "input"),
        (vec!["coefficients", "spheroid9"], "usage"),
        (
            vec!["analytic", "spheroid", "--length", "1", "--diameter", "2"],
            "usage",
        ),
        (
            vec!["run", "configs/spheroid.toml", "--no-such-flag"],
            "usage",
        ),
    ];
    for (args, kind) in cases {
        let mut with_json = args.clone();
        with_json.push("--json");
        let o = hydroid(&with_json);
        let plain = hydroid(&args);
        assert_eq!(o.status.code(), plain.status.code(), "{args:?}");
        let v = json_error(&o, kind);
        assert_eq!(v["error"]["stage"], serde_json::Value::Null, "{args:?}");
        if args[0] == "inspect" && kind == "input" {
            // the place of the problem: the file and its line
            assert!(v["error"]["file"]
                .as_str()
                .unwrap()
                .ends_with("cut_exponent.csv"));
            assert!(v["error"]["line"].as_u64().is_some(), "{v}");
        }
    }
}

/// The bundled configuration in a temporary folder, with its validation run's thrust given by
/// `thrust` (TOML lines for its input table) instead of its thrust column.
fn validation_thrust_as(thrust: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let text = bundled_config_text()
        .replace("thrust = \"Thrust Monitor: Force\"\n", "")
        .replace(
            "turn_validation.csv\"\n",
            &format!("turn_validation.csv\"\n{thrust}\n"),
        );
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("steps.toml");
    std::fs::write(&config, text).unwrap();
    (dir, config)
}

#[test]
fn steps_give_a_time_varying_input_the_file_has_no_column_for() {
    let (_dir, config) = validation_thrust_as(
        "constants = { thrust = \"15 N\" }\nsteps = [{ time = 10.0, thrust = \"30 N\" }]",
    );
    let o = hydroid(&["check", config.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("thrust [N]"),
        "{}",
        text(&o.stdout)
    );
    // a unit that is not a force is named with its line
    let (_dir, config) = validation_thrust_as(
        "constants = { thrust = \"15 N\" }\nsteps = [{ time = 10.0, thrust = \"30 deg\" }]",
    );
    let line = 1 + std::fs::read_to_string(&config)
        .unwrap()
        .lines()
        .position(|l| l.starts_with("steps = "))
        .unwrap();
    let o = hydroid(&["check", config.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains(&format!("steps.toml:{line}: hekf.validation[0].steps[0]: the step at 10 s gives thrust = \"30 deg\": unit 'deg' is an angle")),
        "{stderr}"
    );
}

/// Values a user would give the particulars a template writes as zeros to replace, for the
/// template's 1.2 m vehicle (mmg3: a ship model of that length).
const PARTICULARS: &[(&str, &str)] = &[
    ("draught", "0.08"),
    ("x_g", "0.01"),
    ("propeller_diameter", "0.04"),
    ("propeller_x", "-0.55"),
    ("rudder_area", "0.002"),
    ("rudder_height", "0.06"),
    ("rudder_x", "-0.6"),
    ("wake_c1", "2.0"),
    ("wake_c2_pos", "1.6"),
    ("wake_c2_neg", "1.1"),
];

/// Issue 24, item 7: every `init --model M --stages S` that hydroid accepts writes a
/// template that `check` accepts once filled in: as written, every problem `check` names is
/// a FILL-IN file or a particular written as a zero to replace; with the files (synthetic
/// tables with the template's columns) and the particulars filled in, `check` passes. A
/// combination hydroid refuses names the stages the model supports.
#[test]
fn every_init_combination_hydroid_accepts_gives_a_template_check_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let subsets = [
        "polar",
        "surge",
        "hekf",
        "polar,surge",
        "polar,hekf",
        "surge,hekf",
        "polar,surge,hekf",
    ];
    let (mut written, mut refused) = (0, 0);
    for model in hydroid::stages::hekf::ModelName::NAMES {
        for stages in subsets {
            let config = dir
                .path()
                .join(format!("{model}-{}.toml", stages.replace(',', "-")));
            let c = config.to_str().unwrap();
            let o = hydroid(&["init", c, "--model", model, "--stages", stages]);
            let err = text(&o.stderr);
            if o.status.code() == Some(2) {
                assert!(
                    err.contains("its template has the hekf stage only (--stages hekf"),
                    "{model} {stages}: {err}"
                );
                assert!(!config.exists());
                refused += 1;
                continue;
            }
            assert_eq!(o.status.code(), Some(0), "{model} {stages}: {err}");
            written += 1;
            let template = std::fs::read_to_string(&config).unwrap();
            let o = hydroid(&["check", c]);
            let said = text(&o.stderr);
            for p in said.lines().filter_map(|l| l.strip_prefix("  - ")) {
                let placeholder = PARTICULARS.iter().any(|(k, _)| {
                    p.contains(&format!(": vehicle.particulars.{k}: "))
                        && template.contains(&format!("\n{k} = 0.0\n"))
                });
                assert!(
                    p.contains("FILL-IN") || placeholder,
                    "{model} {stages}: not a placeholder to fill in: {p}"
                );
            }
            let mut filled = template.clone();
            for (k, v) in PARTICULARS {
                filled = filled.replace(&format!("\n{k} = 0.0\n"), &format!("\n{k} = {v}\n"));
            }
            std::fs::write(&config, filled).unwrap();
            fill_in(&config);
            // the synthetic tables are no manoeuvre: the plausibility checks of the HEKF's
            // runs (a rudder of 66 deg, an advance ratio of 38) only warn about them
            let mut args = vec!["check", c];
            if stages.contains("hekf") {
                args.extend(["--set", "hekf.checks=\"warn\""]);
            }
            let o = hydroid(&args);
            assert_eq!(
                o.status.code(),
                Some(0),
                "{model} {stages}: {}{}",
                text(&o.stdout),
                text(&o.stderr)
            );
        }
    }
    assert!(
        written >= 20 && refused >= 16,
        "{written} written, {refused} refused"
    );
}
