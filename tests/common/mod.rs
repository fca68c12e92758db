//! Helpers shared by the integration tests: in-memory records and the paper's vehicle.
#![allow(dead_code)]

use hydroid::config::{FluidConfig, VehicleConfig};
use hydroid::formats::Format;
use hydroid::quantity::Quantity;
use hydroid::record::Record;
use std::collections::BTreeMap;
use std::path::PathBuf;

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
        lines: (2..rows + 2).collect(),
        meta: Vec::new(),
        warnings: Vec::new(),
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
    }
}

/// Sea water as in the paper (Table 1).
pub fn fluid() -> FluidConfig {
    FluidConfig {
        rho: 1025.0,
        mu: 0.0009,
    }
}

/// Runs the `hydroid` binary in `dir` with `args`.
pub fn hydroid_in(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_hydroid"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the hydroid binary runs")
}

/// Runs the `hydroid` binary in the repository's root with `args`.
pub fn hydroid(args: &[&str]) -> std::process::Output {
    hydroid_in(std::path::Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// Bytes a command printed, as text.
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
