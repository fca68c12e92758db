//! The manoeuvre figures of a run that is a turning circle or a zig-zag (docs/manoeuvres.md),
//! the run beside the identified model steered through the same manoeuvre:
//!
//! * turning circle: the track in the frame of the original course (advance up, transfer
//!   across, from the execute), with the advance, transfer and tactical diameter drawn as
//!   dimension lines, the steady turning circle fitted, and the IMO limits;
//! * zig-zag: the heading change and the rudder against time with the executes, the check
//!   angles and the overshoots marked, and the IMO overshoot limits where they are judged;
//!
//! each with the table of measures (measured, identified model, limit) under it, so that
//! every measure is in the figure.

use super::axes::{self, Axes, Chart, Range};
use super::runs::{without_outliers, RunView};
use super::style::{self, colour, size, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::resim::manoeuvre::ManoeuvreComparison;
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use crate::dynamics::manoeuvre::{
    self, ComparisonTable, Criterion, History, Measure, TurningCircle, ZigZag,
};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

const DEG: f64 = 180.0 / std::f64::consts::PI;

/// Height of one row of the table of measures, pixels.
const ROW: i32 = 25;

/// A run's manoeuvre with the histories the figure draws.
pub struct Sailed<'a> {
    run: RunView<'a>,
    cmp: &'a ManoeuvreComparison,
    /// The run's history, as the measures read it.
    measured: History,
    /// The ship length L the measures are judged with, m.
    length: f64,
}

