//! Bad configurations, run and simulate: every problem is listed at once with its file, line
//! and key, units are checked against each key's dimension, limits are named, and no message
//! shows Rust's vocabulary.
//!
//! Each file in tests/fixtures/configs/errors/ says what must be reported in `# expect:`
//! lines at its top (`file:line: key: message`, or a fragment without a place).

use crate::common;

use common::{hydroid, root, text};
use hydroid::base::error::Error;
use std::path::{Path, PathBuf};

/// Fragments that belong to Rust, not to a message for a naval architect.
const FORBIDDEN: &[&str] = &[
    "usize", "isize", "u32", "u64", "f64", "struct ", "Some(", "None", "untagged", "borrowed", "::",
];

fn fixtures() -> PathBuf {
    PathBuf::from("tests/fixtures/configs/errors")
}

/// Loads a run or (for `sim_*` files) a simulate configuration; the problems, one a line.
fn problems(path: &Path, text: &str) -> Option<String> {
    let sim = path
        .file_name()
        .is_some_and(|n| n.to_string_lossy().starts_with("sim_"));
    let r = if sim {
        // through a file, as `hydroid simulate` reads it
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join(path.file_name().unwrap());
        std::fs::write(&file, text).unwrap();
        hydroid::app::simulate::config::load(&file)
            .map(|_| ())
            .map_err(|e| match e {
                Error::Config(list) => Error::Config(
                    list.into_iter()
                        .map(|mut p| {
                            p.file = path.to_path_buf();
                            p
                        })
                        .collect(),
                ),
                e => e,
            })
    } else {
        hydroid::config::load_str(path, text, &[]).map(|_| ())
    };
    match r {
        Ok(()) => None,
        Err(Error::Config(list)) => Some(
            list.iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join("\n"),
        ),
        Err(e) => panic!("{}: not a configuration error: {e}", path.display()),
    }
}

fn assert_words(context: &str, message: &str) {
    for f in FORBIDDEN {
        assert!(
            !message.contains(f),
            "{context}: '{f}' in the message\n{message}"
        );
    }
}

#[test]
fn every_fixture_reports_what_it_expects_and_in_words() {
    std::env::set_current_dir(root()).unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(fixtures())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 15, "{} fixtures", files.len());
    let mut failures = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let expect: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("# expect: "))
            .collect();
        assert!(!expect.is_empty(), "{}: no expectation", f.display());
        let Some(got) = problems(&f, &text) else {
            failures.push(format!("{} loads without a problem", f.display()));
            continue;
        };
        for e in &expect {
            if !got.contains(e) {
                failures.push(format!("{}: expected\n  {e}\nin\n{got}", f.display()));
            }
        }
        // each expectation is one problem, and nothing else is reported
        if got.lines().count() != expect.len() {
            failures.push(format!(
                "{}: not the problems expected:\n{got}",
                f.display()
            ));
        }
        assert_words(&f.display().to_string(), &got);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Replaces the value on the first line that sets `key` with `value`.
