//! The adaptive autopilot (issue 29, item 2; Dinh, Hoang & Pham 2016: the EKF's running K and
//! 1/T retune the PID): the 150 m ship of configs/vehicles/ship150_clarke.toml steered through
//! course changes in waves, slowed from 8 to 5 m/s mid-run (its coefficients scaled with the
//! speed: K falls from 0.1227 to 0.0767 1/s, T rises from 80.0 to 128.1 s). hydroid's adaptive
//! loop against a loop written here from the equations alone (tests/common/ship150_loop.rs),
//! fed the true heading, with the gains re-placed on the slow ship's own indices (the ideal)
//! or kept at the 8 m/s ones (fixed gains).

use crate::common;

use common::root;
use common::ship150_loop::{self as reference, nomoto, rms_from, sway_yaw, U0};
use hydroid::config::autopilot::AutopilotConfig;
use hydroid::dynamics::autopilot::seas::Seas;
use hydroid::dynamics::autopilot::{AutopilotResult, ClosedLoop, Feed};

const SLOW_AT: f64 = 600.0;
const SLOW: f64 = 5.0;
const DURATION: f64 = 1900.0;

/// The course orders: 10 deg at 50 s, then back and forth every 300 s.
fn orders() -> Vec<(f64, f64)> {
    (0..6)
        .map(|i| {
            let at = if i == 0 {
                50.0
            } else {
                50.0 + 300.0 * i as f64
            };
            (at, if i % 2 == 0 { 10f64.to_radians() } else { 0.0 })
        })
        .collect()
}

/// hydroid's configuration: the ship slowed at `SLOW_AT`, every order after the first as an
/// `[[autopilot.orders]]`.
fn config() -> AutopilotConfig {
    let mut text = format!(
        "omega_n = {}\nzeta = {}\ncompass_noise = \"0.1 deg\"\nduration = {DURATION}\n\
         course_change = \"10 deg\"\nchange_at = 50.0\nseed = 5\n\
         feeds = [\"filter\", \"true\", \"adaptive\"]\n",
        reference::OMEGA_N,
        reference::ZETA
    );
    for (at, course) in &orders()[1..] {
        text += &format!("[[orders]]\nat = {at}\ncourse = {course}\n");
    }
    text += "[plant]\nmodel = \"ship_linear\"\nvehicle_file = \"vehicles/ship150_clarke.toml\"\n\
             inputs = { rpm = 1.80101 }\nspeed = \"8 m/s\"\n";
    text += &reference::slow_down_toml(SLOW_AT, SLOW);
    toml::from_str(&text).unwrap()
}

/// hydroid's loops: the identified model nomoto_wave with the 8 m/s ship's K and T, the
/// waves of configs/nomoto.toml on the compass.
fn hydroid_loops(cfg: &AutopilotConfig) -> AutopilotResult {
    reference::hydroid_autopilot(cfg, nomoto(sway_yaw(U0)), &Seas::Generated)
}

/// hydroid's loops on `cfg` (printed), and the reference loop on the same `plant` form with
/// the gains re-placed at the slow-down (the ideal) and kept (fixed): their heading errors.
fn slow_down(
    cfg: &AutopilotConfig,
    plant: fn(f64) -> reference::SwayYaw,
) -> (AutopilotResult, Vec<f64>, Vec<f64>) {
    let r = hydroid_loops(cfg);
    for l in r.lines() {
        println!("{l}");
    }
    for w in r.warnings() {
        println!("warning: {}", w.message);
    }
    let base = |retune| reference::Run {
        plant,
        slow: Some((SLOW_AT, SLOW)),
        retune,
        orders: orders(),
        duration: DURATION,
    };
    let (ideal, _) = reference::run(&base(true));
    let (fixed, _) = reference::run(&base(false));
    (r, ideal, fixed)
}

/// RMS of `v` from the slow-down on.
fn after(v: &[f64]) -> f64 {
    rms_from(v, SLOW_AT)
}

