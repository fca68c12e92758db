//! The paper's figures of the autopilot (Dinh, Hoang & Pham 2016, fig. 6-8;
//! docs/models/nomoto.md, "The paper's figures"): the error of the filtered against the true
//! heading with an ordinary low-pass filter and with the EKF wave filter, the heading's
//! response to the set course, and the rudder angle, every feed. Their data are the
//! autopilot's series (`autopilot/FEED.csv`).

use super::autopilot::look;
use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::dynamics::autopilot::{AutopilotResult, ClosedLoop, Feed};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Samples in degrees against time.
fn degrees(times: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    times
        .iter()
        .zip(v)
        .map(|(t, v)| (*t, v.to_degrees()))
        .collect()
}

/// A filtered heading's error against the true low-frequency heading, in degrees.
fn error(l: &ClosedLoop, filtered: &[f64]) -> Vec<(f64, f64)> {
    l.times
        .iter()
        .zip(filtered.iter().zip(&l.series.heading_lf))
        .map(|(t, (f, lf))| (*t, (f - lf).to_degrees()))
        .collect()
}

/// A line with its legend label and colour.
type Labelled = (String, RGBColor, Vec<(f64, f64)>);

/// Fig. 6: the filtered heading's error, the ordinary low-pass filter's and the EKF's, each
/// from the loop it feeds when that feed ran, else from beside the first loop that has it.
#[derive(Debug, Clone)]
pub struct FilterError<'a> {
    ekf: Option<(&'a ClosedLoop, &'a [f64])>,
    lowpass: Option<(&'a ClosedLoop, &'a [f64])>,
}

impl<'a> FilterError<'a> {
    /// The figure of `a`; None when neither filter ran.
    pub fn new(a: &'a AutopilotResult) -> Option<Self> {
        let pick = |feed: Feed, col: fn(&ClosedLoop) -> Option<&[f64]>| {
            a.feed(feed)
                .into_iter()
                .chain(&a.feeds)
                .find_map(|l| col(l).map(|c| (l, c)))
        };
        let ekf = pick(Feed::Filter, |l| l.series.ekf.as_deref());
        let lowpass = pick(Feed::LowPass, |l| l.series.lowpass.as_deref());
        (ekf.is_some() || lowpass.is_some()).then_some(FilterError { ekf, lowpass })
    }

    /// The lines drawn: label, colour, points.
    fn lines(&self) -> Vec<Labelled> {
        let mut out = Vec::new();
        for (which, name, colour) in [
            (self.lowpass, "ordinary low-pass filter", colour::VERMILLION),
            (self.ekf, "EKF wave filter", colour::BLUE),
        ] {
            if let Some((l, col)) = which {
                let rms = l.series.error_rms(col).to_degrees();
                let label = format!("{name}: RMS {rms:.3} deg (loop fed {})", l.feed.describe());
                out.push((label, colour, error(l, col)));
            }
        }
        out
    }
}

impl Plot for FilterError<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "autopilot_filter_error".into(),
            title: "Filtered heading against the true heading".into(),
            caption: "The paper's fig. 6: the error of the filtered heading against the true \
                      low-frequency heading psi_L, with the ordinary low-pass filter on the \
                      compass (red) and with the EKF wave filter (blue), each in the closed \
                      loop it feeds (the legend names the loop), with its RMS."
                .into(),
            section: Section::Resim,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 600)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let lines = self.lines();
        let keys: Vec<Key> = lines
            .iter()
            .map(|(label, c, _)| Key::new(Mark::Line(*c), label.clone()))
            .collect();
        let body = style::frame(root, "Filtered heading against the true heading", &keys)?;
        let points = || lines.iter().flat_map(|l| l.2.iter());
        let x = Range::require(points().map(|p| p.0), "time")?;
        let y = Range::require(points().map(|p| p.1), "heading error")?
            .symmetric()
            .pad(0.06);
        let desc = "filtered - true heading (deg)";
        let mut chart = axes::panel(&body, &Axes::new(x, y, "time (s)", desc))?;
        for (_, c, pts) in &lines {
            axes::line(&mut chart, pts.iter().copied(), c.stroke_width(2))?;
        }
        Ok(())
    }
}

