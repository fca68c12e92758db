//! The bundled AUV example (configs/npsauv.toml): the 17 coefficients of Mousavian et al.
//! (2015) from the simulated helix export (OpenFOAM sixDoF state, earth-frame velocities,
//! realistic sensor noise) with hydroid's default hybrid EKF from zero, against the
//! published set the export was made with.

mod common;

use hydroid::models::npsauv::{PAPER_17, PUBLISHED};

#[test]
fn the_bundled_helix_identifies_the_papers_17_within_two_sigma() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("npsauv");
    let root = common::root();
    let o = common::hydroid(&[
        "run",
        root.join("configs/npsauv.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let mut inside = 0;
    let mut lines = Vec::new();
    for name in PAPER_17 {
        let c = common::named(&r["coefficients"], name);
        let (v, s) = (c["value"].as_f64().unwrap(), c["sigma"].as_f64().unwrap());
        let truth = PUBLISHED.iter().find(|(n, _)| n == name).unwrap().1;
        let z = (v - truth) / s;
        lines.push(format!(
            "{name}: {v:.4e} ± {s:.2e}, truth {truth:e}, {z:+.2} sigma"
        ));
        assert!(z.abs() < 3.0, "{name} beyond 3 sigma: {}", lines.join("\n"));
        if z.abs() <= 2.0 {
            inside += 1;
        }
    }
    // the target: the truth inside 2 sigma for at least 15 of the 17
    assert!(
        inside >= 15,
        "{inside} of 17 inside 2 sigma:\n{}",
        lines.join("\n")
    );
}
