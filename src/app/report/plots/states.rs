//! The time histories of a run, one figure per plane ([`Plane`]): each state the model has
//! and the run measures (or the smoother estimates) with the data drawn light, the identified
//! model re-simulated open loop and the smoothed estimate of a fit run; under each measured
//! state the difference model − data on an axis scaled to the data's noise; the control
//! inputs under the states they drive.

use super::axes::{self, Axes, Range};
use super::panels::{self, unit_of, Panel, Plane};
use super::runs::{without_outliers, RunView};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::base::numfmt::num;
use crate::numerics::signal;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Height of a state panel with its difference panel, of one without, of a control, pixels.
const HEIGHTS: (u32, u32, u32) = (330, 230, 170);

/// The half-height of a difference axis, in noise sigmas (the noise fills about half of it).
const NOISE_SPAN: f64 = 4.0;

/// Running means of the difference are taken over this share of the run's samples.
const MEAN_SHARE: usize = 100;

/// The time histories of one plane of a run.
pub struct States<'a> {
    run: RunView<'a>,
    plane: Plane,
    panels: Vec<Panel>,
}

impl<'a> States<'a> {
    /// The figures of `run`, one per plane with at least one panel (none without a time).
    pub fn of(run: RunView<'a>) -> Vec<Self> {
        if run.time().is_none() {
            return Vec::new();
        }
        panels::panels(&run)
            .into_iter()
            .map(|(plane, panels)| States { run, plane, panels })
            .collect()
    }

    fn title(&self) -> String {
        format!("{} of {}", self.plane.title(), self.run.label())
    }

    fn has_smoothed(&self) -> bool {
        self.panels
            .iter()
            .any(|p| !p.control && self.run.smoothed(p.shown.quantity).is_some())
    }

    fn keys(&self) -> Vec<Key> {
        let word = self.run.word();
        let mut keys = vec![
            Key::new(Mark::Line(colour::MEASURED), word),
            Key::new(
                Mark::Line(colour::VERMILLION),
                "identified model, open loop",
            ),
        ];
        if self.has_smoothed() {
            keys.push(Key::new(
                Mark::Line(colour::BLUE),
                "smoothed estimate (fit run; under the model where they agree)",
            ));
        }
        if self.panels.iter().any(|p| p.measured && !p.control) {
            keys.push(Key::new(
                Mark::Band(colour::GREY),
                "±2σ of the data's noise",
            ));
        }
        if self.panels.iter().any(|p| p.control) {
            keys.push(Key::new(Mark::Line(colour::GREEN), "control input"));
        }
        keys
    }

    fn height_of(p: &Panel) -> u32 {
        match (p.control, p.measured) {
            (true, _) => HEIGHTS.2,
            (false, true) => HEIGHTS.0,
            (false, false) => HEIGHTS.1,
        }
    }
}

impl Plot for States<'_> {
    fn meta(&self) -> FigureMeta {
        let run = &self.run;
        let names: Vec<String> = self
            .panels
            .iter()
            .map(|p| {
                let l = &p.shown.label;
                l.rsplit_once(" (").map_or(l.clone(), |x| x.0.to_string())
            })
            .collect();
        let constants = panels::constant_inputs(run);
        FigureMeta {
            name: run.stem(self.plane.family()),
            title: self.title(),
            caption: format!(
                "{} of the {} run '{}' against time: the {} data (light), the identified model \
                 re-simulated open loop from the run's first sample with the run's inputs{}. \
                 Under each measured quantity the difference model − {}: the samples (light), \
                 their running mean over {} % of the run (red) and ±2σ of the data's noise \
                 (estimated from the data), on an axis of about ±{} noise σ, so that a model \
                 error shows where it stands out of the noise; the RMS difference in the \
                 corner. {}{}",
                capitalise(&names.join(", ")),
                run.kind(),
                run.record.name,
                run.word(),
                if self.has_smoothed() {
                    ", and the filter's smoothed estimate (RTS smoother, last pass)"
                } else {
                    ""
                },
                run.word(),
                num(100.0 / MEAN_SHARE as f64),
                num(NOISE_SPAN),
                if self.panels.iter().any(|p| p.control) {
                    "Control inputs as the run gives them, under the states they drive. "
                } else {
                    ""
                },
                if constants.is_empty() {
                    String::new()
                } else {
                    format!("Held constant: {}.", constants.join(", "))
                }
            ),
            section: Section::Resim,
            shows: self
                .panels
                .iter()
                .map(|p| p.shown.quantity.key().to_string())
                .collect(),
        }
    }

    fn size(&self) -> (u32, u32) {
        let legend = 110;
        (
            1400,
            legend + self.panels.iter().map(Self::height_of).sum::<u32>(),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let time = self
            .run
            .time()
            .ok_or_else(|| PlotError::new("the run has no time"))?;
        let body = style::frame(root, &self.title(), &self.keys())?;
        let t = Range::require(time.iter().copied(), "time")?;
        let mut rest = body;
        let n = self.panels.len();
        for (i, p) in self.panels.iter().enumerate() {
            let h = Self::height_of(p);
            let (area, below) = if i + 1 == n {
                let a = rest.clone();
                (a, rest.clone())
            } else {
                rest.split_vertically(h)
            };
            let last = i + 1 == n;
            if p.control {
                control_panel(&area, &self.run, p, t, last)?;
            } else {
                state_panel(&area, &self.run, p, t, last)?;
            }
            rest = below;
        }
        Ok(())
    }
}

