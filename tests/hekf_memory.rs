//! Long runs and memory: `hekf.decimate`, the memory check before the filter starts, and
//! (ignored by the plain `cargo test`, run by .ci/run) the peak memory of a run of a million
//! rows.

mod common;

use common::{bundled_config_text, hydroid, json, named, root, run_example, text};
use hydroid::stages::hekf::memory::{self, Demand};

/// Rows of the bundled example's HEKF runs: the paper manoeuvre (fit), the validation turn.
fn bundled_demand() -> Demand {
    Demand {
        rows: 2001 + 501,
        fit_rows: vec![2001],
        states: 6,
    }
}

#[test]
fn decimation_uses_one_sample_in_n_and_says_so() {
    let run = run_example(&["--set", "hekf.decimate=4"]);
    let (out, o) = (&run.out, &run.output);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let r = json(&out.join("results.json"));
    let schema = json(&root().join("docs/results.schema.json"));
    let validator = jsonschema::draft202012::new(&schema).expect("the schema is valid");
    let errors: Vec<String> = validator.iter_errors(&r).map(|e| e.to_string()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    let h = &r["stages"]["hekf"];
    assert_eq!(h["settings"]["decimate"], 4);
    let run = &h["runs"][0];
    assert_eq!(run["samples"], 501, "2001 rows, one in 4 from the first");
    assert!((run["mean_dt"].as_f64().unwrap() - 0.04).abs() < 1e-9);
    assert!(
        run["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["message"]
                .as_str()
                .unwrap()
                .contains("one sample in 4 of the 2001")),
        "{run}"
    );
    // the estimates are still close to the full-rate run's (truth Yvd -23.626)
    let yvd = named(&h["coefficients"], "Yvd")["value"].as_f64().unwrap();
    assert!((yvd + 23.6).abs() < 2.0, "Yvd {yvd}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("one sample in 4 of each run used (hekf.decimate)"));
    // the smoothed estimate is drawn at the samples the filter used
    let states = std::fs::read_to_string(out.join("plots/states_fit_1.svg")).unwrap();
    assert!(states.contains("smoothed estimate"));
}

#[test]
fn a_run_over_its_memory_limit_stops_before_the_filter_with_the_setting_that_fits() {
    let d = bundled_demand();
    // room for one sample in 3, not for one in 2
    let limit = d.bytes(3, true);
    assert!(d.bytes(2, true) > limit);
    let set = format!("hekf.memory_limit={limit} B");
    let run = run_example(&["--set", &set]);
    let (out, o) = (&run.out, &run.output);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "a configuration error: {err}");
    assert!(err.contains("configs/spheroid.toml"), "{err}");
    assert!(err.contains("set in hekf.memory_limit"), "{err}");
    assert!(err.contains("`hekf.decimate = 3`"), "{err}");
    assert!(err.contains(&memory::size(d.bytes(1, true))), "{err}");
    assert!(!out.exists(), "nothing written");
    // `hydroid check` says the same, and the setting offered passes
    let c = hydroid(&["check", "configs/spheroid.toml", "--set", &set]);
    assert_eq!(c.status.code(), Some(2));
    assert!(
        text(&c.stdout).contains("`hekf.decimate = 3`")
            || text(&c.stderr).contains("`hekf.decimate = 3`")
    );
    let ok = hydroid(&[
        "check",
        "configs/spheroid.toml",
        "--set",
        &set,
        "--set",
        "hekf.decimate=3",
    ]);
    assert_eq!(ok.status.code(), Some(0), "{}", text(&ok.stderr));
}

#[test]
fn bad_memory_settings_are_configuration_errors() {
    let o = hydroid(&[
        "check",
        "configs/spheroid.toml",
        "--set",
        "hekf.memory_limit=lots",
        "--set",
        "hekf.decimate=0",
    ]);
    let all = text(&o.stdout) + &text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{all}");
    assert!(
        all.contains(
            "hekf.memory_limit: (from --set hekf.memory_limit=lots) 'lots' is not a memory size"
        ),
        "{all}"
    );
    assert!(
        all.contains("hekf.decimate: (from --set hekf.decimate=0) must be between 1"),
        "{all}"
    );
}

/// Peak resident memory of this process so far, bytes (Linux).
fn peak_rss() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line[6..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// Set in the child process of [`the_estimate_is_within_a_factor_1_4_of_the_measured_peak`]:
/// `CONFIG|OUT|DECIMATE`, the run it makes and measures.
const CHILD: &str = "HYDROID_MEMORY_ESTIMATE_RUN";

/// Overrides of the measured runs: one pass keeps the test quick in a debug build without
/// changing what is held per row or per sample (earlier passes keep bounded histories), so
/// the estimate does not depend on it.
const QUICK: [&str; 2] = ["hekf.passes=1", "hekf.memory_limit=\"1 TB\""];

/// The child: the whole run (stages, report with figures) in this process, then its peak
/// resident memory on stdout.
fn measured_child(spec: &str) {
    let mut parts = spec.split('|');
    let (Some(config), Some(out), Some(decimate)) = (parts.next(), parts.next(), parts.next())
    else {
        panic!("{CHILD}={spec}: expected CONFIG|OUT|DECIMATE");
    };
    let mut set: Vec<String> = QUICK.iter().map(|s| s.to_string()).collect();
    set.push(format!("hekf.decimate={decimate}"));
    let loaded = hydroid::config::load(std::path::Path::new(config), &set).unwrap();
    let staging = hydroid::io::output::Staging::new(std::path::Path::new(out)).unwrap();
    let output =
        hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    hydroid::app::report::write(&staging, &loaded, &output).unwrap();
    staging.commit().unwrap();
    println!("peak_bytes={}", peak_rss().unwrap_or(0));
}

/// Issue 24, item 8: the memory estimate the run is checked against lies within a factor 1.4
/// of the peak resident memory a run takes, measured for two decimations of a 100,000-row
/// manoeuvre (the HEKF alone, report and figures included), each run in a fresh process.
/// Before, it was 1.44 times the peak at this size, and at a million rows left no decimation
/// within a 600 MB limit that one sample in 10 met with 90 MB to spare.
#[test]
fn the_estimate_is_within_a_factor_1_4_of_the_measured_peak() {
    if let Ok(spec) = std::env::var(CHILD) {
        measured_child(&spec);
        return;
    }
    if peak_rss().is_none() {
        return; // not Linux: no VmHWM to measure
    }
    let dir = tempfile::tempdir().unwrap();
    let csv = simulated_turn(dir.path(), "1000.0", "turn_100k.csv");
    // the HEKF alone, the polar and surge stages' coefficients given (no consider passes)
    let exports = root().join("cfd_exports/turn_paper.csv");
    let text_in = bundled_config_text().replace(exports.to_str().unwrap(), csv.to_str().unwrap());
    let (polar, hekf) = (
        text_in.find("[polar]").unwrap(),
        text_in.find("[hekf]").unwrap(),
    );
    let cfg = format!(
        "{}[coefficients]\nXuu = -1.33\nXuv = 0.44\nXvv = -5.38\nYvv = -0.44\nYuvd = 1.33\n\
         Yuvl = -16.31\nNuvl = 13.43\n\n{}",
        &text_in[..polar],
        &text_in[hekf..]
    );
    let cfg_path = dir.path().join("run.toml");
    std::fs::write(&cfg_path, cfg).unwrap();
    let rows = 100_001;
    let demand = Demand {
        rows: rows + 501,
        fit_rows: vec![rows],
        states: 6,
    };
    let mut peaks = Vec::new();
    for decimate in [5, 50] {
        let out = dir.path().join(format!("out{decimate}"));
        let spec = format!("{}|{}|{decimate}", cfg_path.display(), out.display());
        let o = std::process::Command::new(std::env::current_exe().unwrap())
            .args([
                "the_estimate_is_within_a_factor_1_4_of_the_measured_peak",
                "--exact",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD, &spec)
            .output()
            .unwrap();
        let said = text(&o.stdout);
        assert!(o.status.success(), "{said}{}", text(&o.stderr));
        let peak: u64 = said
            .split("peak_bytes=")
            .nth(1)
            .and_then(|v| v.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no peak in: {said}"));
        let estimate = demand.bytes(decimate, true);
        let ratio = estimate as f64 / peak as f64;
        println!(
            "decimate {decimate}: peak {}, estimate {}, estimate / peak {ratio:.2}",
            memory::size(peak),
            memory::size(estimate)
        );
        // within a factor 1.4 (the figures before issue 24 gave 1.44 at this size; the estimate
        // is fitted to release builds, whose peaks are higher than this test binary's)
        assert!(
            (0.8..=1.4).contains(&ratio),
            "decimate {decimate}: estimate {} against a measured peak of {}",
            memory::size(estimate),
            memory::size(peak)
        );
        peaks.push((decimate, peak));
    }
    // at a limit between the two peaks, the decimation offered is one that fits
    let (_, low) = peaks[1];
    let limit = memory::Supply {
        bytes: demand.bytes(50, true).max(low) + 1,
        source: "set in hekf.memory_limit".into(),
    };
    if let Err(e) = memory::check(&demand, 1, true, &limit) {
        assert!(e.contains("`hekf.decimate = "), "{e}");
    }
}

/// The figure: a run of a million rows (the paper manoeuvre's turn continued for
/// 10,000 s at 10 ms) with the bundled configuration, smoother on, in under 2 GB
/// (docs/performance.md, "Memory"). About 3.5 minutes of CPU in the test build (peak 524 MB
/// there, 2026-11-26), so ignored by the plain `cargo test` and run by .ci/run as its own
/// step:
///
///     cargo test --test hekf_memory -- --ignored --nocapture
#[test]
#[ignore = "3.5 min of CPU in the test build; .ci/run runs it"]
fn a_million_rows_run_in_under_2_gb() {
    let dir = tempfile::tempdir().unwrap();
    let csv = simulated_turn(dir.path(), "10000.0", "turn_1m.csv");
    let exports = root().join("cfd_exports/turn_paper.csv");
    let cfg = bundled_config_text().replace(exports.to_str().unwrap(), csv.to_str().unwrap());
    let cfg_path = dir.path().join("run.toml");
    std::fs::write(&cfg_path, cfg).unwrap();

    let start = std::time::Instant::now();
    let before = peak_rss().unwrap_or(0);
    let loaded = hydroid::config::load(&cfg_path, &[]).unwrap();
    let staging = hydroid::io::output::Staging::new(&dir.path().join("out")).unwrap();
    let output =
        hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent).unwrap();
    hydroid::app::report::write(&staging, &loaded, &output).unwrap();
    staging.commit().unwrap();
    let peak = peak_rss().unwrap_or(0);
    let h = output.result.stages.hekf.as_ref().unwrap();
    let rows = h.runs[0].samples;
    println!(
        "{rows} rows: {:.1} s, peak RSS {} (before the run {}), {:.0} bytes per row",
        start.elapsed().as_secs_f64(),
        memory::size(peak),
        memory::size(before),
        peak as f64 / rows as f64
    );
    assert_eq!(rows, 1_000_001);
    assert!(peak < 2_000_000_000, "peak {}", memory::size(peak));
    // the estimate the run was checked against lies above what it took
    let demand = Demand {
        rows: rows + 501,
        fit_rows: vec![rows],
        states: 6,
    };
    assert!(demand.bytes(1, true) > peak);
}

/// The bundled paper turn simulated for `seconds` (as written in the TOML) into `dir/name`
/// (100 rows per second).
fn simulated_turn(dir: &std::path::Path, seconds: &str, name: &str) -> std::path::PathBuf {
    let sim = std::fs::read_to_string(root().join("configs/simulate/turn_paper.toml"))
        .unwrap()
        .replace("duration = 20.0", &format!("duration = {seconds}"));
    let sim_path = dir.join("sim.toml");
    std::fs::write(&sim_path, sim).unwrap();
    let csv = dir.join(name);
    let o = hydroid(&[
        "simulate",
        sim_path.to_str().unwrap(),
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    csv
}

/// docs/hekf.md, "Long runs and memory": the estimates for the bundled configuration pointed at
/// a million-row manoeuvre (docs/performance.md's run_1m.toml: that fit run and the 501-row
/// validation run), at its printed digits: 747 MB, over a 700 MB limit, with one sample in 2
/// (651 MB) or the smoother off (699 MB) offered; at a 600 MB limit one sample in 5 (594 MB).
#[test]
fn the_estimates_docs_hekf_prints_for_a_million_rows() {
    let demand = Demand {
        rows: 1_000_001 + 501,
        fit_rows: vec![1_000_001],
        states: 6,
    };
    let at = |megabytes: u64| {
        let limit = memory::Supply {
            bytes: megabytes * 1_000_000,
            source: "set in hekf.memory_limit".into(),
        };
        memory::check(&demand, 1, true, &limit).unwrap_err()
    };
    assert_eq!(
        at(700),
        "the run would need about 747 MB of memory (1000001 filter samples of 1 run, smoother \
         on), more than the 700 MB set in hekf.memory_limit: set `hekf.decimate = 2` (one sample \
         in 2, about 651 MB) or `hekf.smoother = false` (about 699 MB)"
    );
    let e = at(600);
    assert!(
        e.contains("set `hekf.decimate = 5` (one sample in 5, about 594 MB)"),
        "{e}"
    );
}
