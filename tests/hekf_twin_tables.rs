//! The HEKF twin tables of docs/validation.md ("Hybrid EKF twin experiments"), reproduced from
//! the configurations the docs name (configs/twin.toml, configs/twin_second.toml) to the
//! digits they print, and the calibration over 30 noise realisations of the paper's
//! manoeuvre (configs/simulate/turn_paper.toml with seeds 1 to 30, identified by
//! configs/twin.toml).
//!
//! These are twins: `hydroid simulate` made the data with the model that identifies them
//! (docs/validation.md says so); they check the filter's tuning and its sigmas, not the model.

use crate::common;

use common::root;
use std::path::Path;

/// The six estimated coefficients, in the tables' order, and their truth
/// (configs/simulate/turn_paper.toml: Lamb's added mass, the bounded yaw truth).
const TRUTH: [(&str, f64); 6] = [
    ("Yvd", -23.626),
    ("Yrd", 0.0),
    ("Nrd", -1.4532),
    ("Nvv", 10.0),
    ("Nrr", -5.0),
    ("Yrr", 0.5),
];

/// One identification: per coefficient of [`TRUTH`], value and sigma; the fit run's mean NIS,
/// whether it is consistent, and the 95 % bounds of a consistent mean.
struct Identified {
    estimates: Vec<(f64, f64)>,
    nis: (f64, bool, [f64; 2]),
}

/// Runs `config` (a path under the repository) with the overrides `set`, the HEKF stage only
/// read from the result.
fn identify(config: &Path, set: &[String]) -> Identified {
    let loaded = hydroid::config::load(config, set).unwrap();
    let out = hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    let h = out.result.stages.hekf.as_ref().expect("an HEKF stage");
    let estimates = TRUTH
        .iter()
        .map(|(name, _)| {
            let c = h.coefficients.iter().find(|c| c.name == *name).unwrap();
            (c.value, c.sigma.expect("a sigma"))
        })
        .collect();
    let nis = h.runs[0].nis.as_ref().expect("NIS of the fit run");
    Identified {
        estimates,
        nis: (nis.mean, nis.consistent, nis.mean_bounds),
    }
}

