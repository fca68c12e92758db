//! The static polar stage (paper eq. 5-6) on polars built from the paper's Table 3.

use crate::common;

use common::{fluid, four_figures, record, vehicle};
use hydroid::base::quantity::Quantity;
use hydroid::config::{Config, Problems};
use hydroid::io::record::Record;
use hydroid::model::coefficients::YawMoment;
use hydroid::stages::polar::{self, PolarConfig, PolarResult};
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::path::Path;

// Paper Table 3 (self-consistent reading, docs/paper.md, static polars), alpha in rad.
const A: f64 = 0.293;
const B: f64 = -0.0273;
const C: f64 = 0.0826;
const CLA: f64 = -1.013;
const CMA: f64 = 0.834;

fn cd(al: f64) -> f64 {
    A * al * al + B * al + C
}

/// Angles from `lo` to `hi` degrees in 1 degree steps, in rad.
fn sweep(lo: i32, hi: i32) -> Vec<f64> {
    (lo..=hi).map(|d| (d as f64).to_radians()).collect()
}

fn sweep_record(name: &str, alphas: &[f64], c: [&dyn Fn(f64) -> f64; 3]) -> Record {
    record(
        name,
        &[
            (Quantity::Alpha, alphas.to_vec()),
            (Quantity::Cd, alphas.iter().map(|a| c[0](*a)).collect()),
            (Quantity::Cl, alphas.iter().map(|a| c[1](*a)).collect()),
            (Quantity::Cm, alphas.iter().map(|a| c[2](*a)).collect()),
        ],
        &[],
    )
}

fn table3(alphas: &[f64]) -> Record {
    sweep_record("table3", alphas, [&cd, &|a| CLA * a, &|a| CMA * a])
}

fn config(extra: &str) -> PolarConfig {
    toml::from_str(&format!("runs = []\n{extra}")).unwrap()
}

/// The stage in the paper's reading of C_M (the lift moment only, eq. 5: Nuvl = q L_ref C_Ma)
/// unless the test's configuration says otherwise.
fn run(cfg: &PolarConfig, records: &[Record]) -> PolarResult {
    let mut cfg = cfg.clone();
    cfg.moment.part.get_or_insert(YawMoment::LiftOnly);
    polar::run(&cfg, &vehicle(), &fluid(), records).unwrap()
}

fn coef(r: &PolarResult, name: &str) -> (f64, Option<f64>) {
    let c = r
        .coefficients()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap();
    (c.value, c.sigma)
}

#[test]
fn exact_table3_polars_give_table3() {
    // q = 0.5 * 1025 * pi * 0.1^2 = 16.1007 kg/m; moment reference length 1 m as the paper.
    let r = run(&config(""), &[table3(&sweep(-12, 12))]);
    four_figures(coef(&r, "Xuu").0, -1.330); // -q c
    four_figures(coef(&r, "Xuv").0, 0.4395); // -q b
    four_figures(coef(&r, "Xvv").0, -5.382); // -q (a + c/2)
    four_figures(coef(&r, "Yvv").0, -0.4395); // q b
    four_figures(coef(&r, "Yuvd").0, 1.330); // q c (the paper prints 1.328, see the doc)
    four_figures(coef(&r, "Yuvl").0, -16.31); // q C_La
    four_figures(coef(&r, "Nuvl").0, 13.43); // q L_ref C_Ma with L_ref = 1 m
    assert!((r.reference.q - 16.1007).abs() < 1e-4);
    assert_eq!(r.reference.reference_length, 1.0);
    assert!(r.reference.statement.contains("L_ref = 1 m"));
    assert!(r.pooled.drag.r_squared.unwrap() > 1.0 - 1e-12);
    assert_eq!(r.pooled.drag.residuals.len(), 25);
    // No constraint binds on the paper's polar (b = 0 is not imposed by default).
    assert!(r.pooled.drag.binding_inequalities.is_empty());
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    for c in r.coefficients() {
        assert_eq!(c.source, hydroid::model::coefficients::Source::Polar);
    }
}

