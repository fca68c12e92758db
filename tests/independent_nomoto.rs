//! Identification accuracy of hydroid's `nomoto_wave` model on data it did not make (issue
//! 22): the frigate generator of tests/independent/nomoto.rs (Nomoto's first-order ship with
//! a 1 deg rudder bias, K = 0.18 1/s, T = 27 s; Fossen's linear wave yaw of 1 deg driven by
//! white noise; own RK4 at 10 ms; the rudder moving at 2.32 deg/s through the steering
//! gear; a 600 s 20/20 zig-zag; compass logged at 10 Hz with 0.1 deg of noise), identified by
//! `hydroid run` (as a library) with a configuration like the bundled configs/nomoto.toml:
//! K, 1/T and the bias, and the wave frequency w0 too in 5 s and 20 s waves (started from
//! the compass spectrum, as docs/models/nomoto.md describes), the wave process noise set to
//! the sea's (q = 4 zeta w0 sigma^2).

mod independent;

use independent::accuracy::{identify, Outcome};
use independent::nomoto::{self, NomotoShip};
use std::fmt::Write as _;

fn run(period: f64, estimate_w0: bool, seed: u64) -> Outcome {
    let ship = NomotoShip::frigate(period);
    let run = nomoto::zigzag_in_waves(&ship, seed);
    let dir = tempfile::tempdir().unwrap();
    run.log.write_csv(dir.path(), "zigzag.csv");
    let mut c = String::new();
    writeln!(
        c,
        "title = \"frigate 20/20 zig-zag in {period} s waves (independent generator)\"\n\
         [vehicle]\nname = \"frigate (Van Amerongen 1982), 9 m/s\"\nmass = 3.0e6\n\
         length = 120.0\nizz = 2.7e9\nreference_area = 480.0\nreference_length = 120.0\n\
         [vehicle.particulars]\nwave_model = \"fossen\"\n[fluid]\nrho = 1025.0\nmu = 0.00108\n\
         [coefficients]\nzeta_w = {zeta}",
        zeta = ship.zeta
    )
    .unwrap();
    let mut estimate = vec!["K", "inv_T", "delta0"];
    if estimate_w0 {
        estimate.push("w0");
    } else {
        writeln!(c, "w0 = {}", ship.w0).unwrap();
    }
    writeln!(
        c,
        "[hekf]\nmodel = \"nomoto_wave\"\nestimate = {estimate:?}\nnoise = {{ yaw = \"0.1 deg\" }}\n\
         process_noise = {{ psi_H = {q:e} }}\n[hekf.prior]\n\
         K = {{ initial = 0.1, sigma = 0.1 }}\ninv_T = {{ initial = 0.05, sigma = 0.05 }}\n\
         delta0 = {{ initial = 0.0, sigma = 0.05 }}",
        q = ship.wave_q()
    )
    .unwrap();
    if estimate_w0 {
        writeln!(c, "w0 = {{ sigma = 0.5 }}").unwrap();
    }
    writeln!(
        c,
        "[[hekf.runs]]\nname = \"20/20 zig-zag\"\nfile = \"zigzag.csv\"\n[hekf.runs.columns]\n\
         time = \"time\"\nyaw = \"compass\"\nrudder = \"rudder\""
    )
    .unwrap();
    let config = dir.path().join("nomoto.toml");
    std::fs::write(&config, c).unwrap();
    let truth = vec![
        ("K", ship.k),
        ("inv_T", 1.0 / ship.t),
        ("delta0", ship.delta0),
        ("w0", ship.w0),
    ];
    let o = identify(&config, &truth);
    let inv_t = o.row("inv_T");
    println!(
        "{}T = {:.3} +- {:.3} s (truth {} s, {:+.2} %)",
        o.table(),
        1.0 / inv_t.estimate,
        inv_t.sigma / (inv_t.estimate * inv_t.estimate),
        ship.t,
        100.0 * (1.0 / (ship.t * inv_t.estimate) - 1.0)
    );
    for w in &o.warnings {
        println!("warning: {w}");
    }
    o
}

fn check(o: &Outcome) {
    o.assert_undetermined_flagged();
    let (k, n) = o.within_two_sigma();
    assert_eq!(k, n, "{}", o.table());
}

/// 8 s waves, w0 known (configs/nomoto.toml's set-up). Measured: K 0.17928 +- 0.00105
/// (-0.40 %, z -0.69), 1/T 0.037263 +- 0.000288 (T 26.84 s, -0.61 %, z +0.79), bias
/// 1.0157 +- 0.043 deg (z +0.36). Asserted at 1.5 times those.
#[test]
fn zigzag_in_8_s_waves_w0_known() {
    let o = run(8.0, false, 801);
    check(&o);
    let k = o.row("K");
    let inv_t = o.row("inv_T");
    let d0 = o.row("delta0");
    assert!(k.error_percent().abs() < 0.6, "{}", o.table());
    assert!(inv_t.error_percent().abs() < 0.92, "{}", o.table());
    assert!(
        (d0.estimate - d0.truth).to_degrees().abs() < 0.0235,
        "{}",
        o.table()
    );
    assert!(o.worst_z() < 1.18, "{}", o.table());
}

/// 5 s waves, w0 estimated from the compass spectrum on, the logged rudder read as hydroid
/// reads any log (`between = "auto"`: its ramps interpolated). Measured: K 0.17994 +- 0.00112
/// (-0.03 %, z -0.05), T 26.999 +- 0.217 s (-0.00 %), bias z -0.02, w0 1.2145 +- 0.0211
/// rad/s (truth 1.2566, -3.4 %, z -2.00). (Read held, before `between`: K -0.30 %, T -0.45 %,
/// w0 z -2.5.) Asserted: all four within 2 sigma, K and T within 0.1 %.
#[test]
fn zigzag_in_5_s_waves_w0_estimated() {
    let o = run(5.0, true, 501);
    check(&o);
    for name in ["K", "inv_T"] {
        assert!(o.row(name).error_percent().abs() < 0.1, "{}", o.table());
    }
}

/// 20 s waves (overlapping the zig-zag's own frequencies), w0 estimated, the rudder read by
/// `between = "auto"`. Measured: all four within 2 sigma: K 0.17552 +- 0.00233 (-2.5 %,
/// z -1.92), T 26.34 +- 0.48 s (-2.4 %; 1/T z +1.34), bias +6.4 % (z +0.5, flagged), w0
/// 0.3242 +- 0.0101 (+3.2 %, z +1.0); the sigmas cover the errors (read held, before
/// `between`: K -2.7 % at z -5.2). Issue 22's 1 % for K and T is not met in waves this long:
/// asserted within 2 sigma and 3 %.
#[test]
fn zigzag_in_20_s_waves_w0_estimated() {
    let o = run(20.0, true, 2001);
    check(&o);
    for name in ["K", "inv_T"] {
        assert!(o.row(name).error_percent().abs() < 3.0, "{}", o.table());
    }
}
