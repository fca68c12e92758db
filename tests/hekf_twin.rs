//! Twin experiments for the hybrid EKF stage (issue: "Hybrid EKF on CFD motion histories"):
//! synthetic runs from a known model, identification with hydroid's defaults and with the
//! paper's preset, noise-free recovery, 6-DOF against 3-DOF, and divergence handling.

use crate::common;

use common::accuracy::Accuracy;
use hydroid::app::simulate::config::{
    ExportColumn, ExportConfig, Manoeuvre, NoiseConfig, SimConfig, Step,
};
use hydroid::app::simulate::synth::synthesize;
use hydroid::base::quantity::Quantity;
use hydroid::config::{Constant, FluidConfig, VehicleConfig};
use hydroid::io::formats::Format;
use hydroid::io::record::Record;
use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source, YawMoment, SYMMETRY};
use hydroid::stages::hekf::{
    self, Checks, HekfConfig, HekfResult, ModelName, Outliers, Preset, Prior,
};
use std::collections::BTreeMap;

use hydroid::model::models::spheroid3::BOUNDED_TRUTH as TRUTH;

const ESTIMATED: [&str; 6] = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"];

fn vehicle() -> VehicleConfig {
    VehicleConfig {
        name: "6:1 prolate spheroid".into(),
        mass: 50.0,
        length: 1.2,
        diameter: Some(0.2),
        ixx: Some(0.2),
        iyy: Some(3.7),
        izz: 3.7,
        reference_area: std::f64::consts::PI * 0.01,
        reference_length: 1.0,
        buoyancy: None,
        // CG at the CB: with BG > 0 a turn rolls the body and the axisymmetric (Munk-unstable)
        // pitch plane follows within a second (see six_dof_model_agrees...)
        bg: Some(0.0),
        scale: None,
        particulars: Default::default(),
        yaw_moment: Default::default(),
    }
}

fn fluid() -> FluidConfig {
    FluidConfig {
        rho: 1025.0,
        mu: 0.0009,
    }
}

fn truth_value(name: &str) -> f64 {
    TRUTH.iter().find(|(n, _)| *n == name).unwrap().1
}

fn c(text: &str) -> Constant {
    Constant::parse(text).unwrap()
}

/// A synthetic manoeuvre.
struct Man<'a> {
    model: ModelName,
    initial: &'a [(Quantity, &'a str)],
    thrust: &'a str,
    steps: Vec<Step>,
    duration: f64,
    dt: f64,
    noisy: bool,
    seed: u64,
}

/// Simulates a manoeuvre and returns it as a record with every state measured.
fn simulate(man: Man) -> Record {
    let Man {
        model,
        initial,
        thrust,
        steps,
        duration,
        dt,
        noisy,
        seed,
    } = man;
    let mut sigma = BTreeMap::new();
    if noisy {
        for (q, s) in [
            (Quantity::U, "1e-3 m/s"),
            (Quantity::V, "1e-3 m/s"),
            (Quantity::R, "0.05 deg/s"),
            (Quantity::X, "1e-3 m"),
            (Quantity::Y, "1e-3 m"),
            (Quantity::Yaw, "0.05 deg"),
        ] {
            sigma.insert(q, c(s));
        }
        if model == ModelName::Spheroid6 {
            for (q, s) in [
                (Quantity::W, "1e-3 m/s"),
                (Quantity::P, "0.05 deg/s"),
                (Quantity::Q, "0.05 deg/s"),
                (Quantity::Z, "1e-3 m"),
                (Quantity::Roll, "0.05 deg"),
                (Quantity::Pitch, "0.05 deg"),
            ] {
                sigma.insert(q, c(s));
            }
        }
    }
    let cfg = SimConfig {
        title: None,
        model,
        vehicle: vehicle(),
        fluid: fluid(),
        coefficients: TRUTH.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
        manoeuvre: Manoeuvre::TimeHistory {
            duration,
            dt,
            substeps: 10,
            initial: initial.iter().map(|(q, v)| (*q, c(v))).collect(),
            inputs: [(Quantity::Thrust, c(thrust))].into_iter().collect(),
            steps,
            rates: Default::default(),
            steering: None,
            process_noise: Default::default(),
        },
        noise: NoiseConfig { seed, sigma },
        export: Some(ExportConfig {
            file: "unused.csv".into(),
            layout: "delimited".into(),
            columns: vec![ExportColumn {
                quantity: Quantity::Time,
                name: "t".into(),
                unit: None,
            }],
            wrap_angles: false,
            digits: 17,
            separator: None,
        }),
        sweep: None,
    };
    let cols = synthesize(&cfg).unwrap();
    let rows = cols[&Quantity::Time].len();
    Record {
        name: format!("twin seed {seed}"),
        source: "synthetic".into(),
        format: Format::Delimited,
        units: cols
            .keys()
            .map(|q| (*q, q.si_symbol().to_string()))
            .collect(),
        channels: cols,
        constants: BTreeMap::new(),
        columns: BTreeMap::new(),
        lines: (1..=rows).collect(),
        meta: Vec::new(),
        warnings: Vec::new(),
        resolution: Default::default(),
        between: Default::default(),
    }
}

