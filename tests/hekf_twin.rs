//! Twin experiments for the hybrid EKF stage (issue: "Hybrid EKF on CFD motion histories"):
//! synthetic runs from a known model, identification with hydroid's defaults and with the
//! paper's preset, noise-free recovery, 6-DOF against 3-DOF, and divergence handling.

use hydroid::coefficients::{Coefficient, CoefficientSet, Source, YawMoment, SYMMETRY};
use hydroid::config::{Constant, FluidConfig, VehicleConfig};
use hydroid::formats::Format;
use hydroid::quantity::Quantity;
use hydroid::record::Record;
use hydroid::sim::config::{ExportColumn, ExportConfig, Manoeuvre, NoiseConfig, SimConfig, Step};
use hydroid::sim::synth::synthesize;
use hydroid::stages::hekf::{
    self, Checks, HekfConfig, HekfResult, ModelName, Outliers, Preset, Prior,
};
use std::collections::BTreeMap;

use hydroid::models::spheroid3::BOUNDED_TRUTH as TRUTH;

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
            vehicle: &v,
            fluid: &f,
            known: &known,
            runs,
            base_dir: std::path::Path::new(""),
        },
        &mut hydroid::progress::Silent,
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

fn rel_err(c: &Check) -> f64 {
    (c.value - c.truth).abs() / c.truth.abs()
}

fn assert_issue_accuracy(r: &HekfResult) {
    let ch = checks(r);
    let table: Vec<String> = ch
        .iter()
        .map(|(n, c)| format!("{n} {:.5} +- {:.5} (truth {})", c.value, c.sigma, c.truth))
        .collect();
    for n in ["Yvd", "Nrd", "Nvv", "Nrr"] {
        assert!(
            rel_err(&ch[n]) < 0.01,
            "{n} off by more than 1 %: {table:#?}"
        );
    }
    assert!(
        rel_err(&ch["Yrr"]) < 0.03,
        "Yrr off by more than 3 %: {table:#?}"
    );
    assert!(
        (ch["Yrd"].value - ch["Yrd"].truth).abs() < 0.02,
        "Yrd: {table:#?}"
    );
    let inside = ch
        .values()
        .filter(|c| (c.value - c.truth).abs() <= 2.0 * c.sigma)
        .count();
    assert!(
        inside >= 5,
        "truth inside 2 sigma for only {inside} of 6: {table:#?}"
    );
}

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
    assert_issue_accuracy(&r);
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
    assert_issue_accuracy(&r);
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
    let worst = |r: &HekfResult| {
        checks(r)
            .values()
            .map(|c| (c.value - c.truth).abs() / c.truth.abs().max(1.0))
            .fold(0.0, f64::max)
    };
    let (wp, wo) = (worst(&paper), worst(&ours));
    println!("worst relative error: paper preset {wp:.4}, hydroid {wo:.4}");
    for c in &paper.coefficients {
        println!(
            "paper preset {} = {:.4} +- {:.4}",
            c.name,
            c.value,
            c.sigma.unwrap()
        );
    }
    assert!(
        wp > 5.0 * wo,
        "the paper preset should be clearly worse: {wp} vs {wo}"
    );
}

#[test]
fn noise_free_data_recover_the_truth() {
    let run = paper_manoeuvre(false, 0);
    let r = identify(&config(Preset::Hydroid, ModelName::Spheroid3), &[run]).unwrap();
    for ch in checks(&r).values() {
        let err = (ch.value - ch.truth).abs();
        let tol = 1e-4 * ch.truth.abs().max(1.0);
        assert!(err < tol, "{} vs {} (error {err:e})", ch.value, ch.truth);
    }
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
    assert_issue_accuracy(&joint);
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
