//! The plan on the console and in the output folder: the ranked table (candidate,
//! parameters, each target's sigma before and after, scores, cost), plan.json, and the figure
//! of each candidate's predicted sigma reduction (plots/plan.svg), written atomically into an
//! output folder exactly as hydroid left it (the one read at the start: [`Claim`]) and recorded
//! in its marker.

use super::Plan;
use crate::app::report::plots::{self, style, FigureMeta, Plot, PlotError, Section};
use crate::base::error::Result;
use crate::base::markdown_text::markdown_table;
use crate::base::numfmt::num;
use crate::io::output::Claim;
use plotters::coord::Shift;
use plotters::prelude::*;

/// plan.json in the output folder.
pub const PLAN_JSON: &str = "plan.json";
/// plan.md in the output folder: the table and the assumptions.
pub const PLAN_MD: &str = "plan.md";
/// The figure in the output folder.
pub const PLAN_SVG: &str = "plots/plan.svg";

/// Rows of the table at most (plan.json holds every candidate).
pub const TABLE_ROWS: usize = 20;

/// The ranked table in Markdown: the targets' sigmas before, then each candidate's.
pub fn table(plan: &Plan) -> String {
    let mut header = vec![
        "rank".to_string(),
        "candidate".into(),
        "parameters".into(),
        "fitted".into(),
    ];
    header.extend(plan.targets.iter().map(|t| format!("sigma {t}")));
    header.extend([
        "D score".into(),
        "A score".into(),
        "cost".into(),
        "D / cost".into(),
        "rank by D / cost".into(),
    ]);
    let mut rows = vec![{
        let mut r = vec!["-".to_string(), "now".into(), "-".into(), "-".into()];
        r.extend(plan.sigma_before.iter().map(|s| num(*s)));
        r.extend(["-".into(), "-".into(), "-".into(), "-".into(), "-".into()]);
        r
    }];
    for row in plan.ranked.iter().take(TABLE_ROWS) {
        let mut r = vec![
            row.rank.to_string(),
            row.candidate.name.clone(),
            row.parameters.clone(),
            row.fitted.as_ref().map_or_else(|| "-".into(), fitted),
        ];
        r.extend(row.sigma_after.iter().map(|s| num(*s)));
        r.extend([
            format!("{:.3}", row.d_score),
            format!("{:.3}", row.a_score),
            num(row.candidate.cost),
            num(row.d_per_cost),
            row.rank_per_cost.to_string(),
        ]);
        rows.push(r);
    }
    let right: Vec<bool> = (0..header.len()).map(|i| i == 0 || i > 3).collect();
    let mut s = markdown_table(&header, &rows, &right);
    s.push_str(&joint_note(plan));
    if !plan.verification.is_empty() {
        let mut head = vec!["verified candidate".to_string(), "replicas".into()];
        for t in &plan.targets {
            head.extend([format!("{t} predicted"), format!("{t} achieved")]);
        }
        let rows: Vec<Vec<String>> = plan
            .verification
            .iter()
            .map(|v| {
                let mut r = vec![v.name.clone(), v.replicas.to_string()];
                for (p, a) in v.predicted.iter().zip(&v.achieved) {
                    r.extend([
                        num(*p),
                        format!("{} ({:+.0} %)", num(*a), 100.0 * (a / p - 1.0)),
                    ]);
                }
                r
            })
            .collect();
        let right: Vec<bool> = (0..head.len()).map(|i| i > 0).collect();
        s.push('\n');
        s.push_str(&markdown_table(&head, &rows, &right));
    }
    s
}

/// A predicted sigma this much below the configured mode's counts as paying off in joint
/// mode only.
const JOINT_GAIN: f64 = 0.01;

/// Rows of the joint-mode table at most (best by their D score in joint mode).
const JOINT_ROWS: usize = 5;

