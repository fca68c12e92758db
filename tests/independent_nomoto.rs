//! Identification accuracy of hydroid's `nomoto_wave` model on data it did not make (issue
//! 22): the frigate generator of tests/independent/nomoto.rs (Nomoto's first-order ship with
//! a 1 deg rudder bias, K = 0.18 1/s, T = 27 s; Fossen's linear wave yaw of 1 deg driven by
//! white noise; own RK4 at 10 ms; the rudder moving at 2.32 deg/s through the steering
//! gear; a 600 s 20/20 zig-zag; compass logged at 10 Hz with 0.1 deg of noise), identified by
//! `hydroid run` (as a library) with a configuration like the bundled configs/nomoto.toml:
//! K, 1/T and the bias, and the wave frequency w0 too in 5, 8 and 20 s waves and in calm
//! water (started from the compass spectrum, as docs/models/nomoto.md describes; w0 kept
//! positive, docs/hekf.md "Admissible ranges"), the wave process noise set to the sea's
//! (q = 4 zeta w0 sigma^2).

use crate::independent;

use independent::accuracy::{identify, Outcome, Study};
use independent::nomoto::{self, NomotoShip};
use std::fmt::Write as _;

/// How the wave frequency w0 enters a case.
#[derive(Clone, Copy)]
enum W0 {
    /// Known (given in `[coefficients]`).
    Known,
    /// Estimated with this prior sigma (rad/s), started from the compass spectrum.
    Sigma(f64),
    /// Estimated with hydroid's default prior (half the start read from the compass).
    Default,
}

fn run(period: f64, estimate_w0: bool, seed: u64) -> Outcome {
    let w0 = if estimate_w0 {
        W0::Sigma(0.5)
    } else {
        W0::Known
    };
    run_case(period, w0, true, seed)
}

