//! The KVLCC2 identified from real free-running basin logs with the configurations a user
//! writes from the docs (configs/real/*.toml: no hand-set noise, no hand-set R0_p), checked
//! on the other campaign's runs it was not fitted to (docs/models/ships.md, "Real basin
//! logs"): MARIN's 35 deg turning circles and 20/20 zig-zag (full scale, Froude-scaled to
//! the 1/45.7 model) and HSVA's three model-scale zig-zags (SIMMAN 2014).
//!
//! The logs are not in the repository (their licence is not stated): they are read from
//! `$HYDROID_REAL_DATA`, by default `../shared/data/real` beside the repository. Run by
//! .ci/run as its own step: `cargo test --test suite -- --ignored real_logs::` (`--nocapture`
//! prints the measures).
//!
//! The numbers asserted are the ones docs/models/ships.md states, at the precision it
//! states them: overshoot errors in whole tenths of a degree, turning measures in whole
//! percent.

use crate::common;

use common::{json, run_config, text};
use serde_json::Value;
use std::path::Path;

use common::real_data_dir as data_dir;

/// What `hydroid run` gives for configs/real/`name` with its file paths set to the data
/// folder and `edit` applied to its text: results.json and the console's stderr.
fn identify(name: &str, edit: &dyn Fn(String) -> String) -> (Value, String) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text_in = std::fs::read_to_string(root.join("configs/real").join(name)).unwrap();
    let data = data_dir().display().to_string().replace('\\', "/");
    let config = edit(text_in.replace("../../../shared/data/real", &data));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, config).unwrap();
    let out = dir.path().join("out");
    let o = run_config(&path, &out, &[]);
    let said = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{said}");
    says_measured(&out.join("report.md"));
    let r = json(&out.join("results.json"));
    // results.json says per run how `between = auto` read the rudder: linearly on every
    // run, MARIN's turns too (after the one execution their rudder flickers by one printed
    // digit, many small jumps that the rule weighs against the execution's ramp)
    for run in r["stages"]["hekf"]["runs"].as_array().unwrap() {
        assert_eq!(run["between"]["rudder"], "linear", "{}", run["name"]);
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("Inputs between samples"), "{md}");
    (r, said)
}

/// The report of basin logs calls the data measured, never CFD (issue 27).
fn says_measured(report: &Path) {
    let md = std::fs::read_to_string(report).unwrap();
    assert!(md.contains("measured"), "{md}");
    for cfd in [
        "CFD export",
        "CFD data",
        "model − CFD",
        "CFD points",
        "| CFD |",
    ] {
        assert!(!md.contains(cfd), "'{cfd}' in the report of basin logs");
    }
}

/// Only R0_p estimated: the published hull derivatives, with the surge balance the runs need.
fn published(text: String) -> String {
    let start = text.find("\nestimate = [").expect("an estimate list");
    let end = start + text[start..].find("]\n").unwrap() + 1;
    format!("{}\nestimate = [\"R0_p\"]{}", &text[..start], &text[end..])
}

/// A resimulated run's manoeuvre measures: (measured, model) of `kind` (`turning_circle`,
/// `zigzag`).
fn measures<'a>(r: &'a Value, run: &str, kind: &str) -> (&'a Value, &'a Value) {
    let e = r["resimulation"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["run"] == run)
        .unwrap_or_else(|| panic!("no resimulation of {run}"));
    let m = &e["manoeuvre"];
    (&m["measured"][kind], &m["model"][kind])
}

/// The model's error in the overshoot angles of the zig-zags `runs` that both the log and
/// the model reach, deg.
fn overshoot_errors(r: &Value, runs: &[&str]) -> Vec<f64> {
    let mut out = Vec::new();
    for run in runs {
        let (log, model) = measures(r, run, "zigzag");
        for key in ["first_overshoot", "second_overshoot"] {
            if let (Some(a), Some(b)) = (log[key]["value"].as_f64(), model[key]["value"].as_f64()) {
                out.push((b - a).to_degrees());
            }
        }
    }
    out
}

/// Mean and largest magnitude of `e`.
fn mean_worst(e: &[f64]) -> (f64, f64) {
    let mean = e.iter().map(|x| x.abs()).sum::<f64>() / e.len() as f64;
    (mean, e.iter().fold(0.0f64, |a, x| a.max(x.abs())))
}

/// The model's relative error (%) in the tactical diameter and advance of the turn `run`.
fn turn_errors(r: &Value, run: &str) -> (f64, f64) {
    let (log, model) = measures(r, run, "turning_circle");
    let pct = |k: &str| {
        100.0 * (model[k]["value"].as_f64().unwrap() / log[k]["value"].as_f64().unwrap() - 1.0)
    };
    (pct("tactical_diameter"), pct("advance"))
}

