//! The comparison table (coefficient | hydroid +- sigma | analytic | reference | errors) as
//! aligned text for the terminal and as Markdown for report.md.

use crate::app::results::{ComparisonRow, RunResult};
use crate::base::markdown_text::markdown_table;
use crate::base::numfmt::num;
use crate::model::coefficients::Source;
use crate::model::models::registry::all_coefficients;
use std::io::{self, Write};

/// A relative difference in percent: two decimals, or two significant digits in scientific
/// notation from 1000 % (ten times the other value) on.
fn pct(v: Option<f64>) -> String {
    v.map_or_else(
        || "-".into(),
        |p| {
            if p.abs() < 1000.0 {
                format!("{p:+.2} %")
            } else {
                format!("{p:+.1e} %")
            }
        },
    )
}

/// The groups of the table, in pipeline order: each stage, then the values that did not come
/// from a stage (Fossen's formulas, the configuration), then those derived by symmetry.
const GROUPS: [&[Source]; 6] = [
    &[Source::Polar],
    &[Source::Surge],
    &[Source::Captive],
    &[Source::Hekf],
    &[Source::Analytic, Source::Config],
    &[Source::Symmetry],
];

/// The comparison rows in the table's order: grouped by source in pipeline order
/// (`GROUPS`), and within a group in the catalogue's order (added mass, surge, sway, yaw,
/// heave and pitch, roll; the polar's coefficients as in paper eq. 5).
pub fn ordered(r: &RunResult) -> Vec<&ComparisonRow> {
    in_table_order(&r.comparison)
}

/// `rows` in the table's order (see [`ordered`]).
fn in_table_order(rows: &[ComparisonRow]) -> Vec<&ComparisonRow> {
    let group = |source: &str| {
        GROUPS
            .iter()
            .position(|g| g.iter().any(|s| s.to_string() == source))
            .unwrap_or(GROUPS.len())
    };
    let in_catalogue = |name: &str| {
        all_coefficients()
            .iter()
            .position(|c| c.name == name)
            .unwrap_or(all_coefficients().len())
    };
    let mut rows: Vec<&ComparisonRow> = rows.iter().collect();
    rows.sort_by(|a, b| {
        (group(&a.source), in_catalogue(&a.name), &a.name).cmp(&(
            group(&b.source),
            in_catalogue(&b.name),
            &b.name,
        ))
    });
    rows
}

fn value(row: &ComparisonRow) -> String {
    match row.sigma {
        Some(s) => format!("{} ± {}", num(row.value), num(s)),
        None if row
            .flags
            .iter()
            .any(|f| f == crate::model::coefficients::HELD) =>
        {
            format!("{} (held)", num(row.value))
        }
        None => num(row.value),
    }
}

/// The comparison columns a run's table has: Fossen's analytic values only when some
/// coefficient has one (the added mass of a body with a diameter), the reference set's only
/// when one is configured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Columns {
    /// Fossen's analytic value and the difference from it.
    pub analytic: bool,
    /// The first reference set's value and the difference from it.
    pub reference: bool,
}

impl Columns {
    /// The columns of `r`'s table.
    pub fn of(r: &RunResult) -> Self {
        Columns {
            analytic: r.comparison.iter().any(|c| c.analytic.is_some()),
            reference: r.reference.is_some(),
        }
    }
}

fn cells(row: &ComparisonRow, cols: Columns) -> Vec<String> {
    let mut c = vec![
        row.name.clone(),
        value(row),
        row.unit.clone(),
        row.source.clone(),
    ];
    if cols.analytic {
        c.push(row.analytic.map_or_else(|| "-".into(), num));
        c.push(pct(row.error_vs_analytic_pct));
    }
    if cols.reference {
        c.push(row.reference.map_or_else(|| "-".into(), num));
        c.push(pct(row.error_vs_reference_pct));
    }
    for o in &row.other_references {
        c.push(o.value.map_or_else(|| "-".into(), num));
        c.push(pct(o.error_pct));
    }
    c
}

