//! Course keeping in waves (configs/nomoto.toml, docs/models/nomoto.md): twin experiments of
//! the nomoto_wave model, a 20/20 zig-zag of the frigate in waves with a noisy compass, the
//! hybrid EKF identifying K, T and the rudder bias while separating the wave-induced yaw.

use crate::common;

use common::root;
use hydroid::app::simulate::config::{load as load_sim, Manoeuvre};
use hydroid::app::simulate::synth::synthesize;
use hydroid::base::quantity::Quantity;

/// Truth of the bundled log: K = 0.18 1/s, T = 27 s, bias 1 deg.
const K: f64 = 0.18;
const T: f64 = 27.0;

struct Twin {
    /// K, 1/T, delta0 with sigmas.
    estimates: Vec<(String, f64, f64)>,
    /// RMS error of the low-frequency heading psi_L against the truth, rad: smoothed (the
    /// report's traces) and filtered (the online estimate, each sample from the data up to it).
    psi_l_rms: PsiL,
    /// RMS of the wave-induced heading, rad.
    wave_rms: f64,
}

/// RMS errors of psi_L, rad.
#[derive(Clone, Copy)]
struct PsiL {
    smoothed: f64,
    filtered: f64,
}

/// Simulates `sim` (a simulate configuration in configs/simulate) with `w0` and the process
/// noise `q`, writes its log, and identifies it with configs/nomoto.toml (`estimate_w0`: the
/// wave frequency estimated too, starting from the 8 s guess).
fn twin(w0: f64, q: f64, estimate_w0: bool) -> Twin {
    let dir = tempfile::tempdir().unwrap();
    let sim_path = root().join("configs/simulate/nomoto_zigzag_waves.toml");
    let mut sim = load_sim(&sim_path).unwrap();
    sim.config.coefficients.insert("w0".into(), w0);
    if let Manoeuvre::TimeHistory { process_noise, .. } = &mut sim.config.manoeuvre {
        process_noise.insert(Quantity::WaveYaw, q);
    }
    let noisy = synthesize(&sim.config).unwrap();
    let mut clean_cfg = sim.config.clone();
    clean_cfg.noise.sigma.clear();
    let clean = synthesize(&clean_cfg).unwrap();
    // the compass log in the bundled layout
    let mut csv = String::from("\"time (s)\",\"compass (deg)\",\"rudder (deg)\"\n");
    let (time, yaw, rudder) = (
        &noisy[&Quantity::Time],
        &noisy[&Quantity::Yaw],
        &noisy[&Quantity::Rudder],
    );
    for ((t, y), d) in time.iter().zip(yaw).zip(rudder) {
        csv.push_str(&format!("{t},{},{}\n", y.to_degrees(), d.to_degrees()));
    }
    std::fs::write(dir.path().join("log.csv"), csv).unwrap();
    let mut text = std::fs::read_to_string(root().join("configs/nomoto.toml"))
        .unwrap()
        .replace("../cfd_exports/nomoto_zigzag_waves.csv", "log.csv")
        .replace("w0 = 0.785398163397", &format!("w0 = {w0}"));
    if estimate_w0 {
        text = text
            .replace(
                "estimate = [\"K\", \"inv_T\", \"delta0\"]",
                "estimate = [\"K\", \"inv_T\", \"delta0\", \"w0\"]",
            )
            .replace(&format!("w0 = {w0}"), "")
            .replace(
                "delta0 = { initial = 0.0, sigma = 0.05 }",
                "delta0 = { initial = 0.0, sigma = 0.05 }\nw0 = { sigma = 0.5 }",
            );
    }
    let cfg = dir.path().join("nomoto.toml");
    std::fs::write(&cfg, text).unwrap();
    let loaded = hydroid::config::load(&cfg, &[]).unwrap();
    let out = hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    let h = out.result.stages.hekf.as_ref().unwrap();
    let estimates = h
        .coefficients
        .iter()
        .map(|c| (c.name.clone(), c.value, c.sigma.unwrap()))
        .collect();
    // psi_L is state 1 of 4; truth: the clean compass minus the wave yaw (Fossen's form)
    let tr = &h.traces[0];
    let truth: Vec<f64> = clean[&Quantity::Yaw]
        .iter()
        .zip(&clean[&Quantity::WaveYaw])
        .map(|(c, w)| c - w)
        .collect();
    let n = tr.times.len();
    let rms = |states: &[f64]| {
        ((0..n)
            .map(|k| (states[k * 4 + 1] - truth[k]).powi(2))
            .sum::<f64>()
            / n as f64)
            .sqrt()
    };
    let psi_l_rms = PsiL {
        smoothed: rms(tr
            .smoothed
            .as_ref()
            .expect("the smoother is on in configs/nomoto.toml")),
        filtered: rms(&tr.filtered),
    };
    let waves = &clean[&Quantity::WaveYaw];
    let wave_rms = (waves.iter().map(|w| w * w).sum::<f64>() / waves.len() as f64).sqrt();
    Twin {
        estimates,
        psi_l_rms,
        wave_rms,
    }
}