/// A manoeuvre figure: the turning circle's or the zig-zag's.
pub enum ManoeuvreFigure<'a> {
    /// The track with advance, transfer and diameters marked.
    Turning(Sailed<'a>),
    /// Heading and rudder against time with executes and overshoots marked.
    ZigZag(Sailed<'a>),
}

/// The manoeuvre figure of `run`, when it is a turning circle or a zig-zag; `length` is the
/// ship length L (m) its measures are judged with.
pub fn figure(run: RunView<'_>, length: f64) -> Option<ManoeuvreFigure<'_>> {
    let cmp = run.metrics?.manoeuvre.as_ref()?;
    let measured = manoeuvre::history_of(|q| run.measured(q).map(<[f64]>::to_vec)).ok()??;
    let sailed = Sailed {
        run,
        cmp,
        measured,
        length,
    };
    if cmp.measured.zigzag.is_some() {
        Some(ManoeuvreFigure::ZigZag(sailed))
    } else if cmp.measured.turning_circle.is_some() && sailed.measured.track().is_some() {
        Some(ManoeuvreFigure::Turning(sailed))
    } else {
        None
    }
}

impl Sailed<'_> {
    fn table(&self) -> ComparisonTable {
        self.cmp.table()
    }

    fn title(&self, what: &str) -> String {
        format!("{what} of {}", self.run.label())
    }

    /// The keys of the measures the figure shows (every measure of the run).
    fn shows(&self, quantities: &[Quantity]) -> Vec<String> {
        quantities
            .iter()
            .map(|q| q.key().to_string())
            .chain(
                self.cmp
                    .measured
                    .measures()
                    .iter()
                    .map(|m| m.key.to_string()),
            )
            .collect()
    }

    /// The caption's second half: how the model sailed it, and the limits.
    fn caption_tail(&self) -> String {
        format!(
            "The identified model was steered through the same manoeuvre ({}) from the run's \
             first sample (docs/manoeuvres.md). Under it every measure, the {} run's beside \
             the model's, with the IMO MSC.137(76) limit where a criterion applies; a value \
             marked (fail) exceeds it.",
            self.cmp.steering_text(),
            self.run.word()
        )
    }

    fn table_height(&self) -> u32 {
        (ROW * (self.table().rows.len() as i32 + 2)) as u32 + 20
    }
}

impl Plot for ManoeuvreFigure<'_> {
    fn meta(&self) -> FigureMeta {
        match self {
            ManoeuvreFigure::Turning(s) => FigureMeta {
                name: s.run.stem("turning"),
                title: s.title("Turning circle"),
                caption: format!(
                    "Track of the {} turning circle '{}' in the frame of the original course \
                     (advance along it, up; transfer across it; from the execute; equal \
                     scales): the {} track (light) and the identified model's, each from its \
                     own execute. Marked on the run's track: the advance and transfer at 90 deg \
                     of heading change, the tactical diameter at 180 deg, and the circle \
                     fitted to the steady turn with its diameter; dashed red lines are the \
                     IMO limits (advance 4.5 L, tactical diameter 5 L) where judged. {}",
                    s.run.kind(),
                    s.run.record.name,
                    s.run.word(),
                    s.caption_tail()
                ),
                section: Section::Resim,
                shows: s.shows(&[Quantity::X, Quantity::Y]),
            },
            ManoeuvreFigure::ZigZag(s) => FigureMeta {
                name: s.run.stem("zigzag"),
                title: s.title("Zig-zag"),
                caption: format!(
                    "Heading change from the original course and rudder angle against time \
                     in the {} zig-zag '{}': the {} data (light){} and the identified model \
                     steered through the same test. Marked on the run: the executes E1 to E4, \
                     the check angles (dashed) and the first and second overshoots; dashed red \
                     lines are the IMO overshoot limits where they are judged. {}",
                    s.run.kind(),
                    s.run.record.name,
                    s.run.word(),
                    if s.run.smoothed(Quantity::Yaw).is_some() {
                        ", the filtered heading (the smoother's estimate)"
                    } else {
                        ""
                    },
                    s.caption_tail()
                ),
                section: Section::Resim,
                shows: s.shows(&[Quantity::Yaw, Quantity::Rudder]),
            },
        }
    }

    fn size(&self) -> (u32, u32) {
        match self {
            ManoeuvreFigure::Turning(s) => (1300, 1000 + s.table_height()),
            ManoeuvreFigure::ZigZag(s) => (1400, 720 + s.table_height()),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (s, title, keys) = match self {
            ManoeuvreFigure::Turning(s) => (s, s.title("Turning circle"), turning_keys(s)),
            ManoeuvreFigure::ZigZag(s) => (s, s.title("Zig-zag"), zigzag_keys(s)),
        };
        let body = style::frame(root, &title, &keys)?;
        let (_, h) = body.dim_in_pixel();
        let (plot, table) = body.split_vertically(h.saturating_sub(s.table_height()));
        match self {
            ManoeuvreFigure::Turning(s) => turning(&plot, s)?,
            ManoeuvreFigure::ZigZag(s) => zigzag(&plot, s)?,
        }
        measures_table(&table, &s.table(), s.run.word())
    }
}

/// An angle in degrees for a label: to 0.1 deg, trailing zeros dropped.
fn angle(deg: f64) -> String {
    crate::base::numfmt::fixed_trimmed(deg, 1)
}

/// `v` at time `t`, interpolated linearly (None outside the times).
fn at(time: &[f64], v: &[f64], t: f64) -> Option<f64> {
    if !t.is_finite() || time.is_empty() || t < time[0] || t > time[time.len() - 1] {
        return None;
    }
    let i = time.partition_point(|&s| s <= t).clamp(1, time.len() - 1) - 1;
    let (t0, t1) = (time[i], time[(i + 1).min(time.len() - 1)]);
    let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
    Some(v[i] + w * (v[(i + 1).min(v.len() - 1)] - v[i]))
}

/// The frame of a turn's original course: origin at the execute, advance along the approach
/// heading, transfer across it (positive to starboard).
struct CourseFrame {
    x0: f64,
    y0: f64,
    cos: f64,
    sin: f64,
}

impl CourseFrame {
    fn of(h: &History, t: &TurningCircle) -> Option<Self> {
        let (x, y) = h.track()?;
        Some(CourseFrame {
            x0: at(h.time(), x, t.execute_time)?,
            y0: at(h.time(), y, t.execute_time)?,
            cos: t.approach_heading.cos(),
            sin: t.approach_heading.sin(),
        })
    }

    /// (transfer, advance) of an earth-frame point.
    fn map(&self, x: f64, y: f64) -> (f64, f64) {
        let (dx, dy) = (x - self.x0, y - self.y0);
        (
            -dx * self.sin + dy * self.cos,
            dx * self.cos + dy * self.sin,
        )
    }

    /// The track of `h` in this frame.
    fn track(&self, h: &History) -> Vec<(f64, f64)> {
        h.track().map_or_else(Vec::new, |(x, y)| {
            x.iter().zip(y).map(|(x, y)| self.map(*x, *y)).collect()
        })
    }

    /// Where the track of `h` is `after` s past the execute of `t`.
    fn point(&self, h: &History, t: &TurningCircle, after: &Measure) -> Option<(f64, f64)> {
        let (x, y) = h.track()?;
        let when = t.execute_time + after.value()?;
        Some(self.map(at(h.time(), x, when)?, at(h.time(), y, when)?))
    }
}

fn turning_keys(s: &Sailed) -> Vec<Key> {
    vec![
        Key::new(Mark::Line(colour::MEASURED), s.run.word()),
        Key::new(Mark::Line(colour::VERMILLION), "identified model, steered"),
        Key::new(
            Mark::Dashed(colour::GREEN),
            "steady turning circle (fitted)",
        ),
        Key::new(Mark::Dot(colour::DATA), "90 and 180 deg (run)"),
        Key::new(Mark::Ring(colour::VERMILLION), "90 and 180 deg (model)"),
        Key::new(Mark::Dashed(colour::RED_LIMIT), "IMO limit"),
    ]
}

/// The turning circle's track panel.
fn turning<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, s: &Sailed) -> Result<(), PlotError> {
    let t = s
        .cmp
        .measured
        .turning_circle
        .as_ref()
        .ok_or_else(|| PlotError::new("the run is not a turning circle"))?;
    let frame = CourseFrame::of(&s.measured, t)
        .ok_or_else(|| PlotError::new("the turning circle has no track at its execute"))?;
    let data = frame.track(&s.measured);
    let model = model_track(s);
    let limits = turn_limits(s, t);
    let across = Range::require(data.iter().chain(&model).map(|p| p.0), "transfer")?
        .include(0.0)
        .include(limits.1.unwrap_or(0.0));
    let along = Range::require(data.iter().chain(&model).map(|p| p.1), "advance")?
        .include(limits.0.unwrap_or(0.0));
    let (across, along) = (across.pad(0.06), along.pad(0.06).headroom(0.05));
    let probe = axes::probe_area(area, across, along)?;
    let (across, along) = axes::equal_aspect(across, along, probe);
    let desc = "transfer, across the original course (m; starboard positive)";
    let mut chart = axes::panel(area, &Axes::new(across, along, desc, "advance (m)"))?;
    axes::line(
        &mut chart,
        data.iter().copied(),
        colour::MEASURED.stroke_width(4),
    )?;
    axes::line(
        &mut chart,
        model.iter().copied(),
        colour::VERMILLION.stroke_width(2),
    )?;
    axes::dots(&mut chart, [(0.0, 0.0)], 7, BLACK.stroke_width(2))?;
    let outside = if t.side.sign() > 0.0 {
        HPos::Right
    } else {
        HPos::Left
    };
    label(&mut chart, (0.0, 0.0), "  execute  ", outside, VPos::Center)?;
    if let Some(c) = t.steady_circle(&s.measured) {
        steady_circle(&mut chart, &frame, c, t.side.sign())?;
    }
    turn_dimensions(&mut chart, s, &frame, t)?;
    draw_turn_limits(&mut chart, limits, across, along)?;
    model_turn_points(&mut chart, s)?;
    match &t.advance {
        Measure::Missing(why) => axes::note(&chart, &[format!("advance, transfer: {why}")]),
        Measure::Value(_) => Ok(()),
    }
}

