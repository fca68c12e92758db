//! Each manoeuvre (fit and validation runs): the x-y track of the CFD run against the
//! identified model re-simulated open loop, and the u, v, r and heading histories with the
//! smoother's estimate of the fit runs.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::numfmt::num;
use crate::quantity::Quantity;
use crate::record::Record;
use crate::resim::{ResimMetrics, ResimTrace};
use crate::results::RunOutput;
use plotters::coord::Shift;
use plotters::prelude::*;

/// One manoeuvre with everything the figures show of it.
#[derive(Debug, Clone, Copy)]
pub struct RunView<'a> {
    /// 1-based number among the runs of its kind.
    pub index: usize,
    /// Used for identification (else validation only).
    pub fit: bool,
    /// The CFD run.
    pub record: &'a Record,
    /// The model re-simulated on it.
    pub sim: &'a ResimTrace,
    /// The re-simulation's metrics.
    pub metrics: Option<&'a ResimMetrics>,
    /// Smoothed states (K x nx, in `sim.quantities` order) of a fit run.
    pub smoothed: Option<&'a [f64]>,
    /// Rows of the run per smoothed sample (`hekf.decimate`): smoothed sample j is row
    /// j * stride.
    pub stride: usize,
}

impl RunView<'_> {
    fn kind(&self) -> &'static str {
        if self.fit {
            "fit"
        } else {
            "validation"
        }
    }

    fn stem(&self, family: &str) -> String {
        format!("{family}_{}_{}", self.kind(), self.index)
    }

    fn label(&self) -> String {
        format!("{} run {}: {}", self.kind(), self.index, self.record.name)
    }

    /// The re-simulated history of `q`.
    fn simulated(&self, q: Quantity) -> Option<Vec<f64>> {
        let i = self.sim.quantities.iter().position(|x| *x == q)?;
        Some(self.sim.states.iter().map(|s| s[i]).collect())
    }

    /// The smoothed history of `q`.
    fn smoothed(&self, q: Quantity) -> Option<Vec<f64>> {
        let nx = self.sim.quantities.len();
        let i = self.sim.quantities.iter().position(|x| *x == q)?;
        Some(self.smoothed?.chunks_exact(nx).map(|s| s[i]).collect())
    }
}

/// The runs of `out` in report order (fit runs, then validation runs).
pub fn runs(out: &RunOutput) -> Vec<RunView<'_>> {
    let traces = out.result.stages.hekf.as_ref().map(|h| &h.traces);
    let stride = out
        .result
        .stages
        .hekf
        .as_ref()
        .map_or(1, |h| h.settings.decimate.max(1));
    let (mut n_fit, mut n_val) = (0, 0);
    out.resim_traces
        .iter()
        .enumerate()
        .map(|(i, (record, sim))| {
            let metrics = out
                .result
                .resimulation
                .get(i)
                .filter(|m| m.run == record.name);
            let fit = metrics.map_or(i < traces.map_or(0, Vec::len), |m| m.used_for_fit);
            let index = if fit {
                n_fit += 1;
                n_fit
            } else {
                n_val += 1;
                n_val
            };
            let nx = sim.quantities.len();
            let smoothed = fit
                .then(|| traces?.get(index - 1))
                .flatten()
                .and_then(|t| t.smoothed.as_deref())
                .filter(|s| nx > 0 && s.len() == nx * record.rows().div_ceil(stride));
            RunView {
                index,
                fit,
                record,
                sim,
                metrics,
                smoothed,
                stride,
            }
        })
        .collect()
}

/// The x-y track.
pub struct Track<'a> {
    run: RunView<'a>,
}

impl<'a> Track<'a> {
    /// The track figure, when the run has positions.
    pub fn new(run: RunView<'a>) -> Option<Self> {
        (run.record.channel(Quantity::X).is_some() && run.record.channel(Quantity::Y).is_some())
            .then_some(Track { run })
    }
}

