//! The surge stage: measured u(t) against the fitted integral model with its residuals, and
//! X_udot per speed bin against the overall value.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::results::RunResult;
use crate::base::numfmt::num;
use crate::stages::surge::SurgeResult;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Measured and fitted u(t) of every surge run, residuals below.
pub struct SurgeFit<'a> {
    r: &'a SurgeResult,
    word: &'static str,
}

impl<'a> SurgeFit<'a> {
    /// The figure, when the stage kept residuals; `word` says what the data are ("CFD",
    /// "measured").
    pub fn new(r: &'a SurgeResult, word: &'static str) -> Option<Self> {
        r.residuals
            .iter()
            .any(|x| !x.time.is_empty())
            .then_some(SurgeFit { r, word })
    }
}

impl Plot for SurgeFit<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "surge_fit".into(),
            title: "Surge run: measured and fitted u(t)".into(),
            caption: format!(
                "Surge speed of the acceleration run{} ({}, points) and the fitted model \
                 (line): {}. Residuals u − û below, in mm/s; a pattern in them rather than \
                 noise means the model misses something (lag-1 autocorrelation {}).",
                if self.r.residuals.len() > 1 { "s" } else { "" },
                self.word,
                self.r.method,
                self.r
                    .residual_lag1
                    .map_or_else(|| "not computed".into(), |v| format!("{v:.2}"))
            ),
            section: Section::Surge,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1400, 850)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let multi = self.r.residuals.len() > 1;
        let run_colour = |i: usize| {
            if multi {
                colour::SERIES[i % colour::SERIES.len()]
            } else {
                colour::BLUE
            }
        };
        let mut keys = vec![Key::new(
            Mark::Dot(colour::DATA),
            format!("{} u(t)", self.word),
        )];
        for (i, run) in self.r.residuals.iter().enumerate() {
            let what = "fitted (m − X_udot) du/dt = X_uu u|u| + X_prop";
            keys.push(Key::new(
                Mark::Line(run_colour(i)),
                if multi {
                    format!("{what}: {}", run.record)
                } else {
                    what.to_string()
                },
            ));
        }
        let body = style::frame(root, "Surge run: measured u(t) and the fitted model", &keys)?;
        let all = |f: fn(&crate::stages::surge::RunResiduals) -> &Vec<f64>| {
            self.r
                .residuals
                .iter()
                .flat_map(move |x| f(x).iter().copied())
        };
        let t = Range::require(all(|x| &x.time), "surge time")?.pad(0.01);
        let u = Range::require(all(|x| &x.u), "surge u")?
            .union(Range::require(all(|x| &x.fitted), "fitted u")?)
            .pad(0.06);
        let res = Range::require(all(|x| &x.residual).map(|v| 1e3 * v), "surge residuals")?
            .symmetric()
            .pad(0.1)
            .headroom(0.3);
        let (top, bottom) = body.split_vertically(body.dim_in_pixel().1 * 62 / 100);
        let mut chart = axes::panel(&top, &Axes::new(t, u, "", "surge speed u (m/s)"))?;
        let mut rchart = axes::panel(&bottom, &Axes::new(t, res, "time t (s)", "u − û (mm/s)"))?;
        axes::hline(&mut rchart, t, 0.0, colour::GREY.stroke_width(1), false)?;
        for (i, run) in self.r.residuals.iter().enumerate() {
            let c = run_colour(i);
            let pts: Vec<(f64, f64)> = run
                .time
                .iter()
                .copied()
                .zip(run.u.iter().copied())
                .collect();
            let width = chart.plotting_area().dim_in_pixel().0 as usize;
            // points, thinned to a few per pixel column so the figure stays light
            let shown = if pts.len() > width {
                axes::thin(&pts, width / 2)
            } else {
                pts
            };
            axes::dots(&mut chart, shown, 2, colour::DATA.filled())?;
            let fitted = run.time.iter().copied().zip(run.fitted.iter().copied());
            axes::line(&mut chart, fitted, c.stroke_width(2))?;
            let r = run
                .time
                .iter()
                .copied()
                .zip(run.residual.iter().map(|v| 1e3 * v));
            axes::line(&mut rchart, r, c.stroke_width(1))?;
        }
        let mut note = vec![format!(
            "X_udot = {} ± {} kg (1σ)",
            num(self.r.xud.value),
            self.r.xud.sigma.map_or_else(|| "?".into(), num)
        )];
        note.push(format!(
            "residual SD = {} mm/s, R² = {}",
            num(1e3 * self.r.residual_std),
            self.r
                .r_squared
                .map_or_else(|| "-".into(), |v| format!("{v:.6}"))
        ));
        axes::note(&rchart, &note)?;
        Ok(())
    }
}

/// X_udot per speed bin with error bars, against the overall estimate.
pub struct SurgeBins<'a> {
    r: &'a SurgeResult,
    analytic: Option<f64>,
    reference: Option<(String, f64)>,
}

