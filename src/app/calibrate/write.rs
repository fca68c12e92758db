//! The calibration written into the output folder it checks (calibration.json and
//! calibration.md, each atomically, then recorded in the folder's marker so that the folder
//! stays hydroid's; only into the folder read at the start: [`Claim`]) and its table for the
//! console and the Markdown file.

use super::Calibration;
use crate::base::error::Result;
use crate::base::markdown_text::markdown_table;
use crate::base::numfmt::num;
use crate::io::output::Claim;

/// calibration.json in the output folder.
pub const CALIBRATION_JSON: &str = "calibration.json";
/// calibration.md in the output folder.
pub const CALIBRATION_MD: &str = "calibration.md";

/// Writes calibration.json and calibration.md into the claimed output folder (replacing
/// those hydroid wrote there before) and records them in the folder's marker; nothing is
/// written when another run replaced the folder or it changed since it was read.
pub fn write(claim: &Claim, cal: &Calibration) -> Result<()> {
    let json = crate::io::output::to_json(cal)?;
    let md = markdown(cal);
    claim.write(&[(CALIBRATION_JSON, &json), (CALIBRATION_MD, md.as_bytes())])
}

/// calibration.md: the table and what it means.
pub fn markdown(cal: &Calibration) -> String {
    let mut s = String::from("# Calibration check\n\n");
    s.push_str(&format!(
        "{} replicas of every fitted run made from the identified model with the runs' own \
         noise (seeds {} to {}), each identified again with the run's settings; {} \
         identified, {} failed. Coverage: the share of replicas whose own 1- and 2-sigma \
         interval holds the identified value (Gaussian: 68.3 % and 95.4 %); spread: the \
         replicas' standard deviation in reported sigmas (1 when the sigma is right). See \
         docs/calibrate.md.\n\n",
        cal.replicas,
        cal.seed,
        cal.seed.wrapping_add(cal.replicas.saturating_sub(1) as u64),
        cal.converged,
        cal.failed.len()
    ));
    s.push_str(&table(cal));
    if !cal.settings.variants.is_empty() {
        s.push_str(
            "\n## Settings\n\nThe same data identified again with each setting changed (the \
             inputs read the other way between samples; each run of a stage with several left \
             out): the move in reported sigmas, the largest leave-one-out move over its \
             expected spread (z), and the settings sigma (the systematic part of both, in \
             quadrature). The noise model's part is results.json's budget row \"noise \
             model\".\n\n",
        );
        s.push_str(&settings_table(cal));
    }
    for w in &cal.warnings {
        s.push_str(&format!("\n- warning: {} ({})\n", w.message, w.meaning));
    }
    s
}

/// An optional number, or "-".
fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or_else(|| "-".to_string(), f)
}

/// A share as a percentage with one decimal.
fn pct(v: f64) -> String {
    format!("{:.1} %", 100.0 * v)
}

/// The per-coefficient table with an overall row, in Markdown.
pub fn table(cal: &Calibration) -> String {
    let header: Vec<String> = [
        "coefficient",
        "value",
        "sigma",
        "replica mean",
        "replica sd",
        "spread / sigma",
        "robust / sigma",
        "far",
        "bias / sigma",
        "within 1 sigma",
        "within 2 sigma",
    ]
    .map(String::from)
    .to_vec();
    let mut rows: Vec<Vec<String>> = cal
        .coefficients
        .iter()
        .map(|r| {
            vec![
                r.name.clone(),
                num(r.value),
                num(r.sigma),
                opt(r.replica_mean, num),
                opt(r.replica_sd, num),
                opt(r.spread_ratio, |v| format!("{v:.2}")),
                opt(r.robust_spread_ratio, |v| format!("{v:.2}")),
                r.far.to_string(),
                opt(r.bias_sigmas, |v| format!("{v:+.2}")),
                opt(r.coverage.within_1, pct),
                opt(r.coverage.within_2, pct),
            ]
        })
        .collect();
    let mut overall = vec![String::from("overall"), String::new(), String::new()];
    overall.extend(std::iter::repeat_n(String::new(), 6));
    overall.push(opt(cal.overall.within_1, pct));
    overall.push(opt(cal.overall.within_2, pct));
    rows.push(overall);
    let mut right = vec![true; header.len()];
    right[0] = false;
    markdown_table(&header, &rows, &right)
}

/// The settings table: one row per coefficient.
pub fn settings_table(cal: &Calibration) -> String {
    let header: Vec<String> = [
        "coefficient",
        "inputs other way / sigma",
        "leave-one-out max z",
        "settings sigma",
        "settings / sigma",
    ]
    .map(String::from)
    .to_vec();
    let rows: Vec<Vec<String>> = cal
        .settings
        .coefficients
        .iter()
        .map(|r| {
            vec![
                r.name.clone(),
                opt(r.between_sigmas, |v| format!("{v:+.2}")),
                opt(r.leave_out_max_z, |v| format!("{v:.2}")),
                num(r.settings_sigma),
                format!("{:.2}", r.settings_ratio),
            ]
        })
        .collect();
    let mut right = vec![true; header.len()];
    right[0] = false;
    let failed: Vec<String> = cal
        .settings
        .variants
        .iter()
        .filter_map(|v| {
            v.error
                .as_ref()
                .map(|e| format!("- {}: failed ({e})\n", v.label))
        })
        .collect();
    format!(
        "{}{}",
        markdown_table(&header, &rows, &right),
        failed.concat()
    )
}
