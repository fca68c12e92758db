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

mod independent;

use independent::accuracy::{identify, Outcome};
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

/// 8 s waves, w0 known (configs/nomoto.toml's set-up). Measured (2026-11-26): K 0.17974 +-
/// 0.00251 (-0.14 %, z -0.10), 1/T 0.037097 +- 0.000608 (T 26.96 s, -0.16 %, z +0.10), bias
/// 1.0146 +- 0.076 deg (z +0.19). Asserted at docs/validation.md's printed digits.
#[test]
fn zigzag_in_8_s_waves_w0_known() {
    let o = run(8.0, false, 801);
    check(&o);
    // docs/validation.md: "3 / 3 | K -0.14 %, T -0.16 %, worst z 0.19"
    assert_eq!(
        format!("{}, worst z {:.2}", k_and_t(&o), o.worst_z()),
        "K -0.14 %, T -0.16 %, worst z 0.19",
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

/// 5 s waves, w0 estimated from the compass spectrum on, the logged rudder read as hydroid
/// reads any log (`between = "auto"`: its ramps interpolated). Measured: K 0.17995 +- 0.00121
/// (-0.03 %, z -0.04), 1/T +0.00 %, bias z -0.04, w0 1.2349 +- 0.0225 rad/s (truth 1.2566,
/// -1.7 %, z -0.97). (Started from the heading's spectrum instead of its rate's, a record:
/// w0 -3.4 %, z -2.00.) Asserted: all four within 2 sigma, K and T within 0.1 %.
#[test]
fn zigzag_in_5_s_waves_w0_estimated() {
    let o = run(5.0, true, 501);
    check(&o);
    for name in ["K", "inv_T"] {
        assert!(o.row(name).error_percent().abs() < 0.1, "{}", o.table());
    }
    // docs/validation.md: "4 / 4 | w0 -1.7 % (z -0.97); K -0.03 %, T -0.00 %"
    assert_eq!(
        format!("{}; {}", w0_said(&o, 2), k_and_t(&o)),
        "w0 -1.7 % (z -0.97); K -0.03 %, T -0.00 %",
        "{}",
        o.table()
    );
}

/// 8 s waves, w0 estimated with hydroid's default prior (the peak of the compass rate's
/// spectrum, sigma half of it). Measured: K 0.17998 +- 0.00107 (-0.01 %, z -0.02), 1/T
/// +0.03 % (z +0.04), bias z +0.05; w0 0.7360 +- 0.0153 rad/s (truth 0.7854, -6.3 %, z -3.22:
/// the wave frequency itself is not within 2 sigma; see the seeds below). Asserted: w0
/// positive and within 8.5 %, K and T within 2 sigma and 0.1 %.
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
    k_and_t_within_2_sigma_and(&o, 0.1);
    // docs/validation.md: "3 / 4 | w0 -6.3 % (z -3.22); K -0.01 %, T -0.03 %"
    assert_eq!(o.within_two_sigma(), (3, 4), "{}", o.table());
    assert_eq!(
        format!("{}; {}", w0_said(&o, 2), k_and_t(&o)),
        "w0 -6.3 % (z -3.22); K -0.01 %, T -0.03 %",
        "{}",
        o.table()
    );
    // docs/models/nomoto.md's table
    assert_eq!(o.printed_row("w0", "0.7360 ± 0.0153"), "0.7360 ± 0.0153");
}

/// 20 s waves (overlapping the zig-zag's own frequencies), w0 estimated with hydroid's
/// default prior (sigma half the spectral start, 0.16 rad/s), the rudder read by
/// `between = "auto"`. Measured: all four within 2 sigma: K 0.17873 +- 0.00218 (-0.71 %,
/// z -0.58), 1/T +1.38 % (T -1.36 %, z +1.06), bias +10 % (z +1.86), w0 0.3142 +- 0.0099
/// (+0.00 %). With the prior sigma 0.5 rad/s of before: K -2.49 % (z -1.92),
/// T -2.44 %, w0 +3.2 %. Issue 22's 1 % is met for K, not for T (1.36 %) in waves this long:
/// asserted within 2 sigma, K within 1 % and 1/T within 1.5 %.
#[test]
fn zigzag_in_20_s_waves_w0_estimated() {
    let o = run_case(20.0, W0::Default, true, 2001);
    check(&o);
    assert!(o.row("w0").estimate > 0.0, "{}", o.table());
    assert!(o.row("K").error_percent().abs() < 1.0, "{}", o.table());
    assert!(o.row("inv_T").error_percent().abs() < 1.5, "{}", o.table());
    // docs/validation.md: "4 / 4 | K -0.71 %, T -1.36 % (1/T z +1.06), bias z +1.86"
    assert_eq!(
        format!(
            "{} (1/T z {:+.2}), bias z {:+.2}",
            k_and_t(&o),
            o.row("inv_T").z,
            o.row("delta0").z
        ),
        "K -0.71 %, T -1.36 % (1/T z +1.06), bias z +1.86",
        "{}",
        o.table()
    );
    // docs/models/nomoto.md's table
    assert_eq!(o.printed_row("w0", "0.3142 ± 0.0099"), "0.3142 ± 0.0099");
}

/// 20 s waves, w0 estimated (as above) over 8 seeds (2001-2008): how often issue 22's "K and
/// T within 1 %" holds where the waves overlap the zig-zag's own frequencies. Measured
/// (asserted): K and 1/T both within 1 % in 6 of the 8 seeds (those six within 0.20 % and
/// 0.15 %); seed 2001 has T -1.36 % at z +1.06 (above); seed 2002 ends with K's sigma 79 % of
/// its value, flagged as not determined. In every seed K and 1/T are within 2 sigma or
/// flagged: no confident miss.
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
    assert_eq!(within, [2003, 2004, 2005, 2006, 2007, 2008]);
    let worst = |name: &str| {
        within
            .iter()
            .map(|s| {
                outcomes[(s - 2001) as usize]
                    .row(name)
                    .error_percent()
                    .abs()
            })
            .fold(0.0f64, f64::max)
    };
    assert_eq!(
        format!("{:.2} {:.2}", worst("K"), worst("inv_T")),
        "0.20 0.15"
    );
    let undetermined = &outcomes[1];
    assert!(undetermined.row("K").flagged, "{}", undetermined.table());
    assert!(
        undetermined
            .warnings
            .iter()
            .any(|w| w.contains("not determined by these runs: K")),
        "{:?}",
        undetermined.warnings
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

/// The default w0 prior over 8 seeds (801-808) in 5 and 8 s waves (docs/models/nomoto.md):
/// w0 within 2.6 % in 5 s waves, all 8 within 2 sigma; within 6.3 % in 8 s waves, 6 of 8
/// within 2 sigma (-6.3 % at z -3.2 and +4.6 % at z +2.3: the filter's w0 sigma is too small
/// there); K and 1/T within 2 sigma in every seed. Before the start was read
/// from the rate's spectrum, w0 collapsed towards 0 in all 8 seeds of the 5 s waves.
#[test]
fn the_default_w0_prior_finds_5_and_8_s_waves_over_seeds() {
    let said: Vec<String> = [5.0, 8.0]
        .iter()
        .map(|&period| {
            let (worst, w0_within, kt_within) = w0_over_seeds(period);
            format!("{period} s: {worst:.1} % {w0_within}/8 {kt_within}/8")
        })
        .collect();
    assert_eq!(said.join("; "), "5 s: 2.6 % 8/8 8/8; 8 s: 6.3 % 6/8 8/8");
}

/// Calm water, w0 estimated: the compass shows no wave yaw, and the filter pulls w0 below
/// zero; it is held at its bound (0.0008 rad/s, 0.001 of its expected size above zero) and
/// the run says so in a warning naming w0 and its range. K and T are untouched (measured:
/// K +0.01 %, T +0.01 %, w0 held at 3243 of 6001 samples of the last pass).
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
    // docs/validation.md: "w0 held at its bound (0.0008 rad/s) ...; K, T within 0.01 %"
    // (measured +0.011 % and +0.006 %)
    assert_eq!(format!("{:.4}", w0.estimate), "0.0008", "{}", o.table());
    // docs/models/nomoto.md's table: "+0.01 % | +0.01 %"
    assert_eq!(k_and_t(&o), "K +0.01 %, T +0.01 %", "{}", o.table());
    k_and_t_within_2_sigma_and(&o, 0.015);
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