fn paper_manoeuvre(noisy: bool, seed: u64) -> Record {
    simulate(Man {
        model: ModelName::Spheroid3,
        initial: &[(Quantity::U, "3 m/s"), (Quantity::V, "1 m/s")],
        thrust: "22 N",
        steps: Vec::new(),
        duration: 20.0,
        dt: 0.01,
        noisy,
        seed,
    })
}

fn config(preset: Preset, model: ModelName) -> HekfConfig {
    HekfConfig {
        enabled: true,
        model,
        preset,
        estimate: ESTIMATED.iter().map(|s| s.to_string()).collect(),
        mode: Default::default(),
        passes: None,
        substeps: None,
        smoother: Some(false),
        decimate: None,
        memory_limit: None,
        prior: BTreeMap::new(),
        state_variance: None,
        noise: BTreeMap::new(),
        process_noise: BTreeMap::new(),
        gate: None,
        filter: Default::default(),
        adapt_noise: None,
        balance: Default::default(),
        outliers: Outliers::default(),
        checks: Checks::default(),
        measure: None,
        runs: Vec::new(),
        validation: Vec::new(),
    }
}

fn known() -> CoefficientSet {
    let mut set = CoefficientSet::new();
    for (n, v) in TRUTH {
        if !ESTIMATED.contains(n) {
            set.insert(Coefficient::new(n, *v, None, Source::Config));
        }
    }
    set.complete(SYMMETRY, YawMoment::LiftOnly);
    set
}

fn identify(cfg: &HekfConfig, runs: &[Record]) -> hydroid::Result<HekfResult> {
    let known = known();
    let v = vehicle();
    let f = fluid();
    hekf::run(
        cfg,
        &hekf::StageInputs {
            vehicle: &v.for_model(&f),
            known: &known,
            runs,
            base_dir: std::path::Path::new(""),
        },
        &mut hydroid::base::progress::Silent,
    )
}

struct Check {
    value: f64,
    sigma: f64,
    truth: f64,
}

fn checks(r: &HekfResult) -> BTreeMap<String, Check> {
    r.coefficients
        .iter()
        .map(|c| {
            (
                c.name.clone(),
                Check {
                    value: c.value,
                    sigma: c.sigma.unwrap(),
                    truth: truth_value(&c.name),
                },
            )
        })
        .collect()
}

/// The estimates of `r` against the truth, printed.
fn accuracy(title: &str, r: &HekfResult) -> Accuracy {
    let a = Accuracy::of_hekf_result(title, r, truth_value);
    println!("{}", a.table());
    a
}

