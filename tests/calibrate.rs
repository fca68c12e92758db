//! `hydroid calibrate OUTDIR` (docs/calibrate.md): the parametric bootstrap of the bundled
//! spheroid joint twin agrees with the coverage study (tests/coverage.rs: 100 seeds
//! re-simulated from the truth, 96.2 % within 2 sigma and 73.2 % within 1 sigma), a noise
//! model set 10 times too small is flagged, and the same seed gives the same bytes. A module
//! of the studies target (tests/studies.rs); calibrate as a writer of outputs is tested in
//! tests/calibrate_output.rs.

use crate::common;

use std::path::Path;

/// Replicas of the agreement test.
const REPLICAS: usize = 24;

fn parsed(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| {
        panic!(
            "{e}: {}\n{}",
            common::text(&o.stdout),
            common::text(&o.stderr)
        )
    })
}

#[test]
fn the_spheroid_replicas_agree_with_the_coverage_study() {
    let example = common::example_copy();
    let out = common::joint_run(example.path(), &[]);
    let o = common::calibrate(&out, REPLICAS, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let c = parsed(&o);
    assert_eq!(c["converged"], REPLICAS, "{c}");
    let overall = &c["overall"];
    let (w1, w2) = (
        overall["within_1"].as_f64().unwrap(),
        overall["within_2"].as_f64().unwrap(),
    );
    eprintln!("overall: within 1 sigma {w1}, within 2 sigma {w2}");
    // the coverage study's shares with the binomial spread of 24 replicas (a replica's
    // coefficients move together, so the replicas, not the pairs, are the independent
    // draws): 2 sigma 95.2 % +- 3 x 3.9 % -> 83-100 %; 1 sigma 70.5 % +- 2 x 9.0 % -> 52-89 %
    assert!((0.83..=1.0).contains(&w2), "within 2 sigma: {w2}");
    assert!((0.52..=0.89).contains(&w1), "within 1 sigma: {w1}");
    // each coefficient's spread in reported sigmas: 1 +- 3 x 0.15 (the relative standard
    // error of a standard deviation of 24 draws, 1 / sqrt(2 x 23)), 0.55-1.45
    for row in c["coefficients"].as_array().unwrap() {
        let ratio = row["spread_ratio"].as_f64().unwrap();
        eprintln!("{}: spread / sigma {ratio:.2}", row["name"]);
        assert!((0.55..=1.45).contains(&ratio), "{row}");
    }
    assert_eq!(c["coefficients"].as_array().unwrap().len(), 14);
    // docs/calibrate.md at its printed digits
    let ratios: Vec<f64> = c["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["spread_ratio"].as_f64().unwrap())
        .collect();
    let (lo, hi) = ratios
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), r| (a.min(*r), b.max(*r)));
    assert_eq!(
        format!(
            "{:.1} % within 1 sigma and {:.1} % within 2 sigma; spread {lo:.2}-{hi:.2}",
            100.0 * w1,
            100.0 * w2
        ),
        "72.3 % within 1 sigma and 95.8 % within 2 sigma; spread 0.80-1.18"
    );
    assert!(c["warnings"].as_array().unwrap().is_empty(), "{c}");
    // docs/calibrate.md, "Settings": on this exact twin, leaving out the paper's manoeuvre
    // moves Xuv by 0.52 sigma at z = 5.2, which is not warned (a move within its sigma); the
    // PMM runs cannot be left out (recorded with the error)
    let variants = c["settings"]["variants"].as_array().unwrap();
    let without = |label: &str| {
        variants
            .iter()
            .find(|v| v["label"].as_str().unwrap().contains(label))
            .unwrap_or_else(|| panic!("{label}: {c}"))
    };
    let manoeuvre = without("paper manoeuvre");
    assert_eq!(
        format!(
            "{:+.2} {:.1}",
            manoeuvre["moves"]["Xuv"].as_f64().unwrap(),
            manoeuvre["z"]["Xuv"].as_f64().unwrap()
        ),
        "+0.52 5.2"
    );
    assert!(without("captive run 'pure yaw' left out")["error"].is_string());
    assert!(out.join("calibration.md").is_file());
    // the folder stays hydroid's (calibrate records its files in the marker): a rerun
    // would replace it, and calibrate runs on it again; the same seed gives the same bytes
    let a = common::calibrate(&out, 3, &[]);
    let first = std::fs::read(out.join("calibration.json")).unwrap();
    let b = common::calibrate(&out, 3, &[]);
    let second = std::fs::read(out.join("calibration.json")).unwrap();
    assert_eq!(a.status.code(), Some(0), "{}", common::text(&a.stderr));
    assert_eq!(b.status.code(), Some(0), "{}", common::text(&b.stderr));
    assert_eq!(first, second);
    assert_eq!(a.stdout, b.stdout);
}