/// Every estimated coefficient has a finite, positive sigma.
fn sigmas_are_finite(r: &Value) {
    for c in r["coefficients"].as_array().unwrap() {
        if c["source"] == "hekf" {
            let s = c["sigma"].as_f64().unwrap_or(f64::NAN);
            assert!(s.is_finite() && s > 0.0, "{c}");
        }
    }
}

/// Every run's measurement noise comes from the data (none is set by hand: HSVA's positions,
/// printed to 1e-9 m and smooth, sit at the floor of a millionth of their range, said as
/// such) and its process noise from the model's misfit.
fn noise_from_the_data(r: &Value) {
    for run in r["stages"]["hekf"]["runs"].as_array().unwrap() {
        for n in run["noise"].as_array().unwrap() {
            let source = n["source"].as_str().unwrap();
            assert!(
                source.contains("estimated from the data")
                    || source.contains("consistency")
                    || source.contains("rounding")
                    || source.contains("the data look noise-free"),
                "{n}"
            );
            assert!(n["sigma"].as_f64().unwrap() > 0.0, "{n}");
        }
        assert!(
            run["process_noise"]
                .as_object()
                .is_some_and(|q| !q.is_empty()),
            "{run}"
        );
    }
}

const HSVA_ZIGZAGS: [&str; 3] = ["HSVA 10/10 P", "HSVA 20/10 P", "HSVA 20/10 S"];
const MARIN_TURNS: [&str; 2] = ["MARIN 35 turn (port)", "MARIN 35 turn (starboard)"];

/// Identified from MARIN's turns and zig-zag, the model predicts HSVA's zig-zags (another
/// basin, model scale, never fitted) better than the published MMG set: mean overshoot
/// error 1.6 deg against 2.4, worst 3.4 against 4.3.
#[test]
#[ignore = "reads the real basin logs in ../shared/data/real; .ci/run runs it"]
fn marin_identified_predicts_the_hsva_zigzags_better_than_the_published_set() {
    let (r, said) = identify("kvlcc2_marin.toml", &|t| t);
    // MARIN's 3-digit time stamps: the uniform time base is rebuilt, with a note
    assert!(said.contains("the time column repeats stamps"), "{said}");
    sigmas_are_finite(&r);
    noise_from_the_data(&r);
    let (mean, worst) = mean_worst(&overshoot_errors(&r, &HSVA_ZIGZAGS));
    let (p, _) = identify("kvlcc2_marin.toml", &published);
    let (pub_mean, pub_worst) = mean_worst(&overshoot_errors(&p, &HSVA_ZIGZAGS));
    println!("HSVA overshoot errors: identified {mean:.2}/{worst:.2}, published {pub_mean:.2}/{pub_worst:.2} deg");
    let fitted: Vec<(f64, f64)> = MARIN_TURNS.iter().map(|n| turn_errors(&r, n)).collect();
    println!("MARIN turns (fitted), tactical diameter and advance %: {fitted:?}");
    assert!(mean < pub_mean && worst < pub_worst);
    assert!((mean - 1.6).abs() < 0.05, "{mean}");
    assert!((worst - 3.4).abs() < 0.05, "{worst}");
    assert!((pub_mean - 2.4).abs() < 0.05, "{pub_mean}");
    assert!((pub_worst - 4.3).abs() < 0.05, "{pub_worst}");
    // the turns it was fitted to: tactical diameter +0.4 % and -6.3 %, advance -0.1 % and
    // -1.1 %
    for ((td, adv), (want_td, want_adv)) in fitted.iter().zip([(0.4, -0.1), (-6.3, -1.1)]) {
        assert!(
            (td - want_td).abs() < 0.05 && (adv - want_adv).abs() < 0.05,
            "{fitted:?}"
        );
    }
}

