//! Seas and sensors of the autopilot (issue 29, item 4): a closed loop written here from the
//! equations alone, its wave-induced yaw written to a file, and hydroid's closed loop with
//! that file, the same plant, the same gains and the same feeds.
//!
//! The reference: the frigate T r_dot + r = K (delta + b) (Nomoto first order, Fossen 2011,
//! 7.2; K = 0.18 1/s, T = 27 s, Van Amerongen 1982), solved exactly over each sample with the
//! rudder held; the wave yaw a sum of sines shaped by the linear wave-yaw spectrum
//! w^2 / ((w0^2 - w^2)^2 + (2 zeta w0 w)^2) (Fossen 2011, 8.2.1) at 7 s, 1 deg RMS, added to
//! the compass (its exact rate to the gyro); a PID placed on the Nomoto model (K_p = m w_n^2,
//! K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10, m = T/K, d = 1/K; Fossen 2011, PID pole placement for the Nomoto ship) with
//! anti-windup and a rate- and angle-limited rudder; a third-order reference model (a
//! first-order filter cascaded with a mass-damper-spring, Fossen 2011, 10.2.1), all stepped
//! at 10 Hz with fixed Euler sub-steps.

use hydroid::app::pipeline::autopilot::load_seas;
use hydroid::config::autopilot::AutopilotConfig;
use hydroid::dynamics::autopilot::closed_loop::{run, Scenario};
use hydroid::dynamics::autopilot::{ClosedLoop, Feed, Gains, RudderLimits};
use hydroid::model::models::nomoto_wave::NomotoWave;
use hydroid::model::models::Model;
use std::f64::consts::PI;

const K: f64 = 0.18;
const T: f64 = 27.0;
const BIAS: f64 = PI / 180.0; // the rudder angle the ship's asymmetry is worth, rad
const W0: f64 = 2.0 * PI / 7.0;
const ZETA_W: f64 = 0.1;
const WAVE_RMS: f64 = PI / 180.0;
const DT: f64 = 0.1;
const DURATION: f64 = 600.0;
const OMEGA_N: f64 = 0.1;
const ZETA: f64 = 0.9;
const RATE_LIMIT: f64 = 5.0 * PI / 180.0;
const ANGLE_LIMIT: f64 = 35.0 * PI / 180.0;
const COMPASS_NOISE: f64 = 0.1 * PI / 180.0;
const GYRO_NOISE: f64 = 0.01 * PI / 180.0;
const COURSE: f64 = 10.0 * PI / 180.0;
const CHANGE_AT: f64 = 50.0;
const REFERENCE: (f64, f64) = (0.03, 1.0);

/// A small seeded generator (xorshift64*) with Box-Muller normals: the test's own noise.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        (-2.0 * self.uniform().ln()).sqrt() * (2.0 * PI * self.uniform()).cos()
    }
}

/// The sea: sines of the wave-yaw spectrum between w0/2 and 2 w0, random phases and
/// frequencies within their bins, scaled to `WAVE_RMS`. Returns (amplitude, w, phase).
fn sea(noise: &mut Noise) -> Vec<(f64, f64, f64)> {
    let (n, lo, hi) = (60, 0.5 * W0, 2.0 * W0);
    let dw = (hi - lo) / n as f64;
    let spectrum = |w: f64| w * w / ((W0 * W0 - w * w).powi(2) + (2.0 * ZETA_W * W0 * w).powi(2));
    let mut sines: Vec<(f64, f64, f64)> = (0..n)
        .map(|i| {
            let w = lo + dw * (i as f64 + noise.uniform());
            (
                (2.0 * spectrum(w) * dw).sqrt(),
                w,
                2.0 * PI * noise.uniform(),
            )
        })
        .collect();
    let rms = (sines.iter().map(|s| s.0 * s.0 / 2.0).sum::<f64>()).sqrt();
    sines.iter_mut().for_each(|s| s.0 *= WAVE_RMS / rms);
    sines
}

fn wave(sines: &[(f64, f64, f64)], t: f64) -> (f64, f64) {
    sines.iter().fold((0.0, 0.0), |(y, r), (a, w, p)| {
        (y + a * (w * t + p).sin(), r + a * w * (w * t + p).cos())
    })
}