/// The model's track in its own course frame.
fn model_track(s: &Sailed) -> Vec<(f64, f64)> {
    let (Some(h), Some(t)) = (
        s.cmp.model_history.as_ref(),
        s.cmp.model.as_ref().and_then(|m| m.turning_circle.as_ref()),
    ) else {
        return Vec::new();
    };
    CourseFrame::of(h, t).map_or_else(Vec::new, |f| f.track(h))
}

/// The model's 90 and 180 deg points, marked on its track.
fn model_turn_points<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    s: &Sailed,
) -> Result<(), PlotError> {
    let (Some(h), Some(t)) = (
        s.cmp.model_history.as_ref(),
        s.cmp.model.as_ref().and_then(|m| m.turning_circle.as_ref()),
    ) else {
        return Ok(());
    };
    let Some(f) = CourseFrame::of(h, t) else {
        return Ok(());
    };
    let points = [&t.time_to_90, &t.time_to_180]
        .into_iter()
        .filter_map(|m| f.point(h, t, m));
    axes::dots(chart, points, 8, colour::VERMILLION.stroke_width(2))
}

/// The IMO limits of the advance (along) and the tactical diameter (across, on the turn's
/// side), m, where the run's criteria judge a measured value.
fn turn_limits(s: &Sailed, t: &TurningCircle) -> (Option<f64>, Option<f64>) {
    let limit = |c: Criterion| {
        s.cmp
            .measured
            .checks
            .iter()
            .find(|k| k.criterion == c && k.value.value().is_some())
            .map(|k| k.limit)
    };
    (
        limit(Criterion::Advance),
        limit(Criterion::TacticalDiameter).map(|d| d * t.side.sign()),
    )
}