/// A row of the twin table of docs/models/nomoto.md as printed: K, T errors (%), bias error
/// (deg), psi_L RMS error smoothed and filtered (deg), wave yaw amplitude (deg), and the
/// estimated w0 with its sigma (rad/s) where it is estimated.
struct Row {
    k: &'static str,
    t: &'static str,
    bias: &'static str,
    smoothed: &'static str,
    filtered: &'static str,
    amplitude: &'static str,
    w0: Option<&'static str>,
}

/// The targets (K and T within 2 %, the bias within 0.1 deg, the truth within 2
/// sigma, the smoothed psi_L's RMS error under a fifth of the wave yaw's amplitude), and the
/// table's row to its printed digits.
fn check(t: &Twin, label: &str, row: &Row) {
    for (name, v, s) in &t.estimates {
        println!("{label}: {name} = {v:.6} +- {s:.6}");
    }
    let get = |n: &str| t.estimates.iter().find(|e| e.0 == n).unwrap();
    let (_, k, sk) = get("K");
    let (_, inv_t, st) = get("inv_T");
    let (_, bias, sb) = get("delta0");
    let t_est = 1.0 / inv_t;
    assert!(((k - K) / K).abs() < 0.02, "{label}: K {k}");
    assert!(((t_est - T) / T).abs() < 0.02, "{label}: T {t_est}");
    assert!(
        (bias - 1f64.to_radians()).abs() < 0.1f64.to_radians(),
        "{label}: bias {bias}"
    );
    assert!((k - K).abs() <= 2.0 * sk, "{label}: K {k} +- {sk}");
    assert!(
        (inv_t - 1.0 / T).abs() <= 2.0 * st,
        "{label}: 1/T {inv_t} +- {st}"
    );
    assert!(
        (bias - 1f64.to_radians()).abs() <= 2.0 * sb,
        "{label}: bias {bias} +- {sb}"
    );
    // the wave yaw's amplitude: sqrt(2) times its RMS (a sine of that RMS)
    let amplitude = std::f64::consts::SQRT_2 * t.wave_rms;
    let psi_l = t.psi_l_rms;
    println!(
        "{label}: psi_L RMS error smoothed {:.4} deg, filtered {:.4} deg; wave yaw amplitude {:.3} deg",
        psi_l.smoothed.to_degrees(),
        psi_l.filtered.to_degrees(),
        amplitude.to_degrees()
    );
    assert!(psi_l.smoothed < amplitude / 5.0, "{label}: smoothed psi_L");
    let printed = [
        format!("{:+.2}", 100.0 * (k / K - 1.0)),
        format!("{:+.2}", 100.0 * (t_est / T - 1.0)),
        format!("{:+.3}", (bias - 1f64.to_radians()).to_degrees()),
        format!("{:.3}", psi_l.smoothed.to_degrees()),
        format!("{:.3}", psi_l.filtered.to_degrees()),
        format!("{:.2}", amplitude.to_degrees()),
    ];
    let table = [
        row.k,
        row.t,
        row.bias,
        row.smoothed,
        row.filtered,
        row.amplitude,
    ];
    assert_eq!(
        printed, table,
        "{label}: K, T, bias, psi_L smoothed, filtered, amplitude"
    );
    if let Some(w0) = row.w0 {
        let (_, w, s) = get("w0");
        assert_eq!(format!("{w:.3} ± {s:.3}"), w0, "{label}: w0");
    }
}