/// RMS of `v` from 300 s after the slow-down on (settled).
fn settled(v: &[f64]) -> f64 {
    rms_from(v, SLOW_AT + 300.0)
}

/// The true-heading, adaptive and wave-filter loops of `r`.
fn feeds(r: &AutopilotResult) -> (&ClosedLoop, &ClosedLoop, &ClosedLoop) {
    (
        r.feed(Feed::True).unwrap(),
        r.feed(Feed::Adaptive).unwrap(),
        r.feed(Feed::Filter).unwrap(),
    )
}

/// `v` equals `expected` at the digits written (within half a unit of the last).
fn at_digits(v: f64, expected: f64, half_unit: f64) {
    assert!((v - expected).abs() <= half_unit, "{v} against {expected}");
}

/// After the slow-down the adaptive loop's heading error returns to within 1.5 times the ideal
/// loop's (from 300 s after the change on) while the fixed gains fed the wave filter stay at
/// least three times worse; K/T comes near the slow ship's own; K and T apart are reported
/// with a warning when their sigmas do not cover the plant's. Measured (a record, the
/// asserted bounds below): ideal 0.2667 deg after the change, 0.2607 deg from 900 s (hydroid's
/// true feed and the reference to four digits); adaptive 0.5042 and 0.3208 deg; fixed gains on
/// the wave filter 1.498 deg after, fixed gains on the true heading 0.6986 deg; K/T 6.35e-4
/// against 5.99e-4 1/s^2 (+6.1 %: the plant is second order, see
/// `the_sway_yaw_ship_responds_24_percent_above_its_first_order_model_at_the_loop_frequency`;
/// on the paper's first-order plant K/T ends within 0.03 %).
#[test]
fn the_adaptive_loop_recovers_the_ideal_after_the_ship_slows_down() {
    let deg = f64::to_degrees;
    let (r, ideal, fixed) = slow_down(&config(), reference::sway_yaw);
    let (true_feed, adaptive, filter) = feeds(&r);
    println!(
        "reference ideal after {:.4} settled {:.4}; fixed after {:.4}; hydroid adaptive settled \
         {:.4}",
        deg(after(&ideal)),
        deg(settled(&ideal)),
        deg(after(&fixed)),
        deg(settled(&adaptive.heading_error))
    );
    // hydroid's ideal is the reference's
    let hydroid_ideal = true_feed.after_change.unwrap().heading_error_rms;
    assert!((hydroid_ideal / after(&ideal) - 1.0).abs() < 0.01);
    // the adaptive loop returns within 1.5x the ideal's; the fixed gains stay 3x worse
    assert!(settled(&adaptive.heading_error) <= 1.5 * settled(&ideal));
    assert!(filter.after_change.unwrap().heading_error_rms >= 3.0 * after(&ideal));
    assert!(after(&fixed) >= 2.5 * after(&ideal));
    // K/T near the slow ship's own; K and T apart flagged when they do not cover it
    let (k5, t5) = nomoto(sway_yaw(SLOW));
    let e = adaptive.final_estimate.unwrap();
    assert!((e.ratio / (k5 / t5) - 1.0).abs() < 0.07, "{e:?}");
    let plant_after = r.plant.after.unwrap();
    assert!((plant_after.k / k5 - 1.0).abs() < 1e-4);
    let covered = (e.k - k5).abs() <= 2.0 * e.k_sigma && (e.t_const - t5).abs() <= 2.0 * e.t_sigma;
    let warned = r
        .warnings()
        .iter()
        .any(|w| w.message.contains("do not cover the plant's own"));
    assert_eq!(warned, !covered, "{e:?}");
    // docs/models/nomoto.md's table and numbers, at their digits
    let stats = |l: &ClosedLoop| {
        let (b, a) = (l.before_change.unwrap(), l.after_change.unwrap());
        [
            deg(b.heading_error_rms),
            deg(a.heading_error_rms),
            deg(settled(&l.heading_error)),
            deg(a.rudder_rate_rms),
        ]
    };
    for (l, expected) in [
        (true_feed, [0.319, 0.267, 0.261, f64::NAN]),
        (filter, [0.309, 1.498, 1.573, 0.14]),
        (adaptive, [0.367, 0.504, 0.321, 0.39]),
    ] {
        for (i, (v, x)) in stats(l).iter().zip(expected).enumerate() {
            if x.is_finite() {
                at_digits(*v, x, if i == 3 { 0.005 } else { 0.0005 });
            }
        }
    }
    at_digits(deg(after(&fixed)), 0.699, 0.0005);
    at_digits(deg(settled(&fixed)), 0.696, 0.0005);
    at_digits(100.0 * (e.ratio / (k5 / t5) - 1.0), 6.1, 0.05);
    at_digits(e.k, 0.0534, 0.00005);
    at_digits(e.t_const, 84.0, 0.5);
}