fn noisy_table3(seed: u64) -> Record {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let nd = Normal::new(0.0, 5e-4).unwrap();
    let nl = Normal::new(0.0, 2e-3).unwrap();
    let alphas = sweep(-12, 12);
    let mut ch = [vec![], vec![], vec![]];
    for &a in &alphas {
        ch[0].push(cd(a) + nd.sample(&mut rng));
        ch[1].push(CLA * a + nl.sample(&mut rng));
        ch[2].push(CMA * a + nl.sample(&mut rng));
    }
    let [d, l, m] = ch;
    record(
        "noisy",
        &[
            (Quantity::Alpha, alphas),
            (Quantity::Cd, d),
            (Quantity::Cl, l),
            (Quantity::Cm, m),
        ],
        &[],
    )
}

#[test]
fn noisy_polars_contain_the_truth_within_two_sigma() {
    let r = run(&config(""), &[noisy_table3(1)]);
    let p = &r.pooled;
    let checks = [
        ("a", p.drag.value("a"), p.drag.std_error("a"), A),
        ("b", p.drag.value("b"), p.drag.std_error("b"), B),
        ("c", p.drag.value("c"), p.drag.std_error("c"), C),
        (
            "C_La",
            p.lift.value("slope"),
            p.lift.std_error("slope"),
            CLA,
        ),
        (
            "C_Ma",
            p.moment.value("slope"),
            p.moment.std_error("slope"),
            CMA,
        ),
    ];
    for (name, v, s, truth) in checks {
        let (v, s) = (v.unwrap(), s.unwrap());
        assert!(s > 0.0, "{name}");
        assert!(
            (v - truth).abs() < 2.0 * s,
            "{name} = {v} +- {s}, truth {truth}"
        );
    }
    let q = r.reference.q;
    for (name, truth) in [
        ("Xuu", -q * C),
        ("Xuv", -q * B),
        ("Xvv", -q * (A + C / 2.0)),
        ("Yvv", q * B),
        ("Yuvd", q * C),
        ("Yuvl", q * CLA),
        ("Nuvl", q * CMA),
    ] {
        let (v, s) = coef(&r, name);
        let s = s.unwrap();
        assert!(
            (v - truth).abs() < 2.0 * s,
            "{name} = {v} +- {s}, truth {truth}"
        );
    }
    // The sigma of Xvv = -q (a + c/2) uses the covariance of a and c (negative on a
    // symmetric sweep), so it is smaller than the independent-terms value.
    let cov = p.drag.covariance.as_ref().unwrap();
    assert!(cov[0][2] < 0.0);
    let indep = q * (cov[0][0] + cov[2][2] / 4.0).sqrt();
    let with_cov = q * (cov[0][0] + cov[2][2] / 4.0 + cov[0][2]).sqrt();
    assert!((coef(&r, "Xvv").1.unwrap() - with_cov).abs() < 1e-12 * with_cov);
    assert!(with_cov < indep);
}

#[test]
fn standard_errors_are_calibrated() {
    // Over many noise draws the truth falls within one reported sigma about 68 % of the
    // time and the squared z-scores average dof/(dof - 2) (Student t, 22 dof).
    let cfg = config("");
    let n = 300;
    let (mut inside, mut z2) = ([0usize; 3], [0.0f64; 3]);
    for seed in 0..n {
        let r = run(&cfg, &[noisy_table3(seed)]);
        let p = &r.pooled;
        for (k, (fit, name, truth)) in [
            (&p.drag, "c", C),
            (&p.drag, "a", A),
            (&p.lift, "slope", CLA),
        ]
        .into_iter()
        .enumerate()
        {
            let z = (fit.value(name).unwrap() - truth) / fit.std_error(name).unwrap();
            inside[k] += usize::from(z.abs() < 1.0);
            z2[k] += z * z;
        }
    }
    for k in 0..3 {
        let frac = inside[k] as f64 / n as f64;
        let mean_z2 = z2[k] / n as f64;
        assert!(
            (0.60..0.77).contains(&frac),
            "coverage {frac} for constant {k}"
        );
        assert!(
            (0.8..1.4).contains(&mean_z2),
            "mean z^2 {mean_z2} for constant {k}"
        );
    }
}

/// Ordinary least squares y = X beta, for checking constrained fits independently.
fn ols(cols: &[Vec<f64>], y: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = y.len();
    let x = DMatrix::from_fn(n, cols.len(), |i, j| cols[j][i]);
    let yv = DVector::from_column_slice(y);
    let xtx = x.transpose() * &x;
    let inv = xtx.try_inverse().unwrap();
    let beta = &inv * x.transpose() * &yv;
    let r = &yv - &x * &beta;
    let s2 = r.norm_squared() / (n - cols.len()) as f64;
    let se = (0..cols.len()).map(|j| (s2 * inv[(j, j)]).sqrt()).collect();
    (beta.iter().copied().collect(), se)
}

