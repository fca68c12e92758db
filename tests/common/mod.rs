//! Helpers shared by the integration tests: in-memory records and the paper's vehicle; the
//! `hydroid` binary run from the repository or a folder, its output as text or JSON; the
//! bundled example copied into a temporary folder or run into one.
#![allow(dead_code)]

pub mod accuracy;
pub mod parallel;
pub mod ship150_loop;

use hydroid::app::plan::{Plan, Settings};
use hydroid::base::progress::Silent;
use hydroid::base::quantity::Quantity;
use hydroid::config::{FluidConfig, VehicleConfig};
use hydroid::io::formats::Format;
use hydroid::io::record::Record;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A record named `name` with the given channels and constants (SI).
pub fn record(
    name: &str,
    channels: &[(Quantity, Vec<f64>)],
    constants: &[(Quantity, f64)],
) -> Record {
    let rows = channels.first().map_or(0, |c| c.1.len());
    Record {
        name: name.to_string(),
        source: PathBuf::from(format!("{name}.csv")),
        format: Format::Delimited,
        channels: channels.iter().cloned().collect(),
        constants: constants.iter().copied().collect(),
        units: BTreeMap::new(),
        columns: BTreeMap::new(),
        lines: (2..rows + 2).collect(),
        meta: Vec::new(),
        warnings: Vec::new(),
        resolution: Default::default(),
        between: Default::default(),
    }
}

/// The paper's spheroid (Table 1) with the paper's reference quantities: A_ref = pi b^2,
/// moment reference length 1 m (C_M referred to A_f only).
pub fn vehicle() -> VehicleConfig {
    VehicleConfig {
        name: "spheroid".into(),
        mass: 50.0,
        length: 1.2,
        diameter: Some(0.2),
        ixx: None,
        iyy: Some(3.7),
        izz: 3.7,
        reference_area: std::f64::consts::PI * 0.1 * 0.1,
        reference_length: 1.0,
        buoyancy: None,
        bg: None,
        scale: None,
        particulars: Default::default(),
        yaw_moment: Default::default(),
    }
}

/// Sea water as in the paper (Table 1).
pub fn fluid() -> FluidConfig {
    FluidConfig {
        rho: 1025.0,
        mu: 0.0009,
    }
}

/// `x` rounds to `expected` at four significant figures (the paper's tables).
#[track_caller]
pub fn four_figures(x: f64, expected: f64) {
    let half_unit = 0.5 * 10f64.powf(expected.abs().log10().floor() - 3.0);
    assert!(
        (x - expected).abs() <= half_unit * (1.0 + 1e-9),
        "{x} does not round to {expected}"
    );
}

/// The repository's root: the bundled example's configs/ and cfd_exports/ are there.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// configs/nomoto_ship150.toml for a compass log `log.csv` beside it and the output folder
/// `out`; `calm`: a calm sea read by an exact compass (a small wave-yaw forcing and compass
/// noise keep the filter's gain finite).
pub fn nomoto_ship150_config(calm: bool) -> String {
    let cfg = std::fs::read_to_string(root().join("configs/nomoto_ship150.toml"))
        .unwrap()
        .replace("../cfd_exports/ship150_nomoto_waves.csv", "log.csv")
        .replace("../out/nomoto_ship150", "out");
    if !calm {
        return cfg;
    }
    let cfg = cfg
        .replace(
            "process_noise = { psi_H = 9.6e-5 }",
            "process_noise = { psi_H = 1e-9 }",
        )
        .replace(
            "noise = { yaw = \"0.1 deg\" }",
            "noise = { yaw = \"0.01 deg\" }",
        );
    assert!(cfg.contains("log.csv") && cfg.contains("1e-9") && cfg.contains("0.01 deg"));
    cfg
}

/// Runs the `hydroid` binary in `dir` with `args`.
pub fn hydroid_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the hydroid binary runs")
}