/// Heading error, rudder and rudder-rate RMS of the reference loop fed the raw compass and
/// gyro (`ideal` false) or the ship's true heading and rate (`ideal` true).
fn reference_loop(sines: &[(f64, f64, f64)], ideal: bool) -> (f64, f64, f64) {
    let (m, d) = (T / K, 1.0 / K);
    let kp = m * OMEGA_N * OMEGA_N;
    let kd = 2.0 * ZETA * OMEGA_N * m - d;
    let ki = OMEGA_N * kp / 10.0;
    let mut noise = Noise(0x5EA5);
    let (mut psi, mut r, mut rudder, mut integral) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    // reference model: a = low-passed command, then psi_d'' + 2 z w psi_d' + w^2 psi_d = w^2 a
    let (w, z) = REFERENCE;
    let (mut a, mut psi_d, mut r_d) = (0.0f64, 0.0f64, 0.0f64);
    let n = (DURATION / DT).round() as usize + 1;
    let (mut e2, mut d2, mut rate2) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let t = k as f64 * DT;
        if k > 0 {
            // T r_dot + r = K (delta + b) with the rudder held: exact over the sample
            let r_ss = K * (rudder + BIAS);
            let decay = (-DT / T).exp();
            psi += r_ss * DT + (r - r_ss) * T * (1.0 - decay);
            r = r_ss + (r - r_ss) * decay;
            let command = if t >= CHANGE_AT { COURSE } else { 0.0 };
            let h = DT / 20.0;
            for _ in 0..20 {
                let acc = w * w * (a - psi_d) - 2.0 * z * w * r_d;
                a += h * w * (command - a);
                psi_d += h * r_d;
                r_d += h * acc;
            }
        }
        let (wave_yaw, wave_rate) = wave(sines, t);
        let compass = psi + wave_yaw + COMPASS_NOISE * noise.normal();
        let gyro = r + wave_rate + GYRO_NOISE * noise.normal();
        let (seen, seen_rate) = if ideal { (psi, r) } else { (compass, gyro) };
        let e = psi - psi_d;
        e2 += e * e;
        d2 += rudder * rudder;
        // PID with anti-windup, then the steering gear
        let err = seen - psi_d;
        let wanted = -(kp * err + kd * (seen_rate - r_d) + ki * integral);
        let held = wanted.clamp(-ANGLE_LIMIT, ANGLE_LIMIT);
        if held == wanted {
            integral += err * DT;
        }
        let step = (held - rudder).clamp(-RATE_LIMIT * DT, RATE_LIMIT * DT);
        rudder += step;
        if k + 1 < n {
            rate2 += (step / DT).powi(2);
        }
    }
    let nf = n as f64;
    (
        (e2 / nf).sqrt(),
        (d2 / nf).sqrt(),
        (rate2 / (nf - 1.0)).sqrt(),
    )
}

/// hydroid's configuration for the recorded sea in `dir` (degrees, converted on reading).
fn config(file: &std::path::Path) -> AutopilotConfig {
    toml::from_str(&format!(
        "omega_n = {OMEGA_N}\nzeta = {ZETA}\ncompass_noise = \"0.1 deg\"\n\
         disturbance_file = {file:?}\ndisturbance = \"wave_yaw\"\ndisturbance_unit = \"deg\"\n\
         feeds = [\"raw\", \"differentiated\", \"filter\", \"true\"]\n"
    ))
    .unwrap()
}

/// hydroid's closed loop on the same frigate with the recorded sea, one run per feed.
fn hydroid_loops(cfg: &AutopilotConfig, dir: &std::path::Path) -> Vec<ClosedLoop> {
    let seas = load_seas(cfg, dir).unwrap();
    let m = NomotoWave::build(&NomotoWave::example_vehicle()).unwrap();
    // the plant: delta_0 = -b; the filter's wave model the sea's (q = 4 zeta w0 var)
    let c = m.coefficient_vector(&[
        ("K", K),
        ("inv_T", 1.0 / T),
        ("delta0", -BIAS),
        ("w0", W0),
        ("zeta_w", ZETA_W),
    ]);
    let s = Scenario {
        duration: DURATION,
        dt: DT,
        course_change: COURSE,
        change_at: CHANGE_AT,
        gains: Gains::pole_placement(K, T, OMEGA_N, ZETA).unwrap(),
        reference: REFERENCE,
        limits: RudderLimits {
            angle: ANGLE_LIMIT,
            rate: RATE_LIMIT,
            lag: 0.0,
        },
        compass_noise: COMPASS_NOISE,
        gyro_noise: GYRO_NOISE,
        process_noise: vec![0.0, 0.0, 0.0, 4.0 * ZETA_W * W0 * WAVE_RMS * WAVE_RMS],
        seed: 3,
        rate_noise: None,
        seas,
        orders: Vec::new(),
        adaptive: Default::default(),
        lowpass_cutoff: None,
    };
    cfg.feeds
        .iter()
        .map(|f| run(&m, &c, &s, *f).unwrap())
        .collect()
}

