//! The autopilot in waves (`[autopilot]`, docs/models/nomoto.md): heading error, rudder angle
//! and rudder rate of the closed loop for every feed asked for (raw compass and gyro, the
//! differentiated compass, the wave filter, the true heading), and the heading's spectrum
//! before and after filtering.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::dynamics::autopilot::{AutopilotResult, ClosedLoop, Feed};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Heading error, rudder and rudder rate over time, both feeds.
#[derive(Debug, Clone, Copy)]
pub struct Histories<'a>(pub &'a AutopilotResult);

/// The spectrum of the raw compass and of the filtered heading.
#[derive(Debug, Clone, Copy)]
pub struct Spectrum<'a>(pub &'a AutopilotResult);

/// Each feed's colour and line width.
pub(super) fn look(feed: Feed) -> (RGBColor, u32) {
    match feed {
        Feed::Raw => (colour::VERMILLION, 1),
        Feed::Differentiated => (colour::ORANGE, 1),
        Feed::Filter => (colour::BLUE, 2),
        Feed::LowPass => (colour::SKY, 2),
        Feed::True => (colour::GREEN, 2),
        Feed::Adaptive => (colour::PURPLE, 2),
    }
}

fn keys(a: &AutopilotResult) -> Vec<Key> {
    a.feeds
        .iter()
        .map(|c| Key::new(Mark::Line(look(c.feed).0), c.feed.describe()))
        .collect()
}

impl Plot for Histories<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "autopilot".into(),
            title: "Autopilot in waves".into(),
            caption: "The closed loop per feed: raw compass and gyro (red), compass and its \
                      difference (orange), the wave filter's low-frequency heading and yaw \
                      rate (blue), the true low-frequency heading (green): heading error \
                      from the reference, rudder angle and rudder rate."
                .into(),
            section: Section::Resim,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 1000)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let a = self.0;
        let body = style::frame(root, "Autopilot in waves", &keys(a))?;
        let panels = body.split_evenly((3, 1));
        let rate = |v: &[f64], t: &[f64]| -> Vec<(f64, f64)> {
            t.windows(2)
                .zip(v.windows(2))
                .map(|(t, v)| (t[1], ((v[1] - v[0]) / (t[1] - t[0])).to_degrees()))
                .collect()
        };
        let series = |c: &ClosedLoop, which: usize| -> Vec<(f64, f64)> {
            match which {
                0 => c
                    .times
                    .iter()
                    .zip(&c.heading_error)
                    .map(|(t, v)| (*t, v.to_degrees()))
                    .collect(),
                1 => c
                    .times
                    .iter()
                    .zip(&c.rudder)
                    .map(|(t, v)| (*t, v.to_degrees()))
                    .collect(),
                _ => rate(&c.rudder, &c.times),
            }
        };
        let descs = ["heading error (deg)", "rudder (deg)", "rudder rate (deg/s)"];
        for (i, (area, desc)) in panels.iter().zip(descs).enumerate() {
            let lines: Vec<Vec<(f64, f64)>> = a.feeds.iter().map(|c| series(c, i)).collect();
            let x = Range::require(lines.iter().flatten().map(|p| p.0), "time")?;
            let y = Range::require(lines.iter().flatten().map(|p| p.1), desc)?.pad(0.06);
            let mut chart = axes::panel(
                area,
                &Axes::new(x, y, if i == 2 { "time (s)" } else { "" }, desc),
            )?;
            for (c, line) in a.feeds.iter().zip(&lines) {
                let (colour, width) = look(c.feed);
                axes::line(&mut chart, line.iter().copied(), colour.stroke_width(width))?;
            }
        }
        Ok(())
    }
}

impl Plot for Spectrum<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "heading_spectrum".into(),
            title: "Heading spectrum before and after the wave filter".into(),
            caption: "Periodogram of the compass (red) and of the heading the autopilot saw \
                      (blue) in the closed loop fed the wave filter (or the first feed asked \
                      for without it), log scale: the filter takes out the wave-frequency \
                      peak."
                .into(),
            section: Section::Resim,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 650)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let Some(c) = self.0.feed(Feed::Filter).or(self.0.feeds.first()) else {
            return Ok(());
        };
        let body = style::frame(
            root,
            "Heading spectrum before and after the wave filter",
            &[
                Key::new(Mark::Line(colour::VERMILLION), "compass"),
                Key::new(
                    Mark::Line(colour::BLUE),
                    "heading seen (psi_L with the filter)",
                ),
            ],
        )?;
        let ws = crate::numerics::signal::log_frequencies(0.02, 3.0, 300);
        let floor = 1e-12;
        let log = |p: Vec<f64>| -> Vec<(f64, f64)> {
            ws.iter()
                .zip(p)
                .map(|(w, p)| (*w, p.max(floor).log10()))
                .collect()
        };
        let raw = log(crate::numerics::signal::periodogram(
            &c.times, &c.compass, &ws,
        ));
        let fil = log(crate::numerics::signal::periodogram(&c.times, &c.seen, &ws));
        let x = Range::new(ws[0], ws[ws.len() - 1]);
        let y = Range::require(raw.iter().chain(&fil).map(|p| p.1), "spectrum")?;
        let mut chart = axes::panel(
            &body,
            &Axes::new(x, y, "frequency (rad/s)", "power (rad^2 s/rad), log scale").log_y(),
        )?;
        axes::line(
            &mut chart,
            raw.iter().copied(),
            colour::VERMILLION.stroke_width(2),
        )?;
        axes::line(
            &mut chart,
            fil.iter().copied(),
            colour::BLUE.stroke_width(2),
        )?;
        Ok(())
    }
}