/// A column of a table as printed: per coefficient, value and sigma as the docs write them
/// (decimals as printed), and z = (value - truth) / sigma to one decimal.
type Column = [(&'static str, &'static str, &'static str); 6];

/// Asserts that `got` prints as `column` does (each number to the decimals printed), and its
/// mean NIS as `nis` to two decimals with its consistency.
fn assert_column(label: &str, got: &Identified, column: &Column, nis: (&str, bool)) {
    let decimals = |s: &str| s.split_once('.').map_or(0, |(_, d)| d.len());
    for (((name, truth), (v, s)), (pv, ps, pz)) in TRUTH.iter().zip(&got.estimates).zip(column) {
        let z = (v - truth) / s;
        println!("{label}: {name} {v:.6} +- {s:.6}, z {z:+.2}");
        assert_eq!(
            format!("{v:.*}", decimals(pv)),
            *pv,
            "{label}: {name} value"
        );
        assert_eq!(
            format!("{s:.*}", decimals(ps)),
            *ps,
            "{label}: {name} sigma"
        );
        assert_eq!(format!("{z:+.1}"), *pz, "{label}: {name} z");
    }
    println!(
        "{label}: mean NIS {:.3}, consistent {}",
        got.nis.0, got.nis.1
    );
    assert_eq!(format!("{:.2}", got.nis.0), nis.0, "{label}: mean NIS");
    assert_eq!(got.nis.1, nis.1, "{label}: NIS consistency");
}

/// docs/validation.md, the paper's manoeuvre, hydroid's defaults (value, sigma, z).
const PAPER_DEFAULTS: Column = [
    ("-23.6254", "0.0020", "+0.3"), // Yvd
    ("0.0010", "0.0029", "+0.3"),   // Yrd
    ("-1.4528", "0.0010", "+0.4"),  // Nrd
    ("9.9996", "0.0022", "-0.2"),   // Nvv
    ("-5.0006", "0.0028", "-0.2"),  // Nrr
    ("0.4996", "0.0033", "-0.1"),   // Yrr
];
const PAPER_DEFAULTS_NIS: (&str, bool) = ("6.04", true);
/// The paper's manoeuvre, the paper's tuning.
const PAPER_PAPER: Column = [
    ("-21.93", "0.330", "+5.1"), // Yvd
    ("0.082", "0.161", "+0.5"),  // Yrd
    ("-0.482", "0.185", "+5.2"), // Nrd
    ("8.14", "0.353", "-5.3"),   // Nvv
    ("-4.18", "0.191", "+4.3"),  // Nrr
    ("1.41", "0.60", "+1.5"),    // Yrr
];
const PAPER_PAPER_NIS: (&str, bool) = ("3.59", false);
/// The second manoeuvre, hydroid's defaults.
const SECOND_DEFAULTS: Column = [
    ("-23.6259", "0.0038", "+0.0"), // Yvd
    ("0.0145", "0.0066", "+2.2"),   // Yrd
    ("-1.4551", "0.0019", "-1.0"),  // Nrd
    ("10.0043", "0.0041", "+1.0"),  // Nvv
    ("-5.0148", "0.0058", "-2.6"),  // Nrr
    ("0.5062", "0.0048", "+1.3"),   // Yrr
];
const SECOND_DEFAULTS_NIS: (&str, bool) = ("5.88", true);
/// The second manoeuvre, the paper's tuning.
const SECOND_PAPER: Column = [
    ("-21.62", "0.488", "+4.1"), // Yvd
    ("0.576", "0.269", "+2.1"),  // Yrd
    ("-0.406", "0.256", "+4.1"), // Nrd
    ("7.93", "0.499", "-4.1"),   // Nvv
    ("-4.42", "0.233", "+2.5"),  // Nrr
    ("1.24", "0.69", "+1.1"),    // Yrr
];
const SECOND_PAPER_NIS: (&str, bool) = ("3.98", false);

/// Asserts the error column of the paper's manoeuvre table: |estimate - truth| / |truth| in
/// % (Yrd, whose truth is 0: the absolute error in kg m), to the decimals printed.
fn assert_errors(label: &str, got: &Identified, printed: [&str; 6]) {
    for (((name, truth), (v, _)), p) in TRUTH.iter().zip(&got.estimates).zip(printed) {
        let number = p.trim_end_matches(" %");
        let decimals = number.split_once('.').map_or(0, |(_, d)| d.len());
        let error = if *truth == 0.0 {
            (v - truth).abs()
        } else {
            100.0 * ((v - truth) / truth).abs()
        };
        assert_eq!(
            format!("{error:.decimals$}"),
            number,
            "{label}: {name} error"
        );
    }
}

/// The bounds of a consistent mean NIS as the tables print them.
fn nis_bounds(i: &Identified) -> String {
    format!("{:.2}-{:.2}", i.nis.2[0], i.nis.2[1])
}

fn preset(name: &str) -> Vec<String> {
    vec![format!("hekf.preset=\"{name}\"")]
}

/// docs/validation.md, "The paper's manoeuvre": hydroid's defaults and the paper's tuning.
#[test]
fn twin_toml_reproduces_the_paper_manoeuvre_table() {
    let cfg = root().join("configs/twin.toml");
    let defaults = identify(&cfg, &preset("hydroid"));
    assert_column("defaults", &defaults, &PAPER_DEFAULTS, PAPER_DEFAULTS_NIS);
    assert_eq!(nis_bounds(&defaults), "5.71-6.30");
    assert_errors(
        "defaults",
        &defaults,
        ["0.00 %", "0.001", "0.02 %", "0.00 %", "0.01 %", "0.08 %"],
    );
    let paper = identify(&cfg, &preset("paper"));
    assert_column("paper's tuning", &paper, &PAPER_PAPER, PAPER_PAPER_NIS);
    assert_errors(
        "paper's tuning",
        &paper,
        ["7.2 %", "0.082", "67 %", "19 %", "16 %", "182 %"],
    );
}

/// docs/validation.md, "A second manoeuvre".
#[test]
fn twin_second_toml_reproduces_the_second_manoeuvre_table() {
    let cfg = root().join("configs/twin_second.toml");
    let defaults = identify(&cfg, &preset("hydroid"));
    assert_column("defaults", &defaults, &SECOND_DEFAULTS, SECOND_DEFAULTS_NIS);
    assert_eq!(nis_bounds(&defaults), "5.42-6.59");
    let paper = identify(&cfg, &preset("paper"));
    assert_column("paper's tuning", &paper, &SECOND_PAPER, SECOND_PAPER_NIS);
}

/// Noise seeds of the calibration.
const SEEDS: u64 = 30;

/// The paper's manoeuvre (configs/simulate/turn_paper.toml) with noise seed `seed`, written
/// into `dir`; returns the export's path.
fn paper_manoeuvre(dir: &Path, seed: u64) -> std::path::PathBuf {
    let sim = std::fs::read_to_string(root().join("configs/simulate/turn_paper.toml")).unwrap();
    assert!(sim.contains("\nseed = 13\n"), "the bundled seed line");
    let sim_path = dir.join(format!("sim_{seed}.toml"));
    std::fs::write(
        &sim_path,
        sim.replace("\nseed = 13\n", &format!("\nseed = {seed}\n")),
    )
    .unwrap();
    let csv = dir.join(format!("turn_{seed}.csv"));
    let o = common::hydroid(&[
        "simulate",
        sim_path.to_str().unwrap(),
        "--out",
        csv.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    csv
}

/// Per coefficient of [`TRUTH`] over the seeds: RMS of z, the share of seeds with the truth
/// outside 2 sigma, and the largest error (relative; absolute for Yrd, whose truth is 0).
struct Calibration {
    rms_z: Vec<f64>,
    outside_2_sigma: Vec<f64>,
    largest_error: Vec<f64>,
}

fn calibrate(outcomes: &[Identified]) -> Calibration {
    let n = outcomes.len() as f64;
    let column = |i: usize| outcomes.iter().map(move |o| o.estimates[i]);
    let mut c = Calibration {
        rms_z: Vec::new(),
        outside_2_sigma: Vec::new(),
        largest_error: Vec::new(),
    };
    for (i, (_, truth)) in TRUTH.iter().enumerate() {
        let z = |(v, s): (f64, f64)| (v - truth) / s;
        c.rms_z
            .push((column(i).map(|e| z(e).powi(2)).sum::<f64>() / n).sqrt());
        c.outside_2_sigma
            .push(column(i).filter(|&e| z(e).abs() > 2.0).count() as f64 / n);
        let scale = if *truth == 0.0 { 1.0 } else { truth.abs() };
        c.largest_error.push(
            column(i)
                .map(|(v, _)| (v - truth).abs() / scale)
                .fold(0.0, f64::max),
        );
    }
    c
}

/// docs/validation.md, "Calibration over 30 noise realisations": the paper's manoeuvre
/// re-simulated with noise seeds 1 to 30 and identified with hydroid's defaults
/// (configs/twin.toml). The sigmas are honest when the RMS of z is about 1 and the truth
/// lies outside 2 sigma in about 5 % of the cases.
#[test]
fn calibration_over_30_noise_realisations_of_the_paper_manoeuvre() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = root().join("configs/twin.toml");
    let outcomes: Vec<Identified> = common::parallel::on_two_threads(SEEDS as usize, |_, k| {
        let csv = paper_manoeuvre(dir.path(), k as u64 + 1);
        let file = format!("hekf.runs[0].file={:?}", csv.to_str().unwrap());
        identify(&cfg, &[file])
    });
    assert_eq!(outcomes.len(), SEEDS as usize);
    let c = calibrate(&outcomes);
    for (i, (name, _)) in TRUTH.iter().enumerate() {
        println!(
            "{name}: RMS z {:.3}, outside 2 sigma {:.1} %, largest error {:.3e}",
            c.rms_z[i],
            100.0 * c.outside_2_sigma[i],
            c.largest_error[i]
        );
    }
    // as docs/validation.md prints them: RMS z to two decimals, seeds outside 2 sigma out of
    // 30, the largest error in % (Yrd in kg m) to the digits printed
    let printed = |v: &[f64], f: &dyn Fn(usize, f64) -> String| -> Vec<String> {
        v.iter().enumerate().map(|(i, x)| f(i, *x)).collect()
    };
    assert_eq!(
        printed(&c.rms_z, &|_, x| format!("{x:.2}")),
        ["0.74", "0.83", "0.73", "0.75", "0.80", "0.51"]
    );
    assert_eq!(
        printed(&c.outside_2_sigma, &|_, x| format!(
            "{}",
            (x * SEEDS as f64).round()
        )),
        ["1", "1", "1", "1", "0", "0"]
    );
    let largest = |i: usize, x: f64| match i {
        1 => format!("{x:.3}"),
        5 => format!("{:.1}", 100.0 * x),
        _ => format!("{:.2}", 100.0 * x),
    };
    assert_eq!(
        printed(&c.largest_error, &largest),
        ["0.03", "0.006", "0.25", "0.08", "0.11", "1.0"]
    );
}