fn close(x: f64, y: f64, tol: f64) -> bool {
    (x - y).abs() <= tol * (1.0 + y.abs())
}

#[test]
fn a_nonnegative_binds_on_a_concave_polar() {
    let al = sweep(-12, 12);
    let f = |a: f64| -0.05 * a * a + 0.01 * a + 0.08;
    let rec = sweep_record("concave", &al, [&f, &|a| CLA * a, &|a| CMA * a]);
    let free = run(
        &config("[drag]\na_nonnegative = false\n"),
        std::slice::from_ref(&rec),
    );
    assert!(close(free.pooled.drag.value("a").unwrap(), -0.05, 1e-9));
    let bound = run(&config(""), &[rec]);
    let d = &bound.pooled.drag;
    // With a = 0 the fit is C_D = b alpha + c, an ordinary line fit.
    let y: Vec<f64> = al.iter().map(|a| f(*a)).collect();
    let (beta, _) = ols(&[al.clone(), vec![1.0; al.len()]], &y);
    assert_eq!(d.value("a"), Some(0.0));
    assert!(close(d.value("b").unwrap(), beta[0], 1e-9));
    assert!(close(d.value("c").unwrap(), beta[1], 1e-9));
    assert_eq!(d.std_error("a"), Some(0.0));
    assert!(d.binding_inequalities[0].contains("a >= 0"));
    assert!(bound.warnings.iter().any(|w| w.message.contains("a >= 0")));
}

#[test]
fn c_nonnegative_binds_on_a_negative_intercept() {
    let al = sweep(-12, 12);
    let f = |a: f64| 0.3 * a * a - 0.002;
    let rec = sweep_record("neg", &al, [&f, &|a| CLA * a, &|a| CMA * a]);
    let free = run(
        &config("[drag]\nc_nonnegative = false\n"),
        std::slice::from_ref(&rec),
    );
    assert!(close(free.pooled.drag.value("c").unwrap(), -0.002, 1e-9));
    let d = run(&config(""), &[rec]).pooled.drag;
    let y: Vec<f64> = al.iter().map(|a| f(*a)).collect();
    let (beta, _) = ols(&[al.iter().map(|a| a * a).collect(), al.clone()], &y);
    assert_eq!(d.value("c"), Some(0.0));
    assert!(close(d.value("a").unwrap(), beta[0], 1e-9));
    assert!(close(d.value("b").unwrap(), beta[1], 1e-9));
    assert_eq!(d.binding_inequalities.len(), 1);
    assert!(d.binding_inequalities[0].contains("c >= 0"));
}

#[test]
fn symmetric_drag_fixes_b_and_projects_the_standard_errors() {
    // An asymmetric sweep, so that forcing b = 0 moves a and c as well.
    let al = sweep(-12, 6);
    let r0 = run(&config(""), &[table3(&al)]);
    assert!(close(r0.pooled.drag.value("b").unwrap(), B, 1e-9));
    let r = run(&config("[drag]\nsymmetric = true\n"), &[table3(&al)]);
    let d = &r.pooled.drag;
    let y: Vec<f64> = al.iter().map(|a| cd(*a)).collect();
    let (beta, se) = ols(
        &[al.iter().map(|a| a * a).collect(), vec![1.0; al.len()]],
        &y,
    );
    assert_eq!(d.value("b"), Some(0.0));
    assert_eq!(d.std_error("b"), Some(0.0));
    assert!(close(d.value("a").unwrap(), beta[0], 1e-9));
    assert!(close(d.value("c").unwrap(), beta[1], 1e-9));
    // Standard errors over the two free directions only, with n - 2 degrees of freedom.
    assert_eq!(d.dof, al.len() - 2);
    assert!((d.std_error("a").unwrap() - se[0]).abs() < 1e-9 * se[0]);
    assert!((d.std_error("c").unwrap() - se[1]).abs() < 1e-9 * se[1]);
    assert!(d.active_constraints.iter().any(|c| c.contains("b = 0")));
    assert_eq!(coef(&r, "Xuv").0, 0.0);
    assert_eq!(coef(&r, "Yvv").0, 0.0);
    assert_ne!(coef(&r0, "Xuu").0, coef(&r, "Xuu").0);
}