fn draw_turn_limits<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    (advance, diameter): (Option<f64>, Option<f64>),
    across: Range,
    along: Range,
) -> Result<(), PlotError> {
    let red = colour::RED_LIMIT.stroke_width(2);
    if let Some(a) = advance {
        axes::hline(chart, across, a, red, true)?;
        let at = (across.lo + 0.02 * across.span(), a);
        label(
            chart,
            at,
            "IMO limit: advance 4.5 L",
            HPos::Left,
            VPos::Bottom,
        )?;
    }
    if let Some(d) = diameter {
        axes::dashed(chart, [(d, along.lo), (d, along.hi)], red)?;
        let h = if d >= 0.0 { HPos::Right } else { HPos::Left };
        let at = (d, along.lo + 0.03 * along.span());
        label(
            chart,
            at,
            "IMO limit: tactical diameter 5 L ",
            h,
            VPos::Bottom,
        )?;
    }
    Ok(())
}

/// Advance and transfer at 90 deg and the tactical diameter at 180 deg, as dimension lines
/// from the original course, labelled with their values in m and ship lengths.
fn turn_dimensions<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    s: &Sailed,
    frame: &CourseFrame,
    t: &TurningCircle,
) -> Result<(), PlotError> {
    let value = |name: &str, m: &Measure| {
        m.value().map(|v| {
            if s.length > 0.0 {
                format!("{name} {} m = {} L", num(v), num(v / s.length))
            } else {
                format!("{name} {} m", num(v))
            }
        })
    };
    // the labels go outside the turn, beside the original course
    let h = if t.side.sign() > 0.0 {
        HPos::Right
    } else {
        HPos::Left
    };
    if let (Some(p), Some(a), Some(tr)) = (
        frame.point(&s.measured, t, &t.time_to_90),
        value("advance", &t.advance),
        value("transfer", &t.transfer),
    ) {
        dimension(chart, (0.0, 0.0), (0.0, p.1))?;
        dimension(chart, (0.0, p.1), (p.0, p.1))?;
        label(
            chart,
            (0.0, 0.5 * p.1),
            &format!("  {a}  "),
            h,
            VPos::Center,
        )?;
        label(chart, (0.0, p.1), &format!("  {tr}  "), h, VPos::Bottom)?;
        axes::dots(chart, [p], 6, colour::DATA.filled())?;
    }
    if let (Some(p), Some(d)) = (
        frame.point(&s.measured, t, &t.time_to_180),
        value("tactical diameter", &t.tactical_diameter),
    ) {
        dimension(chart, (0.0, p.1), (p.0, p.1))?;
        label(chart, (0.0, p.1), &format!("  {d}  "), h, VPos::Center)?;
        axes::dots(chart, [p], 6, colour::DATA.filled())?;
    }
    Ok(())
}