/// Each of Yvd, Nrd, Nvv, Nrr, Yrr within its percentage of `limits` (in that order), and
/// every estimate (Yrd, truth 0, too) within 2 sigma of the truth (docs/validation.md,
/// "Tests").
#[track_caller]
fn assert_accuracy(title: &str, r: &HekfResult, limits: [f64; 5]) {
    let a = accuracy(title, r);
    for (name, limit) in ["Yvd", "Nrd", "Nvv", "Nrr", "Yrr"].into_iter().zip(limits) {
        let e = a.row(name).error_percent().abs();
        assert!(
            e < limit,
            "{name} {e:.3} % off (at most {limit} %)\n{}",
            a.table()
        );
    }
    a.assert_determined_within(&[], 2.0);
}

/// The paper's manoeuvre: Yvd, Nrd, Nvv, Nrr within 0.1 %, Yrr within 0.3 %.
const PAPER_LIMITS: [f64; 5] = [0.1, 0.1, 0.1, 0.1, 0.3];

#[test]
fn paper_manoeuvre_with_hydroid_defaults() {
    let run = paper_manoeuvre(true, 1);
    let r = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    // the preset's 3 passes, and more while the noise calibration settles (at most 6 more)
    assert!(
        (3..=9).contains(&r.settings.passes),
        "{}",
        r.settings.passes
    );
    assert_accuracy("the paper's manoeuvre, seed 1", &r, PAPER_LIMITS);
    // the noise model is not too tight: the innovations are at most as large as it says
    // (the yaw rate's consistency with the heading, which also carries the curvature of a
    // 72 deg/s turn at 100 Hz, makes it conservative here: mean NIS 5.05 for 6 measurements,
    // docs/hekf.md "The noise model")
    let nis = r.runs[0].nis.as_ref().unwrap();
    assert!(nis.mean <= nis.mean_bounds[1], "{nis:?}");
    assert!((nis.mean - 5.05).abs() < 0.005, "{nis:?}");
    let r_noise = r.runs[0]
        .noise
        .iter()
        .find(|n| n.quantity == Quantity::R)
        .unwrap();
    assert!(
        (r_noise.sigma.to_degrees() - 0.32).abs() < 0.005,
        "{r_noise:?}"
    );
    // the noise estimated from the data is close to the 1e-3 m/s added
    let u = r.runs[0]
        .noise
        .iter()
        .find(|n| n.quantity == Quantity::U)
        .unwrap();
    assert!((u.sigma / 1e-3 - 1.0).abs() < 0.15, "{u:?}");
}

#[test]
fn second_manoeuvre_coarser_sampling() {
    // different initial state and thrust (with a step), 25 s sampled every 50 ms
    let run = second_manoeuvre(2);
    let r = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    assert_eq!(r.settings.substeps, 5, "10 ms RK4 steps by default");
    // Yvd, Nvv within 0.1 %, Nrd, Nrr within 0.3 %, Yrr within 1 %
    assert_accuracy(
        "the second manoeuvre, seed 2",
        &r,
        [0.1, 0.3, 0.1, 0.3, 1.0],
    );
}

#[test]
fn paper_preset_runs_and_is_worse() {
    let run = paper_manoeuvre(true, 1);
    let paper = identify(
        &config(Preset::Paper, ModelName::Spheroid3),
        std::slice::from_ref(&run),
    )
    .unwrap();
    let ours = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    assert_eq!(paper.settings.passes, 1);
    // every estimate with the paper's tuning more than 7 % off (Yvd 7.2 %, Nrd 65 %, Yrr
    // 184 %), the truth more than 4 of its sigmas away for the four it determines; hydroid's
    // within 0.3 % (docs/validation.md)
    let (p, o) = (
        accuracy("the paper's manoeuvre, seed 1, paper preset", &paper),
        accuracy("the paper's manoeuvre, seed 1, hydroid preset", &ours),
    );
    for r in p.rows.iter().filter(|r| r.truth != 0.0) {
        assert!(r.error_percent().abs() > 7.0, "{}\n{}", r.name, p.table());
        assert!(
            !r.determined || r.z.abs() > 4.0,
            "{}\n{}",
            r.name,
            p.table()
        );
    }
    assert_eq!(p.undetermined_names(), ["Yrr"], "{}", p.table());
    p.assert_undetermined_flagged();
    assert!(o.worst_error_percent() < 0.3, "{}", o.table());
}