/// "heading ψ, rudder" -> "Heading ψ, rudder".
fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

/// `v` scaled by `k` against the run's time (every `stride`-th row).
fn series(time: &[f64], v: &[f64], stride: usize, k: f64) -> Vec<(f64, f64)> {
    time.iter()
        .step_by(stride.max(1))
        .zip(v)
        .map(|(t, y)| (*t, y * k))
        .collect()
}

/// One state: the data light, the smoothed estimate and the model over them; under it, when
/// the run measures the state, the difference model − data scaled to the data's noise.
fn state_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    run: &RunView,
    p: &Panel,
    t: Range,
    last: bool,
) -> Result<(), PlotError> {
    let (q, k, label) = (p.shown.quantity, p.shown.factor, p.shown.label.as_str());
    let time = run.time().unwrap_or(&[]);
    let data: Vec<(f64, f64)> = run
        .measured(q)
        .map(|v| without_outliers(time, v))
        .unwrap_or_default()
        .into_iter()
        .map(|(t, y)| (t, y * k))
        .collect();
    let model = run
        .model_reading(q)
        .map(|v| series(time, &v, 1, k))
        .unwrap_or_default();
    let smooth = run
        .smoothed(q)
        .map(|v| series(time, &v, run.stride, k))
        .unwrap_or_default();
    let y = Range::require(data.iter().chain(&model).chain(&smooth).map(|p| p.1), label)?.pad(0.08);
    let (top, bottom) = if p.measured {
        area.split_vertically(area.dim_in_pixel().1 * 60 / 100)
    } else {
        (area.clone(), area.clone())
    };
    let x_desc = if last && !p.measured {
        "time t (s)"
    } else {
        ""
    };
    let mut chart = axes::panel(&top, &Axes::new(t, y, x_desc, label))?;
    axes::data(&mut chart, &data, colour::MEASURED)?;
    axes::line(&mut chart, smooth, colour::BLUE.stroke_width(4))?;
    axes::line(
        &mut chart,
        model.iter().copied(),
        colour::VERMILLION.stroke_width(2),
    )?;
    if p.measured {
        let rms = run.metrics.and_then(|m| m.rms.get(&q)).map(|r| r * k);
        difference_panel(&bottom, run, &data, &model, (t, unit_of(label)), rms, last)?;
    }
    Ok(())
}