/// Under consider mode: the captive candidates whose information on the HEKF's own
/// coefficients is not used, with their targets' sigmas under `hekf.mode = "joint"`; empty
/// when there are none.
fn joint_note(plan: &Plan) -> String {
    let mut paying: Vec<&super::Row> = plan
        .ranked
        .iter()
        .filter(|row| {
            row.joint.as_ref().is_some_and(|j| {
                j.sigma_after
                    .iter()
                    .zip(&row.sigma_after)
                    .any(|(j, c)| *j < (1.0 - JOINT_GAIN) * c)
            })
        })
        .collect();
    paying.sort_by(|a, b| {
        let d = |r: &super::Row| r.joint.as_ref().map_or(0.0, |j| j.d_score);
        d(b).total_cmp(&d(a))
            .then_with(|| a.candidate.name.cmp(&b.candidate.name))
    });
    let rows: Vec<Vec<String>> = paying
        .iter()
        .take(JOINT_ROWS)
        .map(|row| {
            let joint = row.joint.as_ref().expect("filtered");
            let mut r = vec![row.candidate.name.clone(), row.rank.to_string()];
            r.extend(joint.sigma_after.iter().map(|s| num(*s)));
            r.push(format!("{:.3}", joint.d_score));
            r
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut head = vec![
        "with hekf.mode = \"joint\"".to_string(),
        "rank as configured".into(),
    ];
    head.extend(plan.targets.iter().map(|t| format!("sigma {t}")));
    head.push("D score".into());
    let right: Vec<bool> = (0..head.len()).map(|i| i > 0).collect();
    format!(
        "\nPlanned in the configuration's mode, hekf.mode = \"{}\": the HEKF estimates {} from \
         its own prior, so a captive run's information on them is not used. The captive \
         candidates that would pay off most with hekf.mode = \"joint\" in [hekf] (an earlier stage's \
         estimate is then the HEKF's prior):\n\n{}",
        plan.mode,
        plan.hekf_own.join(", "),
        markdown_table(&head, &rows, &right)
    )
}

/// A captive candidate's fitted record in words: the whole periods and samples the stage
/// fits, and each force's per-sample noise, "(default)" when the planner assumed it.
fn fitted(f: &super::captive::Fitted) -> String {
    let noise: Vec<String> = f
        .noise
        .iter()
        .map(|n| {
            let default = if n.default { " (default)" } else { "" };
            format!("{} {} {}{default}", n.quantity, num(n.sigma), n.unit)
        })
        .collect();
    format!(
        "{}{} samples; noise {}",
        f.periods
            .map_or_else(String::new, |n| format!("{n} periods, ")),
        f.samples,
        noise.join(", ")
    )
}

/// Writes plan.json, plan.md and plots/plan.svg into the claimed output folder (replacing
/// those hydroid wrote there before) and records them in its marker; nothing is written when
/// another run replaced the folder or it changed since it was read.
pub fn write(claim: &Claim, plan: &Plan) -> Result<()> {
    let json = crate::io::output::to_json(plan)?;
    let figure = plots::render(&Reduction(plan), None)?;
    let md = markdown(plan);
    claim.write(&[
        (PLAN_JSON, &json),
        (PLAN_MD, md.as_bytes()),
        (PLAN_SVG, figure.svg.as_bytes()),
    ])
}

/// plan.md: what the table is, the table, and the assumptions.
pub fn markdown(plan: &Plan) -> String {
    let mut s = String::from("# Run plan\n\n");
    s.push_str(&format!(
        "Candidate runs of the {} model ranked by the predicted information on {} (D score: \
         half the log of the ratio of the targets' covariance determinants before and after, \
         nats; A score: the share of the targets' relative variance removed; cost in the \
         candidates' unit). See docs/planner.md.\n\n",
        plan.model,
        plan.targets.join(", ")
    ));
    s.push_str(&table(plan));
    s.push_str("\nAssumptions:\n\n");
    for a in &plan.assumptions {
        s.push_str(&format!("- {a}\n"));
    }
    for k in &plan.skipped {
        s.push_str(&format!("\n- not evaluated: {}: {}\n", k.name, k.reason));
    }
    s
}

/// The figure: per candidate (best first, at most [`TABLE_ROWS`]), each target's predicted
/// sigma after it as a share of its sigma now.
struct Reduction<'a>(&'a Plan);

impl Plot for Reduction<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "plan".into(),
            title: "Predicted sigma after each candidate run".into(),
            caption: "Each target coefficient's predicted sigma after the candidate run, as a \
                      share of its sigma now (1: the run adds nothing), candidates best first \
                      (docs/planner.md)."
                .into(),
            section: Section::Hekf,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1000, 640)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let plan = self.0;
        root.fill(&WHITE)?;
        let rows: Vec<_> = plan.ranked.iter().take(TABLE_ROWS).collect();
        let n = rows.len().max(1);
        let lowest = rows
            .iter()
            .flat_map(|r| {
                r.sigma_after
                    .iter()
                    .zip(&plan.sigma_before)
                    .map(|(a, b)| a / b)
            })
            .fold(1.0f64, f64::min)
            .max(1e-6);
        let mut chart = ChartBuilder::on(root)
            .caption(self.meta().title, style::text(style::size::TITLE))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(0.5..n as f64 + 0.5, (lowest * 0.5..1.5).log_scale())
            .map_err(|e| PlotError::new(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("candidate rank (plan.json names them)")
            .y_desc("sigma after / sigma now")
            .axis_desc_style(style::text(style::size::AXIS))
            .label_style(style::text(style::size::TICK))
            .light_line_style(style::colour::GRID)
            .draw()
            .map_err(|e| PlotError::new(e.to_string()))?;
        for (t, name) in plan.targets.iter().enumerate() {
            let colour = style::colour::SERIES[t % style::colour::SERIES.len()];
            let points: Vec<(f64, f64)> = rows
                .iter()
                .map(|r| (r.rank as f64, r.sigma_after[t] / plan.sigma_before[t]))
                .collect();
            chart
                .draw_series(points.iter().map(|p| Circle::new(*p, 5, colour.filled())))
                .map_err(|e| PlotError::new(e.to_string()))?
                .label(name.clone())
                .legend(move |(x, y)| Circle::new((x, y), 5, colour.filled()));
        }
        chart
            .configure_series_labels()
            .label_font(style::text(style::size::LEGEND))
            .background_style(WHITE.mix(0.8))
            .border_style(style::colour::GREY)
            .draw()
            .map_err(|e| PlotError::new(e.to_string()))?;
        Ok(())
    }
}