#[test]
fn through_origin_removes_the_intercepts() {
    let al = sweep(0, 12);
    let l = |a: f64| 0.02 + CLA * a;
    let m = |a: f64| -0.01 + CMA * a;
    let rec = sweep_record("offset", &al, [&cd, &l, &m]);
    let free = run(
        &config("[lift]\nthrough_origin = false\n[moment]\nthrough_origin = false\n"),
        std::slice::from_ref(&rec),
    );
    assert!(close(
        free.pooled.lift.value("intercept").unwrap(),
        0.02,
        1e-9
    ));
    assert!(close(free.pooled.lift.value("slope").unwrap(), CLA, 1e-9));
    assert!(close(
        free.pooled.moment.value("intercept").unwrap(),
        -0.01,
        1e-9
    ));
    let r = run(&config(""), &[rec]);
    for (fit, g) in [
        (&r.pooled.lift, &l as &dyn Fn(f64) -> f64),
        (&r.pooled.moment, &m),
    ] {
        let y: Vec<f64> = al.iter().map(|a| g(*a)).collect();
        let sxy: f64 = al.iter().zip(&y).map(|(a, y)| a * y).sum();
        let sxx: f64 = al.iter().map(|a| a * a).sum();
        assert_eq!(fit.value("intercept"), Some(0.0));
        assert!(close(fit.value("slope").unwrap(), sxy / sxx, 1e-9));
        assert!(
            (fit.value("slope").unwrap() - free.pooled.lift.value("slope").unwrap()).abs() > 0.05
        );
    }
}

#[test]
fn slope_sign_constraints_bind_on_the_wrong_sign() {
    let al = sweep(0, 12);
    let r = run(
        &config(
            "[lift]\nthrough_origin = false\nslope = \"positive\"\n\
             [moment]\nthrough_origin = false\nslope = \"negative\"\n",
        ),
        &[table3(&al)],
    );
    // C_L has a negative slope and C_M a positive one: both slopes are held at zero and the
    // intercept is the mean.
    for (fit, k) in [(&r.pooled.lift, CLA), (&r.pooled.moment, CMA)] {
        let mean = al.iter().map(|a| k * a).sum::<f64>() / al.len() as f64;
        assert_eq!(fit.value("slope"), Some(0.0));
        assert!(close(fit.value("intercept").unwrap(), mean, 1e-9));
        assert_eq!(fit.binding_inequalities.len(), 1);
    }
    assert_eq!(coef(&r, "Yuvl").0, 0.0);
    // The same signs as the data: nothing binds.
    let ok = run(
        &config("[lift]\nslope = \"negative\"\n[moment]\nslope = \"positive\"\n"),
        &[table3(&al)],
    );
    assert!(close(ok.pooled.lift.value("slope").unwrap(), CLA, 1e-9));
    assert!(ok.pooled.lift.binding_inequalities.is_empty());
}

#[test]
fn bounds_bind_and_the_rest_refits() {
    let al = sweep(-12, 12);
    let r = run(
        &config("[drag.bounds]\nc = { min = 0.09 }\n"),
        &[table3(&al)],
    );
    let d = &r.pooled.drag;
    // With c = 0.09 fixed, a and b are the least squares of C_D - 0.09 on alpha^2, alpha.
    let y: Vec<f64> = al.iter().map(|a| cd(*a) - 0.09).collect();
    let (beta, _) = ols(&[al.iter().map(|a| a * a).collect(), al.clone()], &y);
    assert!(close(d.value("c").unwrap(), 0.09, 1e-9));
    assert!(close(d.value("a").unwrap(), beta[0], 1e-9));
    assert!(close(d.value("b").unwrap(), beta[1], 1e-9));
    assert!(d.binding_inequalities[0].contains("polar.drag.bounds.c.min"));
}

