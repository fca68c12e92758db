//! The paper's figures as data and in the report (issue 29, item 5; docs/models/nomoto.md,
//! "The paper's figures"): `hydroid run configs/nomoto.toml` writes autopilot/FEED.csv per
//! closed-loop run, named in results.json; the statistics recomputed from the tables are the
//! reported ones; the ordinary low-pass filter, written here from its difference equation
//! (the second-order Butterworth low-pass by the bilinear transform with a pre-warped cut-off,
//! Oppenheim & Schafer 7.2), reproduces the table's column; the EKF wave filter's heading is
//! closer to the true low-frequency heading than the low-pass filter's; and the report holds
//! the three figures.

use crate::common;

use std::path::Path;

/// The columns of every table of configs/nomoto.toml (both filters run in every loop).
const COLUMNS: [&str; 14] = [
    "time [s]",
    "course_ordered [rad]",
    "heading_reference [rad]",
    "heading_true [rad]",
    "heading_lf_true [rad]",
    "compass [rad]",
    "heading_seen [rad]",
    "heading_ekf [rad]",
    "error_ekf [rad]",
    "heading_lowpass [rad]",
    "error_lowpass [rad]",
    "heading_error [rad]",
    "rudder_command [rad]",
    "rudder [rad]",
];

/// A table: its header and its columns.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Table {
    fn read(path: &Path) -> Table {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let mut lines = text.lines();
        let header = lines.next().unwrap().split(',').map(String::from).collect();
        let rows = lines
            .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
            .collect();
        Table { header, rows }
    }

    fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

fn rms(v: impl IntoIterator<Item = f64>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for x in v {
        sum += x * x;
        n += 1;
    }
    (sum / n as f64).sqrt()
}

/// The second-order Butterworth low-pass at `wf` (rad/s) sampled every `dt`, started at rest
/// on the first input: H(s) = wf^2 / (s^2 + sqrt(2) wf s + wf^2) with s = (2/dt) (1 - z^-1) /
/// (1 + z^-1) and wf pre-warped to (2/dt) tan(wf dt / 2), multiplied out here from the
/// transfer function (not hydroid's code).
fn butterworth(u: &[f64], wf: f64, dt: f64) -> Vec<f64> {
    // with c = 2/dt and W = c tan(wf dt / 2): denominator c^2 (1 - z^-1)^2 + sqrt(2) W c
    // (1 - z^-2) + W^2 (1 + z^-1)^2, numerator W^2 (1 + z^-1)^2
    let c = 2.0 / dt;
    let w = c * (wf * dt / 2.0).tan();
    let r2 = 2f64.sqrt();
    let d0 = c * c + r2 * w * c + w * w;
    let d1 = -2.0 * c * c + 2.0 * w * w;
    let d2 = c * c - r2 * w * c + w * w;
    let n = [w * w / d0, 2.0 * w * w / d0, w * w / d0];
    let (a1, a2) = (d1 / d0, d2 / d0);
    let mut y: Vec<f64> = Vec::with_capacity(u.len());
    for k in 0..u.len() {
        let ui = |j: usize| u[k.saturating_sub(j)];
        let yi = |y: &Vec<f64>, j: usize| if k >= j { y[k - j] } else { u[0] };
        let v = n[0] * ui(0) + n[1] * ui(1) + n[2] * ui(2) - a1 * yi(&y, 1) - a2 * yi(&y, 2);
        y.push(v);
    }
    y
}

/// The bundled frigate in 8 s waves (configs/nomoto.toml): every feed's table holds its
/// run's statistics, the low-pass column is the Butterworth filter of the compass column, and
/// the EKF's heading error is a tenth of the low-pass filter's or less; the table of
/// docs/models/nomoto.md, "The paper's figures", at its printed digits.
#[test]
fn the_autopilot_series_hold_the_runs_statistics_and_both_filters() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = common::run_config(&common::root().join("configs/nomoto.toml"), &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let feeds = r["autopilot"]["feeds"].as_array().unwrap();
    let names: Vec<&str> = feeds.iter().map(|f| f["feed"].as_str().unwrap()).collect();
    assert_eq!(names, ["raw", "filter", "lowpass", "true"]);
    // configs/nomoto.toml's wave frequency (8 s waves, known: a coefficient of the run)
    let w0 = common::named(&r["coefficients"], "w0")["value"]
        .as_f64()
        .unwrap();
    assert!(
        (w0 - 2.0 * std::f64::consts::PI / 8.0).abs() < 1e-11,
        "{w0}"
    );
    let measured: Vec<String> = feeds.iter().map(|f| feed_checked(f, &out, w0)).collect();
    // docs/models/nomoto.md, "The paper's figures", at its printed digits
    assert_eq!(
        measured,
        [
            "raw: EKF 0.0283 deg, LPF 0.5404 deg, heading error 1.979 deg, rudder 3.348 deg, \
             rate 2.249 deg/s",
            "filter: EKF 0.0283 deg, LPF 0.2889 deg, heading error 1.394 deg, rudder 1.120 deg, \
             rate 0.022 deg/s",
            "lowpass: EKF 0.0283 deg, LPF 0.3056 deg, heading error 1.227 deg, rudder 1.191 \
             deg, rate 0.301 deg/s",
            "true: EKF 0.0283 deg, LPF 0.2895 deg, heading error 1.395 deg, rudder 1.119 deg, \
             rate 0.008 deg/s",
        ]
    );
    the_report_holds_the_papers_figures(&out);
    the_same_run_gives_the_same_bytes(dir.path(), &out, &names);
}