impl Plot for Track<'_> {
    fn meta(&self) -> FigureMeta {
        let m = self.run.metrics;
        FigureMeta {
            name: self.run.stem("track"),
            title: format!("Track of {}", self.run.label()),
            caption: format!(
                "Horizontal track of the {} run '{}' (north x up, east y to the right, equal \
                 scales): CFD against the identified model re-simulated open loop from the \
                 run's first sample with its thrust history.{}",
                self.run.kind(),
                self.run.record.name,
                m.and_then(|m| Some(format!(
                    " Final position error {:.3} % of the {} m travelled.",
                    m.final_position_error_pct?,
                    num(m.distance?)
                )))
                .unwrap_or_default()
            ),
            section: Section::Resim,
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let rec = self.run.record;
        let (cx, cy) = match (rec.channel(Quantity::X), rec.channel(Quantity::Y)) {
            (Some(x), Some(y)) => (x, y),
            _ => return Err(PlotError::new("the run has no x and y positions")),
        };
        let sx = self.run.simulated(Quantity::X);
        let sy = self.run.simulated(Quantity::Y);
        let keys = vec![
            Key::new(Mark::Line(colour::DATA), "CFD"),
            Key::new(
                Mark::Dashed(colour::VERMILLION),
                "identified model, open loop",
            ),
            Key::new(Mark::Ring(colour::DATA), "start"),
            Key::new(Mark::Dot(colour::DATA), "end (CFD)"),
            Key::new(Mark::Dot(colour::VERMILLION), "end (model)"),
        ];
        let body = style::frame(root, &format!("Track of {}", self.run.label()), &keys)?;
        let sim_pts: Vec<(f64, f64)> = match (&sx, &sy) {
            (Some(x), Some(y)) => y.iter().copied().zip(x.iter().copied()).collect(),
            _ => Vec::new(),
        };
        let east = Range::require(cy.iter().copied(), "y positions")?
            .union(Range::of(sim_pts.iter().map(|p| p.0)).unwrap_or(Range::new(cy[0], cy[0])))
            .pad(0.05);
        let north = Range::require(cx.iter().copied(), "x positions")?
            .union(Range::of(sim_pts.iter().map(|p| p.1)).unwrap_or(Range::new(cx[0], cx[0])))
            .pad(0.05)
            .headroom(0.06);
        // a first chart only to learn the size of the plotting area
        let probe = ChartBuilder::on(&body)
            .margin_left(8)
            .margin_right(22)
            .margin_top(10)
            .margin_bottom(6)
            .x_label_area_size(axes::X_LABEL_AREA)
            .y_label_area_size(axes::Y_LABEL_AREA)
            .build_cartesian_2d(east.span_range(), north.span_range())?
            .plotting_area()
            .dim_in_pixel();
        let (east, north) = axes::equal_aspect(east, north, probe);
        let mut chart = axes::panel(&body, &Axes::new(east, north, "east y (m)", "north x (m)"))?;
        let cfd: Vec<(f64, f64)> = cy.iter().copied().zip(cx.iter().copied()).collect();
        axes::line(
            &mut chart,
            cfd.iter().copied(),
            colour::DATA.stroke_width(3),
        )?;
        axes::dashed(
            &mut chart,
            sim_pts.iter().copied(),
            colour::VERMILLION.stroke_width(2),
        )?;
        axes::dots(
            &mut chart,
            cfd.first().copied(),
            7,
            colour::DATA.stroke_width(2),
        )?;
        axes::dots(&mut chart, cfd.last().copied(), 6, colour::DATA.filled())?;
        axes::dots(
            &mut chart,
            sim_pts.last().copied(),
            5,
            colour::VERMILLION.filled(),
        )?;
        if let Some(m) = self.run.metrics {
            if let (Some(p), Some(dist)) = (m.final_position_error_pct, m.distance) {
                axes::note(
                    &chart,
                    &[format!(
                        "final position error {} m = {:.3} % of the {} m travelled",
                        num(p * dist / 100.0),
                        p,
                        num(dist)
                    )],
                )?;
            }
        }
        Ok(())
    }
}

/// How a state is shown: quantity, axis description, factor from SI.
const SHOWN: [(Quantity, &str, f64); 4] = [
    (Quantity::U, "surge u (m/s)", 1.0),
    (Quantity::V, "sway v (m/s)", 1.0),
    (Quantity::R, "yaw rate r (deg/s)", 57.295_779_513_082_32),
    (Quantity::Yaw, "heading ψ (deg)", 57.295_779_513_082_32),
];

/// The u, v, r and heading histories.
pub struct States<'a> {
    run: RunView<'a>,
    shown: Vec<(Quantity, &'static str, f64)>,
}

impl<'a> States<'a> {
    /// The figure, when the run has at least one of u, v, r, heading.
    pub fn new(run: RunView<'a>) -> Option<Self> {
        let shown: Vec<_> = SHOWN
            .iter()
            .copied()
            .filter(|(q, _, _)| run.record.channel(*q).is_some())
            .collect();
        (!shown.is_empty() && run.record.time().is_some()).then_some(States { run, shown })
    }
}

