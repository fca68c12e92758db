//! The comparison table and the uncertainty budget.

use super::fmt::pct;
use super::Figures;
use crate::app::report::doc::{code, text, Col, Document, Table};
use crate::app::report::plots::budget::{lines, stages_of};
use crate::app::report::table::{comparison_header, comparison_rows, ordered, Columns};
use crate::app::results::RunResult;
use crate::base::numfmt::num;

pub fn write<'a>(d: &mut Document<'a>, r: &RunResult, figs: &Figures<'a>) {
    d.heading(2, "Coefficients");
    let ref_name = r.reference.as_ref().map(|x| {
        std::iter::once(x)
            .chain(&r.other_references)
            .map(|x| x.name.as_str())
            .collect::<Vec<_>>()
            .join("; ")
    });
    let analytic = if Columns::of(r).analytic {
        ", Fossen's analytic value (Lamb's k-factors)"
    } else {
        ""
    };
    d.para([text(format!(
        "Every coefficient of the final set: hydroid's value ± one standard deviation (σ \
         includes the uncertainty carried from earlier stages), where it came from (polar, \
         surge, captive, hekf, symmetry = paper eq. 4, config, analytic){analytic}{} and the \
         relative differences (hydroid − other) / |other|. Highlighted rows carry a flag: σ \
         above 10 % of the value, or a correlation above 0.9 with another estimate.",
        ref_name
            .as_ref()
            .map(|n| format!(", the reference values ({n})"))
            .unwrap_or_default()
    ))]);
    let header = comparison_header(r);
    let flags = header.len() - 1;
    let mut t = Table::new(header).col(flags, Col::Text);
    for (row, cells) in ordered(r).into_iter().zip(comparison_rows(r)) {
        if row.flags.is_empty() {
            t.row(cells);
        } else {
            t.marked_row(cells);
        }
    }
    d.table(t);
    d.para([
        text("The same table is in "),
        code("coefficients.csv"),
        text(" with full precision and each coefficient's note (how it was obtained)."),
    ]);
    budget(d, r);
    figs.put(d, "uncertainty_budget");
}

fn budget(d: &mut Document, r: &RunResult) {
    let lines = lines(&r.comparison);
    if lines.is_empty() {
        return;
    }
    d.heading(3, "Uncertainty budget");
    d.text(
        "Each σ split by the stage its uncertainty comes from: the σ it would have if only \
         that stage were uncertain, and its share of the variance (the stages' variances add). \
         A coefficient fixed in a later stage inherits the uncertainty of the earlier ones it \
         depends on.",
    );
    let stages = stages_of(&lines);
    let mut header = vec!["coefficient".to_string(), "unit".into(), "σ".into()];
    header.extend(stages.iter().map(|s| format!("from {s}")));
    header.push("dominant".into());
    let last = header.len() - 1;
    let mut t = Table::new(header).numeric_from(2).col(last, Col::Tag);
    for l in &lines {
        let mut row = vec![l.name.clone(), l.unit.clone(), num(l.sigma)];
        for s in &stages {
            row.push(match l.shares.iter().find(|x| &x.0 == s) {
                Some((_, share)) => format!("{} ({})", num(l.sigma * share.sqrt()), pct(*share)),
                None => "-".into(),
            });
        }
        let top = l
            .shares
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or("-".to_string(), |s| s.0.clone());
        row.push(top);
        t.row(row);
    }
    d.table(t);
}
