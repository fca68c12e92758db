//! Convergence of the HEKF estimates: each coefficient over every filter pass, the passes
//! laid end to end on one time axis, with the filter's ±2σ band, the reference and analytic
//! values, and the final estimate with its total uncertainty.

use super::axes::{self, Axes, Range};
use super::style::{self, anchored, colour, size, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::results::RunResult;
use crate::base::numfmt::num;
use crate::model::coefficients::Coefficient;
use crate::stages::hekf::HekfResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// One coefficient's history over all passes and runs.
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// Concatenated filter time, s.
    pub x: Vec<f64>,
    /// Estimate.
    pub value: Vec<f64>,
    /// Filter sigma.
    pub sigma: Vec<f64>,
}

/// The time axis of the passes laid end to end: per (pass, run), the offset to add to the
/// run's own time since its first sample, and the starts of the passes.
fn layout(h: &HekfResult) -> (Vec<Vec<f64>>, Vec<f64>, Vec<f64>) {
    let passes = h.traces.first().map_or(0, |t| t.history.len());
    let durations: Vec<f64> = h
        .traces
        .iter()
        .map(|t| match (t.times.first(), t.times.last()) {
            (Some(a), Some(b)) if (b - a).is_finite() => b - a,
            _ => 0.0,
        })
        .collect();
    // a sample interval between consecutive runs so that they do not share an abscissa
    let gap = h
        .traces
        .iter()
        .find_map(|t| (t.times.len() > 1).then(|| t.times[1] - t.times[0]))
        .unwrap_or(0.0);
    let mut offsets = vec![vec![0.0; h.traces.len()]; passes];
    let (mut pass_starts, mut run_starts) = (Vec::new(), Vec::new());
    let mut x = 0.0;
    for row in offsets.iter_mut() {
        pass_starts.push(x);
        for (r, d) in durations.iter().enumerate() {
            if r > 0 {
                run_starts.push(x);
            }
            row[r] = x;
            x += d + gap;
        }
    }
    pass_starts.push(x - gap);
    (offsets, pass_starts, run_starts)
}

/// The history of coefficient `j`.
pub fn history(h: &HekfResult, j: usize) -> History {
    let nb = h.estimated.len();
    let (offsets, _, _) = layout(h);
    let mut out = History {
        x: Vec::new(),
        value: Vec::new(),
        sigma: Vec::new(),
    };
    for (p, row) in offsets.iter().enumerate() {
        for (r, tr) in h.traces.iter().enumerate() {
            let Some(hist) = tr.history.get(p) else {
                continue;
            };
            let t0 = tr.times.first().copied().unwrap_or(0.0);
            for (k, t) in hist.times.iter().enumerate() {
                out.x.push(row[r] + t - t0);
                out.value
                    .push(hist.values.get(k * nb + j).copied().unwrap_or(f64::NAN));
                out.sigma
                    .push(hist.sigmas.get(k * nb + j).copied().unwrap_or(f64::NAN));
            }
        }
    }
    out
}

/// The convergence figure.
pub struct Convergence<'a> {
    h: &'a HekfResult,
    reference: Option<&'a crate::config::ReferenceConfig>,
    analytic: &'a [crate::model::coefficients::Coefficient],
}

impl<'a> Convergence<'a> {
    /// The figure, when the filter kept its traces.
    pub fn new(h: &'a HekfResult, r: &'a RunResult) -> Option<Self> {
        let has = !h.estimated.is_empty()
            && h.traces
                .iter()
                .any(|t| t.history.iter().any(|c| !c.is_empty()));
        has.then_some(Convergence {
            h,
            reference: r.reference.as_ref(),
            analytic: &r.analytic,
        })
    }

    fn reference(&self, name: &str) -> Option<f64> {
        self.reference?.values.get(name).copied()
    }