impl Plot for States<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: self.run.stem("states"),
            title: format!("Motion of {}", self.run.label()),
            caption: format!(
                "Surge, sway, yaw rate and heading of the {} run '{}': CFD, the identified \
                 model re-simulated open loop{}. Under each quantity its difference from the \
                 CFD, with the RMS difference of the re-simulation in the corner.",
                self.run.kind(),
                self.run.record.name,
                if self.run.smoothed.is_some() {
                    ", and the filter's smoothed estimate (RTS smoother, last pass)"
                } else {
                    ""
                }
            ),
            section: Section::Resim,
        }
    }

    fn size(&self) -> (u32, u32) {
        (1400, 160 + 360 * self.shown.len() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let time = self
            .run
            .record
            .time()
            .ok_or_else(|| PlotError::new("the run has no time"))?;
        let mut keys = vec![
            Key::new(Mark::Line(colour::DATA), "CFD"),
            Key::new(
                Mark::Line(colour::VERMILLION),
                "identified model, open loop",
            ),
        ];
        if self.run.smoothed.is_some() {
            keys.push(Key::new(
                Mark::Line(colour::BLUE),
                "smoothed estimate (fit run)",
            ));
        }
        let body = style::frame(root, &format!("Motion of {}", self.run.label()), &keys)?;
        let t = Range::require(time.iter().copied(), "time")?;
        let n = self.shown.len();
        for (i, (area, (q, desc, k))) in body
            .split_evenly((n, 1))
            .iter()
            .zip(&self.shown)
            .enumerate()
        {
            let scaled = |v: Option<Vec<f64>>| -> Vec<f64> {
                v.map(|v| v.iter().map(|x| x * k).collect())
                    .unwrap_or_default()
            };
            let cfd = scaled(self.run.record.channel(*q).map(<[f64]>::to_vec));
            let sim = scaled(self.run.simulated(*q));
            let smooth = scaled(self.run.smoothed(*q));
            // a series with one value every `stride` rows, against the CFD at those rows
            let diff = |v: &[f64], stride: usize| -> Vec<(f64, f64)> {
                time.iter()
                    .step_by(stride)
                    .zip(v.iter().zip(cfd.iter().step_by(stride)))
                    .map(|(t, (a, b))| (*t, a - b))
                    .collect()
            };
            let stride = self.run.stride.max(1);
            let (d_sim, d_smooth) = (diff(&sim, 1), diff(&smooth, stride));
            let y = Range::require(cfd.iter().copied(), desc)?
                .union(Range::of(sim.iter().copied()).unwrap_or(Range::new(cfd[0], cfd[0])))
                .pad(0.08);
            let (top, bottom) = area.split_vertically(area.dim_in_pixel().1 * 62 / 100);
            let mut chart = axes::panel(&top, &Axes::new(t, y, "", desc))?;
            let series = |v: &[f64], stride: usize| {
                time.iter()
                    .step_by(stride)
                    .copied()
                    .zip(v.iter().copied())
                    .collect::<Vec<_>>()
            };
            axes::line(&mut chart, series(&cfd, 1), colour::DATA.stroke_width(3))?;
            axes::line(
                &mut chart,
                series(&sim, 1),
                colour::VERMILLION.stroke_width(2),
            )?;
            axes::line(
                &mut chart,
                series(&smooth, stride),
                colour::BLUE.stroke_width(1),
            )?;
            let unit = desc.rsplit('(').next().unwrap_or(")").trim_end_matches(')');
            let dy = Range::of(d_sim.iter().chain(&d_smooth).map(|p| p.1))
                .unwrap_or(Range::new(-1.0, 1.0))
                .symmetric()
                .pad(0.1)
                .headroom(0.5);
            let d_desc = format!("difference ({unit})");
            let mut dchart = axes::panel(
                &bottom,
                &Axes::new(t, dy, if i + 1 == n { "time t (s)" } else { "" }, &d_desc),
            )?;
            axes::hline(&mut dchart, t, 0.0, colour::GREY.stroke_width(1), false)?;
            axes::line(&mut dchart, d_smooth, colour::BLUE.stroke_width(1))?;
            axes::line(&mut dchart, d_sim, colour::VERMILLION.stroke_width(1))?;
            if let Some(rms) = self.run.metrics.and_then(|m| m.rms.get(q)) {
                axes::note(
                    &dchart,
                    &[format!("RMS(model − CFD) = {} {unit}", num(rms * k))],
                )?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn a_long_turning_run_draws_a_small_track() {
        // 300,000 samples going round 50 times, the model drifting away slowly
        let k = 300_000;
        let a = |i: usize| i as f64 * 50.0 * std::f64::consts::TAU / k as f64;
        let ch = |f: &dyn Fn(usize) -> f64| (0..k).map(f).collect::<Vec<f64>>();
        let mut channels = BTreeMap::new();
        channels.insert(Quantity::Time, ch(&|i| i as f64 * 0.01));
        channels.insert(Quantity::X, ch(&|i| 4.0 * a(i).sin()));
        channels.insert(Quantity::Y, ch(&|i| 4.0 * (1.0 - a(i).cos())));
        let record = Record::from_channels("circles", "circles.csv", channels);
        let sim = ResimTrace {
            times: record.time().unwrap().to_vec(),
            states: (0..k)
                .map(|i| {
                    let d = 1.0 + i as f64 * 1e-6;
                    vec![4.0 * d * a(i).sin(), 4.0 * d * (1.0 - a(i).cos())]
                })
                .collect(),
            quantities: vec![Quantity::X, Quantity::Y],
            outputs: Vec::new(),
            output_values: Vec::new(),
            inputs: Vec::new(),
        };
        let run = RunView {
            index: 1,
            fit: true,
            record: &record,
            sim: &sim,
            metrics: None,
            smoothed: None,
            stride: 1,
        };
        let fig = super::super::render(&Track::new(run).unwrap(), None).unwrap();
        assert!(fig.svg.len() < 150_000, "{} bytes", fig.svg.len());
    }
}
