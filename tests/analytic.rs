//! Fossen's analytic added mass of a prolate spheroid (Lamb's k-factors), library and CLI.

use crate::common;

use common::{four_figures, named, ANALYTIC_PAPER_SPHEROID};
use hydroid::model::analytic::Spheroid;
use hydroid::model::coefficients::Source;

#[test]
fn the_papers_spheroid() {
    // L = 1.2 m, D = 0.2 m, rho = 1025 kg/m^3 (paper Table 1; doc section 5).
    let s = Spheroid::from_length_diameter(1.2, 0.2, 1025.0).unwrap();
    four_figures(s.displaced_mass, 25.76); // 4/3 pi 1025 * 0.6 * 0.1^2 = 25.761 kg
    assert!((s.displaced_mass - 25.761).abs() < 5e-4);
    four_figures(s.xud(), -1.164);
    four_figures(s.yvd(), -23.63);
    four_figures(s.nrd(), -1.453);
    assert!((s.xud() + 1.1640).abs() < 5e-5);
    assert!((s.yvd() + 23.626).abs() < 5e-4);
    assert!((s.nrd() + 1.4532).abs() < 5e-5);
    let c = s.coefficients();
    let get = |n: &str| c.iter().find(|k| k.name == n).unwrap();
    assert_eq!(get("Zwd").value, get("Yvd").value);
    assert_eq!(get("Mqd").value, get("Nrd").value);
    for zero in ["Kpd", "Yrd", "Nvd"] {
        assert_eq!(get(zero).value, 0.0);
    }
    for k in &c {
        assert_eq!(k.source, Source::Analytic);
        assert!(k.note.as_deref().unwrap().contains("Fossen"));
    }
    assert_eq!(get("Nrd").unit, "kg m^2");
}

#[test]
fn lambs_table_at_length_over_diameter_six() {
    // Lamb's k-factors for L/D = 6 as tabulated by Fossen (1994) and Newman (1977):
    // k1 = 0.045, k2 = 0.917, k' = 0.762, independent of size and density.
    for (a, rho) in [(6.0, 1.0), (0.6, 1025.0), (30.0, 998.0)] {
        let s = Spheroid::new(a, a / 6.0, rho).unwrap();
        assert!((s.k1 - 0.045).abs() < 5e-4, "k1 {}", s.k1);
        assert!((s.k2 - 0.917).abs() < 5e-4, "k2 {}", s.k2);
        assert!((s.k_prime - 0.762).abs() < 5e-4, "k' {}", s.k_prime);
    }
}

#[test]
fn towards_a_sphere_k1_and_k2_tend_to_one_half() {
    // A sphere's added mass is half the displaced mass in every direction, and a sphere
    // turning about its centre displaces no fluid: k1 = k2 -> 1/2, k' -> 0, smoothly.
    let mut last = f64::INFINITY;
    for eps in [1e-1, 1e-2, 1e-3, 1e-5, 1e-8, 1e-12] {
        let s = Spheroid::new(1.0, 1.0 - eps, 1.0).unwrap();
        let gap = (s.k1 - 0.5).abs().max((s.k2 - 0.5).abs());
        assert!(gap < 2.0 * eps, "eps {eps}: k1 {} k2 {}", s.k1, s.k2);
        assert!(gap <= last);
        last = gap;
        assert!(s.k1 < 0.5 && s.k2 > 0.5, "prolate: k1 < 1/2 < k2");
        assert!(
            s.k_prime >= 0.0 && s.k_prime < 2.0 * eps,
            "k' {}",
            s.k_prime
        );
        assert!(s.xud().is_finite() && s.nrd().is_finite());
    }
}

#[test]
fn towards_a_needle_k1_tends_to_zero_and_k2_to_one() {
    // Slender-body limit: no axial added mass, the full displaced mass sideways.
    let s = Spheroid::new(1.0, 1e-4, 1.0).unwrap();
    assert!(s.k1 < 1e-6 && (1.0 - s.k2) < 1e-6 && (1.0 - s.k_prime) < 1e-6);
}

#[test]
fn bad_geometry_is_an_error() {
    for (l, d, rho) in [
        (1.2, 1.2, 1025.0),
        (0.2, 1.2, 1025.0),
        (1.2, 0.0, 1025.0),
        (-1.2, 0.2, 1025.0),
        (1.2, 0.2, -1.0),
        (f64::INFINITY, 0.2, 1025.0),
    ] {
        let e = Spheroid::from_length_diameter(l, d, rho).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("prolate spheroid"), "{e}");
    }
}

/// Exit code, stdout and stderr (both UTF-8) of `hydroid args`.
fn hydroid(args: &[&str]) -> (i32, String, String) {
    let out = common::hydroid(args);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn cli_prints_the_three_values() {
    let (code, out, err) = hydroid(&[&ANALYTIC_PAPER_SPHEROID[..], &["--rho", "1025"]].concat());
    assert_eq!(code, 0, "{err}");
    for line in [
        "Xud        -1.16396",
        "Yvd       -23.62607",
        "Nrd        -1.45321",
    ] {
        assert!(out.contains(line), "{line} not in\n{out}");
    }
    assert!(out.contains("k1") && out.contains("Fossen"));
}

#[test]
fn cli_json() {
    let (code, out, _) = hydroid(&[&ANALYTIC_PAPER_SPHEROID[..], &["--json"]].concat());
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["rho"], 1025.0);
    let xud = named(&v["coefficients"], "Xud");
    assert!((xud["value"].as_f64().unwrap() + 1.1640).abs() < 5e-5);
    assert_eq!(xud["source"], "analytic");
    assert!((v["factors"]["k2"].as_f64().unwrap() - 0.917).abs() < 5e-4);
}

#[test]
fn cli_bad_geometry_exits_2_with_a_clear_message() {
    let (code, out, err) = hydroid(&[
        "analytic",
        "spheroid",
        "--length",
        "0.2",
        "--diameter",
        "1.2",
    ]);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert!(err.contains("must be smaller than the length"), "{err}");
    let (code, _, err) = hydroid(&[
        "analytic",
        "spheroid",
        "--length",
        "-1",
        "--diameter",
        "0.2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("length must be a positive number"), "{err}");
    // A missing argument is clap's usage error, also 2.
    let (code, _, _) = hydroid(&["analytic", "spheroid", "--length", "1.2"]);
    assert_eq!(code, 2);
}