/// The paper's ship model as the plant (Dinh, Hoang & Pham 2016: the first-order Nomoto model
/// r' = (K delta - r) / T, K and T from the sway-yaw equations at the speed), slowed from 8 to
/// 5 m/s at `SLOW_AT`: hydroid's `[plant]` (nomoto_wave with the plant's K and 1/T, changed
/// at the slow-down).
fn first_order_config() -> AutopilotConfig {
    let mut cfg = config();
    let (k8, t8) = nomoto(sway_yaw(U0));
    let (k5, t5) = nomoto(sway_yaw(SLOW));
    let w0 = std::f64::consts::FRAC_PI_4;
    let text = format!(
        "model = \"nomoto_wave\"\n\
         coefficients = {{ K = {k8}, inv_T = {}, delta0 = 0.0, w0 = {w0}, zeta_w = 0.1 }}\n\
         [change]\nat = {SLOW_AT}\ncoefficients = {{ K = {k5}, inv_T = {} }}\n",
        1.0 / t8,
        1.0 / t5
    );
    cfg.plant = Some(toml::from_str(&text).unwrap());
    cfg
}

/// On the paper's plant (the first-order Nomoto model whose K and T the filter estimates),
/// after the slow-down the adaptive loop's heading error returns to within 1.5 times the
/// ideal loop's while fixed gains stay at least three times worse, and K/T comes within 5 %
/// of the slow ship's own, K and T apart within their sigmas. Measured (asserted at these
/// digits): K/T +0.03 %, K 0.0745 +- 0.0082 1/s (plant 0.0767), T 124.5 +- 13.2 s (128.1);
/// heading error from 300 s after the change 0.299 deg against the ideal's 0.274; fixed
/// gains on the wave filter 1.558 deg after the change (the ideal 0.280).
#[test]
fn on_the_papers_plant_the_adaptive_estimate_of_k_over_t_comes_within_5_percent() {
    let deg = f64::to_degrees;
    let (r, ideal, fixed) = slow_down(&first_order_config(), reference::first_order);
    let (true_feed, adaptive, filter) = feeds(&r);
    let (k5, t5) = nomoto(sway_yaw(SLOW));
    let e = adaptive.final_estimate.unwrap();
    println!(
        "reference ideal after {:.4} settled {:.4}; fixed after {:.4}; hydroid true after {:.4}, \
         adaptive settled {:.4}, filter after {:.4}; K/T {:+.2} %",
        deg(after(&ideal)),
        deg(settled(&ideal)),
        deg(after(&fixed)),
        deg(true_feed.after_change.unwrap().heading_error_rms),
        deg(settled(&adaptive.heading_error)),
        deg(filter.after_change.unwrap().heading_error_rms),
        100.0 * (e.ratio / (k5 / t5) - 1.0)
    );
    let hydroid_ideal = true_feed.after_change.unwrap().heading_error_rms;
    assert!((hydroid_ideal / after(&ideal) - 1.0).abs() < 0.01);
    assert!(settled(&adaptive.heading_error) <= 1.5 * settled(&ideal));
    assert!(filter.after_change.unwrap().heading_error_rms >= 3.0 * after(&ideal));
    assert!((e.ratio / (k5 / t5) - 1.0).abs() < 0.05, "{e:?}");
    assert!((e.k - k5).abs() <= e.k_sigma && (e.t_const - t5).abs() <= e.t_sigma);
    at_digits(100.0 * (e.ratio / (k5 / t5) - 1.0), 0.03, 0.005);
    at_digits(e.k, 0.0745, 0.00005);
    at_digits(e.k_sigma, 0.0082, 0.00005);
    at_digits(e.t_const, 124.5, 0.05);
    at_digits(e.t_sigma, 13.2, 0.05);
    at_digits(deg(settled(&adaptive.heading_error)), 0.299, 0.0005);
    at_digits(deg(settled(&ideal)), 0.274, 0.0005);
    at_digits(
        deg(filter.after_change.unwrap().heading_error_rms),
        1.558,
        0.0005,
    );
    at_digits(deg(after(&ideal)), 0.280, 0.0005);
}

