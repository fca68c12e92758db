//! Each run's track: the plan view (north x up, east y to the right, equal scales) and, for a
//! run with depth, the vertical plane beside it (north x across, depth z down): the data
//! light, the identified model re-simulated open loop, and the smoothed estimate of a fit run.

use super::axes::{self, Axes, Range};
use super::runs::RunView;
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The track of one run.
pub struct Track<'a> {
    run: RunView<'a>,
    vertical: bool,
}

impl<'a> Track<'a> {
    /// The track figure, when the run has positions (measured, re-simulated or smoothed);
    /// with the vertical plane when it has a depth.
    pub fn new(run: RunView<'a>) -> Option<Self> {
        let has = |q| {
            run.measured(q).is_some() || run.simulated(q).is_some() || run.smoothed(q).is_some()
        };
        let vertical = has(Quantity::Z);
        (has(Quantity::X) && has(Quantity::Y)).then_some(Track { run, vertical })
    }

    fn title(&self) -> String {
        format!("Track of {}", self.run.label())
    }
}

/// A path of the run in two coordinates: data, model, smoothed estimate.
struct Paths {
    data: Vec<(f64, f64)>,
    model: Vec<(f64, f64)>,
    smooth: Vec<(f64, f64)>,
}

impl Paths {
    /// The paths of (`across`, `up`) (each scaled by its sign: -1 draws depth down).
    fn of(run: &RunView, across: (Quantity, f64), up: (Quantity, f64)) -> Self {
        let pair = |a: Option<Vec<f64>>, b: Option<Vec<f64>>| -> Vec<(f64, f64)> {
            match (a, b) {
                (Some(a), Some(b)) => a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (x * across.1, y * up.1))
                    .collect(),
                _ => Vec::new(),
            }
        };
        let meas = |q: Quantity| run.measured(q).map(<[f64]>::to_vec);
        Paths {
            data: pair(meas(across.0), meas(up.0)),
            model: pair(run.simulated(across.0), run.simulated(up.0)),
            smooth: pair(run.smoothed(across.0), run.smoothed(up.0)),
        }
    }

    fn range(&self, f: fn(&(f64, f64)) -> f64, what: &str) -> Result<Range, PlotError> {
        Range::require(
            self.data
                .iter()
                .chain(&self.model)
                .chain(&self.smooth)
                .map(f),
            what,
        )
    }

    /// Draws the three paths and the start and end marks.
    fn draw<DB: DrawingBackend>(&self, chart: &mut axes::Chart<'_, DB>) -> Result<(), PlotError> {
        axes::line(
            chart,
            self.data.iter().copied(),
            colour::MEASURED.stroke_width(7),
        )?;
        axes::line(
            chart,
            self.smooth.iter().copied(),
            colour::BLUE.stroke_width(4),
        )?;
        axes::line(
            chart,
            self.model.iter().copied(),
            colour::VERMILLION.stroke_width(2),
        )?;
        axes::dots(chart, self.data.first().copied(), 7, BLACK.stroke_width(2))?;
        axes::dots(chart, self.data.last().copied(), 6, colour::GREY.filled())?;
        axes::dots(
            chart,
            self.model.last().copied(),
            5,
            colour::VERMILLION.filled(),
        )
    }
}