fn run_case(period: f64, w0: W0, waves: bool, seed: u64) -> Outcome {
    let ship = NomotoShip::frigate(period);
    let run = if waves {
        nomoto::zigzag_in_waves(&ship, seed)
    } else {
        nomoto::zigzag_in_calm(&ship, seed)
    };
    let estimate_w0 = !matches!(w0, W0::Known);
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
    match w0 {
        W0::Sigma(s) => writeln!(c, "w0 = {{ sigma = {s} }}").unwrap(),
        W0::Known | W0::Default => {}
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

/// 8 s waves, w0 known (configs/nomoto.toml's set-up). Measured (2026-11-27): K 0.17998 +-
/// 0.00108 (-0.01 %, z -0.02), 1/T 0.037046 +- 0.000288 (T 26.99 s, -0.02 %, z +0.03), bias
/// 1.0009 +- 0.043 deg (z +0.02). Asserted at docs/validation.md's printed digits.
#[test]
fn zigzag_in_8_s_waves_w0_known() {
    let o = run(8.0, false, 801);
    check(&o);
    // docs/validation.md: "3 / 3 | K -0.01 %, T -0.02 %, worst z 0.03"
    assert_eq!(
        format!("{}, worst z {:.2}", k_and_t(&o), o.worst_z()),
        "K -0.01 %, T -0.02 %, worst z 0.03",
        "{}",
        o.table()
    );
}

/// "K -0.14 %, T -0.16 %": the errors of K and of T = 1 / inv_T, as docs/validation.md
/// prints them.
fn k_and_t(o: &Outcome) -> String {
    let inv_t = o.row("inv_T");
    format!(
        "K {:+.2} %, T {:+.2} %",
        o.row("K").error_percent(),
        100.0 * (inv_t.truth / inv_t.estimate - 1.0)
    )
}

/// "w0 -3.4 % (z -2.00)": the wave frequency's error and z as docs/validation.md prints
/// them, z to `decimals`.
fn w0_said(o: &Outcome, decimals: usize) -> String {
    let w0 = o.row("w0");
    format!("w0 {:+.1} % (z {:+.decimals$})", w0.error_percent(), w0.z)
}

/// 5 s waves, w0 estimated (by the innovations' likelihood, from the compass spectrum's
/// start), the logged rudder read as hydroid reads any log (`between = "auto"`: its ramps
/// interpolated). Measured (2026-11-28): K -0.03 % (z -0.05), 1/T +0.01 %, bias z +0.02,
/// w0 1.2443 +- 0.0161 rad/s (truth 1.2566, -1.0 %, z -0.77). (w0 appended to the filter's
/// state instead, 2026-11-27: w0 -1.6 %, z -1.17, K -0.04 %.) Asserted: all four within
/// 2 sigma, K and T within 0.1 %.
#[test]
fn zigzag_in_5_s_waves_w0_estimated() {
    let o = run(5.0, true, 501);
    check(&o);
    for name in ["K", "inv_T"] {
        assert!(o.row(name).error_percent().abs() < 0.1, "{}", o.table());
    }
    // docs/validation.md: "4 / 4 | w0 -1.0 % (z -0.77); K -0.03 %, T -0.01 %"
    assert_eq!(
        format!("{}; {}", w0_said(&o, 2), k_and_t(&o)),
        "w0 -1.0 % (z -0.77); K -0.03 %, T -0.01 %",
        "{}",
        o.table()
    );
}

/// 8 s waves, w0 estimated by the innovations' likelihood from hydroid's default start (the
/// peak of the compass rate's spectrum). Measured (2026-11-28): K 0.17998 +- 0.00108
/// (-0.01 %, z -0.02), 1/T +0.02 % (z +0.03), bias z +0.01; w0 0.7738 +- 0.0144 rad/s (truth
/// 0.7854, -1.5 %, z -0.81). (w0 appended to the filter's state instead, 2026-11-27: w0
/// -5.0 % at z -1.28, K -0.09 %, T -0.11 %.) Asserted: w0 positive and within 8.5 %, all
/// four within 2 sigma, K and T within 0.15 %.
#[test]
fn zigzag_in_8_s_waves_w0_estimated() {
    let o = run_case(8.0, W0::Default, true, 801);
    o.assert_undetermined_flagged();
    let w0 = o.row("w0");
    assert!(
        w0.estimate > 0.0 && w0.error_percent().abs() < 8.5,
        "{}",
        o.table()
    );
    k_and_t_within_2_sigma_and(&o, 0.15);
    // docs/validation.md: "4 / 4 | w0 -1.5 % (z -0.81); K -0.01 %, T -0.02 %"
    assert_eq!(o.within_two_sigma(), (4, 4), "{}", o.table());
    assert_eq!(
        format!("{}; {}", w0_said(&o, 2), k_and_t(&o)),
        "w0 -1.5 % (z -0.81); K -0.01 %, T -0.02 %",
        "{}",
        o.table()
    );
    // docs/models/nomoto.md's table
    assert_eq!(o.printed_row("w0", "0.7738 ± 0.0144"), "0.7738 ± 0.0144");
}

/// 20 s waves (overlapping the zig-zag's own frequencies), w0 estimated by the innovations'
/// likelihood from the spectral start, the rudder read by `between = "auto"`. Measured
/// (2026-11-28): all four within 2 sigma: K 0.17954 +- 0.00198 (-0.25 %, z -0.23; the sigma
/// carries w0's, 0.00108 with w0 held), 1/T +0.11 % (T -0.11 %, z +0.09), bias -1.1 %
/// (z -0.17), w0 0.3176 +- 0.0089 (+1.1 %, z +0.39). (w0 appended to the filter's state,
/// 2026-11-27: K -0.26 %, bias z -0.48; before the heading started with the unmeasured
/// variance: K -0.71 %, T -1.36 %.) Asserted within 2 sigma, K and 1/T within issue 22's 1 %.
#[test]
fn zigzag_in_20_s_waves_w0_estimated() {
    let o = run_case(20.0, W0::Default, true, 2001);
    check(&o);
    assert!(o.row("w0").estimate > 0.0, "{}", o.table());
    assert!(o.row("K").error_percent().abs() < 1.0, "{}", o.table());
    assert!(o.row("inv_T").error_percent().abs() < 1.0, "{}", o.table());
    // docs/validation.md: "4 / 4 | K -0.25 %, T -0.11 % (1/T z +0.09), bias z -0.17"
    assert_eq!(
        format!(
            "{} (1/T z {:+.2}), bias z {:+.2}",
            k_and_t(&o),
            o.row("inv_T").z,
            o.row("delta0").z
        ),
        "K -0.25 %, T -0.11 % (1/T z +0.09), bias z -0.17",
        "{}",
        o.table()
    );
    // docs/models/nomoto.md's table
    assert_eq!(o.printed_row("w0", "0.3176 ± 0.0089"), "0.3176 ± 0.0089");
}

/// 20 s waves, w0 estimated (as above) over 8 seeds (2001-2008): how often issue 22's "K and
/// T within 1 %" holds where the waves overlap the zig-zag's own frequencies. Measured
/// (2026-11-28, asserted): in all 8 seeds, K within 0.58 % and 1/T within 0.50 %, all within
/// 2 sigma (w0 appended to the filter's state, 2026-11-27: 0.33 % and 0.21 %; before the
/// heading started with the unmeasured variance: 6 of the 8, seed 2001 at T -1.36 % and seed
/// 2002 with K undetermined).
#[test]
fn zigzag_in_20_s_waves_over_seeds_k_and_t_within_1_percent_or_flagged() {
    let outcomes: Vec<Outcome> = (2001..2009)
        .map(|seed| run_case(20.0, W0::Default, true, seed))
        .collect();
    let mut within = Vec::new();
    for (seed, o) in (2001..).zip(&outcomes) {
        o.assert_undetermined_flagged();
        let (k, t) = (o.row("K"), o.row("inv_T"));
        for r in [k, t] {
            assert!(r.z.abs() < 2.0 || r.flagged, "seed {seed}\n{}", o.table());
        }
        if k.error_percent().abs() < 1.0 && t.error_percent().abs() < 1.0 && !k.flagged {
            within.push(seed);
        }
    }
    assert_eq!(within, (2001..2009).collect::<Vec<u64>>());
    let worst = |name: &str| {
        outcomes
            .iter()
            .map(|o| o.row(name).error_percent().abs())
            .fold(0.0f64, f64::max)
    };
    assert_eq!(
        format!("{:.2} {:.2}", worst("K"), worst("inv_T")),
        "0.58 0.50"
    );
}

/// Over seeds 801-808, with hydroid's default w0 prior (the start from the compass rate's
/// spectrum, sigma half of it): the largest w0 error (per cent), how many seeds have w0
/// within 2 sigma, and how many have K and 1/T both within 2 sigma.
fn w0_over_seeds(period: f64) -> (f64, usize, usize) {
    let (mut worst, mut w0_within, mut kt_within) = (0.0f64, 0, 0);
    for seed in 801..809 {
        let o = run_case(period, W0::Default, true, seed);
        let w0 = o.row("w0");
        assert!(w0.estimate > 0.0, "{}", o.table());
        worst = worst.max(w0.error_percent().abs());
        w0_within += usize::from(w0.z.abs() < 2.0);
        kt_within += usize::from(o.row("K").z.abs() < 2.0 && o.row("inv_T").z.abs() < 2.0);
    }
    (worst, w0_within, kt_within)
}

/// The default w0 start over 8 seeds (801-808) in 5 and 8 s waves (docs/models/nomoto.md),
/// w0 by the innovations' likelihood, measured 2026-11-28: w0 within 3.3 % (5 s) and 3.2 %
/// (8 s), within 2 sigma in 7 and 8 of the 8, K and 1/T within 2 sigma in all. (w0 appended to
/// the filter's state, 2026-11-27: seed 804 did not converge in either, w0 -64 % and K -3.3 %
/// at z -2.11 in 5 s waves, w0 -16 % in 8 s waves, "64.3 % 7/8 7/8; 15.8 % 7/8 8/8"; before
/// the start was read from the rate's spectrum, w0 collapsed towards 0 in all 8 seeds of the
/// 5 s waves.)
#[test]
fn the_default_w0_prior_finds_5_and_8_s_waves_over_seeds() {
    let said: Vec<String> = [5.0, 8.0]
        .iter()
        .map(|&period| {
            let (worst, w0_within, kt_within) = w0_over_seeds(period);
            format!("{period} s: {worst:.1} % {w0_within}/8 {kt_within}/8")
        })
        .collect();
    assert_eq!(said.join("; "), "5 s: 3.3 % 7/8 8/8; 8 s: 3.2 % 8/8 8/8");
}

/// Calm water, w0 estimated: the compass shows no wave yaw, and the filter pulls w0 below
/// zero; it is held at its bound (0.0008 rad/s, 0.001 of its expected size above zero) and
/// the run says so in a warning naming w0 and its range. The innovations' likelihood has no
/// maximum to find w0 by (it keeps rising as w0 falls), so w0 stays a filter state, and a
/// second warning says that. K and T are untouched (measured 2026-11-27: K +0.04 %,
/// T +0.03 %, w0 held at 3073 of 6001 samples of the last pass).
#[test]
fn in_calm_water_w0_ends_at_its_bound_with_a_warning() {
    let o = run_case(8.0, W0::Default, false, 801);
    let w0 = o.row("w0");
    assert!(w0.estimate > 0.0 && w0.estimate < 1e-3, "{}", o.table());
    assert!(
        o.warnings
            .iter()
            .any(|w| w.contains("w0 ended at the bound") && w.contains("> 0 rad/s")),
        "{:?}",
        o.warnings
    );
    // the likelihood keeps rising as w0 falls: no maximum to profile, and the run says so
    assert!(
        o.warnings
            .iter()
            .any(|w| w.contains("w0 not found by the innovations' likelihood")),
        "{:?}",
        o.warnings
    );
    // docs/validation.md: "w0 held at its bound (0.0008 rad/s) ...; K, T within 0.05 %"
    // (measured +0.042 % and +0.026 %)
    assert_eq!(format!("{:.4}", w0.estimate), "0.0008", "{}", o.table());
    // docs/models/nomoto.md's table: "+0.04 % | +0.03 %"
    assert_eq!(k_and_t(&o), "K +0.04 %, T +0.03 %", "{}", o.table());
    k_and_t_within_2_sigma_and(&o, 0.05);
}

/// K and 1/T within 2 sigma of the truth and within `percent` of it.
fn k_and_t_within_2_sigma_and(o: &Outcome, percent: f64) {
    for name in ["K", "inv_T"] {
        let r = o.row(name);
        assert!(
            r.z.abs() < 2.0 && r.error_percent().abs() < percent,
            "{}",
            o.table()
        );
    }
}

/// The 8 s waves with w0 known (the bundled set-up) over 100 noise seeds (5001-5100), two at
/// a time: no confident miss. Measured (2026-11-27): K, 1/T and the bias within 2 sigma in
/// every seed (300 of 300 pairs within 1 sigma: the sigmas are conservative, rms z 0.10,
/// 0.08, 0.14, from the heading's random walk, src/stages/hekf/prepare.rs `jitter_variance`);
/// K within 0.64 % of the truth in every seed. Before the heading started with the
/// unmeasured states' variance (`initial_state`) 95.0 % were within 1 sigma and 99.0 % within
/// 2, K's errors had a heavy low tail: seed 5019 K -9.1 % at z -20.6 (its first compass
/// sample holds 2.6 deg of wave yaw), 5069 -4.7 %, 5099 -4.5 %.
#[test]
fn over_100_seeds_in_8_s_waves_no_confident_miss() {
    let outcomes = crate::common::parallel::on_two_threads(100, |_, k| {
        run_case(8.0, W0::Known, true, 5001 + k as u64)
    });
    let study = Study { outcomes };
    let table = study.table();
    println!("{table}");
    for o in &study.outcomes {
        o.assert_undetermined_flagged();
    }
    let (one, two, pairs) = study.coverage();
    assert_eq!((pairs, one, two), (300, 1.0, 1.0), "{table}");
    let worst_k = study
        .outcomes
        .iter()
        .map(|o| o.row("K").error_percent().abs())
        .fold(0.0f64, f64::max);
    let said: Vec<String> = study
        .spreads()
        .iter()
        .map(|c| format!("{} {:.2}", c.name, c.rms_z))
        .collect();
    assert_eq!(
        format!("worst K {worst_k:.2} %; rms z {}", said.join(", ")),
        "worst K 0.64 %; rms z K 0.10, inv_T 0.08, delta0 0.14",
        "{table}"
    );
}