#[test]
fn a_zigzag_in_8_s_waves_gives_k_t_and_the_bias_and_the_low_frequency_heading() {
    let w0 = 2.0 * std::f64::consts::PI / 8.0;
    let row = Row {
        k: "-0.03",
        t: "-0.05",
        bias: "+0.002",
        smoothed: "0.075",
        filtered: "0.414",
        amplitude: "1.37",
        w0: None,
    };
    check(&twin(w0, 9.6e-5, false), "8 s waves", &row);
}

/// Waves of 5 s and of 20 s period (a wave yaw of about 1 deg each), the wave frequency
/// estimated (by the innovations' likelihood, docs/hekf.md), starting where the model reads it
/// from the compass spectrum.
#[test]
fn short_and_long_waves_with_the_wave_frequency_estimated() {
    let rows = [
        Row {
            k: "-0.03",
            t: "-0.04",
            bias: "+0.002",
            smoothed: "0.078",
            filtered: "0.295",
            amplitude: "1.39",
            w0: Some("1.266 ± 0.013"),
        },
        Row {
            k: "-0.02",
            t: "+0.01",
            bias: "-0.006",
            smoothed: "0.080",
            filtered: "0.460",
            amplitude: "1.29",
            w0: Some("0.301 ± 0.016"),
        },
    ];
    for (period, row) in [5.0, 20.0].into_iter().zip(&rows) {
        let w0 = 2.0 * std::f64::consts::PI / period;
        let q = 4.0 * 0.1 * w0 * 1f64.to_radians().powi(2);
        let t = twin(w0, q, true);
        let label = format!("{period} s waves");
        check(&t, &label, row);
        let (_, w, s) = t.estimates.iter().find(|e| e.0 == "w0").unwrap();
        println!("{label}: w0 {w:.4} +- {s:.4}, truth {w0:.4}");
        // measured 2026-11-28: 5 s +0.7 % (z +0.72), 20 s -4.3 % (z -0.84; waves this long
        // overlap the zig-zag's own frequencies; appended to the filter's state, 2026-11-27:
        // -8.5 %, z -1.65)
        assert!(
            ((w - w0) / w0).abs() < 0.1 && (w - w0).abs() < 2.0 * s,
            "{label}: w0 {w}, truth {w0}"
        );
    }
}

/// A compass log with the rudder held amidships: nothing identifies K, and the run says so,
/// while the filter still gives the low-frequency heading, finite everywhere.
#[test]
fn a_log_without_rudder_action_is_reported_and_still_filtered() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(root().join("cfd_exports/nomoto_zigzag_waves.csv")).unwrap();
    let mut csv = String::new();
    for (i, line) in src.lines().enumerate() {
        if i == 0 {
            csv.push_str(line);
        } else {
            let mut cells: Vec<&str> = line.split(',').collect();
            cells[2] = "0";
            csv.push_str(&cells.join(","));
        }
        csv.push('\n');
    }
    std::fs::write(dir.path().join("log.csv"), csv).unwrap();
    let text = std::fs::read_to_string(root().join("configs/nomoto.toml"))
        .unwrap()
        .replace("../cfd_exports/nomoto_zigzag_waves.csv", "log.csv");
    let cfg = dir.path().join("nomoto.toml");
    std::fs::write(&cfg, text).unwrap();
    let loaded = hydroid::config::load(&cfg, &[]).unwrap();
    let out = hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    assert!(
        out.result
            .warnings
            .iter()
            .any(|w| w.message.contains("the rudder does not move in this run")),
        "{:?}",
        out.result.warnings
    );
    // the autopilot cannot be tuned from an unidentified K: said, and the run stands
    assert!(out
        .result
        .warnings
        .iter()
        .any(|w| w.stage == "autopilot" && w.message.contains("was not run")));
    let h = out.result.stages.hekf.as_ref().unwrap();
    let tr = &h.traces[0];
    assert!(tr.filtered.iter().all(|v| v.is_finite()));
    assert!(h
        .coefficients
        .iter()
        .all(|c| c.value.is_finite() && c.sigma.is_some_and(f64::is_finite)));
}