/// The terminal table's header: short names, each further reference set by its name.
fn text_header(r: &RunResult) -> Vec<String> {
    let cols = Columns::of(r);
    let mut h: Vec<String> = ["coefficient", "hydroid", "unit", "source"]
        .map(String::from)
        .to_vec();
    if cols.analytic {
        h.extend(["Fossen".to_string(), "vs Fossen".to_string()]);
    }
    if cols.reference {
        // with several sets each column carries its set's name
        let first = match (&r.reference, r.other_references.is_empty()) {
            (Some(x), false) => x.name.as_str(),
            _ => "reference",
        };
        h.push(first.to_string());
        h.push(format!("vs {first}"));
    }
    h.extend(further_reference_columns(r));
    h
}

/// The header cells of the further reference sets: each set's name and its error column.
fn further_reference_columns(r: &RunResult) -> impl Iterator<Item = String> + '_ {
    r.other_references
        .iter()
        .flat_map(|o| [o.name.clone(), format!("vs {}", o.name)])
}

/// Writes the comparison table as aligned text, flags below it.
pub fn write_text(out: &mut impl Write, r: &RunResult) -> io::Result<()> {
    let ordered = ordered(r);
    let header = text_header(r);
    let cols = Columns::of(r);
    let rows: Vec<Vec<String>> = ordered.iter().map(|row| cells(row, cols)).collect();
    let mut width: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in &rows {
        for (w, c) in width.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        cells
            .iter()
            .zip(&width)
            .map(|(c, &w)| format!("{c:<w$}"))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
    };
    writeln!(out, "{}", line(&header))?;
    for row in &rows {
        writeln!(out, "{}", line(row))?;
    }
    for row in &ordered {
        for f in &row.flags {
            writeln!(out, "  {}: {f}", row.name)?;
        }
    }
    Ok(())
}

/// The header of the comparison table, with the reference's name.
pub fn comparison_header(r: &RunResult) -> Vec<String> {
    let cols = Columns::of(r);
    let mut h: Vec<String> = ["coefficient", "hydroid ± σ", "unit", "source"]
        .map(String::from)
        .to_vec();
    if cols.analytic {
        h.extend(["Fossen analytic".to_string(), "vs Fossen".to_string()]);
    }
    if let (true, Some(x)) = (cols.reference, &r.reference) {
        h.push(x.name.clone());
        h.push(format!("vs {}", x.name));
    }
    h.extend(further_reference_columns(r));
    h.push("flags".into());
    h
}

/// The rows of the comparison table (as in [`comparison_header`]), in [`ordered`] order.
pub fn comparison_rows(r: &RunResult) -> Vec<Vec<String>> {
    let cols = Columns::of(r);
    ordered(r)
        .into_iter()
        .map(|row| {
            let mut c = cells(row, cols);
            c.push(row.flags.join("; "));
            c
        })
        .collect()
}

/// The comparison table in Markdown, with the reference's name in its header.
pub fn markdown(r: &RunResult) -> String {
    markdown_table(&comparison_header(r), &comparison_rows(r), &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_grouped_by_stage_in_pipeline_order() {
        let row = |name: &str, source: &str| ComparisonRow {
            name: name.into(),
            unit: String::new(),
            value: 1.0,
            sigma: None,
            source: source.into(),
            analytic: None,
            error_vs_analytic_pct: None,
            reference: None,
            error_vs_reference_pct: None,
            other_references: Vec::new(),
            flags: Vec::new(),
            budget: Default::default(),
        };
        // alphabetical, as the coefficient set gives them
        let rows = [
            row("Kpp", "config"),
            row("Nrd", "hekf"),
            row("Nuva", "symmetry"),
            row("Nuvl", "polar"),
            row("Xud", "surge"),
            row("Xuu", "polar"),
            row("Xvr", "symmetry"),
            row("Yvd", "hekf"),
            row("Zwd", "analytic"),
        ];
        let names: Vec<&str> = in_table_order(&rows)
            .iter()
            .map(|r| r.name.as_str())
            .collect();
        assert_eq!(
            names,
            ["Xuu", "Nuvl", "Xud", "Yvd", "Nrd", "Zwd", "Kpp", "Xvr", "Nuva"]
        );
    }

    #[test]
    fn huge_relative_differences_in_scientific_notation() {
        assert_eq!(pct(Some(22.4137)), "+22.41 %");
        assert_eq!(pct(Some(-999.0)), "-999.00 %");
        assert_eq!(pct(Some(131003125175.0)), "+1.3e11 %");
        assert_eq!(pct(None), "-");
    }
}