#[test]
fn infeasible_constraints_are_a_clear_error() {
    let cfg = config("[drag]\nsymmetric = true\n[drag.bounds]\nb = { min = 0.01 }\n");
    let e = polar::run(&cfg, &vehicle(), &fluid(), &[table3(&sweep(-12, 12))])
        .unwrap_err()
        .to_string();
    assert!(e.contains("infeasible"), "{e}");
    assert!(e.contains("b = 0 (polar.drag.symmetric)"), "{e}");
    assert!(e.contains("b >= 0.01"), "{e}");

    // Validation finds it first, at the key.
    let text = "[vehicle]\nmass = 50\nlength = 1.2\nizz = 3.7\nreference_area = 0.0314\n\
                reference_length = 1\n[fluid]\nrho = 1025\nmu = 0.0009\n[polar]\nruns = []\n\
                [polar.drag]\nsymmetric = true\n[polar.drag.bounds]\nb = { min = 0.01 }\n\
                c = { min = 0.2, max = 0.1 }\n[polar.lift.bounds]\nslpe = { max = 0 }\n";
    let cfg: Config = toml::from_str(text).unwrap();
    let mut p = Problems::new(Path::new("c.toml"), text);
    cfg.validate(&cfg.vehicle.for_model(&cfg.fluid), &mut p);
    let keys: Vec<&str> = p.list.iter().filter_map(|x| x.key.as_deref()).collect();
    assert!(keys.contains(&"polar.drag.bounds.b"), "{keys:?}");
    assert!(keys.contains(&"polar.drag.bounds.c"), "{keys:?}");
    assert!(keys.contains(&"polar.lift.bounds.slpe"), "{keys:?}");
    let slpe = p
        .list
        .iter()
        .find(|x| x.key.as_deref() == Some("polar.lift.bounds.slpe"));
    assert!(slpe.unwrap().message.contains("did you mean 'slope'"));
}

#[test]
fn forces_in_newtons_give_the_same_answer() {
    let (v, f) = (vehicle(), fluid());
    let al = sweep(-12, 12);
    let speed = 3.0;
    // q_dyn = 0.5 rho U^2 A_ref; X = -q_dyn C_D, Y = q_dyn C_L, N = q_dyn L_ref C_M.
    let qd = 0.5 * f.rho * speed * speed * v.reference_area;
    let fx: Vec<f64> = al.iter().map(|a| -qd * cd(*a)).collect();
    let fy: Vec<f64> = al.iter().map(|a| qd * CLA * a).collect();
    let mz: Vec<f64> = al
        .iter()
        .map(|a| qd * v.reference_length * CMA * a)
        .collect();
    let body = record(
        "forces",
        &[
            (Quantity::Alpha, al.clone()),
            (Quantity::Fx, fx.clone()),
            (Quantity::Fy, fy.clone()),
            (Quantity::Mz, mz.clone()),
            (Quantity::Speed, vec![speed; al.len()]),
        ],
        &[],
    );
    let by_coef = run(&config(""), &[table3(&al)]);
    let by_force = run(&config("data = \"forces\"\n"), &[body]);
    // The same forces in flow axes (x along the velocity): f = R(-alpha) f_body.
    let (fxf, fyf): (Vec<f64>, Vec<f64>) = al
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let (s, c) = a.sin_cos();
            (fx[i] * c + fy[i] * s, -fx[i] * s + fy[i] * c)
        })
        .unzip();
    let flow = record(
        "flow",
        &[
            (Quantity::Alpha, al.clone()),
            (Quantity::Fx, fxf),
            (Quantity::Fy, fyf),
            (Quantity::Mz, mz),
        ],
        &[(Quantity::Speed, speed)],
    );
    let by_flow = run(&config("data = \"forces\"\naxes = \"flow\"\n"), &[flow]);
    for c in by_coef.coefficients() {
        for other in [&by_force, &by_flow] {
            let (v, _) = coef(other, &c.name);
            assert!(
                (v - c.value).abs() < 1e-9 * c.value.abs().max(1.0),
                "{}",
                c.name
            );
        }
    }
    // Reynolds number of the single speed: rho U L / mu.
    let re = by_force.per_speed[0].reynolds;
    assert!((re - 1025.0 * 3.0 * 1.2 / 0.0009).abs() < 1e-6 * re);
}

#[test]
fn flow_axis_drag_alone_is_a_negative_side_force_in_body_axes() {
    // Pure drag along the velocity of a body moving to starboard (alpha > 0) pushes it to
    // port: body C_L = -C_D sin(alpha), body C_D = C_D cos(alpha).
    let al = sweep(-10, 10);
    let rec = sweep_record("drag-only", &al, [&|_| 0.1, &|_| 0.0, &|_| 0.0]);
    let r = run(&config("axes = \"flow\"\n"), &[rec]);
    for p in &r.points {
        assert!((p.cd - 0.1 * p.alpha.cos()).abs() < 1e-15);
        assert!((p.cl + 0.1 * p.alpha.sin()).abs() < 1e-15);
    }
    assert!((r.pooled.lift.value("slope").unwrap() + 0.1).abs() < 0.01);
}

