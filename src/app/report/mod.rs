//! Everything written to the output folder: results.json, coefficients.csv, the effective
//! configuration, and (with plots enabled) figures and the Markdown/HTML reports.

mod autopilot_series;
pub mod content;
pub mod doc;
pub mod html;
pub mod markdown;
pub mod plots;
pub mod states;
pub mod table;

use crate::app::results::{RunOutput, RunResult};
use crate::base::error::{Error, Result};
use crate::config::LoadedConfig;
use crate::io::output::{to_json, Staging};

/// Files every run writes.
pub const RESULTS_JSON: &str = "results.json";
/// The coefficient table.
pub const COEFFICIENTS_CSV: &str = "coefficients.csv";
/// The effective configuration.
pub const CONFIG_TOML: &str = "config.toml";
/// The inputs and their hashes.
pub const INPUTS_JSON: &str = "inputs.json";
/// Where the configuration and its inputs live, for `hydroid rerun`.
pub const RERUN_JSON: &str = "rerun.json";
/// The report in Markdown (always written).
pub const REPORT_MD: &str = "report.md";
/// The self-contained HTML report (with plots on).
pub const REPORT_HTML: &str = "report.html";

/// What `hydroid rerun` needs besides config.toml and inputs.json.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RerunManifest {
    /// The configuration file the run was made from.
    pub config: std::path::PathBuf,
    /// The absolute folder its relative paths were resolved against.
    pub base_dir: std::path::PathBuf,
    /// The `--set` overrides applied (already in config.toml).
    pub overrides: Vec<String>,
}

/// The staging folder a run of `loaded` writes its output into: `out`, else the
/// configuration's `output.dir` (relative to it), guarded as `hydroid run` guards it (a
/// folder hydroid did not write, or a configuration or input inside it, is refused; a
/// hydroid output changed since it was written is replaced only when `force`). Call it
/// before the stages run, so that a refusal does not come after the work.
pub fn staging(
    loaded: &LoadedConfig,
    out: Option<&std::path::Path>,
    force: bool,
) -> Result<Staging> {
    use crate::io::output::{Protected, Replace};
    let dir = out.map_or_else(|| loaded.resolve(&loaded.config.output.dir), Into::into);
    Staging::guarded(&dir, &Protected::for_config(loaded), Replace::forced(force))
}

/// Writes the run's outputs into the staging folder: results.json, inputs.json,
/// coefficients.csv, the HEKF runs' state series (states/), config.toml, rerun.json and
/// report.md; with `output.plots` also the
/// figures in plots/ (SVG and PNG) and report.html.
pub fn write(staging: &Staging, loaded: &LoadedConfig, out: &RunOutput) -> Result<()> {
    check_finite(&out.result)?;
    staging.write(RESULTS_JSON, &to_json(&out.result)?)?;
    staging.write(INPUTS_JSON, &to_json(&out.result.inputs)?)?;
    staging.write(COEFFICIENTS_CSV, &coefficients_csv(&out.result)?)?;
    states::write(staging, out)?;
    if let Some(a) = out.result.autopilot.as_ref() {
        autopilot_series::write(staging, a)?;
    }
    staging.write(CONFIG_TOML, effective_config(loaded).as_bytes())?;
    let base_dir = std::fs::canonicalize(if loaded.base_dir.as_os_str().is_empty() {
        std::path::Path::new(".")
    } else {
        &loaded.base_dir
    })
    .map_err(|e| Error::io(&loaded.base_dir, e))?;
    let manifest = RerunManifest {
        config: loaded.path.clone(),
        base_dir,
        overrides: loaded.overrides.clone(),
    };
    staging.write(RERUN_JSON, &to_json(&manifest)?)?;
    write_reports(staging, out, loaded.config.output.plots)
}

/// Writes report.md and, with `plots`, the figures and report.html.
pub fn write_reports(staging: &Staging, out: &RunOutput, plots: bool) -> Result<()> {
    let figures = if plots {
        // created inside the staging folder only (never re-created after a signal removed it)
        let dir = staging.create_dir(plots::PLOTS_DIR)?;
        let figures = plots::render_all(out, Some(&dir)).map_err(|e| staging.as_target(e))?;
        for f in &figures {
            staging.write(&f.svg_path(), f.svg.as_bytes())?;
        }
        Some(figures)
    } else {
        None
    };
    let doc = content::document(&out.result, figures.as_deref());
    staging.write(REPORT_MD, markdown::render(&doc).as_bytes())?;
    if figures.is_some() {
        staging.write(REPORT_HTML, html::render(&doc).as_bytes())?;
    }
    Ok(())
}

/// The effective configuration with a header saying where it came from.
pub fn effective_config(loaded: &LoadedConfig) -> String {
    let mut s = format!(
        "# Effective configuration of this run (defaults and --set overrides applied).\n\
         # Source: {}\n",
        loaded.path.display()
    );
    for o in &loaded.overrides {
        s.push_str(&format!("# --set {o}\n"));
    }
    s.push_str(&loaded.effective_toml());
    s
}

/// The columns of coefficients.csv before those of further reference sets and the note (the
/// Python package's `Result.coefficients` has the same).
pub const COEFFICIENT_COLUMNS: [&str; 9] = [
    "name",
    "value",
    "sigma",
    "unit",
    "source",
    "analytic",
    "error_vs_analytic_pct",
    "reference",
    "error_vs_reference_pct",
];

/// coefficients.csv: one row per coefficient with sigma, unit, source and the comparisons.
pub fn coefficients_csv(r: &RunResult) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e: csv::Error| Error::Usage(format!("cannot write coefficients.csv: {e}"));
    // a further reference set adds its value and error columns, named after it
    let mut header: Vec<String> = COEFFICIENT_COLUMNS.map(String::from).to_vec();
    for o in &r.other_references {
        header.push(format!("reference: {}", o.name));
        header.push(format!("error_vs_reference_pct: {}", o.name));
    }
    header.push("note".into());
    w.write_record(&header).map_err(err)?;
    let opt = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
    for row in &r.comparison {
        let note = r
            .coefficients
            .iter()
            .find(|c| c.name == row.name)
            .and_then(|c| c.note.clone())
            .unwrap_or_default();
        let mut record = vec![
            row.name.clone(),
            row.value.to_string(),
            opt(row.sigma),
            row.unit.clone(),
            row.source.clone(),
            opt(row.analytic),
            opt(row.error_vs_analytic_pct),
            opt(row.reference),
            opt(row.error_vs_reference_pct),
        ];
        for o in &row.other_references {
            record.push(opt(o.value));
            record.push(opt(o.error_pct));
        }
        record.push(note);
        w.write_record(&record).map_err(err)?;
    }
    w.into_inner()
        .map_err(|e| Error::Usage(format!("cannot write coefficients.csv: {e}")))
}

/// Refuses to write a report with a non-finite coefficient (serde_json would turn it into
/// null silently).
fn check_finite(r: &RunResult) -> Result<()> {
    for c in &r.coefficients {
        if !c.value.is_finite() || c.sigma.is_some_and(|s| !s.is_finite()) {
            return Err(Error::numerical(
                "report",
                format!(
                    "coefficient {} is not finite ({} +- {:?})",
                    c.name, c.value, c.sigma
                ),
            ));
        }
    }
    Ok(())
}
