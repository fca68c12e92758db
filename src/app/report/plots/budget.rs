//! The uncertainty budget: for each coefficient, the share of its variance that comes from
//! each stage (variances add, so the shares add to 100 %), with the total sigma beside it.

use super::style::{self, anchored, colour, size, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::results::ComparisonRow;
use crate::base::numfmt::num;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// One coefficient's budget: (stage, share of the variance in 0..1) in stage order.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Coefficient.
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// Total sigma (square root of the sum of the stage variances).
    pub sigma: f64,
    /// sigma / |value|, when the value is not zero.
    pub relative: Option<f64>,
    /// Share of the variance by stage.
    pub shares: Vec<(String, f64)>,
}

/// The stages in pipeline order, then any other in name order.
fn stage_order(stages: &mut [String]) {
    let rank = |s: &str| match s {
        "polar" => 0,
        "surge" => 1,
        "hekf" => 2,
        _ => 3,
    };
    stages.sort_by(|a, b| rank(a).cmp(&rank(b)).then(a.cmp(b)));
}

/// Every stage some line's budget names, once each, in pipeline order.
pub fn stages_of(lines: &[Line]) -> Vec<String> {
    let mut stages: Vec<String> = lines
        .iter()
        .flat_map(|l| l.shares.iter().map(|s| s.0.clone()))
        .collect();
    stage_order(&mut stages);
    stages.dedup();
    stages
}

/// The budget lines of every coefficient with a finite, positive budget.
pub fn lines(rows: &[ComparisonRow]) -> Vec<Line> {
    rows.iter()
        .filter_map(|r| {
            let var: f64 = r.budget.values().map(|s| s * s).sum();
            if !(var > 0.0 && var.is_finite()) {
                return None;
            }
            let mut stages: Vec<String> = r.budget.keys().cloned().collect();
            stage_order(&mut stages);
            let sigma = var.sqrt();
            Some(Line {
                name: r.name.clone(),
                unit: r.unit.clone(),
                sigma,
                relative: (r.value != 0.0).then(|| sigma / r.value.abs()),
                shares: stages
                    .into_iter()
                    .map(|s| {
                        let v = r.budget[&s];
                        (s, v * v / var)
                    })
                    .collect(),
            })
        })
        .collect()
}

/// The colour of a stage.
pub fn stage_colour(stage: &str) -> RGBColor {
    match stage {
        "polar" => colour::BLUE,
        "surge" => colour::ORANGE,
        "hekf" => colour::GREEN,
        _ => colour::PURPLE,
    }
}

/// The budget figure.
pub struct Budget {
    lines: Vec<Line>,
    stages: Vec<String>,
}

impl Budget {
    /// The figure, when some coefficient has a budget.
    pub fn new(rows: &[ComparisonRow]) -> Option<Self> {
        let lines = lines(rows);
        let stages = stages_of(&lines);
        (!lines.is_empty()).then_some(Budget { lines, stages })
    }
}

const LEFT: i32 = 200;
const RIGHT: i32 = 360;
const ROW: i32 = 34;
const BARS: i32 = 760;

impl Plot for Budget {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "uncertainty_budget".into(),
            title: "Uncertainty budget by stage".into(),
            caption: "For each coefficient, the share of its variance σ² that comes from the \
                      uncertainty of each stage (polar: the polar fit's constants; surge: the \
                      surge fit; hekf: the filter's own, from the data of the manoeuvres), \
                      carried through the later stages by linear propagation. The shares add \
                      to 100 %; the total σ is written on the right."
                .into(),
            section: Section::Budget,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (
            (LEFT + BARS + RIGHT) as u32,
            (130 + ROW * self.lines.len() as i32 + 40) as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let keys: Vec<Key> = self
            .stages
            .iter()
            .map(|s| Key::new(Mark::Band(stage_colour(s)), format!("from {s}")))
            .collect();
        let area = style::frame(
            root,
            "Uncertainty budget: share of each coefficient's variance by stage",
            &keys,
        )?;
        let y0 = 12;
        let x_of = |f: f64| LEFT + (f * BARS as f64).round() as i32;
        for (i, l) in self.lines.iter().enumerate() {
            let y = y0 + i as i32 * ROW;
            let mut acc = 0.0;
            for (s, share) in &l.shares {
                let (a, b) = (x_of(acc), x_of(acc + share));
                if b > a {
                    area.draw(&Rectangle::new(
                        [(a, y + 4), (b, y + ROW - 4)],
                        stage_colour(s).mix(0.85).filled(),
                    ))?;
                }
                acc += share;
            }
            area.draw(&Text::new(
                format!("{} ({})", l.name, l.unit),
                (LEFT - 10, y + ROW / 2),
                anchored(size::LEGEND, HPos::Right, VPos::Center),
            ))?;
            let rel = l
                .relative
                .map(|r| format!(" ({} |value|)", crate::base::numfmt::proportion(r)))
                .unwrap_or_default();
            area.draw(&Text::new(
                format!("σ = {}{rel}", num(l.sigma)),
                (LEFT + BARS + 12, y + ROW / 2),
                anchored(size::LEGEND, HPos::Left, VPos::Center),
            ))?;
        }
        let yb = y0 + ROW * self.lines.len() as i32;
        area.draw(&PathElement::new(
            vec![(LEFT, yb + 2), (LEFT + BARS, yb + 2)],
            colour::GREY.stroke_width(1),
        ))?;
        for p in (0..=100).step_by(20) {
            let x = x_of(p as f64 / 100.0);
            area.draw(&PathElement::new(
                vec![(x, y0), (x, yb + 8)],
                colour::GRID.stroke_width(1),
            ))?;
            area.draw(&Text::new(
                p.to_string(),
                (x, yb + 12),
                anchored(size::TICK, HPos::Center, VPos::Top),
            ))?;
        }
        area.draw(&Text::new(
            "share of the variance σ² (%)".to_string(),
            (LEFT + BARS / 2, yb + 38),
            anchored(size::AXIS, HPos::Center, VPos::Top),
        ))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(name: &str, value: f64, budget: &[(&str, f64)]) -> ComparisonRow {
        ComparisonRow {
            name: name.into(),
            unit: "kg".into(),
            value,
            sigma: None,
            source: "hekf".into(),
            analytic: None,
            error_vs_analytic_pct: None,
            reference: None,
            error_vs_reference_pct: None,
            other_references: Vec::new(),
            flags: vec![],
            budget: budget.iter().map(|(s, v)| (s.to_string(), *v)).collect(),
        }
    }

    #[test]
    fn shares_of_the_variance_add_to_one() {
        let rows = vec![
            row("Nrd", -2.0, &[("hekf", 0.3), ("polar", 0.4)]),
            row("Xuu", -1.3, &[]),
            row("Yvd", 0.0, &[("surge", 0.1), ("zeta", 0.1)]),
        ];
        let l = lines(&rows);
        assert_eq!(l.len(), 2, "no budget, no line");
        assert_eq!(l[0].shares[0].0, "polar", "pipeline order");
        assert!((l[0].sigma - 0.5).abs() < 1e-15);
        assert!((l[0].shares[0].1 - 0.64).abs() < 1e-12);
        assert!((l[0].shares[1].1 - 0.36).abs() < 1e-12);
        assert_eq!(l[0].relative, Some(0.25));
        assert_eq!(l[1].relative, None);
        assert_eq!(l[1].shares[1].0, "zeta");
        let b = Budget::new(&rows).unwrap();
        assert_eq!(b.stages, vec!["polar", "surge", "hekf", "zeta"]);
    }
}