/// The circle fitted to the steady turn (earth-frame centre and radius), dashed, with its
/// diameter across the original course labelled.
fn steady_circle<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    frame: &CourseFrame,
    (cx, cy, radius): (f64, f64, f64),
    side: f64,
) -> Result<(), PlotError> {
    let (a, b) = frame.map(cx, cy);
    let ring: Vec<(f64, f64)> = (0..=180)
        .map(|k| {
            let phi = k as f64 * std::f64::consts::TAU / 180.0;
            (a + radius * phi.cos(), b + radius * phi.sin())
        })
        .collect();
    axes::dashed(chart, ring, colour::GREEN.stroke_width(2))?;
    let (l, r) = ((a - radius, b), (a + radius, b));
    chart.draw_series(std::iter::once(DashedPathElement::new(
        vec![l, r],
        6,
        4,
        colour::GREEN.stroke_width(1),
    )))?;
    let text = format!("steady turning diameter {} m", num(2.0 * radius));
    let at = (a + 0.05 * radius * side, b);
    label(chart, at, &text, HPos::Center, VPos::Bottom)
}

/// A dimension line from `a` to `b` with end ticks.
fn dimension<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    a: (f64, f64),
    b: (f64, f64),
) -> Result<(), PlotError> {
    let style = colour::DATA.stroke_width(2);
    chart.draw_series(std::iter::once(PathElement::new(vec![a, b], style)))?;
    let vertical = (a.0 - b.0).abs() < (a.1 - b.1).abs();
    let tick: Vec<(i32, i32)> = if vertical {
        vec![(-6, 0), (6, 0)]
    } else {
        vec![(0, -6), (0, 6)]
    };
    for p in [a, b] {
        chart.draw_series(std::iter::once(
            EmptyElement::at(p) + PathElement::new(tick.clone(), style),
        ))?;
    }
    Ok(())
}

/// Text at a data point, anchored at `h`, `v`.
fn label<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    at: (f64, f64),
    text: &str,
    h: HPos,
    v: VPos,
) -> Result<(), PlotError> {
    if !(at.0.is_finite() && at.1.is_finite()) {
        return Ok(());
    }
    chart.draw_series(std::iter::once(Text::new(
        text.to_string(),
        at,
        style::anchored(size::LEGEND, h, v),
    )))?;
    Ok(())
}

fn zigzag_keys(s: &Sailed) -> Vec<Key> {
    let mut keys = vec![
        Key::new(
            Mark::Line(colour::MEASURED),
            format!("heading change, {}", s.run.word()),
        ),
        Key::new(
            Mark::Line(colour::VERMILLION),
            "heading change, identified model",
        ),
    ];
    if s.run.smoothed(Quantity::Yaw).is_some() {
        keys.push(Key::new(
            Mark::Line(colour::BLUE),
            "filtered heading (smoothed)",
        ));
    }
    keys.extend([
        Key::new(
            Mark::Line(colour::GREEN),
            format!("rudder, {}", s.run.word()),
        ),
        Key::new(Mark::Dashed(colour::GREEN), "rudder, model's helm"),
        Key::new(Mark::Dashed(colour::RED_LIMIT), "IMO limit"),
    ]);
    keys
}

/// The executes (up to four) and the two peaks (time, heading change in deg, signed) of a
/// zig-zag in history `h`.
fn swings(h: &History, z: &ZigZag) -> (Vec<f64>, Vec<(f64, f64)>) {
    let (time, side, check) = (h.time(), z.side.sign(), z.heading_angle);
    let change: Vec<f64> = h
        .heading()
        .iter()
        .map(|p| side * (p - z.approach_heading))
        .collect();
    let e1 = z.execute_time;
    let e2 = z.initial_turning_time.value().map(|d| e1 + d);
    let peak1 = e2.zip(z.time_to_check_yaw.value()).map(|(e, d)| e + d);
    let e3 = peak1.and_then(|p| {
        let from = time.partition_point(|&s| s < p);
        (from..time.len())
            .find(|&i| change[i] <= -check)
            .map(|i| time[i])
    });
    let e4 = e2.zip(z.period.value()).map(|(e, d)| e + d);
    let mut peaks = Vec::new();
    if let (Some(p), Some(o)) = (peak1, z.first_overshoot.value()) {
        peaks.push((p, side * (check + o) * DEG));
    }
    if let (Some(e), Some(o)) = (e3, z.second_overshoot.value()) {
        let (a, b) = (
            time.partition_point(|&s| s < e),
            time.partition_point(|&s| s <= e4.unwrap_or(f64::INFINITY)),
        );
        let low = (a..b).min_by(|&i, &j| change[i].total_cmp(&change[j]));
        if let Some(i) = low {
            peaks.push((time[i], -side * (check + o) * DEG));
        }
    }
    let executes = [Some(e1), e2, e3, e4].into_iter().flatten().collect();
    (executes, peaks)
}

