//! `hydroid compare A/results.json B/results.json`: coefficient-by-coefficient differences.

use super::{json, CmdResult};
use crate::base::error::{Error, InputError, Place};
use crate::base::numfmt::num;
use crate::model::coefficients::Coefficient;
use serde_json::{json, Value};
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
    pub(super) json: bool,
}

#[derive(serde::Deserialize)]
struct Results {
    /// The layout's version (`hydroid-results/2`); absent in files of other tools.
    #[serde(default)]
    schema: Option<String>,
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

fn read(path: &Path) -> crate::Result<Results> {
    let file = if path.is_dir() {
        path.join("results.json")
    } else {
        path.to_path_buf()
    };
    let text = crate::config::read(&file)?;
    let expected = "the results.json of a hydroid run, or its output folder";
    let results: Results = serde_json::from_str(&text).map_err(|e| -> Error {
        InputError::new(
            Place::line(&file, e.line()).with_column(e.column()),
            "not a hydroid results.json",
        )
        .expected(expected)
        .into()
    })?;
    check(&file, &text, &results)?;
    Ok(results)
}

/// Refuses what would make the comparison wrong without a word: a file of another schema
/// version, a sigma that is negative or not finite, a coefficient listed twice.
fn check(file: &Path, text: &str, r: &Results) -> crate::Result<()> {
    let schema = crate::app::results::SCHEMA;
    let fail = |place: Place, message: String, expected: String| -> crate::Result<()> {
        Err(InputError::new(place, message).expected(expected).into())
    };
    match r.schema.as_deref() {
        Some(s) if s == schema => {}
        found => {
            let what = found.map_or_else(
                || "has no `schema` field: not written by hydroid".to_string(),
                |s| format!("has schema '{s}', and this hydroid compares '{schema}' only"),
            );
            return fail(
                Place::file(file),
                format!("{what}; coefficients of another layout may differ in meaning"),
                format!(
                    "a results.json with \"schema\": \"{schema}\" (rerun the older output with \
                     this hydroid: hydroid rerun OUTDIR --out NEW)"
                ),
            );
        }
    }
    let lines = coefficient_lines(text);
    let place = |i: usize| match lines.get(i) {
        Some(&l) => Place::line(file, l),
        None => Place::file(file),
    };
    for (i, c) in r.coefficients.iter().enumerate() {
        if let Some(s) = c.sigma.filter(|s| !(s.is_finite() && *s >= 0.0)) {
            return fail(
                place(i),
                format!("coefficients[{i}] '{}': sigma {s} is negative", c.name),
                "a standard deviation of 0 or more (or null)".into(),
            );
        }
        if let Some(j) = r.coefficients[..i].iter().position(|o| o.name == c.name) {
            return fail(
                place(i),
                format!(
                    "coefficients[{i}] '{}' is listed twice (also coefficients[{j}]{})",
                    c.name,
                    lines
                        .get(j)
                        .map_or_else(String::new, |l| format!(", line {l}"))
                ),
                "each coefficient once".into(),
            );
        }
    }
    Ok(())
}

/// The 1-based line of each entry of the top-level `coefficients` list of a results.json
/// as hydroid writes it (pretty JSON, two spaces per level); empty for another layout.
fn coefficient_lines(text: &str) -> Vec<usize> {
    let mut out = Vec::new();
    let mut inside = false;
    for (k, line) in text.lines().enumerate() {
        if line == "  \"coefficients\": [" {
            inside = true;
        } else if inside && (line == "  ]," || line == "  ]") {
            break;
        } else if inside && line == "    {" {
            out.push(k + 1);
        }
    }
    out
}

/// One coefficient of A and B side by side: the JSON entry and the table row. Differing
/// units make the difference meaningless: it is left out and the unit cell says both.
fn compare_one(
    n: &str,
    ca: Option<&Coefficient>,
    cb: Option<&Coefficient>,
) -> (Value, [String; 6]) {
    let units_differ = matches!((ca, cb), (Some(x), Some(y)) if x.unit != y.unit);
    // B - A, and in units of the combined sigma (when either has one)
    let (d, z) = match (ca, cb) {
        (Some(x), Some(y)) if !units_differ => {
            let d = y.value - x.value;
            let s = (x.sigma.unwrap_or(0.0).powi(2) + y.sigma.unwrap_or(0.0).powi(2)).sqrt();
            (Some(d), (s > 0.0).then(|| d / s))
        }
        _ => (None, None),
    };
    let unit = match (ca, cb) {
        (Some(x), Some(y)) if units_differ => format!("{} (A) vs {} (B)", x.unit, y.unit),
        (Some(c), _) | (None, Some(c)) => c.unit.clone(),
        (None, None) => String::new(),
    };
    let side = |c: Option<&Coefficient>| {
        c.map(|c| json!({ "value": c.value, "sigma": c.sigma, "source": c.source, "unit": c.unit }))
    };
    let cell = |c: Option<&Coefficient>| match c {
        Some(c) => match c.sigma {
            Some(s) => format!("{} ± {} ({})", num(c.value), num(s), c.source),
            None => format!("{} ({})", num(c.value), c.source),
        },
        None => "-".into(),
    };
    let entry = json!({
        "name": n,
        "unit": unit,
        "units_differ": units_differ,
        "a": side(ca),
        "b": side(cb),
        "difference": d,
        "difference_in_sigma": z,
    });
    let row = [
        n.to_string(),
        cell(ca),
        cell(cb),
        d.map_or_else(|| "-".into(), num),
        z.map_or_else(|| "-".into(), |z| format!("{z:+.2}")),
        unit,
    ];
    (entry, row)
}

/// The warnings about A and B: different vehicles or models, coefficients in different units.
fn warnings(ra: &Results, rb: &Results) -> Vec<String> {
    let mut w = Vec::new();
    let differ = differences(ra, rb);
    if !differ.is_empty() {
        w.push(
            "A and B are runs of different vehicles or models, so their coefficients need not \
             agree:"
                .to_string(),
        );
        w.extend(differ.iter().map(|d| format!("  {d}")));
    }
    for x in &ra.coefficients {
        if let Some(y) = rb
            .coefficients
            .iter()
            .find(|y| y.name == x.name && y.unit != x.unit)
        {
            w.push(format!(
                "{} is in {} in A and in {} in B: not compared (the difference would mix units)",
                x.name, x.unit, y.unit
            ));
        }
    }
    w
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let (ra, rb) = (read(&args.a)?, read(&args.b)?);
    let warned = warnings(&ra, &rb);
    for w in &warned {
        super::warning(w);
    }
    let names: BTreeSet<&str> = ra
        .coefficients
        .iter()
        .chain(&rb.coefficients)
        .map(|c| c.name.as_str())
        .collect();
    fn find<'c>(v: &'c [Coefficient], n: &str) -> Option<&'c Coefficient> {
        v.iter().find(|c| c.name == n)
    }
    let (entries, rows): (Vec<Value>, Vec<[String; 6]>) = names
        .into_iter()
        .map(|n| compare_one(n, find(&ra.coefficients, n), find(&rb.coefficients, n)))
        .unzip();
    if args.json {
        return json::write(
            out,
            &json!({ "a": args.a, "b": args.b, "warnings": warned, "coefficients": entries }),
        );
    }
    for w in &warned {
        writeln!(out, "warning: {w}")?;
    }
    if !warned.is_empty() {
        writeln!(out)?;
    }
    let head = ["coefficient", "A", "B", "B - A", "(B - A)/sigma", "unit"].map(String::from);
    let rows: Vec<[String; 6]> = std::iter::once(head).chain(rows).collect();
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