/// Why the sway-yaw plant's K/T is not the 5 % target: at the loop's natural frequency
/// (omega_n 0.05 rad/s) the slow ship's yaw-rate response to the rudder, from its sway-yaw
/// equations (Fossen 2011, 7.1: r/delta = (b_r s + a21 b_v - a11 b_r) / det(sI - A)), is
/// 24 % larger than its first-order Nomoto model's K / (1 + T s): the gain a loop sees is
/// not the first-order model's, and the running estimate (+6.1 %) lies between them.
#[test]
fn the_sway_yaw_ship_responds_24_percent_above_its_first_order_model_at_the_loop_frequency() {
    let (a, b) = sway_yaw(SLOW);
    let (k, t) = nomoto((a, b));
    let w = reference::OMEGA_N;
    // |(i w - a11) b_r + a21 b_v| / |(i w - a11)(i w - a22) - a12 a21|, in real arithmetic
    let (nr, ni) = (-a[0][0] * b[1] + a[1][0] * b[0], w * b[1]);
    let (dr, di) = (
        -w * w + a[0][0] * a[1][1] - a[0][1] * a[1][0],
        -w * (a[0][0] + a[1][1]),
    );
    let second = (nr.hypot(ni)) / dr.hypot(di);
    let first = k / (1.0f64).hypot(t * w);
    at_digits(100.0 * (second / first - 1.0), 24.0, 0.5);
}

/// The bundled example (configs/nomoto_adaptive.toml) runs end to end as `hydroid run` does:
/// results.json gives the plant's indices before and after the slow-down and the three loops
/// with their statistics before and after it, the adaptive one with its last estimates.
#[test]
fn the_bundled_adaptive_example_runs_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = common::run_config(&root().join("configs/nomoto_adaptive.toml"), &out, &[]);
    assert!(o.status.success(), "{}", common::text(&o.stderr));
    let results = common::json(&out.join("results.json"));
    let a = &results["autopilot"];
    let (k5, t5) = nomoto(sway_yaw(SLOW));
    let after = &a["plant"]["after"];
    assert!(
        (after["k"].as_f64().unwrap() / k5 - 1.0).abs() < 1e-3,
        "{after}"
    );
    assert!(
        (after["t"].as_f64().unwrap() / t5 - 1.0).abs() < 1e-3,
        "{after}"
    );
    let feeds = a["feeds"].as_array().unwrap();
    let names: Vec<&str> = feeds.iter().map(|f| f["feed"].as_str().unwrap()).collect();
    assert_eq!(names, ["filter", "adaptive", "true"]);
    for f in feeds {
        assert!(f["after_change"]["heading_error_rms"].as_f64().unwrap() > 0.0);
    }
    let e = &feeds[1]["final_estimate"];
    let ratio = e["ratio"].as_f64().unwrap();
    assert!((ratio / (k5 / t5) - 1.0).abs() < 0.1, "{e}");
    let stdout = common::text(&o.stdout);
    println!("{stdout}");
    assert!(stdout.contains("plant ship_linear"), "{stdout}");
}

