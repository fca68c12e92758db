//! The filter forms of `hekf.filter` (docs/hekf.md, "Filter forms") on the bundled Nomoto
//! log (truth K = 0.18 1/s, T = 27 s, bias 1 deg; docs/models/nomoto.md): the paper's
//! discrete Euler EKF (configs/nomoto_paper.toml) and the continuous Kalman-Bucy filter.

use crate::common;

use common::root;
use hydroid::numerics::estimation::FilterKind;
use hydroid::stages::hekf::HekfResult;

const K: f64 = 0.18;
const T: f64 = 27.0;

/// Writes `text` (a configuration for the bundled log) into `dir`, the log's path made
/// absolute.
fn write_config(dir: &std::path::Path, text: &str) -> std::path::PathBuf {
    let log = root().join("cfd_exports/nomoto_zigzag_waves.csv");
    let text = text.replace(
        "../cfd_exports/nomoto_zigzag_waves.csv",
        log.to_str().unwrap(),
    );
    let cfg = dir.join("filter.toml");
    std::fs::write(&cfg, text).unwrap();
    cfg
}

/// Runs `text` (a configuration for the bundled log) and returns the HEKF result.
fn run(text: &str) -> HekfResult {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), text);
    let loaded = hydroid::config::load(&cfg, &[]).unwrap();
    let out = hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    out.result.stages.hekf.clone().unwrap()
}

fn estimate(h: &HekfResult, name: &str) -> (f64, f64) {
    let c = h.coefficients.iter().find(|c| c.name == name).unwrap();
    (c.value, c.sigma.unwrap())
}

/// A column of docs/models/nomoto.md's table "Results on the bundled log" as it prints it:
/// K (error), 1/T, T (error), delta0.
fn column(h: &HekfResult) -> [String; 4] {
    let (k, sk) = estimate(h, "K");
    let (inv_t, st) = estimate(h, "inv_T");
    let (bias, sb) = estimate(h, "delta0");
    [
        format!("{k:.5} ± {sk:.5} ({:+.2} %)", 100.0 * (k / K - 1.0)),
        format!("{inv_t:.6} ± {st:.6}"),
        format!(
            "{:.2} s ({:+.2} %)",
            1.0 / inv_t,
            100.0 * (1.0 / (inv_t * T) - 1.0)
        ),
        format!("{:.4} ± {:.3} deg", bias.to_degrees(), sb.to_degrees()),
    ]
}

/// The default (hybrid) filter's column of docs/models/nomoto.md's table.
#[test]
fn the_hybrid_filter_gives_its_column_of_the_docs() {
    let h = run(&nomoto_without_autopilot());
    assert_eq!(h.settings.filter, FilterKind::Hybrid);
    assert_eq!(
        column(&h),
        [
            "0.17994 ± 0.00108 (-0.03 %)",
            "0.037055 ± 0.000290",
            "26.99 s (-0.05 %)",
            "1.0023 ± 0.044 deg"
        ]
    );
}

/// The bundled configuration without its autopilot (not what is tested here).
fn nomoto_without_autopilot() -> String {
    let text = std::fs::read_to_string(root().join("configs/nomoto.toml")).unwrap();
    text.split("# The autopilot tuned")
        .next()
        .unwrap()
        .to_string()
}