/// The default example (polar, surge run, HEKF on the paper's manoeuvre): the surge stage's
/// runs are replicated and Xud calibrates; Nrd, Nrr and Nvv, which the manoeuvre does not
/// separate, end far off in most replicas and the far warning names them (docs/calibrate.md,
/// "The bundled spheroid").
#[test]
fn the_default_example_calibrates_its_surge_run_and_names_what_the_manoeuvre_leaves_open() {
    let example = common::example_copy();
    let out = example.path().join("out");
    let o = common::run_config(&example.path().join("configs/spheroid.toml"), &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let o = common::calibrate(&out, REPLICAS, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let c = parsed(&o);
    assert_eq!(c["converged"], REPLICAS, "{c}");
    let row = |name: &str| {
        c["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("{name} in {c}"))
            .clone()
    };
    let ratio = row("Xud")["spread_ratio"].as_f64().unwrap();
    assert!((0.55..=1.45).contains(&ratio), "Xud spread {ratio}");
    // docs/calibrate.md: "Xud spread 0.86 sigma, Xuu 0.86, Yuvl 1.07"
    let spreads = ["Xud", "Xuu", "Yuvl"]
        .map(|n| format!("{:.2}", row(n)["spread_ratio"].as_f64().unwrap()))
        .join(" ");
    assert_eq!(spreads, "0.86 0.86 1.07");
    let far: Vec<u64> = ["Nrd", "Nrr", "Nvv"]
        .map(|n| row(n)["far"].as_u64().unwrap())
        .to_vec();
    assert_eq!(far, [8, 14, 9]);
    for n in ["Xud", "Xuu", "Yuvl"] {
        assert_eq!(row(n)["far"], 0, "{n}");
    }
    let warning = c["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["message"].as_str().unwrap())
        .find(|m| m.contains("more than 5 reported"))
        .unwrap_or_else(|| panic!("no far warning: {c}"));
    assert!(warning.contains("Nrd 8, Nrr 14, Nvv 9"), "{warning}");
}

/// nomoto_wave's replicas carry the waves (the process noise of the wave-yaw state): their
/// spread of K, 1/T and delta0 is within the check's band of the reported sigmas (without
/// the waves it was 0.02-0.03 of them; docs/calibrate.md).
#[test]
fn the_nomoto_replicas_carry_the_waves() {
    let example = common::example_copy();
    let out = example.path().join("out");
    let o = common::run_config(&example.path().join("configs/nomoto.toml"), &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let o = common::calibrate(&out, 8, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let c = parsed(&o);
    assert_eq!(c["converged"], 8, "{c}");
    let ratios: Vec<f64> = c["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| row["spread_ratio"].as_f64().unwrap())
        .collect();
    for r in &ratios {
        // the check's band at 8 replicas: 0.67 / (1 + 2 se) to 1.5 / (1 - 2 se), se = 1/sqrt(14)
        assert!((0.44..=3.2).contains(r), "{ratios:?}");
    }
    // docs/calibrate.md: "spread/sigma 0.98-1.23 for K, 1/T and delta0"
    let (lo, hi) = ratios
        .iter()
        .fold((f64::INFINITY, 0f64), |(l, h), r| (l.min(*r), h.max(*r)));
    assert_eq!(format!("{lo:.2}-{hi:.2}"), "0.98-1.23");
    assert!(
        c["warnings"].as_array().unwrap().is_empty(),
        "{}",
        c["warnings"]
    );
}

#[test]
fn a_noise_model_ten_times_too_small_is_flagged() {
    let example = common::example_copy();
    // the manoeuvres' noise is about 1e-3 SI (results.json); the filter is told 1e-4
    let set: Vec<String> = ["u", "v", "r", "x", "y", "yaw"]
        .iter()
        .map(|q| format!("hekf.noise.{q}=0.0001"))
        .collect();
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let out = common::joint_run(example.path(), &set);
    let o = common::calibrate(&out, 12, &["--strict"]);
    let stderr = common::text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("warning: the replicas' spread is outside 0.67-1.5 reported sigmas"),
        "{stderr}"
    );
    let c = parsed(&o);
    let xuu = common::named(&c["coefficients"], "Xuu");
    assert!(xuu["spread_ratio"].as_f64().unwrap() > 1.5, "{xuu}");
    assert!(c["overall"]["within_2"].as_f64().unwrap() < 0.9, "{c}");
}

/// Coefficients by name: (value, sigma).
type Values = std::collections::BTreeMap<String, (f64, f64)>;

/// Each coefficient of a results.json as (value, sigma) by name.
fn values(r: &serde_json::Value) -> Values {
    r["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|c| {
            Some((
                c["name"].as_str()?.to_string(),
                (c["value"].as_f64()?, c["sigma"].as_f64()?),
            ))
        })
        .collect()
}

#[test]
fn the_settings_row_is_what_runs_with_those_settings_give() {
    // docs/calibrate.md, "Settings": the KVLCC2 turns identified again with the inputs read
    // the other way between samples and with each turn left out. Checked against `hydroid
    // run` on configurations written here with those settings.
    let example = common::example_copy();
    let dir = example.path();
    let config = dir.join("configs/ship_kvlcc2.toml");
    let out = dir.join("out");
    let o = common::run_config(&config, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let original = common::json(&out.join("results.json"));
    let base = values(&original);
    let o = common::calibrate(&out, 2, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let c = parsed(&o);
    let variants = c["settings"]["variants"].as_array().unwrap();
    let labels: Vec<&str> = variants
        .iter()
        .map(|v| v["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "the inputs read the other way between samples (held <-> linear)",
            "hekf run '35 deg starboard turn' left out",
            "hekf run '35 deg port turn' left out",
        ]
    );
    // the inputs read the other way: each run's `between` flipped in the configuration
    let set = between_flipped(&original);
    assert!(!set.is_empty());
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let flipped_out = dir.join("flipped");
    let o = common::run_config(&config, &flipped_out, &set);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let flipped = values(&common::json(&flipped_out.join("results.json")));
    expect_moves(&base, &variants[0], &flipped);
    // the port turn left out: the configuration without its [[hekf.runs]] block
    let alone = values(&starboard_only_run(dir, &config));
    expect_moves(&base, &variants[2], &alone);
    the_z_of_a_run_left_out(&base, &variants[2], &alone);
    the_settings_rows_and_warning(&c);
}

/// The `--set` overrides reading each hekf run's inputs of `original` (a results.json) the
/// other way between samples: each run's `between` flipped.
fn between_flipped(original: &serde_json::Value) -> Vec<String> {
    let mut set = Vec::new();
    for (i, run) in original["stages"]["hekf"]["runs"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        for (q, rule) in run["between"].as_object().unwrap() {
            let other = if rule == "held" { "linear" } else { "hold" };
            set.push(format!("hekf.runs[{i}].between.{q}=\"{other}\""));
        }
    }
    set
}

/// A settings variant `v`'s moves: each coefficient's move from `base` to `other`, in the
/// sigmas of `base`.
fn expect_moves(base: &Values, v: &serde_json::Value, other: &Values) {
    for (name, m) in v["moves"].as_object().unwrap() {
        let ((v0, s0), (v1, _)) = (base[name], other[name]);
        let want = (v1 - v0) / s0;
        let got = m.as_f64().unwrap();
        assert!(
            (got - want).abs() < 1e-6 * want.abs().max(1.0),
            "{name}: {got} {want}"
        );
    }
}

/// The results.json of `config` (in the example copy `dir`) run without its second
/// [[hekf.runs]] block, the port turn (written to configs/starboard_only.toml).
fn starboard_only_run(dir: &Path, config: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(config).unwrap();
    let second = text.match_indices("[[hekf.runs]]").nth(1).unwrap().0;
    let end = text.find("[[hekf.validation]]").unwrap();
    let starboard_only = dir.join("configs/starboard_only.toml");
    std::fs::write(
        &starboard_only,
        format!("{}{}", &text[..second], &text[end..]),
    )
    .unwrap();
    let alone_out = dir.join("alone");
    let o = common::run_config(&starboard_only, &alone_out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    common::json(&alone_out.join("results.json"))
}

/// A run left out (variant `v`, the coefficients `alone` without it): its z, the move over
/// sqrt(sigma_alone^2 - sigma^2) (Hausman 1978).
fn the_z_of_a_run_left_out(base: &Values, v: &serde_json::Value, alone: &Values) {
    for (name, z) in v["z"].as_object().unwrap() {
        let ((v0, s0), (v1, s1)) = (base[name], alone[name]);
        let spread = (s1 * s1 - s0 * s0).max(0.01 * s0 * s0).sqrt();
        assert!(
            (z.as_f64().unwrap() - (v1 - v0) / spread).abs() < 1e-6,
            "{name}"
        );
    }
}

/// The calibration `c`'s settings rows and warning: Nr_p moves by 7.1 sigma when the inputs
/// are read the other way (docs/calibrate.md), which the run is told about.
fn the_settings_rows_and_warning(c: &serde_json::Value) {
    let rows = c["settings"]["coefficients"].as_array().unwrap();
    let nr = common::named(&c["settings"]["coefficients"], "Nr_p");
    assert_eq!(
        format!("{:+.1}", nr["between_sigmas"].as_f64().unwrap()),
        "+7.1"
    );
    assert!(rows
        .iter()
        .all(|r| r["settings_sigma"].as_f64().unwrap() >= 0.0));
    let warned = c["warnings"].as_array().unwrap().iter().any(|w| {
        w["message"]
            .as_str()
            .unwrap()
            .starts_with("with the inputs read the other way")
    });
    assert!(warned, "{c}");
}