/// The difference model − data under a state: the samples light, their running mean, and
/// ±2σ of the data's noise, on an axis of about ±[`NOISE_SPAN`] noise sigmas (wider when the
/// running mean needs it).
fn difference_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    run: &RunView,
    data: &[(f64, f64)],
    model: &[(f64, f64)],
    (t, unit): (Range, &str),
    rms: Option<f64>,
    last: bool,
) -> Result<(), PlotError> {
    let diff = differences(data, model);
    let values: Vec<f64> = diff.iter().map(|p| p.1).collect();
    let raw: Vec<f64> = data.iter().map(|p| p.1).collect();
    let (lo, hi) = signal::range(raw.iter().copied());
    // a noise below a part in 10^6 of the signal is the export's rounding: no noise
    let noise = signal::noise_sigma(&raw)
        .filter(|s| s.is_finite() && *s > 1e-6 * (hi - lo).abs().max(hi.abs()))
        .unwrap_or(0.0);
    let mean = running_mean(&values, (values.len() / MEAN_SHARE).max(1));
    let drift = mean.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let widest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let half = if noise > 0.0 {
        (NOISE_SPAN * noise).max(1.25 * drift)
    } else {
        1.1 * widest
    };
    let dy = Range::new(-half, half).pad(0.0).headroom(0.35);
    let desc = format!("difference ({unit})");
    let x_desc = if last { "time t (s)" } else { "" };
    let mut chart = axes::panel(area, &Axes::new(t, dy, x_desc, &desc))?;
    if noise > 0.0 {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(t.lo, -2.0 * noise), (t.hi, 2.0 * noise)],
            colour::GREY.mix(0.18).filled(),
        )))?;
    }
    axes::hline(&mut chart, t, 0.0, colour::GREY.stroke_width(1), false)?;
    axes::data(&mut chart, &diff, colour::MEASURED)?;
    let mean_pts: Vec<(f64, f64)> = diff.iter().map(|p| p.0).zip(mean).collect();
    axes::line(&mut chart, mean_pts, colour::VERMILLION.stroke_width(2))?;
    let mut note = Vec::new();
    if let Some(r) = rms {
        note.push(format!("RMS(model − {}) = {} {unit}", run.word(), num(r)));
    }
    if noise > 0.0 {
        note.push(format!("noise σ of the data ≈ {} {unit}", num(noise)));
    }
    axes::note(&chart, &[note.join(";  ")])
}

/// model − data at the data's times (the model's samples are the run's rows; data points
/// left out as outliers are skipped).
fn differences(data: &[(f64, f64)], model: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(data.len());
    let mut j = 0;
    for &(t, y) in data {
        while j < model.len() && model[j].0 < t {
            j += 1;
        }
        match model.get(j) {
            Some(&(tm, m)) if tm == t => out.push((t, m - y)),
            Some(_) => {}
            None => break,
        }
    }
    out
}

/// The centred running mean of `v` over `window` samples (shorter at the ends); non-finite
/// values are left out of each mean.
pub fn running_mean(v: &[f64], window: usize) -> Vec<f64> {
    let mut sum = vec![0.0; v.len() + 1];
    let mut count = vec![0usize; v.len() + 1];
    for (i, x) in v.iter().enumerate() {
        let ok = x.is_finite();
        sum[i + 1] = sum[i] + if ok { *x } else { 0.0 };
        count[i + 1] = count[i] + usize::from(ok);
    }
    let half = window / 2;
    (0..v.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(v.len()));
            let n = count[b] - count[a];
            if n == 0 {
                f64::NAN
            } else {
                (sum[b] - sum[a]) / n as f64
            }
        })
        .collect()
}

/// A control input as the run gives it.
fn control_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    run: &RunView,
    p: &Panel,
    t: Range,
    last: bool,
) -> Result<(), PlotError> {
    let time = run.time().unwrap_or(&[]);
    let (k, label) = (p.shown.factor, p.shown.label.as_str());
    let v = run.measured(p.shown.quantity).unwrap_or(&[]);
    let pts = series(time, v, 1, k);
    let y = Range::require(pts.iter().map(|p| p.1), label)?.pad(0.12);
    let x_desc = if last { "time t (s)" } else { "" };
    let mut chart = axes::panel(area, &Axes::new(t, y, x_desc, label))?;
    axes::hline(&mut chart, t, 0.0, colour::GREY.stroke_width(1), false)?;
    axes::line(&mut chart, pts, colour::GREEN.stroke_width(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_means_skip_gaps_and_shrink_at_the_ends() {
        let m = running_mean(&[1.0, 2.0, f64::NAN, 4.0, 5.0], 3);
        assert_eq!(m[0], 1.5);
        assert_eq!(m[1], 1.5);
        assert_eq!(m[2], 3.0);
        assert_eq!(m[4], 4.5);
        assert!(running_mean(&[f64::NAN], 1)[0].is_nan());
    }

    #[test]
    fn differences_pair_the_same_times() {
        let data = [(0.0, 1.0), (2.0, 3.0), (3.0, 1.0)];
        let model = [(0.0, 2.0), (1.0, 0.0), (2.0, 2.0)];
        assert_eq!(differences(&data, &model), vec![(0.0, 1.0), (2.0, -1.0)]);
    }
}