#[test]
fn noise_free_data_recover_the_truth() {
    let run = paper_manoeuvre(false, 0);
    let r = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    let a = accuracy("the paper's manoeuvre without noise", &r);
    // within 0.01 % (docs/validation.md; Yrd, truth 0, within 1e-4 kg m)
    assert!(a.worst_error_percent() < 0.01, "{}", a.table());
    assert!(a.row("Yrd").estimate.abs() < 1e-4, "{}", a.table());
}

/// The axisymmetric truth mirrors the paper's yaw plane into pitch, where the Munk moment is
/// as destabilising: any heave or pitch disturbance grows into a vertical loop within seconds
/// (BG = 0.01 m gives 10 deg of pitch after 1 s). A run with small out-of-plane motion is
/// therefore the planar one, with noise on every out-of-plane channel.
#[test]
fn six_dof_model_agrees_with_three_dof_on_a_nearly_planar_run() {
    let run = simulate(Man {
        model: ModelName::Spheroid6,
        initial: &[(Quantity::U, "3 m/s"), (Quantity::V, "1 m/s")],
        thrust: "22 N",
        steps: Vec::new(),
        duration: 20.0,
        dt: 0.01,
        noisy: true,
        seed: 5,
    });
    let r6 = identify(
        &config(Preset::Hydroid, ModelName::Spheroid6),
        std::slice::from_ref(&run),
    )
    .unwrap();
    let r3 = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    let (c6, c3) = (checks(&r6), checks(&r3));
    for n in ESTIMATED {
        let d = (c6[n].value - c3[n].value).abs();
        let s = c3[n].sigma;
        assert!(
            d < s,
            "{n}: 6-DOF {} vs 3-DOF {} (sigma {s})",
            c6[n].value,
            c3[n].value
        );
    }
    assert_eq!(r6.runs[0].measured.len(), 12);
    assert_eq!(r3.runs[0].measured.len(), 6);
    // the out-of-plane noise is small: no warning that the 3-DOF model ignores motion
    assert!(
        r3.runs[0]
            .warnings
            .iter()
            .all(|w| !w.message.contains("model ignores")),
        "{:?}",
        r3.runs[0].warnings
    );
}

#[test]
fn a_bad_prior_gives_a_clear_error_not_a_nan() {
    let run = paper_manoeuvre(true, 3);
    let mut cfg = config(Preset::Hydroid, ModelName::Spheroid3);
    // Yvd = +80 kg would make m - Yvd negative (the mass matrix no longer positive
    // definite); a sway added mass is negative in Fossen's convention, so the start is
    // refused before filtering, naming the key and the admissible range (docs/hekf.md,
    // "Admissible ranges")
    cfg.prior.insert(
        "Yvd".into(),
        Prior {
            initial: Some(80.0),
            sigma: Some(1.0),
        },
    );
    let e = identify(&cfg, &[run]).unwrap_err().to_string();
    assert!(e.contains("hekf.prior.Yvd.initial = 80"), "{e}");
    assert!(e.contains("admissible range (<= 0 kg)"), "{e}");
    assert!(!e.contains("NaN"), "{e}");
}