/// Runs the `hydroid` binary in the repository's root with `args`.
pub fn hydroid(args: &[&str]) -> Output {
    hydroid_in(&root(), args)
}

/// `hydroid calibrate OUT --replicas N --json -q` plus `extra`.
pub fn calibrate(out: &Path, replicas: usize, extra: &[&str]) -> Output {
    let n = replicas.to_string();
    let mut args = vec![
        "calibrate",
        out.to_str().unwrap(),
        "--replicas",
        &n,
        "--json",
        "-q",
    ];
    args.extend(extra);
    hydroid(&args)
}

/// The run calibrate's tests check: configs/spheroid_joint.toml of an example copy, with
/// `set` overrides, into its out/.
pub fn joint_run(example: &Path, set: &[&str]) -> PathBuf {
    let out = example.join("out");
    let o = run_config(&example.join("configs/spheroid_joint.toml"), &out, set);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    out
}

/// `hydroid plan` of `config` (run first) for `targets`, verified with `verify` candidates.
pub fn plan_for(config: &str, targets: &[&str], verify: usize) -> Plan {
    plan_with(config, targets, verify, &[])
}

/// [`plan_for`] with each of `set` as a `--set` override of the configuration.
pub fn plan_with(config: &str, targets: &[&str], verify: usize, set: &[&str]) -> Plan {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let loaded = hydroid::config::load(Path::new(config), &set).unwrap();
    let output = hydroid::app::pipeline::run(&loaded, &mut Silent).unwrap();
    let settings = Settings {
        targets: targets.iter().map(|t| t.to_string()).collect(),
        verify,
        replicas: 40,
        seed: 2026,
        ..Settings::default()
    };
    hydroid::app::plan::plan(&loaded, &output, &settings).unwrap()
}

/// `hydroid run CONFIG --out OUT` with each of `set` as a `--set` override.
pub fn run_config(config: &Path, out: &Path, set: &[&str]) -> Output {
    let mut args = vec![
        "run",
        config.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    for s in set {
        args.extend(["--set", s]);
    }
    hydroid(&args)
}

/// Bytes a command printed, as text.
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A JSON file (results.json, the schema ...), parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `hydroid analytic` for the paper's spheroid (1.2 m long, 0.2 m in diameter); a test adds
/// `--rho`, `--json` ...
pub const ANALYTIC_PAPER_SPHEROID: [&str; 6] = [
    "analytic",
    "spheroid",
    "--length",
    "1.2",
    "--diameter",
    "0.2",
];

/// The entry named `name` of a JSON array (the coefficients of results.json, the columns of
/// `hydroid inspect --json` ...); a test failure naming it when there is none.
pub fn named<'a>(list: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    named_by(list, "name", name)
}

/// The entry of a JSON array whose `key` is `name`; a test failure naming it when there is none.
pub fn named_by<'a>(list: &'a serde_json::Value, key: &str, name: &str) -> &'a serde_json::Value {
    list.as_array()
        .unwrap_or_else(|| panic!("a list, looking for {name}: {list}"))
        .iter()
        .find(|e| e[key] == name)
        .unwrap_or_else(|| panic!("{name} in the list {list}"))
}

/// Copies the bundled example (the files of configs/, configs/simulate/, configs/vehicles/ and cfd_exports/)
/// into the same folders under `to`, so that a test can change it or run it from elsewhere.
pub fn copy_example(to: &Path) {
    for d in [
        "configs",
        "configs/simulate",
        "configs/vehicles",
        "cfd_exports",
    ] {
        std::fs::create_dir_all(to.join(d)).unwrap();
        for e in std::fs::read_dir(root().join(d)).unwrap() {
            let e = e.unwrap();
            if e.file_type().unwrap().is_file() {
                std::fs::copy(e.path(), to.join(d).join(e.file_name())).unwrap();
            }
        }
    }
}

/// A copy of the bundled example in a new temporary folder.
pub fn example_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    copy_example(dir.path());
    dir
}