/// Fig. 7: the course ordered, the reference model's heading and each feed's true
/// low-frequency heading.
#[derive(Debug, Clone, Copy)]
pub struct CourseChange<'a>(pub &'a AutopilotResult);

impl Plot for CourseChange<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "autopilot_course_change".into(),
            title: "Heading response to the course change".into(),
            caption: "The paper's fig. 7: the course ordered (dashed), the reference model's \
                      heading (grey) and the ship's true low-frequency heading in the closed \
                      loop of each feed."
                .into(),
            section: Section::Resim,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 650)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let a = self.0;
        let Some(first) = a.feeds.first() else {
            return Err(PlotError::new("no closed-loop run"));
        };
        let mut keys = vec![
            Key::new(Mark::Dashed(colour::DATA), "course ordered"),
            Key::new(Mark::Line(colour::GREY), "reference heading"),
        ];
        keys.extend(
            a.feeds
                .iter()
                .map(|c| Key::new(Mark::Line(look(c.feed).0), c.feed.describe())),
        );
        let body = style::frame(root, "Heading response to the course change", &keys)?;
        let ordered = degrees(&first.times, &first.series.ordered);
        let reference = degrees(&first.times, &first.series.reference);
        let headings: Vec<Vec<(f64, f64)>> = a
            .feeds
            .iter()
            .map(|c| degrees(&c.times, &c.series.heading_lf))
            .collect();
        let all = || {
            ordered
                .iter()
                .chain(&reference)
                .chain(headings.iter().flatten())
        };
        let x = Range::require(all().map(|p| p.0), "time")?;
        let y = Range::require(all().map(|p| p.1), "heading")?.pad(0.06);
        let mut chart = axes::panel(&body, &Axes::new(x, y, "time (s)", "heading (deg)"))?;
        axes::dashed(&mut chart, ordered, colour::DATA.stroke_width(2))?;
        axes::line(&mut chart, reference, colour::GREY.stroke_width(2))?;
        for (c, line) in a.feeds.iter().zip(&headings) {
            let (colour, width) = look(c.feed);
            axes::line(&mut chart, line.iter().copied(), colour.stroke_width(width))?;
        }
        Ok(())
    }
}

/// Fig. 8: the rudder angle of each feed's loop, a panel each on a common scale.
#[derive(Debug, Clone, Copy)]
pub struct Rudder<'a>(pub &'a AutopilotResult);

/// Height of one feed's panel, pixels.
const RUDDER_PANEL: u32 = 230;

impl Plot for Rudder<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "autopilot_rudder".into(),
            title: "Rudder angle per feed".into(),
            caption: "The paper's fig. 8: the rudder angle in the closed loop of each feed, \
                      one panel each on the same scale, with its RMS and its rate's RMS."
                .into(),
            section: Section::Resim,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 120 + RUDDER_PANEL * self.0.feeds.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let a = self.0;
        let body = style::frame(root, "Rudder angle per feed", &[])?;
        let lines: Vec<Vec<(f64, f64)>> = a
            .feeds
            .iter()
            .map(|c| degrees(&c.times, &c.rudder))
            .collect();
        let x = Range::require(lines.iter().flatten().map(|p| p.0), "time")?;
        let y = Range::require(lines.iter().flatten().map(|p| p.1), "rudder")?.pad(0.06);
        let panels = body.split_evenly((a.feeds.len().max(1), 1));
        let last = a.feeds.len().saturating_sub(1);
        for (i, ((area, c), line)) in panels.iter().zip(&a.feeds).zip(&lines).enumerate() {
            let title = format!(
                "{}: RMS {:.3} deg, rate RMS {:.3} deg/s",
                c.feed.describe(),
                c.rudder_rms.to_degrees(),
                c.rudder_rate_rms.to_degrees()
            );
            let x_desc = if i == last { "time (s)" } else { "" };
            let axes = Axes::new(x, y, x_desc, "rudder (deg)").title(&title);
            let mut chart = axes::panel(area, &axes)?;
            let (colour, width) = look(c.feed);
            axes::line(&mut chart, line.iter().copied(), colour.stroke_width(width))?;
        }
        Ok(())
    }
}