/// Second manoeuvre of the issue: different initial state, a thrust step, 50 ms sampling.
fn second_manoeuvre(seed: u64) -> Record {
    simulate(Man {
        model: ModelName::Spheroid3,
        initial: &[
            (Quantity::U, "2 m/s"),
            (Quantity::V, "-0.5 m/s"),
            (Quantity::R, "0.2 rad/s"),
        ],
        thrust: "15 N",
        steps: vec![Step {
            time: 10.0,
            values: [(Quantity::Thrust, c("30 N"))].into_iter().collect(),
        }],
        duration: 25.0,
        dt: 0.05,
        noisy: true,
        seed,
    })
}

#[test]
fn two_runs_identified_jointly_beat_either_alone() {
    let (a, b) = (paper_manoeuvre(true, 7), second_manoeuvre(8));
    let cfg = config(Preset::Hydroid, ModelName::Spheroid3);
    let ra = identify(&cfg, std::slice::from_ref(&a)).unwrap();
    let rb = identify(&cfg, std::slice::from_ref(&b)).unwrap();
    let joint = identify(&cfg, &[a, b]).unwrap();
    assert_eq!(joint.runs.len(), 2);
    let (ca, cb, cj) = (checks(&ra), checks(&rb), checks(&joint));
    for n in ESTIMATED {
        // more data: a sigma no larger than either run's alone
        assert!(cj[n].sigma <= ca[n].sigma.min(cb[n].sigma) * 1.0001, "{n}");
        assert!((cj[n].value - cj[n].truth).abs() < 3.0 * cj[n].sigma, "{n}");
    }
    assert_accuracy("both manoeuvres, seeds 7 and 8", &joint, PAPER_LIMITS);
}

#[test]
fn smoothed_states_are_closer_to_the_truth_than_filtered_ones() {
    let noisy = paper_manoeuvre(true, 4);
    let clean = paper_manoeuvre(false, 0);
    let mut cfg = config(Preset::Hydroid, ModelName::Spheroid3);
    cfg.smoother = Some(true);
    let r = identify(&cfg, &[noisy]).unwrap();
    let tr = &r.traces[0];
    let smoothed = tr.smoothed.as_ref().expect("smoother ran");
    let v_true = clean.channel(Quantity::V).unwrap();
    let rms = |xs: &[f64]| {
        let s: f64 = (0..v_true.len())
            .map(|k| (xs[k * 6 + 1] - v_true[k]).powi(2))
            .sum();
        (s / v_true.len() as f64).sqrt()
    };
    let (f, s) = (rms(&tr.filtered), rms(smoothed));
    assert!(s < f, "smoothed v RMS error {s} not below filtered {f}");
    assert!(s < 1e-3, "smoothed v within the measurement noise: {s}");
}

/// A bundled export identified with the HEKF section of configs/spheroid.toml, every
/// coefficient it does not estimate held at its truth, with `preset` (`hydroid`, `paper`):
/// the paper's manoeuvre (cfd_exports/turn_paper.csv, the CFX reader, its fit run) or, with
/// `validation`, the second manoeuvre (cfd_exports/turn_validation.csv, STAR-CCM+, its
/// validation run) as the fit run. The experiments of docs/validation.md's twin tables.
fn bundled(validation: bool, preset: &str) -> (Accuracy, String) {
    let text = std::fs::read_to_string(common::root().join("configs/spheroid.toml")).unwrap();
    let head = &text[..text.find("[output]").unwrap()];
    let (hekf, fit, rest) = (
        text.find("[hekf]").unwrap(),
        text.find("[[hekf.runs]]").unwrap(),
        text.find("[[hekf.validation]]").unwrap(),
    );
    let runs = if validation {
        text[rest..]
            .replace("[[hekf.validation]]", "[[hekf.runs]]")
            .replace("[hekf.validation.columns]", "[hekf.runs.columns]")
    } else {
        text[fit..rest].to_string()
    };
    let known: String = TRUTH
        .iter()
        .filter(|(n, _)| !ESTIMATED.contains(n) && !n.starts_with('K'))
        .map(|(n, v)| format!("{n} = {v:?}\n"))
        .collect();
    let exports = common::root().join("cfd_exports").display().to_string() + "/";
    let config = format!("{head}[coefficients]\n{known}\n{}{runs}", &text[hekf..fit])
        .replace("../cfd_exports/", &exports);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("twin.toml");
    std::fs::write(&path, config).unwrap();
    let set = [format!("hekf.preset=\"{preset}\"")];
    let loaded = hydroid::load(&path, &set).unwrap_or_else(|e| panic!("{e}"));
    let out = hydroid::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    let h = out.result.stages.hekf.as_ref().expect("an HEKF stage");
    let run = if validation { "second" } else { "paper's" };
    let nis = h.runs[0].nis.as_ref().expect("an innovation test");
    let consistent = if nis.consistent { "" } else { "not " };
    (
        accuracy(&format!("the {run} manoeuvre, {preset} preset"), h),
        format!("{:.2}, {consistent}consistent", nis.mean),
    )
}