#[test]
fn per_speed_and_pooled_fits() {
    let al = sweep(-12, 12);
    // Drag at zero drift falls with Reynolds number: c = 0.0850 at 2 m/s, 0.0800 at 4 m/s.
    let slow = |a: f64| A * a * a + B * a + 0.0850;
    let fast = |a: f64| A * a * a + B * a + 0.0800;
    let mut r2 = sweep_record("2 m/s", &al, [&slow, &|a| CLA * a, &|a| CMA * a]);
    let mut r4 = sweep_record("4 m/s", &al, [&fast, &|a| CLA * a, &|a| CMA * a]);
    r2.constants.insert(Quantity::Speed, 2.0);
    r4.constants.insert(Quantity::Speed, 4.0);
    let r = run(&config(""), &[r4, r2]);
    assert_eq!(r.per_speed.len(), 2);
    let (s2, s4) = (&r.per_speed[0], &r.per_speed[1]);
    assert_eq!((s2.speed, s4.speed), (2.0, 4.0));
    // Re = rho U L / mu with L = 1.2 m.
    assert!((s2.reynolds - 2_733_333.33).abs() < 1.0);
    assert!((s4.reynolds - 5_466_666.67).abs() < 1.0);
    let c2 = s2.fit.as_ref().unwrap().drag.value("c").unwrap();
    let c4 = s4.fit.as_ref().unwrap().drag.value("c").unwrap();
    assert!(close(c2, 0.0850, 1e-9) && close(c4, 0.0800, 1e-9));
    // Pooled over both speeds with equal sweeps: the mean c, the common a and b.
    assert!(close(r.pooled.drag.value("c").unwrap(), 0.0825, 1e-9));
    assert!(close(r.pooled.drag.value("a").unwrap(), A, 1e-9));
    let q = r.reference.q;
    let xuu = r.spread.iter().find(|s| s.name == "Xuu").unwrap();
    assert!((xuu.range - q * 0.005).abs() < 1e-9);
    assert!((xuu.values[0] + q * 0.0850).abs() < 1e-9);
    let yuvl = r.spread.iter().find(|s| s.name == "Yuvl").unwrap();
    assert!(yuvl.range < 1e-9);
}

#[test]
fn one_history_per_angle_uses_the_steady_end() {
    // Each run starts with a decaying transient; the mean over the last quarter is steady.
    let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.01).collect();
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let noise = Normal::new(0.0, 1e-4).unwrap();
    let mut records = Vec::new();
    for deg in (-12..=12).step_by(3) {
        let a = (deg as f64).to_radians();
        let mut ch = |steady: f64| -> Vec<f64> {
            t.iter()
                .map(|ti| steady + 0.05 * (-ti / 0.5f64).exp() + noise.sample(&mut rng))
                .collect()
        };
        let (d, l, m) = (ch(cd(a)), ch(CLA * a), ch(CMA * a));
        records.push(record(
            &format!("alpha {deg}"),
            &[
                (Quantity::Time, t.clone()),
                (Quantity::Cd, d),
                (Quantity::Cl, l),
                (Quantity::Cm, m),
            ],
            &[(Quantity::Alpha, a), (Quantity::Speed, 3.0)],
        ));
    }
    let r = run(&config(""), &records);
    assert_eq!(r.points.len(), 9);
    let p = &r.points[0];
    assert_eq!(p.samples, 251); // t >= 7.5 s
    assert!(p.cd_se.unwrap() > 0.0 && p.cd_se.unwrap() < 1e-4);
    for (name, truth) in [
        ("Xuu", -1.330),
        ("Xvv", -5.382),
        ("Yuvl", -16.31),
        ("Nuvl", 13.43),
    ] {
        four_figures(coef(&r, name).0, truth);
    }
    // Inverse-variance weights need and use those standard errors.
    let w = run(&config("weights = \"inverse_variance\"\n"), &records);
    four_figures(coef(&w, "Xuu").0, -1.330);
    // Averaging the whole history keeps the transient: c is off by its mean over 10 s,
    // 0.05 * 0.5 s / 10 s = 0.0025 (3 % of c).
    let all = run(&config("steady_fraction = 1.0\n"), &records);
    let bias = all.pooled.drag.value("c").unwrap() - C;
    assert!((bias - 0.0025).abs() < 1e-4, "{bias}");
    assert!((r.pooled.drag.value("c").unwrap() - C).abs() < 1e-4);
}