/// The bundled run's autopilot (configs/nomoto.toml [autopilot]): fed the wave filter, the
/// rudder rate RMS falls tenfold at least against the raw compass and gyro, the heading kept
/// no worse than 20 % (the paper's result), on the console and in results.json.
#[test]
fn the_bundled_autopilot_calms_the_rudder_with_the_filtered_heading() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = common::hydroid(&["run", "configs/nomoto.toml", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let console = common::text(&o.stdout);
    assert!(
        console.contains("wave filter (psi_L, r_L): heading error RMS"),
        "{console}"
    );
    let r = common::json(&out.join("results.json"));
    let a = &r["autopilot"];
    let feed = |name: &str| {
        a["feeds"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["feed"] == name)
            .unwrap()
    };
    let (raw, filtered) = (feed("raw"), feed("filter"));
    let get = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap();
    assert!(
        get(filtered, "rudder_rate_rms") <= 0.1 * get(raw, "rudder_rate_rms"),
        "{a}"
    );
    assert!(
        get(filtered, "heading_error_rms") <= 1.2 * get(raw, "heading_error_rms"),
        "{a}"
    );
    let schema = common::json(&root().join("docs/results.schema.json"));
    let validator = jsonschema::draft202012::new(&schema).unwrap();
    assert!(validator.is_valid(&r));
    // docs/models/nomoto.md, "The autopilot", at its printed digits (rates and errors RMS)
    let deg = |v: &serde_json::Value, k: &str| get(v, k).to_degrees();
    assert_eq!(
        format!(
            "K = {:.4} 1/s and T = {:.2} s give K_p = {:.3}, K_d = {:.2} s, K_i = {:.4} 1/s; raw \
             {:.2} deg/s with {:.2} deg; filtered {:.3} deg/s with {:.2} deg",
            get(a, "k"),
            get(a, "t"),
            get(&a["gains"], "kp"),
            get(&a["gains"], "kd"),
            get(&a["gains"], "ki"),
            deg(raw, "rudder_rate_rms"),
            deg(raw, "heading_error_rms"),
            deg(filtered, "rudder_rate_rms"),
            deg(filtered, "heading_error_rms")
        ),
        "K = 0.1799 1/s and T = 26.99 s give K_p = 0.375, K_d = 7.94 s, K_i = 0.0019 1/s; raw \
         2.25 deg/s with 1.98 deg; filtered 0.022 deg/s with 1.39 deg"
    );
    // docs/models/nomoto.md, "The bundled example": its table at the printed digits
    let c = |name: &str| {
        let c = common::named(&r["coefficients"], name);
        (c["value"].as_f64().unwrap(), c["sigma"].as_f64().unwrap())
    };
    let ((k, sk), (inv_t, st), (d0, sd)) = (c("K"), c("inv_T"), c("delta0"));
    assert_eq!(
        format!(
            "K {k:.4} ± {sk:.4}; 1/T {inv_t:.5} ± {st:.5} (T = {:.2} ± {:.2} s); delta0 {:.3} ± \
             {:.3} deg",
            1.0 / inv_t,
            st / (inv_t * inv_t),
            d0.to_degrees(),
            sd.to_degrees()
        ),
        "K 0.1799 ± 0.0011; 1/T 0.03705 ± 0.00029 (T = 26.99 ± 0.21 s); delta0 1.002 ± 0.044 deg"
    );
}

/// Bad autopilot and process-noise values are named with their key (and line).
#[test]
fn bad_autopilot_and_process_noise_values_name_their_keys() {
    let o = common::hydroid(&[
        "check",
        "configs/nomoto.toml",
        "--set",
        "autopilot.omega_n=-1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(common::text(&o.stderr).contains("autopilot.omega_n"));
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(root().join("configs/simulate/nomoto_zigzag_waves.toml"))
        .unwrap()
        .replace("../../cfd_exports/", "");
    for (bad, key) in [
        ("wave_yaw = -1.0", "manoeuvre.process_noise.wave_yaw"),
        ("rudder = 1e-4", "manoeuvre.process_noise.rudder"),
    ] {
        let cfg = dir.path().join("bad.toml");
        std::fs::write(&cfg, src.replace("wave_yaw = 9.6e-5", bad)).unwrap();
        let o = common::hydroid(&["simulate", cfg.to_str().unwrap()]);
        let err = common::text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains(key) && err.contains("bad.toml:"),
            "{bad}: {err}"
        );
    }
}