/// A row of docs/validation.md's twin tables from `ours` (hydroid's defaults) and `paper`
/// (the paper's preset) at the digits the tables print: value ± sigma, error (in percent,
/// absolute for a zero truth; with `errors`) and z, for each.
fn docs_row(name: &str, ours: &Accuracy, paper: &Accuracy, errors: bool) -> String {
    let (o, p) = (ours.row(name), paper.row(name));
    let error = |r: &common::accuracy::Row, decimals: usize| {
        if r.truth == 0.0 {
            format!("{:.*}", decimals + 1, (r.estimate - r.truth).abs())
        } else {
            format!("{:.*} %", decimals, r.error_percent().abs())
        }
    };
    if errors {
        format!(
            "{name} | {:.4} ± {:.4} | {} | {:+.1} | {:.2} ± {:.2} | {} | {:+.1}",
            o.estimate,
            o.sigma,
            error(o, 2),
            o.z,
            p.estimate,
            p.sigma,
            error(p, 1),
            p.z
        )
    } else {
        format!(
            "{name} | {:.4} ± {:.4} | {:+.1} | {:.2} ± {:.2} | {:+.1}",
            o.estimate, o.sigma, o.z, p.estimate, p.sigma, p.z
        )
    }
}

/// docs/validation.md's twin tables, row by row, at their printed digits; on the paper's
/// manoeuvre every estimate with hydroid's defaults within 0.1 % and 0.4 sigma of the truth,
/// the paper's tuning 7 to 182 % off with the truth 4.3 to 5.3 of its sigmas away (Yrr,
/// undetermined: 1.5), its sigmas 68 to 180 times hydroid's (README.md, docs/validation.md).
#[test]
fn bundled_manoeuvres_give_the_tables_of_the_docs() {
    let ((ours, nis_ours), (paper, nis_paper)) =
        (bundled(false, "hydroid"), bundled(false, "paper"));
    // the table's last row: the mean NIS (bounds 5.71-6.30)
    assert_eq!(
        [nis_ours, nis_paper],
        ["6.04, consistent", "3.59, not consistent"]
    );
    let rows: Vec<String> = ESTIMATED
        .iter()
        .map(|n| docs_row(n, &ours, &paper, true))
        .collect();
    println!("{}", rows.join("\n"));
    assert_eq!(
        rows,
        [
            "Yvd | -23.6254 ± 0.0020 | 0.00 % | +0.3 | -21.93 ± 0.33 | 7.2 % | +5.1",
            "Yrd | 0.0010 ± 0.0029 | 0.001 | +0.3 | 0.08 ± 0.16 | 0.08 | +0.5",
            "Nrd | -1.4528 ± 0.0010 | 0.02 % | +0.4 | -0.48 ± 0.19 | 66.9 % | +5.2",
            "Nvv | 9.9996 ± 0.0022 | 0.00 % | -0.2 | 8.14 ± 0.35 | 18.6 % | -5.3",
            "Nrr | -5.0006 ± 0.0028 | 0.01 % | -0.2 | -4.18 ± 0.19 | 16.4 % | +4.3",
            "Yrr | 0.4996 ± 0.0033 | 0.08 % | -0.1 | 1.41 ± 0.60 | 182.0 % | +1.5",
        ]
    );
    assert!(ours.worst_error_percent() < 0.1, "{}", ours.table());
    assert!(ours.worst_z() < 0.4, "{}", ours.table());
    for r in paper.rows.iter().filter(|r| r.truth != 0.0) {
        let e = r.error_percent().abs();
        assert!((7.0..=182.0).contains(&e), "{}\n{}", r.name, paper.table());
        let times = r.sigma / ours.row(&r.name).sigma;
        assert!((68.0..=182.0).contains(&times), "{}: {times}", r.name);
        if r.determined {
            assert!((4.25..5.35).contains(&r.z.abs()), "{}", paper.table());
        }
    }
    // the paper's tuning leaves Yrr undetermined and says so
    assert_eq!(paper.undetermined_names(), ["Yrr"], "{}", paper.table());
    paper.assert_undetermined_flagged();

    let ((ours, _), (paper, _)) = (bundled(true, "hydroid"), bundled(true, "paper"));
    let rows: Vec<String> = ESTIMATED
        .iter()
        .map(|n| docs_row(n, &ours, &paper, false))
        .collect();
    println!("{}", rows.join("\n"));
    assert_eq!(
        rows,
        [
            "Yvd | -23.6259 ± 0.0038 | +0.0 | -21.62 ± 0.49 | +4.1",
            "Yrd | 0.0145 ± 0.0066 | +2.2 | 0.58 ± 0.27 | +2.1",
            "Nrd | -1.4551 ± 0.0019 | -1.0 | -0.41 ± 0.26 | +4.1",
            "Nvv | 10.0043 ± 0.0041 | +1.0 | 7.93 ± 0.50 | -4.1",
            "Nrr | -5.0148 ± 0.0058 | -2.6 | -4.42 ± 0.23 | +2.5",
            "Yrr | 0.5062 ± 0.0048 | +1.3 | 1.24 ± 0.69 | +1.1",
        ]
    );
}