#[test]
fn inverse_variance_weights_need_histories() {
    let e = polar::run(
        &config("weights = \"inverse_variance\"\n"),
        &vehicle(),
        &fluid(),
        &[table3(&sweep(-12, 12))],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("inverse_variance") && e.contains("table3"),
        "{e}"
    );
}

#[test]
fn cubic_term_recovers_the_slope_of_a_wide_sweep() {
    let al = sweep(-20, 20);
    let l = |a: f64| CLA * a - 0.8 * a.powi(3);
    let rec = sweep_record("wide", &al, [&cd, &l, &|a| CMA * a]);
    let linear = run(&config(""), std::slice::from_ref(&rec));
    let err_linear = (linear.pooled.lift.value("slope").unwrap() - CLA).abs();
    assert!(err_linear > 0.02 * CLA.abs(), "{err_linear}");
    assert!(linear
        .warnings
        .iter()
        .any(|w| w.meaning.contains("polar.lift.cubic")));
    let cubic = run(
        &config("[lift]\ncubic = true\n"),
        std::slice::from_ref(&rec),
    );
    assert!(close(cubic.pooled.lift.value("slope").unwrap(), CLA, 1e-9));
    assert!(close(cubic.pooled.lift.value("cubic").unwrap(), -0.8, 1e-9));
    // A narrower fitting range also helps, and the points outside it are kept but unused.
    let narrow = run(&config("alpha_max_deg = 6\n"), &[rec]);
    let err_narrow = (narrow.pooled.lift.value("slope").unwrap() - CLA).abs();
    assert!(err_narrow < err_linear / 5.0);
    assert_eq!(narrow.pooled.n_points, 13);
    assert_eq!(narrow.points.iter().filter(|p| !p.used).count(), 28);
}

#[test]
fn too_few_angles_are_reported() {
    let e = polar::run(&config(""), &vehicle(), &fluid(), &[table3(&sweep(0, 1))])
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 distinct angle(s)"), "{e}");
}

#[test]
fn result_serialises_to_json() {
    let r = run(&config(""), &[table3(&sweep(-12, 12))]);
    let v: serde_json::Value = serde_json::to_value(&r).unwrap();
    assert!(v["pooled"]["drag"]["covariance"].is_array());
    assert_eq!(v["coefficients"][0]["name"], "Xuu");
    assert_eq!(v["reference"]["data"], "coefficients");
}

#[test]
fn configuration_problems_have_key_paths() {
    let text = "[vehicle]\nmass = 50\nlength = 1.2\nizz = 3.7\nreference_area = 0.0314\n\
                reference_length = 1\n[fluid]\nrho = 1025\nmu = 0.0009\n[polar]\nruns = []\n\
                alpha_max_deg = 120\nsteady_fraction = 0\nspeed_tolerance = 2\n\
                [polar.moment]\ncubic = false\n[polar.moment.bounds]\ncubic = { max = 1 }\n";
    let cfg: Config = toml::from_str(text).unwrap();
    let mut p = Problems::new(Path::new("c.toml"), text);
    cfg.validate(&cfg.vehicle.for_model(&cfg.fluid), &mut p);
    let keys: Vec<&str> = p.list.iter().filter_map(|x| x.key.as_deref()).collect();
    for k in [
        "polar.runs",
        "polar.alpha_max_deg",
        "polar.steady_fraction",
        "polar.speed_tolerance",
        "polar.moment.bounds.cubic",
    ] {
        assert!(keys.contains(&k), "{k} not in {keys:?}");
    }
    let a = p
        .list
        .iter()
        .find(|x| x.key.as_deref() == Some("polar.alpha_max_deg"));
    assert_eq!(a.unwrap().line, Some(12));
}

#[test]
fn needs_follow_the_data_kind() {
    let n = polar::needs(&config(""));
    assert_eq!(
        n.required,
        &[Quantity::Alpha, Quantity::Cd, Quantity::Cl, Quantity::Cm]
    );
    let n = polar::needs(&config("data = \"forces\"\n"));
    assert!(n.required.contains(&Quantity::Fx) && n.required.contains(&Quantity::Speed));
}