/// The statistic `key` of a feed of results.json.
fn stat(feed: &serde_json::Value, key: &str) -> f64 {
    feed[key].as_f64().unwrap()
}

/// One feed's table (its `series`, autopilot/FEED.csv): its columns and length, its run's
/// statistics, both filters; the EKF's error a tenth of the low-pass filter's or less. Returns
/// the feed's row of the docs' table.
fn feed_checked(f: &serde_json::Value, out: &Path, w0: f64) -> String {
    let name = f["feed"].as_str().unwrap();
    assert_eq!(f["series"], format!("autopilot/{name}.csv"));
    let t = Table::read(&out.join(f["series"].as_str().unwrap()));
    assert_eq!(t.header, COLUMNS);
    assert_eq!(t.rows.len(), 6001, "600 s at 10 Hz");
    the_statistics_are_the_tables(name, f, &t);
    the_filters_are_the_tables(name, &t, w0);
    let (ekf, lpf) = (stat(f, "ekf_error_rms"), stat(f, "lowpass_error_rms"));
    assert!(ekf * 10.0 <= lpf, "{name}: EKF {ekf} against LPF {lpf}");
    format!(
        "{name}: EKF {:.4} deg, LPF {:.4} deg, heading error {:.3} deg, rudder {:.3} deg, \
         rate {:.3} deg/s",
        ekf.to_degrees(),
        lpf.to_degrees(),
        stat(f, "heading_error_rms").to_degrees(),
        stat(f, "rudder_rms").to_degrees(),
        stat(f, "rudder_rate_rms").to_degrees()
    )
}

/// The feed `f`'s statistics in results.json recomputed from its table `t` (to 1e-12): the
/// heading error, the rudder and its rate, both filters' errors.
fn the_statistics_are_the_tables(name: &str, f: &serde_json::Value, t: &Table) {
    let get = |k: &str| stat(f, k);
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-12 * b.abs(),
            "{name} {what}: {a} vs {b}"
        )
    };
    // the heading error from the reference: the true low-frequency heading less psi_d
    let lf = t.col("heading_lf_true [rad]");
    let e: Vec<f64> = lf
        .iter()
        .zip(t.col("heading_reference [rad]"))
        .map(|(a, b)| a - b)
        .collect();
    close(rms(e), get("heading_error_rms"), "heading error");
    close(
        rms(t.col("heading_error [rad]")),
        get("heading_error_rms"),
        "column",
    );
    let rudder = t.col("rudder [rad]");
    close(rms(rudder.iter().copied()), get("rudder_rms"), "rudder");
    let rate = rudder.windows(2).map(|w| (w[1] - w[0]) / 0.1);
    close(rms(rate), get("rudder_rate_rms"), "rudder rate");
    // the filters' errors against the true low-frequency heading
    let err = |col: &str| {
        let v = t.col(col);
        rms(v.iter().zip(&lf).map(|(a, b)| a - b))
    };
    close(err("heading_ekf [rad]"), get("ekf_error_rms"), "EKF error");
    close(
        err("heading_lowpass [rad]"),
        get("lowpass_error_rms"),
        "LPF error",
    );
    close(
        rms(t.col("error_lowpass [rad]")),
        get("lowpass_error_rms"),
        "LPF col",
    );
}

/// The feed `name`'s table `t`: its low-pass column is the Butterworth filter (cut-off
/// `w0 / 4`) of its compass column, the heading the autopilot saw is the feed's own, the
/// course ordered steps at 50 s; the largest filter errors of the lowpass feed.
fn the_filters_are_the_tables(name: &str, t: &Table, w0: f64) {
    // the ordinary filter written here from its transfer function, on the compass
    let low = butterworth(&t.col("compass [rad]"), w0 / 4.0, 0.1);
    let worst = low
        .iter()
        .zip(t.col("heading_lowpass [rad]"))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-12,
        "{name}: the low-pass column is off by {worst} rad"
    );
    // the feed's own filter is the heading the autopilot saw
    let own = match name {
        "filter" => Some("heading_ekf [rad]"),
        "lowpass" => Some("heading_lowpass [rad]"),
        "raw" => Some("compass [rad]"),
        _ => None,
    };
    if let Some(own) = own {
        assert_eq!(t.col(own), t.col("heading_seen [rad]"), "{name}");
    }
    // the course ordered: 0 until 50 s, then 10 deg
    let ordered = t.col("course_ordered [rad]");
    assert_eq!(ordered[499], 0.0);
    assert!((ordered[500] - 10f64.to_radians()).abs() < 1e-15);
    if name == "lowpass" {
        // the largest errors: the low-pass filter's lag in the turn, the EKF's start
        let peak = |col: &str| {
            let v = t.col(col);
            let i = (0..v.len())
                .max_by(|a, b| v[*a].abs().total_cmp(&v[*b].abs()))
                .unwrap();
            format!(
                "{:.3} deg at {:.1} s",
                v[i].abs().to_degrees(),
                i as f64 * 0.1
            )
        };
        assert_eq!(
            [peak("error_lowpass [rad]"), peak("error_ekf [rad]")],
            ["0.838 deg at 135.2 s", "0.168 deg at 0.3 s"]
        );
    }
}