/// The sea's wave yaw at the loop's samples, in degrees, as a table of time and value.
fn write_sea(path: &std::path::Path, sines: &[(f64, f64, f64)], duration: f64) {
    let n = (duration / DT).round() as usize + 1;
    let mut text = String::from("time,wave_yaw\n");
    for k in 0..n {
        let t = k as f64 * DT;
        text += &format!("{t:.1},{:.9}\n", wave(sines, t).0.to_degrees());
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn the_recorded_sea_reproduces_the_reference_and_the_filter_calms_the_rudder() {
    let sines = sea(&mut Noise(29));
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sea.csv");
    write_sea(&file, &sines, DURATION);
    let (raw_e, raw_d, raw_rate) = reference_loop(&sines, false);
    let (true_e, true_d, true_rate) = reference_loop(&sines, true);
    let deg = f64::to_degrees;
    println!(
        "reference raw: {:.3} deg, rudder {:.3} deg, {:.4} deg/s; true: {:.3} deg, {:.3} deg, \
         {:.4} deg/s",
        deg(raw_e),
        deg(raw_d),
        deg(raw_rate),
        deg(true_e),
        deg(true_d),
        deg(true_rate)
    );
    let cfg = config(&file);
    let loops = hydroid_loops(&cfg, dir.path());
    for c in &loops {
        println!(
            "hydroid {}: {:.3} deg, rudder {:.3} deg, {:.4} deg/s",
            c.feed.name(),
            deg(c.heading_error_rms),
            deg(c.rudder_rms),
            deg(c.rudder_rate_rms)
        );
    }
    // docs/models/nomoto.md, "Seas and sensors", its table at the printed digits
    let row = |e: f64, d: f64, r: f64| format!("{:.3} {:.3} {:.4}", deg(e), deg(d), deg(r));
    let mut rows = vec![row(raw_e, raw_d, raw_rate), row(true_e, true_d, true_rate)];
    rows.extend(
        loops
            .iter()
            .map(|c| row(c.heading_error_rms, c.rudder_rms, c.rudder_rate_rms)),
    );
    assert_eq!(
        rows.join("; "),
        "1.458 5.685 4.9391; 0.180 0.925 0.0131; 1.492 5.724 4.9423; 0.978 3.182 4.9787; \
         0.184 0.932 0.0952; 0.180 0.925 0.0131"
    );
    let get = |f: Feed| loops.iter().find(|c| c.feed == f).unwrap();
    let within = |a: f64, b: f64| (a / b - 1.0).abs() <= 0.1;
    let (raw, filter, ideal) = (get(Feed::Raw), get(Feed::Filter), get(Feed::True));
    assert!(within(raw.heading_error_rms, raw_e), "raw heading error");
    assert!(within(raw.rudder_rate_rms, raw_rate), "raw rudder rate");
    assert!(
        within(ideal.heading_error_rms, true_e),
        "true heading error"
    );
    assert!(
        filter.rudder_rate_rms * 10.0 <= raw.rudder_rate_rms,
        "the filter calms the rudder tenfold"
    );
    assert!(filter.heading_error_rms <= 2.0 * ideal.heading_error_rms);
}

#[test]
fn a_short_recording_or_an_unknown_feed_is_refused_with_the_file_or_the_key() {
    let sines = sea(&mut Noise(29));
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("short.csv");
    write_sea(&file, &sines, 100.0);
    let e = load_seas(&config(&file), dir.path())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("short.csv") && e.contains("covers 0 to 100 s") && e.contains("600"),
        "{e}"
    );
    let bad: Result<AutopilotConfig, _> =
        toml::from_str("compass_noise = \"0.1 deg\"\nfeeds = [\"raw\", \"gyro\"]\n");
    let e = bad.unwrap_err().to_string();
    assert!(e.contains("feeds") && e.contains("gyro"), "{e}");
    // through the command line: the key named, before anything runs
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args([
            "check",
            "configs/nomoto.toml",
            "--set",
            "autopilot.feeds=[\"gyro\"]",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("autopilot.feeds"), "{err}");
}