/// configs/nomoto_paper.toml: the paper's discrete EKF, its wave model and random walks on
/// K, 1/T and the bias give K and T within 2 % of the truth of the log (simulated with
/// Fossen's wave model, which the paper's form only approximates; measured: -0.61 % and
/// -0.76 %), the bias within 0.1 deg, each within 2 sigma.
#[test]
fn the_papers_discrete_filter_gives_k_and_t() {
    let text = std::fs::read_to_string(root().join("configs/nomoto_paper.toml")).unwrap();
    let h = run(&text);
    assert_eq!(h.settings.filter, FilterKind::Discrete);
    assert_eq!(h.settings.substeps, 1, "one Euler step per sample");
    let (k, sk) = estimate(&h, "K");
    let (inv_t, st) = estimate(&h, "inv_T");
    let (bias, sb) = estimate(&h, "delta0");
    println!(
        "discrete: K = {k:.5} +- {sk:.5}, T = {:.3} (1/T {inv_t:.6} +- {st:.6}), bias = {:.4} \
         +- {:.4} deg",
        1.0 / inv_t,
        bias.to_degrees(),
        sb.to_degrees()
    );
    assert!(((k - K) / K).abs() < 0.02, "K {k}");
    assert!(((1.0 / inv_t - T) / T).abs() < 0.02, "T {}", 1.0 / inv_t);
    assert!(
        (bias - 1f64.to_radians()).abs() < 0.1f64.to_radians(),
        "bias {}",
        bias.to_degrees()
    );
    assert!((k - K).abs() <= 2.0 * sk, "K {k} +- {sk}");
    assert!((inv_t - 1.0 / T).abs() <= 2.0 * st, "1/T {inv_t} +- {st}");
    assert!(
        (bias - 1f64.to_radians()).abs() <= 2.0 * sb,
        "bias {bias} +- {sb}"
    );
    assert!(h.traces[0].smoothed.is_some(), "the smoother runs on Phi");
    // docs/models/nomoto.md's table at its printed digits
    assert_eq!(
        column(&h),
        [
            "0.17872 ± 0.00152 (-0.71 %)",
            "0.037363 ± 0.000367",
            "26.76 s (-0.87 %)",
            "1.0128 ± 0.057 deg"
        ]
    );
}

/// The continuous (Kalman-Bucy) filter on configs/nomoto.toml: the truth within 2 sigma, no
/// smoother (nor smoothed columns in the state series), and the result says so.
#[test]
fn the_continuous_filter_recovers_the_truth_within_two_sigma() {
    let text = nomoto_without_autopilot().replace(
        "model = \"nomoto_wave\"",
        "model = \"nomoto_wave\"\nfilter = \"continuous\"",
    );
    let h = run(&text);
    assert_eq!(h.settings.filter, FilterKind::Continuous);
    assert!(!h.settings.smoother);
    assert!(h.traces[0].smoothed.is_none());
    assert!(h.tuning.iter().any(|t| t.contains("no smoother")));
    // its state series has the filtered states only, the compass named as the model's output
    let table = h.traces[0].states.as_ref().expect("a state series");
    assert!(!table.columns.iter().any(|c| c.contains("_smoothed")));
    assert!(table
        .columns
        .iter()
        .any(|c| c == "psi_L_filtered_sigma [rad]"));
    assert!(table
        .columns
        .iter()
        .any(|c| c == "compass_innovation_sigma [rad]"));
    assert_eq!(table.spool.rows(), h.runs[0].samples);
    let truth = [("K", K), ("inv_T", 1.0 / T), ("delta0", 1f64.to_radians())];
    for (name, want) in truth {
        let (v, s) = estimate(&h, name);
        println!("continuous: {name} = {v:.6} +- {s:.6} (truth {want:.6})");
        assert!(
            (v - want).abs() <= 2.0 * s,
            "{name}: {v} +- {s}, truth {want}"
        );
    }
    let (k, _) = estimate(&h, "K");
    assert!(((k - K) / K).abs() < 0.02, "K {k}");
    // docs/models/nomoto.md's table at its printed digits
    assert_eq!(
        column(&h),
        [
            "0.18043 ± 0.00109 (+0.24 %)",
            "0.036884 ± 0.000288",
            "27.11 s (+0.41 %)",
            "1.0008 ± 0.044 deg"
        ]
    );
}

/// `hekf.filter` takes hybrid, discrete or continuous; anything else is a configuration
/// problem naming the key and the allowed values.
#[test]
fn an_unknown_filter_names_the_key_and_the_choices() {
    let dir = tempfile::tempdir().unwrap();
    let text = nomoto_without_autopilot().replace(
        "model = \"nomoto_wave\"",
        "model = \"nomoto_wave\"\nfilter = \"euler\"",
    );
    let cfg = write_config(dir.path(), &text);
    let e = hydroid::config::load(&cfg, &[]).unwrap_err().to_string();
    assert!(e.contains("hekf.filter"), "{e}");
    for choice in ["hybrid", "discrete", "continuous"] {
        assert!(e.contains(choice), "{e}");
    }
}