/// The bundled configuration (configs/spheroid.toml) with its exports' paths made absolute,
/// so that a test can change it and write it anywhere.
pub fn bundled_config_text() -> String {
    let exports = root().join("cfd_exports").display().to_string() + "/";
    std::fs::read_to_string(root().join("configs/spheroid.toml"))
        .unwrap()
        .replace("../cfd_exports/", &exports)
}

/// A run of the bundled example into a temporary folder: its output folder and what the
/// command printed.
pub struct ExampleRun {
    /// The temporary folder (removed when dropped).
    pub dir: tempfile::TempDir,
    /// The output folder, `dir/out` (absent when the run wrote nothing).
    pub out: PathBuf,
    /// Exit status, stdout and stderr.
    pub output: Output,
}

/// `hydroid run configs/spheroid.toml --out <temporary folder>/out <extra>` from the
/// repository's root.
pub fn run_example(extra: &[&str]) -> ExampleRun {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = vec![
        "run",
        "configs/spheroid.toml",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = hydroid(&args);
    ExampleRun { dir, out, output }
}

/// The coefficients configs/spheroid_joint.toml estimates (captive stage and HEKF), each
/// with the truth the bundled spheroid exports were simulated with
/// (`spheroid3::BOUNDED_TRUTH`).
pub fn spheroid_joint_truth() -> Vec<(&'static str, f64)> {
    const ESTIMATED: [&str; 13] = [
        "Xud", "Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr", "Yuvl", "Nuvl", "Xuu", "Xuv", "Xvv", "Yvv",
    ];
    ESTIMATED
        .iter()
        .map(|n| {
            let truth = hydroid::model::models::spheroid3::BOUNDED_TRUTH
                .iter()
                .find(|(m, _)| m == n)
                .unwrap_or_else(|| panic!("no truth for {n}"));
            (*n, truth.1)
        })
        .collect()
}

/// The conditions of the ITTC steady captive programme, (drift deg, r', rudder deg): static
/// drift -20..20 deg, rudder -35..35 deg straight ahead, drift 10 deg with rudder +-20 deg,
/// and circular motion at r' 0.2, 0.4, 0.6 with drift -12..12 deg.
pub fn ittc_programme() -> Vec<(f64, f64, f64)> {
    let mut points = Vec::new();
    for b in (-20..=20).step_by(4) {
        points.push((f64::from(b), 0.0, 0.0));
    }
    for d in (-35..=35).step_by(10) {
        points.push((0.0, 0.0, f64::from(d)));
    }
    for d in [-20.0, 20.0] {
        points.push((10.0, 0.0, d));
    }
    for rp in [0.2, 0.4, 0.6] {
        for b in (-12..=12).step_by(6) {
            points.push((f64::from(b), rp, 0.0));
        }
    }
    points
}

/// The folder of the real basin logs (not in the repository: `$HYDROID_REAL_DATA`, by
/// default `../shared/data/real` beside it); panics with what to do when it is absent.
pub fn real_data_dir() -> PathBuf {
    let dir = std::env::var_os("HYDROID_REAL_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("../shared/data/real"));
    assert!(
        dir.join("marin").is_dir() && dir.join("hsva").is_dir(),
        "the real KVLCC2 logs are not at {}: set HYDROID_REAL_DATA to the folder that holds \
         marin/ and hsva/ (../shared/data/real/README.md)",
        dir.display()
    );
    dir
}

/// The file `name` of the real data folder ([`real_data_dir`]); panics with what to do when
/// it is absent.
pub fn real_data_file(name: &str) -> PathBuf {
    let file = real_data_dir().join(name);
    assert!(
        file.is_file(),
        "no {name} in the real data folder {}: set HYDROID_REAL_DATA to the folder that \
         holds it (../shared/data/real/README.md)",
        file.parent().unwrap_or(&file).display()
    );
    file
}