/// The shared accuracy checks (tests/common/accuracy.rs) fail where they should: an
/// undetermined coefficient hydroid does not flag, a determined one beyond the limit, a
/// coefficient counted as determined that is not, a docs row that is not what the run gave.
#[test]
fn the_accuracy_checks_can_fail() {
    use common::accuracy::Row;
    let made_up = |flagged: bool| Accuracy {
        title: "made up".into(),
        rows: vec![
            // determined, +1 sigma
            Row::new("A", 1.0, 1.01, 0.01, false),
            // undetermined (sigma above half the value), the wrong sign
            Row::new("B", 0.5, -0.2, 0.6, flagged),
        ],
    };
    let fails = |f: &dyn Fn()| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).is_err();
    assert!(!fails(
        &|| made_up(true).assert_determined_within(&["B"], 2.0)
    ));
    assert!(fails(
        &|| made_up(false).assert_determined_within(&["B"], 2.0)
    ));
    assert!(fails(
        &|| made_up(true).assert_determined_within(&["B"], 0.5)
    ));
    assert!(fails(&|| made_up(true).assert_determined_within(&[], 2.0)));
    assert!(!fails(
        &|| made_up(true).assert_printed(&[("A", "1.01 ± 0.01 | +1.0")])
    ));
    assert!(fails(
        &|| made_up(true).assert_printed(&[("A", "1.02 ± 0.01 | +1.0")])
    ));
    assert!(fails(
        &|| made_up(true).assert_printed(&[("A", "1.01 ± 0.01 | 2 %")])
    ));
    assert_eq!(made_up(true).within_two_sigma(), (1, 1));
}