/// The zig-zag's heading and rudder panel.
fn zigzag<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, s: &Sailed) -> Result<(), PlotError> {
    let z = s
        .cmp
        .measured
        .zigzag
        .as_ref()
        .ok_or_else(|| PlotError::new("the run is not a zig-zag"))?;
    let series = zigzag_series(s, z);
    let (executes, peaks) = swings(&s.measured, z);
    let limits = zigzag_limits(s, z);
    let check = z.heading_angle * DEG;
    let all = series.iter().flat_map(|(_, p)| p.iter().map(|q| q.1));
    let y = Range::require(all, "heading change")?
        .union(Range::of(limits.iter().map(|l| l.1)).unwrap_or(Range::new(check, check)))
        .pad(0.08)
        .headroom(0.08);
    let t = Range::require(s.measured.time().iter().copied(), "time")?;
    let desc = "heading change ψ − ψ₀, rudder δ (deg)";
    let mut chart = axes::panel(area, &Axes::new(t, y, "time t (s)", desc))?;
    for (style, pts) in &series {
        match style {
            SeriesStyle::Data => axes::data(&mut chart, pts, colour::MEASURED)?,
            SeriesStyle::Line(c, w) => {
                axes::line(&mut chart, pts.iter().copied(), c.stroke_width(*w))?
            }
            SeriesStyle::Dashed(c) => {
                axes::dashed(&mut chart, pts.iter().copied(), c.stroke_width(2))?
            }
        }
    }
    let grey = colour::GREY.stroke_width(1);
    for c in [check, -check] {
        axes::hline(&mut chart, t, c, grey, true)?;
    }
    label(
        &mut chart,
        (t.lo, check),
        &format!(" check angle ±{}°", angle(check)),
        HPos::Left,
        VPos::Bottom,
    )?;
    for (k, e) in executes.iter().enumerate() {
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(*e, y.lo), (*e, y.hi)],
            grey,
        )))?;
        label(
            &mut chart,
            (*e, y.hi),
            &format!(" E{}", k + 1),
            HPos::Left,
            VPos::Top,
        )?;
    }
    overshoots(&mut chart, &peaks, check, z)?;
    for (text, v) in &limits {
        axes::hline(&mut chart, t, *v, colour::RED_LIMIT.stroke_width(2), true)?;
        label(&mut chart, (t.hi, *v), text, HPos::Right, VPos::Bottom)?;
    }
    let missing: Vec<String> = [
        ("first overshoot", &z.first_overshoot),
        ("second overshoot", &z.second_overshoot),
    ]
    .into_iter()
    .filter_map(|(what, m)| match m {
        Measure::Missing(why) => Some(format!("{what}: {why}")),
        Measure::Value(_) => None,
    })
    .collect();
    axes::note(&chart, &missing)
}

/// How a zig-zag series is drawn.
enum SeriesStyle {
    Data,
    Line(RGBColor, u32),
    Dashed(RGBColor),
}

/// The zig-zag's series in deg: the data's heading change (light) and rudder, the filtered
/// heading, and the model's heading change and helm.
fn zigzag_series(s: &Sailed, z: &ZigZag) -> Vec<(SeriesStyle, Vec<(f64, f64)>)> {
    let h = &s.measured;
    let deg = |v: &[f64], psi0: f64| -> Vec<(f64, f64)> {
        h.time()
            .iter()
            .zip(v)
            .map(|(t, p)| (*t, (p - psi0) * DEG))
            .collect()
    };
    let data: Vec<(f64, f64)> = without_outliers(h.time(), h.heading())
        .into_iter()
        .map(|(t, p)| (t, (p - z.approach_heading) * DEG))
        .collect();
    let mut out = vec![(SeriesStyle::Data, data)];
    if let Some(r) = h.rudder() {
        out.push((SeriesStyle::Line(colour::GREEN, 2), deg(r, 0.0)));
    }
    if let Some(f) = s.run.smoothed(Quantity::Yaw) {
        let time = s.run.time().unwrap_or(&[]);
        let pts = time
            .iter()
            .step_by(s.run.stride.max(1))
            .zip(&f)
            .map(|(t, p)| (*t, (p - z.approach_heading) * DEG))
            .collect();
        out.push((SeriesStyle::Line(colour::BLUE, 2), pts));
    }
    let model = s.cmp.model.as_ref().and_then(|m| m.zigzag.as_ref());
    if let (Some(mh), Some(mz)) = (s.cmp.model_history.as_ref(), model) {
        let heading = mh
            .time()
            .iter()
            .zip(mh.heading())
            .map(|(t, p)| (*t, (p - mz.approach_heading) * DEG))
            .collect();
        out.push((SeriesStyle::Line(colour::VERMILLION, 2), heading));
        if let Some(r) = mh.rudder() {
            let helm = mh
                .time()
                .iter()
                .zip(r)
                .map(|(t, d)| (*t, d * DEG))
                .collect();
            out.push((SeriesStyle::Dashed(colour::GREEN), helm));
        }
    }
    out
}

