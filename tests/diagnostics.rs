//! Wrong answers are not said confidently: every stage's warnings, a failed innovation
//! consistency test and a poor re-simulation reach the console, results.json and the report;
//! plausibility checks name the likely cause of common mistakes before filtering; gaps in
//! time and spike cells neither bias nor break the identification.
//!
//! Each test starts from a copy of the bundled example (configs/ and cfd_exports/) in a
//! temporary folder and changes one thing, as a user would.

use crate::common;

use common::accuracy::Accuracy;
use common::{example_copy, json, named, text};
use serde_json::Value;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// `hydroid run configs/spheroid.toml --out out <extra>` in `dir` (figures off unless asked).
fn run(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["run", "configs/spheroid.toml", "--out", "out"];
    if !extra.contains(&"output.plots=true") {
        args.extend(["--set", "output.plots=false"]);
    }
    args.extend(extra);
    let mut child = Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(&args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the hydroid binary runs");
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut b = Vec::new();
            let _ = r.read_to_end(&mut b);
            b
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    // a hang is a failure, not a stuck CI job (a debug run takes seconds)
    let deadline = Instant::now() + Duration::from_secs(300);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("hydroid {args:?} did not finish within 300 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

fn stderr(o: &Output) -> String {
    text(&o.stderr)
}

fn results(dir: &Path) -> Value {
    json(&dir.join("out/results.json"))
}

/// The results.json warnings whose message contains `fragment`.
fn warnings_with(r: &Value, fragment: &str) -> Vec<Value> {
    r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["message"].as_str().unwrap().contains(fragment))
        .cloned()
        .collect()
}

/// Value and sigma of a coefficient in results.json.
fn coefficient(r: &Value, name: &str) -> (f64, f64) {
    let c = named(&r["coefficients"], name);
    (c["value"].as_f64().unwrap(), c["sigma"].as_f64().unwrap())
}

/// Rewrites the data rows (lines that start with a number) of an export: `edit` gets the
/// row's index and its cells, and returns false to drop the row.
fn edit_rows(path: &Path, edit: impl Fn(usize, &mut Vec<String>) -> bool) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    let mut row = 0;
    for line in text.lines() {
        let data = line
            .split(',')
            .next()
            .is_some_and(|c| c.trim().parse::<f64>().is_ok());
        if data {
            let mut cells: Vec<String> = line.split(',').map(String::from).collect();
            if edit(row, &mut cells) {
                out.push(cells.join(","));
            }
            row += 1;
        } else {
            out.push(line.to_string());
        }
    }
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

const TURN: &str = "cfd_exports/turn_paper.csv";
/// Columns of the CFX export of the paper's manoeuvre.
const U: usize = 4;
const V: usize = 5;

/// The estimates of the bundled example, unchanged.
fn clean_estimates() -> &'static Value {
    static R: std::sync::OnceLock<Value> = std::sync::OnceLock::new();
    R.get_or_init(|| {
        let dir = example_copy();
        let o = run(dir.path(), &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        results(dir.path())
    })
}

const ESTIMATED: [&str; 6] = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"];

/// The HEKF's sigma of `name` from the data alone (`stages.hekf.sigma_filter`, in
/// `estimated` order: the polar and surge coefficients it holds taken as exact). A gap or a
/// spike in the motion can move an estimate only through the data, so a shift is measured
/// in this sigma: the total one, two hundred times larger here (the polar's drag carried
/// into the HEKF, docs/validation.md), would let a shift of 20 % pass as "under 1 sigma".
fn data_sigma(r: &Value, name: &str) -> f64 {
    let h = &r["stages"]["hekf"];
    let i = h["estimated"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("{name} not in {}", h["estimated"]));
    h["sigma_filter"][i].as_f64().unwrap()
}

/// Each HEKF estimate's change against the clean run, in the clean run's sigmas from the
/// data alone ([`data_sigma`]); each printed, with the spread that losing data explains
/// (sqrt(sigma^2 - sigma_clean^2), the run's data a subset of the clean run's).
fn shifts(r: &Value) -> Vec<(&'static str, f64)> {
    ESTIMATED
        .iter()
        .map(|n| {
            let (v0, total) = coefficient(clean_estimates(), n);
            let s0 = data_sigma(clean_estimates(), n);
            let (v, _) = coefficient(r, n);
            let lost = (data_sigma(r, n).powi(2) - s0 * s0).max(0.0).sqrt();
            println!(
                "{n}: {v0:.6} -> {v:.6}, {:+.3} data sigma ({s0:.2e}), {:+.2} of the spread \
                 losing data explains ({lost:.2e}), {:+.4} total sigma",
                (v - v0) / s0,
                (v - v0) / lost,
                (v - v0) / total
            );
            (*n, (v - v0) / s0)
        })
        .collect()
}

/// The largest |change| of an HEKF estimate against the clean run, in data sigmas ([`shifts`]).
fn largest_shift(r: &Value) -> f64 {
    shifts(r).iter().map(|(_, z)| z.abs()).fold(0.0, f64::max)
}

/// docs/validation.md, "The whole pipeline on the bundled example": per HEKF and surge
/// coefficient, value ± sigma and z against the truth, the sigma from the data alone
/// (`stages.hekf.sigma_filter`; the surge stage's `sigma_statistical` for Xud) and the
/// budget's other stages (above 0.0005), at the table's printed digits.
#[test]
fn the_bundled_pipeline_gives_the_table_of_the_docs() {
    let r = clean_estimates();
    let truth = [
        ("Xud", -1.164),
        ("Yvd", -23.626),
        ("Nrd", -1.4532),
        ("Nvv", 10.0),
        ("Nrr", -5.0),
        ("Yrr", 0.5),
    ];
    let a = Accuracy::from_json("the bundled example", &r["coefficients"], &truth, &[]);
    println!("{}", a.table());
    a.assert_printed(&[
        ("Xud", "-0.903 ± 0.128 | +2.0"),
        ("Yvd", "-23.22 ± 0.18 | +2.3"),
        ("Nrd", "-1.390 ± 0.105 | +0.6"),
        ("Nvv", "9.88 ± 0.20 | -0.6"),
        ("Nrr", "-4.957 ± 0.043 | +1.0"),
        ("Yrr", "0.65 ± 0.63 | +0.2"),
    ]);
    let columns: Vec<String> = truth
        .iter()
        .map(|(name, _)| {
            let data = match *name {
                "Xud" => r["stages"]["surge"]["xud"]["sigma_statistical"]
                    .as_f64()
                    .unwrap(),
                _ => data_sigma(r, name),
            };
            let budget = &named(&r["comparison"], name)["budget"];
            let mut stages: Vec<(&str, f64)> = budget
                .as_object()
                .unwrap()
                .iter()
                .filter(|(stage, _)| *stage != "hekf")
                .map(|(stage, s)| (stage.as_str(), s.as_f64().unwrap()))
                .filter(|(_, s)| *s >= 0.0005)
                .collect();
            stages.sort_by(|x, y| y.1.total_cmp(&x.1));
            let stages: Vec<String> = stages.iter().map(|(n, s)| format!("{n} {s:.3}")).collect();
            format!("{name} | {data:.4} | {}", stages.join(", "))
        })
        .collect();
    println!("{columns:#?}");
    assert_eq!(
        columns,
        [
            "Xud | 0.0238 | polar 0.126, surge 0.024",
            "Yvd | 0.0097 | polar 0.179, surge 0.009, noise 0.003",
            "Nrd | 0.0054 | polar 0.105, surge 0.008, noise 0.002",
            "Nvv | 0.0110 | polar 0.196, surge 0.015, noise 0.004",
            "Nrr | 0.0070 | polar 0.042, noise 0.001",
            "Yrr | 0.0042 | polar 0.625, surge 0.074",
        ]
    );
    // docs/stages.md: the surge run's residuals (lag-1 0.92) widen its statistical sigma
    // "4.0 times (0.0059 to 0.0238 kg)"
    let xud = &r["stages"]["surge"]["xud"];
    let factor = xud["misfit_factor"].as_f64().unwrap();
    let stat = xud["sigma_statistical"].as_f64().unwrap();
    assert_eq!(
        format!("{factor:.1} {:.4} {stat:.4}", stat / factor),
        "4.0 0.0059 0.0238"
    );
    // what limits it: the polar's drag (Xuu 0.4 % off, 2.0 of its sigmas) through
    // d Xud / d Xuu = -51.5 kg per kg/m moves Xud by 22 %; without the consider analysis
    // Yvd's sigma would be the data's alone, 42 of them from the truth
    let xuu = named(&r["coefficients"], "Xuu");
    let (v, s) = (
        xuu["value"].as_f64().unwrap(),
        xuu["sigma"].as_f64().unwrap(),
    );
    let dxud = r["stages"]["surge"]["xud"]["sensitivity_to_xuu"]
        .as_f64()
        .unwrap();
    let said = format!(
        "Xuu {:.1} % off, {:.1} sigma; d Xud / d Xuu = {dxud:.1}; Xud {:.0} % off; Yvd \
         {:.3} ± {:.3}, {:.0} data sigmas off",
        100.0 * (v / -1.33 - 1.0),
        (v + 1.33).abs() / s,
        a.row("Xud").error_percent(),
        a.row("Yvd").estimate,
        data_sigma(r, "Yvd"),
        (a.row("Yvd").estimate + 23.626).abs() / data_sigma(r, "Yvd")
    );
    assert_eq!(
        said,
        "Xuu 0.4 % off, 2.0 sigma; d Xud / d Xuu = -51.5; Xud -22 % off; Yvd -23.217 ± 0.010, \
         42 data sigmas off"
    );
}

#[test]
fn the_bundled_example_says_its_warnings_with_their_meaning() {
    let dir = example_copy();
    let o = run(dir.path(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    // the surge stage's warning and the identifiability advice reach the console, each with
    // its meaning ...
    assert!(
        e.contains("warning: surge: Xud differs between speed bins"),
        "{e}"
    );
    assert!(
        e.contains("warning: hekf: not determined by these runs"),
        "{e}"
    );
    assert!(
        e.contains("meaning: their values rest on little information"),
        "{e}"
    );
    assert!(e.contains("warnings above, grouped by kind"), "{e}");
    // ... results.json: with the noise model from the data (docs/hekf.md, "The noise
    // model") the paper manoeuvre's innovations are consistent, and no NIS warning is raised
    let r = results(dir.path());
    let run = &r["stages"]["hekf"]["runs"][0];
    assert_eq!(run["nis"]["consistent"], true, "{}", run["nis"]);
    assert!(
        warnings_with(&r, "mean NIS").is_empty(),
        "{:#?}",
        r["warnings"]
    );
    assert_eq!(warnings_with(&r, "speed bins")[0]["stage"], "surge");
    // ... and the report's Warnings section
    let md = std::fs::read_to_string(dir.path().join("out/report.md")).unwrap();
    let section = &md[md.find("## Warnings").unwrap()..];
    assert!(
        section.contains("not determined by these runs"),
        "{section}"
    );
    assert!(
        section.contains("Xud differs between speed bins"),
        "{section}"
    );
}

#[test]
fn a_wrong_constant_thrust_is_named_not_hidden() {
    let dir = example_copy();
    let o = run(
        dir.path(),
        &["--set", "hekf.runs[0].constants.thrust=\"30 N\""],
    );
    let e = stderr(&o);
    assert!(
        e.contains("the constant thrust of 30.00 N does not fit the motion"),
        "{e}"
    );
    // docs/hekf.md: "implies 21.84 +- 0.1020 N"
    assert!(e.contains("implies 21.84 +- 0.1020 N"), "{e}");
    // the bundled polar and surge run are precise: no held coefficient explains 8 N
    assert!(!e.contains("held at an earlier stage's estimate"), "{e}");
    assert!(e.contains("mean NIS"), "{e}");
    let r = results(dir.path());
    assert_eq!(warnings_with(&r, "does not fit the motion").len(), 1);
    // the misfit shows in the process noise calibrated for u: 1e-5 m^2/s^3 on the bundled
    // run, 2.6e-2 with the wrong thrust
    let q_u = r["stages"]["hekf"]["runs"][0]["process_noise"]["u"]
        .as_f64()
        .unwrap();
    assert!(q_u > 1e-3, "{q_u}");
    // the validation run, re-simulated with these coefficients, says so too
    assert!(
        !warnings_with(&r, "poor re-simulation").is_empty(),
        "{:#?}",
        r["warnings"]
    );
}

/// A noisy polar (issue 24, item 7): its drag coefficients with noise of 0.05 (half their
/// size) leave X_vv uncertain by more than its value; the manoeuvre's thrust then looks
/// wrong, and the check says that the polar's X_vv explains the misfit within its sigmas
/// instead of blaming the thrust alone.
#[test]
fn a_noisy_polar_is_named_beside_the_thrust_it_would_be_blamed_on() {
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};
    let dir = example_copy();
    let noise = Normal::new(0.0, 0.05).unwrap();
    let rng = std::cell::RefCell::new(StdRng::seed_from_u64(SEED));
    edit_rows(&dir.path().join("cfd_exports/polar_sweep.csv"), |_, c| {
        let cd: f64 = c[2].trim().parse().unwrap();
        c[2] = format!("{}", cd + noise.sample(&mut *rng.borrow_mut()));
        true
    });
    let e = stderr(&run(dir.path(), &[]));
    let finding = e
        .lines()
        .find(|l| l.contains("the constant thrust of 22.00 N does not fit the motion"))
        .unwrap_or_else(|| panic!("{e}"));
    assert!(
        finding.contains("a coefficient held at an earlier stage's estimate: ")
            && finding.contains(" kg/m from the polar stage, at "),
        "{finding}"
    );
    assert!(finding.contains("Xvv = "), "{finding}");
    assert!(
        e.contains("rather than this run's thrust may be the cause"),
        "{e}"
    );
    // a model that runs away in the re-simulation is "over 1000 %", never a number of fifty
    // digits
    let longest = e
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest < 12, "{e}");
}

/// The noise seed of [`a_noisy_polar_is_named_beside_the_thrust_it_would_be_blamed_on`]: one
/// whose polar is far enough off for the thrust check to fire (seeds 1, 3, 5 and 9 of 1-11
/// do; with the others the manoeuvre fits the thrust and nothing is said).
const SEED: u64 = 1;

#[test]
fn a_two_second_gap_is_crossed_in_regular_steps_and_reported() {
    let dir = example_copy();
    edit_rows(&dir.path().join(TURN), |_, c| {
        let t: f64 = c[0].trim().parse().unwrap();
        !(t > 8.0 && t <= 10.0)
    });
    let o = run(dir.path(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = results(dir.path());
    let gap = warnings_with(&r, "gap in the time axis");
    assert_eq!(gap.len(), 1, "{:#?}", r["warnings"]);
    let m = gap[0]["message"].as_str().unwrap();
    assert!(m.contains("2.01 s after t = 8 s (lines 806-807)"), "{m}");
    // integrated in 10 ms steps, the gap moves no estimate by more than a fraction of its
    // sigma from the data (measured: 0.24, Yrr)
    let shift = largest_shift(&r);
    assert!(shift < 0.3, "largest shift {shift} sigma");
}

#[test]
fn a_five_second_gap_does_not_end_the_run() {
    let dir = example_copy();
    edit_rows(&dir.path().join(TURN), |_, c| {
        let t: f64 = c[0].trim().parse().unwrap();
        !(t > 8.0 && t <= 13.0)
    });
    let o = run(dir.path(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = results(dir.path());
    assert_eq!(warnings_with(&r, "5.01 s after t = 8 s").len(), 1);
    // a quarter of the run lost: every estimate within 1 sigma from the data of the clean
    // run (measured: at most 0.74), but Yrr, 2.9 of them (1.9 % of Yrr, 0.02 of its total
    // sigma; 3.5 of the spread the lost data explain: what crossing 5 s without data costs)
    for (name, z) in shifts(&r) {
        let limit = if name == "Yrr" { 3.0 } else { 1.0 };
        assert!(z.abs() < limit, "{name} moved by {z:+.2} sigma");
    }
}

#[test]
fn spike_cells_are_left_out_and_named_by_line() {
    let dir = example_copy();
    edit_rows(&dir.path().join(TURN), |row, c| {
        match row {
            0 => c[U] = "1e308".into(),
            700 => c[V] = "1e-320".into(),
            1200 => c[U] = "-1e308".into(),
            _ => {}
        }
        true
    });
    // with the figures: a 1e308 cell must neither hang nor overflow the plotting
    let o = run(dir.path(), &["--set", "output.plots=true"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = results(dir.path());
    let u = warnings_with(&r, "outliers in u left out");
    assert_eq!(u.len(), 1, "{:#?}", r["warnings"]);
    let m = u[0]["message"].as_str().unwrap();
    assert!(
        m.contains("line 6 (t = 0 s: 1e308") && m.contains("line 1206"),
        "{m}"
    );
    let v = warnings_with(&r, "1 outlier in v left out: line 706");
    assert_eq!(v.len(), 1, "{:#?}", r["warnings"]);
    assert!(warnings_with(&r, "re-simulation").is_empty());
    // left out, the three spikes move no estimate by more than 0.05 sigma from the data
    // (measured: 0.031, Nrr)
    let shift = largest_shift(&r);
    assert!(shift < 0.05, "largest shift {shift} sigma");
    assert!(dir.path().join("out/plots").is_dir());
}

/// Runs the example with `set` and expects the plausibility checks to stop it with a message
/// containing `says`.
fn stopped_before_filtering(set: &[&str], says: &str) {
    let dir = example_copy();
    let mut extra = Vec::new();
    for s in set {
        extra.extend(["--set", s]);
    }
    let o = run(dir.path(), &extra);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{set:?}: {e}");
    assert!(e.contains(says), "{set:?}: {e}");
    assert!(e.contains("hekf.checks = \"warn\" runs anyway"), "{e}");
    assert!(!dir.path().join("out").exists());
}

#[test]
fn earth_frame_velocities_under_a_body_label_are_named() {
    let dir = example_copy();
    // u and v replaced by dx/dt and dy/dt (the heading column is in degrees)
    edit_rows(&dir.path().join(TURN), |_, c| {
        let psi = c[3].trim().parse::<f64>().unwrap().to_radians();
        let (u, v): (f64, f64) = (c[U].trim().parse().unwrap(), c[V].trim().parse().unwrap());
        c[U] = format!("{:.9}", u * psi.cos() - v * psi.sin());
        c[V] = format!("{:.9}", u * psi.sin() + v * psi.cos());
        true
    });
    let o = run(dir.path(), &[]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("set `velocity_frame = \"earth\"` for this run"),
        "{e}"
    );
    // told it is earth-frame, the run goes through
    let o = run(
        dir.path(),
        &["--set", "hekf.runs[0].velocity_frame=\"earth\""],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn knots_under_a_metre_per_second_label_are_named() {
    let dir = example_copy();
    edit_rows(&dir.path().join(TURN), |_, c| {
        for k in [U, V] {
            c[k] = format!(
                "{:.9}",
                c[k].trim().parse::<f64>().unwrap() * 3600.0 / 1852.0
            );
        }
        true
    });
    let o = run(dir.path(), &[]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("the velocities look like knots read as m/s"),
        "{e}"
    );
}

#[test]
fn heading_units_and_signs_and_shared_columns_are_named() {
    stopped_before_filtering(
        &["hekf.runs[0].columns.yaw={column=\"Heading\",unit=\"rad\"}"],
        "the angle looks like degrees read as radians",
    );
    stopped_before_filtering(
        &["hekf.runs[0].columns.r={column=\"Yaw Rate\",unit=\"rad/s\"}"],
        "the rate looks like deg/s read as rad/s",
    );
    stopped_before_filtering(
        &["hekf.runs[0].columns.yaw={column=\"Heading\",scale=-1}"],
        "heading and yaw rate follow opposite sign conventions",
    );
    stopped_before_filtering(
        &["hekf.runs[0].columns.v={column=\"Velocity v\",scale=-1}"],
        "the sway velocity has the opposite sign convention",
    );
    stopped_before_filtering(
        &["hekf.runs[0].columns.v=\"Velocity u\""],
        "u, v hold identical values in all 2001 rows",
    );
}

#[test]
fn checks_can_be_turned_into_warnings() {
    let dir = example_copy();
    let o = run(
        dir.path(),
        &[
            "--set",
            "hekf.runs[0].columns.r={column=\"Yaw Rate\",unit=\"rad/s\"}",
            "--set",
            "hekf.checks=\"warn\"",
            "--set",
            "hekf.validation=[]",
        ],
    );
    let e = stderr(&o);
    // the filter runs (here it fails: r is 57 times too small) and the likely cause is said
    // with the failure, not only with a finished result
    assert_ne!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("the rate looks like deg/s read as rad/s"), "{e}");
    assert!(!e.contains("hekf.checks = \"warn\" runs anyway"), "{e}");
}

#[test]
fn a_polar_in_radians_under_a_degree_label_is_named() {
    let dir = example_copy();
    edit_rows(&dir.path().join("cfd_exports/polar_sweep.csv"), |_, c| {
        c[0] = format!("{:.9}", c[0].trim().parse::<f64>().unwrap().to_radians());
        true
    });
    let o = run(dir.path(), &["--set", "hekf.enabled=false"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("as radians they would span -12.0 to 12.0 deg"),
        "{e}"
    );
    assert!(e.contains("57.3 times too large"), "{e}");
}