impl Plot for Track<'_> {
    fn meta(&self) -> FigureMeta {
        let m = self.run.metrics;
        let word = self.run.word();
        FigureMeta {
            name: self.run.stem("track"),
            title: self.title(),
            caption: format!(
                "Horizontal track of the {} run '{}' (north x up, east y to the right, equal \
                 scales){}: the {word} track (light) against the identified model \
                 re-simulated open loop from the run's first sample with its inputs{}.{}",
                self.run.kind(),
                self.run.record.name,
                if self.vertical {
                    ", and beside it the vertical plane (north x across, depth z down; the \
                     depth scale is the plane's own)"
                } else {
                    ""
                },
                if self.run.smoothed.is_some() {
                    ", and the filter's smoothed estimate"
                } else {
                    ""
                },
                m.and_then(|m| Some(format!(
                    " Final position error {:.3} % of the {} m travelled.",
                    m.final_position_error_pct?,
                    num(m.distance?)
                )))
                .unwrap_or_default()
            ),
            section: Section::Resim,
            shows: ["x", "y"]
                .into_iter()
                .chain(self.vertical.then_some("z"))
                .map(String::from)
                .collect(),
        }
    }

    fn size(&self) -> (u32, u32) {
        if self.vertical {
            (1600, 850)
        } else {
            (1100, 900)
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let mut keys = vec![
            Key::new(Mark::Line(colour::MEASURED), self.run.word()),
            Key::new(
                Mark::Line(colour::VERMILLION),
                "identified model, open loop",
            ),
        ];
        if self.run.smoothed.is_some() {
            keys.push(Key::new(Mark::Line(colour::BLUE), "smoothed estimate"));
        }
        keys.extend([
            Key::new(Mark::Ring(BLACK), "start"),
            Key::new(Mark::Dot(colour::GREY), "end (data)"),
            Key::new(Mark::Dot(colour::VERMILLION), "end (model)"),
        ]);
        let body = style::frame(root, &self.title(), &keys)?;
        let plan_area = if self.vertical {
            let (w, _) = body.dim_in_pixel();
            let (plan, side) = body.split_horizontally(w * 52 / 100);
            self.side_view(&side)?;
            plan
        } else {
            body
        };
        self.plan(&plan_area)
    }
}

impl Track<'_> {
    /// The plan view, equal scales, with the final position error in the corner.
    fn plan<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let paths = Paths::of(&self.run, (Quantity::Y, 1.0), (Quantity::X, 1.0));
        let east = paths.range(|p| p.0, "y positions")?.pad(0.05);
        let north = paths
            .range(|p| p.1, "x positions")?
            .pad(0.05)
            .headroom(0.06);
        let probe = axes::probe_area(area, east, north)?;
        let (east, north) = axes::equal_aspect(east, north, probe);
        let mut chart = axes::panel(area, &Axes::new(east, north, "east y (m)", "north x (m)"))?;
        paths.draw(&mut chart)?;
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

    /// The vertical plane: north x across, depth z down, the depth on its own scale.
    fn side_view<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), PlotError> {
        let paths = Paths::of(&self.run, (Quantity::X, 1.0), (Quantity::Z, -1.0));
        let north = paths.range(|p| p.0, "x positions")?.pad(0.05);
        let depth = paths.range(|p| p.1, "depths")?.pad(0.08).headroom(0.08);
        let axes = Axes::new(north, depth, "north x (m)", "depth z (m), down")
            .title("vertical plane")
            .flip_y();
        let mut chart = axes::panel(area, &axes)?;
        paths.draw(&mut chart)?;
        let data_depth = Range::of(paths.data.iter().map(|p| -p.1));
        if let Some(d) = data_depth {
            axes::note(
                &chart,
                &[format!(
                    "depth {} m to {} m; depth scale {}× the horizontal",
                    num(d.lo),
                    num(d.hi),
                    num(exaggeration(
                        axes::probe_area(area, north, depth)?,
                        north,
                        depth
                    ))
                )],
            )?;
        }
        Ok(())
    }
}

/// How many times a metre of depth is drawn longer than a metre across in a plotting area of
/// `(w, h)` pixels over `x` and `y` (rounded to two significant digits).
fn exaggeration((w, h): (u32, u32), x: Range, y: Range) -> f64 {
    let per_x = f64::from(w.max(1)) / x.span().max(1e-12);
    let per_y = f64::from(h.max(1)) / y.span().max(1e-12);
    let e = per_y / per_x;
    let digits = 10f64.powi(e.abs().log10().floor() as i32 - 1);
    if e.is_finite() && digits.is_finite() && digits > 0.0 {
        (e / digits).round() * digits
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::resim::ResimTrace;
    use crate::config::DataSource;
    use crate::io::record::Record;
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
            source: DataSource::Cfd,
        };
        let fig = super::super::render(&Track::new(run).unwrap(), None).unwrap();
        assert!(fig.svg.len() < 150_000, "{} bytes", fig.svg.len());
    }
}