/// Identified from HSVA's three zig-zags (the four linear derivatives, docs/models/ships.md
/// "Which terms a run can give"): the surge balance the logged propeller speed contradicts
/// is estimated by default (R0_p 0.0150 against the published 0.022) and said; MARIN's turns
/// (other basin, full scale) are predicted with the tactical diameter +5.5 % and -1.6 % and
/// the advance +1.8 % and +0.6 % (the published set, R0_p balanced the same way: +8.3 %,
/// +0.8 % and +4.7 %, +4.3 %): the advance within issue 21's 2 %, the diameter not within
/// its 3 % on both sides, since MARIN's own turns differ by 8.0 % between port and
/// starboard (tactical diameters 21.47 and 23.34 m).
#[test]
#[ignore = "reads the real basin logs in ../shared/data/real; .ci/run runs it"]
fn hsva_identified_estimates_the_surge_balance_and_predicts_the_marin_turns() {
    let (r, said) = identify("kvlcc2_hsva.toml", &|t| t);
    assert!(
        said.contains("the approach is not an equilibrium"),
        "{said}"
    );
    sigmas_are_finite(&r);
    noise_from_the_data(&r);
    let r0 = r["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "R0_p")
        .unwrap();
    assert_eq!(r0["source"], "hekf", "{r0}");
    assert!(
        (r0["value"].as_f64().unwrap() - 0.0150).abs() < 0.00005,
        "{r0}"
    );
    let (p, _) = identify("kvlcc2_hsva.toml", &published);
    for (model, want, want_mean) in [
        (&r, [(5.5, 1.8), (-1.6, 0.6)], 1.75),
        (&p, [(8.3, 4.7), (0.8, 4.3)], 2.33),
    ] {
        let turns: Vec<(f64, f64)> = MARIN_TURNS.iter().map(|n| turn_errors(model, n)).collect();
        let (mean, _) = mean_worst(&overshoot_errors(model, &HSVA_ZIGZAGS));
        println!("MARIN turns (not fitted), TD and advance %: {turns:?}; HSVA overshoot {mean:.3}");
        for ((td, adv), (want_td, want_adv)) in turns.iter().zip(want) {
            assert!(
                (td - want_td).abs() < 0.05 && (adv - want_adv).abs() < 0.05,
                "{turns:?}"
            );
        }
        assert!((mean - want_mean).abs() < 0.005, "{mean}");
    }
    // MARIN's measured turns: 8.0 % apart between port and starboard
    let measured: Vec<f64> = MARIN_TURNS
        .iter()
        .map(|n| {
            measures(&r, n, "turning_circle").0["tactical_diameter"]["value"]
                .as_f64()
                .unwrap()
        })
        .collect();
    assert_eq!(
        format!(
            "{:.2} {:.2} {:+.1} %",
            measured[0],
            measured[1],
            100.0 * (measured[0] / measured[1] - 1.0)
        ),
        "21.47 23.34 -8.0 %"
    );
}

/// All 12 sway and yaw derivatives from HSVA's zig-zags, the cubic terms too: the zig-zags
/// fit them to what the rest of the model misses (Y'vvv -5.7 +- 0.7 against the published
/// -1.607, N'vvr -0.71 +- 0.11 against -0.294), the zig-zags themselves a little better (mean
/// overshoot error 1.5 deg), MARIN's 35 deg turns extrapolated: tactical diameter +16.3 % and
/// +8.0 % (docs/models/ships.md, "Which terms a run can give").
#[test]
#[ignore = "reads the real basin logs in ../shared/data/real; .ci/run runs it"]
fn hsva_zigzags_fitting_the_cubic_terms_extrapolate_the_marin_turns() {
    let all = |t: String| {
        let start = t.find("\nestimate = [").expect("an estimate list");
        let end = start + t[start..].find("]\n").unwrap() + 1;
        format!(
            "{}\nestimate = [\"Yv_p\", \"Yr_p\", \"Yvvv_p\", \"Yvvr_p\", \"Yvrr_p\", \
             \"Yrrr_p\", \"Nv_p\", \"Nr_p\", \"Nvvv_p\", \"Nvvr_p\", \"Nvrr_p\", \
             \"Nrrr_p\"]{}",
            &t[..start],
            &t[end..]
        )
    };
    let (r, _) = identify("kvlcc2_hsva.toml", &all);
    let printed = |name: &str| {
        let c = r["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap();
        (c["value"].as_f64().unwrap(), c["sigma"].as_f64().unwrap())
    };
    let ((yv, ys), (nv, ns)) = (printed("Yvvv_p"), printed("Nvvr_p"));
    assert_eq!(
        format!("{yv:.1} {ys:.1} {nv:.2} {ns:.2}"),
        "-5.7 0.7 -0.71 0.11"
    );
    let turns: Vec<(f64, f64)> = MARIN_TURNS.iter().map(|n| turn_errors(&r, n)).collect();
    for ((td, _), want) in turns.iter().zip([16.3, 8.0]) {
        assert!((td - want).abs() < 0.05, "{turns:?}");
    }
    let (mean, _) = mean_worst(&overshoot_errors(&r, &HSVA_ZIGZAGS));
    assert!((mean - 1.5).abs() < 0.05, "{mean}");
}
