//! `hydroid compare A/results.json B/results.json`: coefficient-by-coefficient differences.

use super::{json, CmdResult};
use hydroid::coefficients::Coefficient;
use hydroid::error::{Error, InputError, Place};
use hydroid::numfmt::num;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Compare the coefficients of two runs: value and sigma in each, the difference, and the
/// difference in units of the combined sigma.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// results.json of the first run (or its output folder).
    a: PathBuf,
    /// results.json of the second run (or its output folder).
    b: PathBuf,
    /// Print machine-readable JSON: every coefficient with its value in A and B, the
    /// difference B - A and that difference in units of the combined sigma.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Deserialize)]
struct Results {
    coefficients: Vec<Coefficient>,
    /// The vehicle and fluid summary (absent in files of other tools).
    #[serde(default)]
    vehicle: serde_json::Map<String, serde_json::Value>,
    /// The effective configuration, for the model.
    #[serde(default)]
    configuration: serde_json::Value,
}

impl Results {
    /// What says which vehicle and model the coefficients belong to, by name.
    fn identity(&self) -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = self
            .vehicle
            .iter()
            .filter(|(k, _)| k.as_str() != "q") // derived from rho and reference_area
            .map(|(k, x)| (format!("vehicle {k}"), plain(x)))
            .collect();
        if let Some(m) = self.configuration.pointer("/hekf/model") {
            v.push(("hekf model".into(), plain(m)));
        }
        v
    }
}

fn plain(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Null => "none".into(),
        other => other.to_string(),
    }
}

/// Where the two runs describe different vehicles or models: "vehicle mass: 50 vs 60".
fn differences(a: &Results, b: &Results) -> Vec<String> {
    let (ia, ib) = (a.identity(), b.identity());
    let get = |v: &[(String, String)], k: &str| {
        v.iter()
            .find(|(n, _)| n == k)
            .map_or_else(|| "none".to_string(), |(_, x)| x.clone())
    };
    let mut keys: Vec<&String> = ia.iter().chain(&ib).map(|(k, _)| k).collect();
    keys.dedup();
    let mut seen = BTreeSet::new();
    keys.into_iter()
        .filter(|k| seen.insert(k.as_str()))
        .filter_map(|k| {
            let (x, y) = (get(&ia, k), get(&ib, k));
            (x != y).then(|| format!("{k}: {x} (A) vs {y} (B)"))
        })
        .collect()
}

fn read(path: &Path) -> hydroid::Result<Results> {
    let file = if path.is_dir() {
        path.join("results.json")
    } else {
        path.to_path_buf()
    };
    let text = hydroid::config::read(&file)?;
    serde_json::from_str(&text).map_err(|e| -> Error {
        InputError::new(
            Place::line(&file, e.line()).with_column(e.column()),
            "not a hydroid results.json",
        )
        .expected("the results.json of a hydroid run, or its output folder")
        .into()
    })
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let (ra, rb) = (read(&args.a)?, read(&args.b)?);
    let differ = differences(&ra, &rb);
    if !differ.is_empty() {
        let head = "warning: A and B are runs of different vehicles or models, so their \
                    coefficients need not agree:";
        eprintln!("{head}");
        writeln!(out, "{head}")?;
        for d in &differ {
            eprintln!("  {d}");
            writeln!(out, "  {d}")?;
        }
        writeln!(out)?;
    }
    let (a, b) = (ra.coefficients, rb.coefficients);
    let names: BTreeSet<&str> = a.iter().chain(&b).map(|c| c.name.as_str()).collect();
    let find = |v: &[Coefficient], n: &str| v.iter().find(|c| c.name == n).cloned();
    let cell = |c: &Option<Coefficient>| match c {
        Some(c) => match c.sigma {
            Some(s) => format!("{} ± {} ({})", num(c.value), num(s), c.source),
            None => format!("{} ({})", num(c.value), c.source),
        },
        None => "-".into(),
    };
    let mut rows = vec![[
        "coefficient".to_string(),
        "A".into(),
        "B".into(),
        "B - A".into(),
        "(B - A)/sigma".into(),
        "unit".into(),
    ]];
    let mut differences = Vec::new();
    for n in names {
        let (ca, cb) = (find(&a, n), find(&b, n));
        // B - A, and in units of the combined sigma (when either has one)
        let (d, z) = match (&ca, &cb) {
            (Some(x), Some(y)) => {
                let d = y.value - x.value;
                let s = (x.sigma.unwrap_or(0.0).powi(2) + y.sigma.unwrap_or(0.0).powi(2)).sqrt();
                (Some(d), (s > 0.0).then(|| d / s))
            }
            _ => (None, None),
        };
        let unit = ca
            .as_ref()
            .or(cb.as_ref())
            .map_or(String::new(), |c| c.unit.clone());
        let side = |c: &Option<Coefficient>| {
            c.as_ref().map(
                |c| serde_json::json!({ "value": c.value, "sigma": c.sigma, "source": c.source }),
            )
        };
        differences.push(serde_json::json!({
            "name": n,
            "unit": unit,
            "a": side(&ca),
            "b": side(&cb),
            "difference": d,
            "difference_in_sigma": z,
        }));
        rows.push([
            n.to_string(),
            cell(&ca),
            cell(&cb),
            d.map_or_else(|| "-".into(), num),
            z.map_or_else(|| "-".into(), |z| format!("{z:+.2}")),
            unit,
        ]);
    }
    if args.json {
        return json::write(
            out,
            &serde_json::json!({ "a": args.a, "b": args.b, "coefficients": differences }),
        );
    }
    let mut width = [0usize; 6];
    for r in &rows {
        for (w, c) in width.iter_mut().zip(r) {
            *w = (*w).max(c.chars().count());
        }
    }
    for r in &rows {
        let line: Vec<String> = r
            .iter()
            .zip(width)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect();
        writeln!(out, "{}", line.join("  ").trim_end())?;
    }
    Ok(0)
}