    fn analytic(&self, name: &str) -> Option<f64> {
        self.analytic
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.value)
    }

    fn cols(&self) -> usize {
        if self.h.estimated.len() > 1 {
            2
        } else {
            1
        }
    }

    fn rows(&self) -> usize {
        self.h.estimated.len().div_ceil(self.cols())
    }

    /// The vertical range of a coefficient's panel: the settled estimate, its final 2-sigma
    /// band, the reference and the analytic value.
    fn y_range(
        &self,
        name: &str,
        c: &Coefficient,
        hist: &History,
        pass_starts: &[f64],
    ) -> Result<Range, PlotError> {
        let end = *pass_starts.last().unwrap_or(&0.0);
        let total = c.sigma.unwrap_or(0.0);
        // the vertical range leaves out the first tenth of the first pass, where the estimate
        // leaves its starting value; the line is clipped there
        let settle = 0.1 * pass_starts.get(1).map_or(end, |p1| p1 - pass_starts[0]);
        let settled = hist
            .x
            .iter()
            .zip(&hist.value)
            .filter(|(t, _)| **t >= settle)
            .map(|(_, v)| *v);
        Ok(Range::require(settled, name)?
            .include(c.value - 2.0 * total)
            .include(c.value + 2.0 * total)
            .include(self.reference(name).unwrap_or(f64::NAN))
            .include(self.analytic(name).unwrap_or(f64::NAN))
            .pad(0.08)
            .headroom(0.1))
    }

    fn draw_one<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        j: usize,
        bottom_row: bool,
        pass_starts: &[f64],
        run_starts: &[f64],
    ) -> Result<(), PlotError> {
        let name = &self.h.estimated[j];
        let c = &self.h.coefficients[j];
        let hist = history(self.h, j);
        let end = *pass_starts.last().unwrap_or(&0.0);
        let x = Range::new(0.0, end.max(1e-9) * 1.04);
        let total = c.sigma.unwrap_or(0.0);
        let y = self.y_range(name, c, &hist, pass_starts)?;
        let y_desc = format!("{name} ({})", c.unit);
        let title = format!(
            "{name} = {} ± {} {} (1σ, total)",
            num(c.value),
            num(total),
            c.unit
        );
        let mut chart = axes::panel(
            area,
            &Axes::new(
                x,
                y,
                if bottom_row {
                    "filter time, passes laid end to end (s)"
                } else {
                    ""
                },
                &y_desc,
            )
            .title(&title),
        )?;
        let lower: Vec<f64> = hist
            .value
            .iter()
            .zip(&hist.sigma)
            .map(|(v, s)| v - 2.0 * s)
            .collect();
        let upper: Vec<f64> = hist
            .value
            .iter()
            .zip(&hist.sigma)
            .map(|(v, s)| v + 2.0 * s)
            .collect();
        axes::band(&mut chart, &hist.x, &lower, &upper, y, colour::BLUE)?;
        pass_marks(&mut chart, x, y, pass_starts, run_starts)?;
        if let Some(r) = self.reference(name) {
            axes::hline(&mut chart, x, r, colour::GREEN.stroke_width(2), true)?;
        }
        if let Some(a) = self.analytic(name) {
            axes::hline(&mut chart, x, a, colour::ORANGE.stroke_width(2), true)?;
        }
        let inside = |v: f64| if y.contains(v) { v } else { f64::NAN };
        axes::line(
            &mut chart,
            hist.x
                .iter()
                .copied()
                .zip(hist.value.iter().map(|v| inside(*v))),
            colour::BLUE.stroke_width(2),
        )?;
        let xe = end + 0.02 * end;
        axes::error_bar(
            &mut chart,
            xe,
            c.value - 2.0 * total,
            c.value + 2.0 * total,
            colour::DATA.stroke_width(2),
        )?;
        axes::dots(&mut chart, [(xe, c.value)], 4, colour::DATA.filled())?;
        Ok(())
    }
}

/// The passes' boundaries (dashed grey) and labels, and the runs' starts (dashed grid).
fn pass_marks<DB: DrawingBackend>(
    chart: &mut axes::Chart<'_, DB>,
    x: Range,
    y: Range,
    pass_starts: &[f64],
    run_starts: &[f64],
) -> Result<(), PlotError> {
    for s in &pass_starts[1..pass_starts.len().saturating_sub(1)] {
        axes::dashed(
            chart,
            [(*s, y.lo), (*s, y.hi)],
            colour::GREY.stroke_width(2),
        )?;
    }
    for s in run_starts {
        axes::dashed(
            chart,
            [(*s, y.lo), (*s, y.hi)],
            colour::GRID.stroke_width(1),
        )?;
    }
    for (p, w) in pass_starts.windows(2).enumerate() {
        chart.draw_series(std::iter::once(Text::new(
            format!("pass {}", p + 1),
            (w[0] + 0.01 * x.span(), y.hi),
            anchored(size::TICK, HPos::Left, VPos::Top).color(&colour::GREY),
        )))?;
    }
    Ok(())
}

impl Plot for Convergence<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "hekf_convergence".into(),
            title: "Convergence of the HEKF estimates over the filter passes".into(),
            caption: format!(
                "Each estimated coefficient over the {} filter pass{} laid end to end (each \
                 pass restarts the states from the first samples and the coefficients from the \
                 previous pass), with the filter's ±2σ band (from the data alone, the fixed \
                 coefficients taken as exact). The black bar at the right end is the final \
                 estimate ±2σ including the uncertainty of the fixed coefficients. Dashed \
                 lines: {}Fossen's analytic value, where they exist. The vertical range is set \
                 by the estimates after the first tenth of the first pass: the line leaves the \
                 panel where the estimate moves away from its starting value.",
                self.h.settings.passes,
                if self.h.settings.passes == 1 {
                    ""
                } else {
                    "es"
                },
                self.reference
                    .map(|r| format!("the reference values ({}), ", r.name))
                    .unwrap_or_default()
            ),
            section: Section::Hekf,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1600, 170 + 330 * self.rows() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let mut keys = vec![
            Key::new(Mark::Line(colour::BLUE), "estimate"),
            Key::new(Mark::Band(colour::BLUE), "±2σ of the filter (data only)"),
            Key::new(
                Mark::Bar(colour::DATA),
                "final ±2σ incl. fixed coefficients",
            ),
        ];
        if let Some(r) = self.reference {
            if self.h.estimated.iter().any(|n| r.values.contains_key(n)) {
                keys.push(Key::new(Mark::Dashed(colour::GREEN), r.name.clone()));
            }
        }
        if self.h.estimated.iter().any(|n| self.analytic(n).is_some()) {
            keys.push(Key::new(Mark::Dashed(colour::ORANGE), "Fossen analytic"));
        }
        keys.push(Key::new(Mark::Dashed(colour::GREY), "start of a pass"));
        let body = style::frame(root, "HEKF estimates over the filter passes", &keys)?;
        let (_, pass_starts, run_starts) = layout(self.h);
        let (rows, cols) = (self.rows(), self.cols());
        for (j, area) in body
            .split_evenly((rows, cols))
            .iter()
            .enumerate()
            .take(self.h.estimated.len())
        {
            self.draw_one(area, j, j / cols + 1 == rows, &pass_starts, &run_starts)?;
        }
        Ok(())
    }
}
