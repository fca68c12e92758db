//! The measures as a table a report shows: measure | unit | measured | identified model |
//! limit, as plain text ([`std::fmt::Display`]) or Markdown.

use super::imo::{Check, Verdict};
use super::measure::{Measure, Named};
use crate::base::markdown_text::markdown_table;
use crate::base::numfmt::num;
use std::fmt;

/// One row: a measure's values written for people (degrees for angles).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// What the measure is called.
    pub label: String,
    /// The unit the values are written in.
    pub unit: String,
    /// The measured run's value ("-" if missing, "(fail)" after a failed criterion).
    pub measured: String,
    /// The identified model's value, or empty without a model.
    pub model: String,
    /// The limit and the rule, or empty.
    pub limit: String,
}

/// The measures of a run beside the identified model's and the IMO limits, with the reason
/// for every missing value.
#[derive(Debug, Clone, PartialEq)]
pub struct ComparisonTable {
    /// The rows, in the order of the measured run's measures.
    pub rows: Vec<Row>,
    /// Why a value is missing: "advance (measured): the heading changes ...".
    pub notes: Vec<String>,
}

impl ComparisonTable {
    /// The table of `measured` (a run's [`super::TurningCircle::measures`] or
    /// [`super::ZigZag::measures`]), beside `model`'s same measures if given, with the
    /// criteria checked on each (`measured_checks`, `model_checks`; either may be empty).
    pub fn new(
        measured: &[Named],
        model: Option<&[Named]>,
        measured_checks: &[Check],
        model_checks: &[Check],
    ) -> Self {
        let mut notes = Vec::new();
        let mut cell = |n: &Named, checks: &[Check], who: &str| {
            if let Measure::Missing(reason) = &n.value {
                notes.push(format!("{} ({who}): {reason}", n.label));
            }
            let failed = checks
                .iter()
                .any(|c| c.criterion.measure_key() == n.key && matches!(c.verdict, Verdict::Fail));
            let text = n.value.display(n.kind);
            if failed {
                format!("{text} (fail)")
            } else {
                text
            }
        };
        let mut rows = Vec::new();
        for m in measured {
            let model_cell = match model {
                Some(list) => match list.iter().find(|n| n.key == m.key) {
                    Some(n) => cell(n, model_checks, "identified model"),
                    None => "-".to_string(),
                },
                None => String::new(),
            };
            let limit = measured_checks
                .iter()
                .chain(model_checks)
                .find(|c| c.criterion.measure_key() == m.key)
                .map(|c| {
                    format!(
                        "<= {} ({})",
                        num(c.criterion.kind().to_display(c.limit)),
                        c.rule
                    )
                })
                .unwrap_or_default();
            rows.push(Row {
                label: m.label.to_string(),
                unit: m.kind.unit().to_string(),
                measured: cell(m, measured_checks, "measured"),
                model: model_cell,
                limit,
            });
        }
        ComparisonTable { rows, notes }
    }

    /// The table with `notes` added after the reasons for missing values (where the nominal
    /// angles come from, why a criterion is not judged); a note already there is not repeated.
    pub fn with_notes(mut self, notes: impl IntoIterator<Item = String>) -> Self {
        for n in notes {
            if !self.notes.contains(&n) {
                self.notes.push(n);
            }
        }
        self
    }

    /// The column headings.
    pub const HEADER: [&'static str; 5] =
        ["measure", "unit", "measured", "identified model", "limit"];

    /// The cells, row by row, in the order of [`Self::HEADER`].
    pub fn cells(&self) -> Vec<Vec<String>> {
        self.rows
            .iter()
            .map(|r| {
                vec![
                    r.label.clone(),
                    r.unit.clone(),
                    r.measured.clone(),
                    r.model.clone(),
                    r.limit.clone(),
                ]
            })
            .collect()
    }

    /// The table in Markdown, the notes after it as a list.
    pub fn to_markdown(&self) -> String {
        let header: Vec<String> = Self::HEADER.iter().map(|s| s.to_string()).collect();
        let mut s = markdown_table(&header, &self.cells(), &[false, false, true, true, false]);
        for n in &self.notes {
            s.push_str(&format!(
                "\n- {}",
                crate::base::markdown_text::escape_markdown(n)
            ));
        }
        if !self.notes.is_empty() {
            s.push('\n');
        }
        s
    }
}

impl fmt::Display for ComparisonTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cells = self.cells();
        let mut widths: Vec<usize> = Self::HEADER.iter().map(|h| h.chars().count()).collect();
        for row in &cells {
            for (w, c) in widths.iter_mut().zip(row) {
                *w = (*w).max(c.chars().count());
            }
        }
        let header: Vec<String> = Self::HEADER.iter().map(|s| s.to_string()).collect();
        for row in std::iter::once(&header).chain(&cells) {
            let line: Vec<String> = row
                .iter()
                .zip(&widths)
                .enumerate()
                .map(|(i, (c, w))| {
                    if i == 2 || i == 3 {
                        format!("{c:>w$}")
                    } else {
                        format!("{c:<w$}")
                    }
                })
                .collect();
            writeln!(f, "{}", line.join("  ").trim_end())?;
        }
        for n in &self.notes {
            writeln!(f, "  {n}")?;
        }
        Ok(())
    }
}