impl<'a> SurgeBins<'a> {
    /// The figure, when at least one bin has a fit.
    pub fn new(r: &'a SurgeResult, run: &RunResult) -> Option<Self> {
        if !r.bins.iter().any(|b| b.fit.is_some()) {
            return None;
        }
        let analytic = run
            .analytic
            .iter()
            .find(|c| c.name == "Xud")
            .map(|c| c.value);
        let reference = run
            .reference
            .as_ref()
            .and_then(|x| Some((x.name.clone(), *x.values.get("Xud")?)));
        Some(SurgeBins {
            r,
            analytic,
            reference,
        })
    }
}

impl Plot for SurgeBins<'_> {
    fn meta(&self) -> FigureMeta {
        let spread = self.r.bin_spread.as_ref().and_then(|s| {
            Some(format!(
                " The bins differ by χ² = {:.1} on {} degrees of freedom (p = {}): {}.",
                s.chi2?,
                s.dof,
                crate::app::report::content::p_value(s.p_value?),
                if s.p_value? < 0.01 {
                    "more than their statistical errors explain, so one X_uu does not describe \
                     the whole speed range"
                } else {
                    "consistent with their statistical errors"
                }
            ))
        });
        FigureMeta {
            name: "surge_bins".into(),
            title: "X_udot per speed bin".into(),
            caption: format!(
                "X_udot fitted on each speed bin of the surge run (paper fig. 8): the bin's \
                 extent (horizontal bar), ±2σ statistical (thick) and ±2σ including the \
                 uncertainty of X_uu (thin). The band is the value over the whole run ±2σ.{}",
                spread.unwrap_or_default()
            ),
            section: Section::Surge,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1200, 720)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let xud = self.r.xud;
        let s_all = xud.sigma.unwrap_or(0.0);
        let mut keys = vec![
            Key::new(Mark::Dot(colour::BLUE), "X_udot of a speed bin"),
            Key::new(
                Mark::Bar(colour::BLUE),
                "±2σ (thick: statistical; thin: with X_uu)",
            ),
            Key::new(
                Mark::Band(colour::DATA),
                format!(
                    "whole run: {} kg, σ = {} kg (band: ±2σ)",
                    num(xud.value),
                    num(s_all)
                ),
            ),
        ];
        if let Some(a) = self.analytic {
            keys.push(Key::new(
                Mark::Dashed(colour::ORANGE),
                format!("Fossen analytic {}", num(a)),
            ));
        }
        if let Some((n, v)) = &self.reference {
            keys.push(Key::new(
                Mark::Dashed(colour::GREEN),
                format!("{n}: {}", num(*v)),
            ));
        }
        let body = style::frame(root, "Surge added mass X_udot per speed bin", &keys)?;
        let fits: Vec<(f64, f64, f64, f64, f64)> = self
            .r
            .bins
            .iter()
            .filter_map(|b| {
                let f = b.fit.as_ref()?;
                let tot = f.xud.sigma.unwrap_or(0.0);
                let stat = f.xud.sigma_statistical.unwrap_or(tot);
                Some((b.u_min, b.u_max, f.xud.value, stat, tot))
            })
            .collect();
        let x = Range::require(fits.iter().flat_map(|f| [f.0, f.1]), "speed bins")?.pad(0.04);
        let y = Range::require(
            fits.iter().flat_map(|f| [f.2 - 2.0 * f.4, f.2 + 2.0 * f.4]),
            "X_udot of the bins",
        )?
        .include(xud.value - 2.0 * s_all)
        .include(xud.value + 2.0 * s_all)
        .include(self.analytic.unwrap_or(f64::NAN))
        .include(self.reference.as_ref().map_or(f64::NAN, |r| r.1))
        .pad(0.08);
        let mut chart = axes::panel(
            &body,
            &Axes::new(x, y, "surge speed u (m/s)", "X_udot (kg)"),
        )?;
        axes::band(
            &mut chart,
            &[x.lo, x.hi],
            &[xud.value - 2.0 * s_all; 2],
            &[xud.value + 2.0 * s_all; 2],
            y,
            colour::DATA,
        )?;
        axes::hline(
            &mut chart,
            x,
            xud.value,
            colour::DATA.stroke_width(2),
            false,
        )?;
        if let Some(a) = self.analytic {
            axes::hline(&mut chart, x, a, colour::ORANGE.stroke_width(2), true)?;
        }
        if let Some((_, v)) = &self.reference {
            axes::hline(&mut chart, x, *v, colour::GREEN.stroke_width(2), true)?;
        }
        for (lo, hi, v, stat, tot) in fits {
            let mid = 0.5 * (lo + hi);
            axes::line(&mut chart, [(lo, v), (hi, v)], colour::BLUE.stroke_width(2))?;
            axes::error_bar(
                &mut chart,
                mid,
                v - 2.0 * tot,
                v + 2.0 * tot,
                colour::BLUE.stroke_width(1),
            )?;
            axes::error_bar(
                &mut chart,
                mid,
                v - 2.0 * stat,
                v + 2.0 * stat,
                colour::BLUE.stroke_width(4),
            )?;
            axes::dots(&mut chart, [(mid, v)], 6, colour::BLUE.filled())?;
        }
        Ok(())
    }
}