fn with_value(text: &str, line: usize, value: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            if i == line {
                let (k, _) = l.split_once('=').unwrap();
                format!("{k}= {value}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn wrong_values_for_every_key_are_reported_in_words() {
    std::env::set_current_dir(root()).unwrap();
    let values = [
        "\"text\"",
        "true",
        "[1, 2]",
        "{ a = 1 }",
        "-1",
        "0",
        "2.5",
        "nan",
        "-inf",
        "\"3 furlongs\"",
        "\"3 deg\"",
        "1979-05-27",
    ];
    let mut checked = 0;
    for (name, file) in [
        ("run", "tests/fixtures/configs/base.toml"),
        ("sim", "configs/simulate/turn_validation.toml"),
        ("sim", "configs/simulate/polar_sweep.toml"),
    ] {
        let text = std::fs::read_to_string(file).unwrap();
        let path = Path::new(file).with_file_name(format!("{name}_mutated.toml"));
        for (i, line) in text.lines().enumerate() {
            let l = line.trim_start();
            if l.starts_with('#') || l.starts_with('[') || !l.contains('=') || l.ends_with('[') {
                continue;
            }
            for v in values {
                let bad = with_value(&text, i, v);
                if let Some(m) = problems(&path, &bad) {
                    assert_words(&format!("{file} line {} = {v}", i + 1), &m);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn a_type_error_leaves_the_rest_checked() {
    std::env::set_current_dir(root()).unwrap();
    let text = std::fs::read_to_string("tests/fixtures/configs/base.toml").unwrap();
    // a required key of the wrong type in every section, and a semantic problem in each
    let bad = text
        .replace("length = 1.2", "length = [1.2]")
        .replace("mu = 0.0009", "mu = \"thin\"")
        .replace("rho = 1025.0", "rho = 10250.0")
        .replace("file = \"", "file = 3\nname = \"")
        .replace("estimate = [\"Yvd\"", "passes = 1000\nestimate = [\"Yvdd\"");
    let path = Path::new("tests/fixtures/configs/all_at_once.toml");
    let got = problems(path, &bad).unwrap();
    for e in [
        "all_at_once.toml:4: vehicle.length: expected a number in SI units or a string with a unit",
        "fluid.mu: \"thin\" is not a number",
        "fluid.rho: 10250 kg/m^3 is outside the plausible range",
        "hekf.runs[0].file: expected text in quotes, got the whole number 3",
        "hekf.passes: must be a whole number from 1 to 100",
        "hekf.estimate[0]: unknown coefficient 'Yvdd'; did you mean 'Yvd'?",
    ] {
        assert!(got.contains(e), "expected\n  {e}\nin\n{got}");
    }
    assert_eq!(got.lines().count(), 6, "{got}");
}

#[test]
fn nothing_to_run_is_refused_by_check_and_run() {
    let f = "tests/fixtures/configs/errors/every_stage_disabled.toml";
    let o = hydroid(&["check", f]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("nothing to run"),
        "{}",
        text(&o.stderr)
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = hydroid(&["run", f, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(!out.exists());
}

#[test]
fn simulate_refuses_unbounded_requests_quickly_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "sim_duration_huge",
        "sim_dt_1e-9",
        "sim_substeps_huge",
        "sim_separator_dot",
    ] {
        let out = dir.path().join(format!("{f}.csv"));
        let start = std::time::Instant::now();
        let o = hydroid(&[
            "simulate",
            &format!("tests/fixtures/configs/errors/{f}.toml"),
            "--out",
            out.to_str().unwrap(),
        ]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{f}: {e}");
        assert!(
            !e.contains("panicked") && !e.contains("memory allocation"),
            "{f}: {e}"
        );
        assert!(
            start.elapsed().as_secs() < 20,
            "{f} took {:?}",
            start.elapsed()
        );
        assert!(!out.exists(), "{f} wrote");
    }
}

#[test]
fn set_messages_name_the_override_in_words() {
    let o = hydroid(&[
        "check",
        "tests/fixtures/configs/base.toml",
        "--set",
        "hekf.estimate[0]=3",
        "--set",
        "vehicle.mass[0]=1",
        "--set",
        "hekf.passes=\"many\"",
    ]);
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains(
            "--set 'vehicle.mass[0]=1': vehicle.mass is the value 50.0, not a list: [0] cannot \
             follow it; set it whole, vehicle.mass=VALUE"
        ),
        "{e}"
    );
    assert!(
        e.contains("hekf.passes: (from --set hekf.passes=\"many\") expected a whole number"),
        "{e}"
    );
    assert_words("--set", &e);
}

/// Issue 24, item 5: `--set` takes TOML's key syntax (quoted keys, single or double quotes,
/// list positions) and TOML values, and its errors say what was expected: the syntax, the
/// nearest keys of an unknown one, the entries of a list indexed past its end.
#[test]
fn set_takes_toml_keys_and_values_and_says_what_was_expected() {
    let check = |config: &str, sets: &[&str]| {
        let mut args = vec!["check", config];
        for s in sets {
            args.extend(["--set", s]);
        }
        let o = hydroid(&args);
        (o.status.code(), text(&o.stdout) + &text(&o.stderr))
    };
    let joint = "configs/spheroid_joint.toml";
    // quoted keys reach the oscillation of a named run, and TOML values of every kind parse
    let (code, all) = check(
        joint,
        &[
            "captive.oscillations.\"pure sway\".amplitude={ v = \"0.2 m/s\" }",
            "captive.oscillations.'pure yaw'.frequency=\"0.5 Hz\"",
            "hekf.runs[0].columns.yaw.scale=1",
            "hekf.estimate[0]=Xud",
            "hekf.smoother=true",
            "output.plots=false",
        ],
    );
    assert_eq!(code, Some(0), "{all}");
    let (code, all) = check(joint, &["captive.oscillations.\"pure sway\".frequency=-1"]);
    assert_eq!(code, Some(2), "{all}");
    assert!(
        all.contains(
            "captive.oscillations.\"pure sway\".frequency: (from --set \
             captive.oscillations.\"pure sway\".frequency=-1)"
        ),
        "{all}"
    );
    let (_, all) = check(joint, &["captive.oscillations.'pure swey'.frequency=1"]);
    assert!(all.contains("did you mean 'pure sway'?"), "{all}");
    // the errors
    let base = "configs/spheroid.toml";
    for (set, says) in [
        (
            "a.b",
            "--set 'a.b': expected KEY=VALUE with a TOML key (a.b.\"quoted key\", runs[0].file) \
             and a TOML value",
        ),
        ("hekf.passes=[1,", "`[1,` is not a TOML value"),
        (
            "captive.oscillations.\"pure sway.frequency=1",
            "an unclosed quote",
        ),
        (
            "hekf.runs[3].file=x.csv",
            "hekf.runs has 1 entry, so [3] does not exist (the only position is [0])",
        ),
        (
            "hekf.runs.file=x.csv",
            "hekf.runs is a list of 1 entry: give a position, e.g. hekf.runs[0].file",
        ),
        (
            "hekff.passes=3",
            "hekff: (from --set hekff.passes=3) unknown key `hekff`; did you mean `hekf`?",
        ),
        (
            "hekf.runs[0].colums.yaw=x",
            "(from --set hekf.runs[0].colums.yaw=x) unknown key `colums`; did you mean \
             `columns`?",
        ),
        (
            "hekf.passes=many",
            "hekf.passes: (from --set hekf.passes=many) expected a whole number",
        ),
    ] {
        let (code, all) = check(base, &[set]);
        assert_eq!(code, Some(2), "{set}: {all}");
        assert!(all.contains(says), "{set}: expected '{says}' in\n{all}");
        assert_words(set, &all);
    }
}

/// A minimal results.json of a run of `vehicle` with `model`.
fn results(dir: &Path, name: &str, mass: f64, model: &str) -> PathBuf {
    let p = dir.join(format!("{name}.json"));
    let json = format!(
        r#"{{"schema": "hydroid-results/2", "coefficients": [], "vehicle": {{"name": "sub", "mass": {mass}, "length": 1.2,
            "q": 16.1}}, "configuration": {{"hekf": {{"model": "{model}"}}}}}}"#
    );
    std::fs::write(&p, json).unwrap();
    p
}

#[test]
fn compare_warns_about_different_vehicles_and_models() {
    let dir = tempfile::tempdir().unwrap();
    let a = results(dir.path(), "a", 50.0, "spheroid3");
    let b = results(dir.path(), "b", 60.0, "spheroid6");
    let o = hydroid(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    for s in [text(&o.stderr), text(&o.stdout)] {
        assert!(s.contains("different vehicles or models"), "{s}");
        assert!(s.contains("vehicle mass: 50 (A) vs 60 (B)"), "{s}");
        assert!(
            s.contains("hekf model: spheroid3 (A) vs spheroid6 (B)"),
            "{s}"
        );
        assert!(!s.contains("vehicle length"), "{s}");
    }
    let same = results(dir.path(), "c", 50.0, "spheroid3");
    let o = hydroid(&["compare", a.to_str().unwrap(), same.to_str().unwrap()]);
    assert!(
        !text(&o.stderr).contains("different"),
        "{}",
        text(&o.stderr)
    );
}

/// What would make a comparison wrong without a word is refused (another schema version, a
/// negative sigma, a coefficient listed twice) or flagged (the same coefficient in two units).
#[test]
fn compare_refuses_other_schemas_bad_sigmas_and_duplicates_and_flags_units() {
    let dir = tempfile::tempdir().unwrap();
    let coef = |name: &str, sigma: f64, unit: &str| serde_json::json!({"name": name, "value": 1.5, "sigma": sigma, "unit": unit, "source": "hekf"});
    let write = |name: &str, schema: Option<&str>, coefficients: Vec<serde_json::Value>| {
        let mut v = serde_json::json!({ "coefficients": coefficients });
        if let Some(s) = schema {
            v["schema"] = s.into();
        }
        let p = dir.path().join(name);
        std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        p.to_str().unwrap().to_string()
    };
    let good = write(
        "good.json",
        Some("hydroid-results/2"),
        vec![coef("Yvd", 0.1, "kg")],
    );
    let cases = [
        (
            write(
                "v1.json",
                Some("hydroid-results/1"),
                vec![coef("Yvd", 0.1, "kg")],
            ),
            vec!["v1.json", "schema 'hydroid-results/1'", "hydroid-results/2"],
        ),
        (
            write("none.json", None, vec![coef("Yvd", 0.1, "kg")]),
            vec!["none.json", "no `schema`"],
        ),
        (
            write(
                "negative.json",
                Some("hydroid-results/2"),
                vec![coef("Nrd", 0.1, "kg m^2"), coef("Yvd", -0.2, "kg")],
            ),
            vec!["negative.json:10", "'Yvd': sigma -0.2 is negative"],
        ),
        (
            write(
                "twice.json",
                Some("hydroid-results/2"),
                vec![coef("Yvd", 0.1, "kg"), coef("Yvd", 0.2, "kg")],
            ),
            vec!["twice.json:10", "'Yvd' is listed twice", "line 3"],
        ),
    ];
    for (bad, says) in cases {
        for args in [[&good, &bad], [&bad, &good]] {
            let o = hydroid(&["compare", args[0], args[1]]);
            let e = text(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{e}");
            for s in &says {
                assert!(e.contains(s), "{s}: {e}");
            }
        }
    }
    let grams = write(
        "grams.json",
        Some("hydroid-results/2"),
        vec![coef("Yvd", 0.1, "g")],
    );
    let o = hydroid(&["compare", &good, &grams]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let (e, s) = (text(&o.stderr), text(&o.stdout));
    assert!(e.contains("Yvd is in kg in A and in g in B"), "{e}");
    let row = s.lines().find(|l| l.starts_with("Yvd")).unwrap();
    assert!(
        row.contains("kg (A) vs g (B)") && !row.contains("+0"),
        "{row}"
    );
    let o = hydroid(&["compare", &good, &grams, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["coefficients"][0]["units_differ"], true);
    assert!(v["coefficients"][0]["difference"].is_null());
}

/// The first line of each error `hydroid run` or `hydroid check` printed on stderr (the
/// problems of a list, or the one error), and whether a stage had finished before it.
fn stated_errors(stderr: &str) -> (Vec<String>, bool) {
    let mut found = Vec::new();
    let mut after_work = false;
    for l in stderr.lines() {
        if let Some(p) = l.strip_prefix("  - ") {
            found.push(p.to_string());
        } else if let Some(e) = l.strip_prefix("error: ") {
            if !e.contains(" in the configuration:") {
                found.push(e.to_string());
            }
        } else if ["polar: ", "surge: ", "captive: ", "hekf: "]
            .iter()
            .any(|s| l.starts_with(s))
            && found.is_empty()
        {
            after_work = true;
        }
    }
    (found, after_work)
}

/// Mutations of a `[vehicle.particulars]` block: each key removed, then given each of
/// `values` (wrong signs, zero, NaN-like, wrong types and units), then an unknown key and
/// the block of another type.
fn particulars_mutations(text: &str) -> Vec<(String, String)> {
    let start = text
        .find("[vehicle.particulars]")
        .expect("a particulars block");
    let end = start + text[start..].find("\n\n").expect("a blank line after it");
    let block = &text[start..end];
    let values = [
        "-1.0",
        "0.0",
        "nan",
        "-inf",
        "\"nan m\"",
        "\"-0.5 m\"",
        "\"1 kg\"",
        "\"abc\"",
        "\"\"",
        "true",
        "[1, 2]",
        "{ a = 1 }",
        "1e300",
    ];
    let mut out = Vec::new();
    for line in block.lines().skip(1) {
        let Some((key, _)) = line.split_once('=') else {
            continue;
        };
        let key = key.trim();
        let edit = |new: &str| {
            let b = block.replacen(line, new, 1);
            text.replacen(block, &b, 1)
        };
        out.push((format!("{key} removed"), edit("")));
        for v in values {
            out.push((format!("{key} = {v}"), edit(&format!("{key} = {v}"))));
        }
    }
    out.push((
        "unknown key".into(),
        text.replacen(block, &format!("{block}\nbeam_typo = 1.0"), 1),
    ));
    out.push((
        "particulars a number".into(),
        text.replacen(block, "[vehicle.particulars_gone]", 1)
            .replacen("[vehicle]\n", "[vehicle]\nparticulars = 3\n", 1),
    ));
    out
}

/// Mutations of the captive stage of configs/ship_captive.toml: each held coefficient left
/// without a value, an estimated name the model lacks, a model that gives no forces, a run
/// that does not read into conditions, a window with nothing in it.
fn captive_mutations(text: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = text
        .lines()
        .filter(|l| l.starts_with("R0_p =") || l.starts_with("k1 =") || l.starts_with("tR ="))
        .map(|l| (format!("no {l}"), text.replacen(l, "", 1)))
        .collect();
    let swap = |what: &str, from: &str, to: &str| {
        assert!(text.contains(from), "{from}");
        (what.to_string(), text.replacen(from, to, 1))
    };
    out.extend([
        swap("estimate Yvd", "estimate = [\"Yv_p\"", "estimate = [\"Yvd\", \"Yv_p\""),
        swap("estimate R0_p twice", "estimate = [\"Yv_p\"", "estimate = [\"R0_p\", \"R0_p\", \"Yv_p\""),
        swap("ship_linear", "model = \"mmg3\"", "model = \"ship_linear\""),
        swap("surge1", "model = \"mmg3\"", "model = \"surge1\""),
        swap("no Fy column", "fy = \"Fy\"", "fy = \"Side force\""),
        swap("rudder a constant", "rudder = \"rudder\"\n", ""),
        swap("prime columns", "fy = \"Fy\"", "y_prime = \"Fy\""),
        swap("averaged after the end", "[captive]\n", "[captive]\naverage_after = \"1e6 s\"\n"),
        swap("oscillation of a steady table", "[captive]\n", "[captive]\noscillations.\"captive programme, 1.179 m/s\" = { amplitude = { v = \"0.1 m/s\" }, frequency = \"0.5 Hz\" }\n"),
        swap("captive disabled", "[captive]\n", "[captive]\nenabled = false\n"),
    ]);
    out
}

/// Issue 24, item 4: for every mutation of the bundled captive configuration (its ship's
/// particulars and its captive stage), `hydroid check` fails exactly when `hydroid run` fails
/// before its work starts, with the same exit code and the same problems.
#[test]
fn check_fails_exactly_when_run_fails_before_its_work() {
    let dir = tempfile::tempdir().unwrap();
    let exports = root().join("cfd_exports").display().to_string() + "/";
    let base = std::fs::read_to_string(root().join("configs/ship_captive.toml"))
        .unwrap()
        .replace("../cfd_exports/", &exports);
    let mut mutations = particulars_mutations(&base);
    mutations.extend(captive_mutations(&base));
    let (mut refused, mut passed) = (0, 0);
    for (i, (what, mutated)) in mutations.iter().enumerate() {
        let config = dir.path().join(format!("m{i}.toml"));
        std::fs::write(&config, mutated).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let (c, o) = (config.to_str().unwrap(), out.to_str().unwrap());
        let check = hydroid(&["check", c, "--out", o]);
        let run = hydroid(&["run", c, "--out", o, "--set", "output.plots=false"]);
        let (check_err, run_err) = (text(&check.stderr), text(&run.stderr));
        let context = format!("{what}:\ncheck: {check_err}\nrun: {run_err}");
        let (run_says, after_work) = stated_errors(&run_err);
        if run.status.success() || after_work {
            assert_eq!(check.status.code(), Some(0), "{context}");
            passed += 1;
            continue;
        }
        refused += 1;
        assert!(!out.exists(), "{context}: run wrote an output");
        assert_eq!(check.status.code(), run.status.code(), "{context}");
        let (check_says, _) = stated_errors(&check_err);
        assert!(!run_says.is_empty(), "{context}");
        for said in &run_says {
            assert!(
                check_says.contains(said),
                "{said} not said by check\n{context}"
            );
        }
    }
    // the mutations are not all of one kind
    assert!(
        refused > 100 && passed >= 3,
        "{refused} refused, {passed} passed"
    );
}

/// Issue 24, item 4: what the polar or surge stage would refuse in its runs is said by
/// `check` (the same message and exit code) and by `run` before any stage runs.
#[test]
fn check_and_run_say_what_a_stage_would_refuse_before_any_stage_runs() {
    for (set, says) in [
        (
            "surge.t_start=1000",
            "only 0 samples between t_start and t_end",
        ),
        (
            "polar.alpha_max_deg=0.001",
            "which determine only 1 of the 3 free constants",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let c = hydroid(&["check", "configs/spheroid.toml", "--set", set]);
        let r = common::run_config(Path::new("configs/spheroid.toml"), &out, &[set]);
        let (ce, re) = (text(&c.stderr), text(&r.stderr));
        assert_eq!(c.status.code(), Some(1), "{set}: {ce}");
        assert_eq!(r.status.code(), Some(1), "{set}: {re}");
        assert!(ce.contains(says) && re.contains(says), "{set}:\n{ce}\n{re}");
        let ran = re.lines().any(|l| l.starts_with("polar: "));
        assert!(!ran, "{set}: a stage ran first: {re}");
        assert!(!out.exists());
    }
}