/// A narrow-band wave yaw of period `period` s, written here from the wave model
/// psi_H = K_w s / (s^2 + 2 zeta w0 s + w0^2) w (Fossen 2011, 8.2.1, eq. 8.125): the rate x2
/// of x1'' + 2 zeta w0 x1' + w0^2 x1 = w, driven by white noise of spectral density `q`
/// (seeded) and integrated by semi-implicit Euler at 0.01 s, sampled every 0.1 s over
/// `duration` s; its variance is q / (4 zeta w0) (the same model's stationary variance).
fn wave_yaw(period: f64, q: f64, duration: f64) -> (Vec<f64>, Vec<f64>) {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let (w0, zeta, h) = (2.0 * std::f64::consts::PI / period, 0.1, 0.01);
    let mut rng = rand::rngs::StdRng::seed_from_u64(12);
    let (mut x1, mut x2) = (0.0f64, 0.0f64);
    let (mut t, mut y) = (Vec::new(), Vec::new());
    // 300 s of spin-up so that the recording starts stationary
    let steps = ((duration + 300.0) / h).round() as usize;
    for k in 0..=steps {
        let time = k as f64 * h - 300.0;
        if time >= -1e-9 && k % 10 == 0 {
            t.push(time.max(0.0));
            y.push(x2);
        }
        let w: f64 = StandardNormal.sample(&mut rng);
        x2 += h * (-2.0 * zeta * w0 * x2 - w0 * w0 * x1) + (q * h).sqrt() * w;
        x1 += h * x2;
    }
    (t, y)
}

/// `estimate_w0`: with a sea of 12 s waves (0.524 rad/s) recorded on the compass while the
/// identified model's w0 is that of 8 s waves (0.785 rad/s), the 150 m ship at 8 m/s, the
/// adaptive feed's running w0 comes to the sea's within its sigma (docs/models/nomoto.md, "The
/// adaptive autopilot"); without it the estimates carry no w0.
#[test]
fn the_adaptive_feed_finds_the_wave_frequency_when_asked() {
    use hydroid::dynamics::autopilot::seas::{DisturbanceKind, Recording};
    let (t, y) = wave_yaw(12.0, 9.6e-5, DURATION);
    let sea = Seas::Recorded(Recording::new(DisturbanceKind::WaveYaw, t, y).unwrap());
    let mut cfg = config();
    cfg.feeds = vec![Feed::Adaptive];
    // the ship keeps its speed: the identified K and T stay the plant's
    cfg.plant.as_mut().unwrap().change = None;
    let off = reference::hydroid_autopilot(&cfg, nomoto(sway_yaw(U0)), &sea);
    let e = off.feed(Feed::Adaptive).unwrap().final_estimate.unwrap();
    assert!(e.w0.is_none(), "{e:?}");
    cfg.adaptive.estimate_w0 = true;
    let on = reference::hydroid_autopilot(&cfg, nomoto(sway_yaw(U0)), &sea);
    let e = on.feed(Feed::Adaptive).unwrap().final_estimate.unwrap();
    let (w0, sigma) = e.w0.unwrap();
    let truth = 2.0 * std::f64::consts::PI / 12.0;
    println!("w0 {w0:.4} +- {sigma:.4} (sea {truth:.4}, model 0.7854)");
    // docs/models/nomoto.md: "0.5264 +- 0.0235 rad/s against the sea's 0.5236"
    assert_eq!(format!("{w0:.4} {sigma:.4}"), "0.5264 0.0235");
    assert!((w0 - truth).abs() < 2.0 * sigma, "{w0} {sigma}");
}