/// The same run of configs/nomoto.toml (into `dir`/again) gives the same bytes as `out` in
/// every feed's table.
fn the_same_run_gives_the_same_bytes(dir: &Path, out: &Path, names: &[&str]) {
    let again = dir.join("again");
    let o = common::run_config(&common::root().join("configs/nomoto.toml"), &again, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    for name in names {
        let file = format!("autopilot/{name}.csv");
        let read = |d: &Path| std::fs::read(d.join(&file)).unwrap();
        assert!(read(out) == read(&again), "{file} differs between two runs");
    }
}

/// The three figures as SVG and PNG, linked from report.md and inline in report.html.
fn the_report_holds_the_papers_figures(out: &Path) {
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for name in [
        "autopilot_filter_error",
        "autopilot_course_change",
        "autopilot_rudder",
    ] {
        let svg = std::fs::read_to_string(out.join(format!("plots/{name}.svg"))).unwrap();
        assert!(roxmltree::Document::parse(&svg).is_ok(), "{name}.svg");
        let png = std::fs::read(out.join(format!("plots/{name}.png"))).unwrap();
        assert!(png.starts_with(b"\x89PNG"), "{name}.png");
        assert!(
            md.contains(&format!("](plots/{name}.svg)")),
            "{name} in report.md"
        );
        assert!(html.contains(name), "{name} in report.html");
    }
    assert!(md.contains("#### The paper's figures"));
    assert!(md.contains(
        "| ordinary low-pass filter on the compass | 0.0283 | 0.3056 | autopilot/lowpass.csv |"
    ));
}

/// A cut-off above the compass's Nyquist frequency, or a lowpass feed without a wave
/// frequency to place its cut-off below, is refused naming the key or the reason.
#[test]
fn a_bad_cutoff_is_refused_with_its_key() {
    let path = common::root().join("configs/nomoto.toml");
    for (set, says) in [
        ("autopilot.lowpass_cutoff=40", "autopilot.lowpass_cutoff"),
        ("autopilot.lowpass_cutoff=-1", "autopilot.lowpass_cutoff"),
    ] {
        let e = hydroid::config::load(&path, &[set.to_string()]).unwrap_err();
        assert!(e.to_string().contains(says), "{set}: {e}");
    }
    let o = common::hydroid(&[
        "check",
        "configs/nomoto.toml",
        "--set",
        "autopilot.dt=10",
        "--set",
        "autopilot.lowpass_cutoff=0.5",
    ]);
    assert_ne!(o.status.code(), Some(0));
    let err = common::text(&o.stdout) + &common::text(&o.stderr);
    assert!(err.contains("Nyquist"), "{err}");
}

/// Where the wave filter's model is not the plant (configs/nomoto_adaptive.toml: the 150 m
/// ship_linear plant without a rudder bias, slowed from 8 to 5 m/s at 600 s, steered with the
/// first-order model identified from the nomoto_wave log, its 1 deg bias and 8 m/s indices
/// held), the plain EKF's heading is no closer to the truth than the low-pass filter's; the
/// adaptive filter, which estimates K, 1/T and the bias as it steers, is. The table of
/// docs/models/nomoto.md, "The paper's figures", at its printed digits.
#[test]
fn with_a_plant_unlike_its_model_the_plain_ekf_loses_its_edge() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let feeds = "autopilot.feeds=[\"filter\", \"lowpass\", \"adaptive\"]";
    let config = common::root().join("configs/nomoto_adaptive.toml");
    let o = common::run_config(&config, &out, &[feeds]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let mut measured = Vec::new();
    for f in r["autopilot"]["feeds"].as_array().unwrap() {
        let t = Table::read(&out.join(f["series"].as_str().unwrap()));
        let lf = t.col("heading_lf_true [rad]");
        let seen = t.col("heading_seen [rad]");
        let own = rms(seen.iter().zip(&lf).map(|(a, b)| a - b));
        let deg = |k: &str| f[k].as_f64().unwrap().to_degrees();
        measured.push(format!(
            "{}: EKF {:.4} deg, LPF {:.4} deg, its own {:.4} deg",
            f["feed"].as_str().unwrap(),
            deg("ekf_error_rms"),
            deg("lowpass_error_rms"),
            own.to_degrees()
        ));
    }
    assert_eq!(
        measured,
        [
            "filter: EKF 0.4263 deg, LPF 0.3528 deg, its own 0.4263 deg",
            "lowpass: EKF 0.4464 deg, LPF 0.3523 deg, its own 0.3523 deg",
            "adaptive: EKF 0.4345 deg, LPF 0.3331 deg, its own 0.0636 deg",
        ]
    );
}
