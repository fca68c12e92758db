//! The comparison table (coefficient | hydroid +- sigma | analytic | reference | errors) as
//! aligned text for the terminal and as Markdown for report.md.

use super::results::{ComparisonRow, RunResult};
use std::io::{self, Write};

/// Significant-figure formatting used in every table: 4 significant digits, plain for
/// moderate magnitudes.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..6).contains(&mag) {
        let decimals = (3 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

fn pct(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), |p| format!("{p:+.2} %"))
}

fn value(row: &ComparisonRow) -> String {
    match row.sigma {
        Some(s) => format!("{} ± {}", num(row.value), num(s)),
        None => num(row.value),
    }
}

fn cells(row: &ComparisonRow) -> [String; 8] {
    [
        row.name.clone(),
        value(row),
        row.unit.clone(),
        row.source.clone(),
        row.analytic.map_or_else(|| "-".into(), num),
        pct(row.error_vs_analytic_pct),
        row.reference.map_or_else(|| "-".into(), num),
        pct(row.error_vs_reference_pct),
    ]
}

const HEADER: [&str; 8] = [
    "coefficient",
    "hydroid",
    "unit",
    "source",
    "Fossen",
    "vs Fossen",
    "reference",
    "vs reference",
];

/// Writes the comparison table as aligned text, flags below it.
pub fn write_text(out: &mut impl Write, r: &RunResult) -> io::Result<()> {
    let rows: Vec<[String; 8]> = r.comparison.iter().map(cells).collect();
    let mut width = HEADER.map(|h| h.chars().count());
    for row in &rows {
        for (w, c) in width.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        cells
            .iter()
            .zip(width)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
    };
    writeln!(out, "{}", line(&HEADER.map(String::from)))?;
    for row in &rows {
        writeln!(out, "{}", line(row))?;
    }
    for row in &r.comparison {
        for f in &row.flags {
            writeln!(out, "  {}: {f}", row.name)?;
        }
    }
    Ok(())
}

/// The comparison table in Markdown, with the reference's name in its header.
pub fn markdown(r: &RunResult) -> String {
    let ref_name = r
        .reference
        .as_ref()
        .map_or("reference", |x| x.name.as_str());
    let mut s = format!(
        "| coefficient | hydroid ± σ | unit | source | Fossen analytic | vs Fossen | {ref_name} | vs {ref_name} | flags |\n\
         |---|---|---|---|---|---|---|---|---|\n"
    );
    for row in &r.comparison {
        let c = cells(row);
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            c[0],
            c[1],
            c[2],
            c[3],
            c[4],
            c[5],
            c[6],
            c[7],
            row.flags.join("; ")
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_significant_figures() {
        assert_eq!(num(-23.6261), "-23.63");
        assert_eq!(num(-1.16404), "-1.164");
        assert_eq!(num(0.0017), "0.001700");
        assert_eq!(num(13.43), "13.43");
        assert_eq!(num(1234.5), "1234");
        assert_eq!(num(2.5e-7), "2.500e-7");
    }
}