/// The IMO overshoot limits the run's criteria judge, as (label, heading change in deg).
fn zigzag_limits(s: &Sailed, z: &ZigZag) -> Vec<(String, f64)> {
    let (side, check) = (z.side.sign(), z.heading_angle);
    s.cmp
        .measured
        .checks
        .iter()
        .filter_map(|c| {
            let (which, sign) = match c.criterion {
                Criterion::FirstOvershoot10 | Criterion::FirstOvershoot20 => ("1st", side),
                Criterion::SecondOvershoot10 => ("2nd", -side),
                _ => return None,
            };
            let v = sign * (check + c.limit) * DEG;
            Some((
                format!("IMO limit, {which} overshoot {}° ", angle(c.limit * DEG)),
                v,
            ))
        })
        .collect()
}

/// Each overshoot as a bar from the check angle to the peak, labelled.
fn overshoots<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    peaks: &[(f64, f64)],
    check: f64,
    z: &ZigZag,
) -> Result<(), PlotError> {
    let values = [&z.first_overshoot, &z.second_overshoot];
    for (k, ((t, peak), m)) in peaks.iter().zip(values).enumerate() {
        let Some(o) = m.value() else { continue };
        let base = check * peak.signum();
        dimension(chart, (*t, base), (*t, *peak))?;
        let which = if k == 0 { "1st" } else { "2nd" };
        let v = if *peak > 0.0 { VPos::Bottom } else { VPos::Top };
        let text = format!("{which} overshoot {}°", angle(o * DEG));
        label(chart, (*t, *peak), &text, HPos::Center, v)?;
    }
    Ok(())
}

/// The table of measures (measure | unit | data | model | limit) as text, a failed value in
/// red.
fn measures_table<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    table: &ComparisonTable,
    word: &str,
) -> Result<(), PlotError> {
    let header = ["measure", "unit", word, "identified model", "IMO limit"];
    let mut rows: Vec<Vec<String>> = vec![header.iter().map(|s| s.to_string()).collect()];
    rows.extend(table.cells().into_iter().map(|mut r| {
        r[4] = r[4].replace("<=", "≤");
        r
    }));
    let px = size::LEGEND;
    let widths: Vec<i32> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|r| style::text_width(&r[c], px) as i32)
                .max()
                .unwrap_or(0)
        })
        .collect();
    let (x0, y0, gap) = (30, 12, 28);
    let right_aligned = [false, false, true, true, false];
    let mut x = x0;
    for (c, w) in widths.iter().enumerate() {
        for (r, row) in rows.iter().enumerate() {
            let y = y0 + r as i32 * ROW + if r > 0 { 6 } else { 0 };
            let (px_x, h) = if right_aligned[c] {
                (x + w, HPos::Right)
            } else {
                (x, HPos::Left)
            };
            let failed = row[c].contains("(fail)");
            let text_style = style::anchored(px, h, VPos::Top).color(if failed {
                &colour::RED_LIMIT
            } else {
                &BLACK
            });
            area.draw(&Text::new(row[c].clone(), (px_x, y), text_style))?;
        }
        x += w + gap;
    }
    let rule = y0 + ROW;
    area.draw(&PathElement::new(
        vec![(x0, rule), (x - gap, rule)],
        colour::GREY.stroke_width(1),
    ))?;
    Ok(())
}
