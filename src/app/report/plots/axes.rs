//! Axes shared by the figures: data ranges that ignore non-finite values, the standard
//! Cartesian panel (grid, tick labels, axis descriptions), equal aspect ratio, and the
//! thinning of long series so that a figure stays small without changing what it shows:
//! every line, band, path and scatter is drawn with at most about four points per pixel
//! column of its panel, whatever the length of the run.

use super::style::{self, colour, size};
use super::PlotError;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

/// A closed interval of data values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Range {
    /// An interval.
    pub fn new(lo: f64, hi: f64) -> Self {
        Range { lo, hi }
    }

    /// The smallest interval holding every finite value (None when there is none).
    pub fn of(values: impl IntoIterator<Item = f64>) -> Option<Self> {
        values
            .into_iter()
            .filter(|v| v.is_finite())
            .fold(None, |r: Option<Range>, v| {
                Some(r.map_or(Range::new(v, v), |r| r.include(v)))
            })
    }

    /// Like [`Range::of`], but an error naming `what` when nothing is finite.
    pub fn require(values: impl IntoIterator<Item = f64>, what: &str) -> Result<Self, PlotError> {
        Range::of(values).ok_or_else(|| PlotError::new(format!("{what}: no finite value to plot")))
    }

    /// Extended to hold `v` (ignored when not finite).
    pub fn include(self, v: f64) -> Self {
        if v.is_finite() {
            Range::new(self.lo.min(v), self.hi.max(v))
        } else {
            self
        }
    }

    /// Extended to hold another interval.
    pub fn union(self, o: Range) -> Self {
        self.include(o.lo).include(o.hi)
    }

    /// Widened by `frac` of its span on each side; a zero span is widened to a sensible
    /// width around its value.
    pub fn pad(self, frac: f64) -> Self {
        let span = self.hi - self.lo;
        if span > 0.0 {
            Range::new(self.lo - frac * span, self.hi + frac * span)
        } else {
            let d = if self.lo == 0.0 {
                1.0
            } else {
                0.1 * self.lo.abs()
            };
            Range::new(self.lo - d, self.hi + d)
        }
    }

    /// Raised at the top by `frac` of its span (room for a note in the corner).
    pub fn headroom(self, frac: f64) -> Self {
        Range::new(self.lo, self.hi + frac * self.span())
    }

    /// Whether `v` lies inside.
    pub fn contains(self, v: f64) -> bool {
        v >= self.lo && v <= self.hi
    }

    /// Symmetric about zero.
    pub fn symmetric(self) -> Self {
        let m = self.lo.abs().max(self.hi.abs());
        Range::new(-m, m)
    }

    /// Its span.
    pub fn span(self) -> f64 {
        self.hi - self.lo
    }

    /// `v` moved into the interval (non-finite values stay as they are).
    pub fn clamp(self, v: f64) -> f64 {
        if v.is_finite() {
            v.clamp(self.lo, self.hi)
        } else {
            v
        }
    }

    /// As a plotters range, kept within +-1e300 so that its span stays finite (plotters'
    /// tick search never ends on an infinite span, e.g. a 1e308 spike cell in the data).
    pub fn span_range(self) -> std::ops::Range<f64> {
        const LIMIT: f64 = 1e300;
        let lo = self.lo.clamp(-LIMIT, LIMIT);
        let hi = self.hi.clamp(-LIMIT, LIMIT);
        lo..hi
    }
}

/// What a Cartesian panel shows.
#[derive(Debug, Clone)]
pub struct Axes<'s> {
    /// Horizontal range.
    pub x: Range,
    /// Vertical range (of log10 of the values when `log_y`).
    pub y: Range,
    /// Horizontal axis description with unit.
    pub x_desc: &'s str,
    /// Vertical axis description with unit.
    pub y_desc: &'s str,
    /// Panel title, if any.
    pub title: Option<&'s str>,
    /// The vertical coordinate is log10 of the value; tick labels show the value.
    pub log_y: bool,
    /// The vertical axis points down: the caller plots minus the value and the tick labels
    /// show the value (depth down).
    pub flip_y: bool,
}

impl<'s> Axes<'s> {
    /// A panel over `x` and `y` with the axis descriptions (units in them).
    pub fn new(x: Range, y: Range, x_desc: &'s str, y_desc: &'s str) -> Self {
        Axes {
            x,
            y,
            x_desc,
            y_desc,
            title: None,
            log_y: false,
            flip_y: false,
        }
    }

    /// With a panel title.
    pub fn title(mut self, title: &'s str) -> Self {
        self.title = Some(title);
        self
    }

    /// With the vertical axis pointing down: plot minus the values; ticks show the values.
    pub fn flip_y(mut self) -> Self {
        self.flip_y = true;
        self
    }

    /// With a logarithmic vertical axis: plot log10 of the values, `y` in decades (widened
    /// to whole decades, one tick each).
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }
}

/// A Cartesian chart of two f64 axes.
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Pixel sizes of the label areas of a panel.
pub const Y_LABEL_AREA: u32 = 92;
/// Height of the horizontal label area.
pub const X_LABEL_AREA: u32 = 56;

/// Builds the standard panel in `area` and draws its grid and labels.
pub fn panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    axes: &Axes,
) -> Result<Chart<'a, DB>, PlotError> {
    let mut builder = ChartBuilder::on(area);
    builder
        .margin_left(8)
        .margin_right(22)
        .margin_top(10)
        .margin_bottom(6)
        .x_label_area_size(if axes.x_desc.is_empty() {
            X_LABEL_AREA / 2
        } else {
            X_LABEL_AREA
        })
        .y_label_area_size(Y_LABEL_AREA);
    if let Some(t) = axes.title {
        builder.caption(t, style::text(size::PANEL));
    }
    let y = if axes.log_y {
        Range::new(
            axes.y.lo.floor(),
            axes.y.hi.ceil().max(axes.y.lo.floor() + 1.0),
        )
    } else {
        axes.y
    };
    let mut chart = builder.build_cartesian_2d(axes.x.span_range(), y.span_range())?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .bold_line_style(colour::GRID.stroke_width(1))
        .axis_style(colour::GREY.stroke_width(1))
        .x_labels(8)
        .y_labels(if axes.log_y { y.span() as usize + 1 } else { 6 })
        .label_style(style::text(size::TICK))
        .axis_desc_style(style::text(size::AXIS))
        .x_desc(axes.x_desc)
        .y_desc(axes.y_desc)
        .y_label_formatter(if axes.log_y {
            &log_tick
        } else if axes.flip_y {
            &flipped_tick
        } else {
            &tick
        })
        .x_label_formatter(&tick)
        .draw()?;
    Ok(chart)
}

/// A tick label: few digits, no float noise, a true minus sign.
pub fn tick(v: &f64) -> String {
    let v = *v;
    if v == 0.0 || v.abs() < 1e-12 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    let s = if (-4..5).contains(&mag) {
        crate::base::numfmt::fixed_trimmed(v, (2 - mag).clamp(0, 6) as usize)
    } else {
        format!("{v:.1e}")
    };
    s.replace('-', "\u{2212}")
}

/// A tick label of an axis pointing down: the value -v.
pub fn flipped_tick(v: &f64) -> String {
    tick(&-*v)
}

/// A tick label of a log10 axis: the value 10^v.
pub fn log_tick(v: &f64) -> String {
    tick(&10f64.powf(*v))
}

/// The plotting area a panel over `x`, `y` in `area` would have (to fit equal scales).
pub fn probe_area<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: Range,
    y: Range,
) -> Result<(u32, u32), PlotError> {
    Ok(ChartBuilder::on(area)
        .margin_left(8)
        .margin_right(22)
        .margin_top(10)
        .margin_bottom(6)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x.span_range(), y.span_range())?
        .plotting_area()
        .dim_in_pixel())
}

/// Ranges widened so that one unit is as long on both axes in a plotting area of `px`
/// pixels.
pub fn equal_aspect(x: Range, y: Range, px: (u32, u32)) -> (Range, Range) {
    let (w, h) = (px.0.max(1) as f64, px.1.max(1) as f64);
    let (sx, sy) = (x.span().max(1e-9), y.span().max(1e-9));
    // units per pixel needed by each axis; use the larger for both
    let upp = (sx / w).max(sy / h);
    let grow = |r: Range, n: f64| {
        let mid = 0.5 * (r.lo + r.hi);
        Range::new(mid - 0.5 * upp * n, mid + 0.5 * upp * n)
    };
    (grow(x, w), grow(y, h))
}

/// The finite stretches of a series: a non-finite point ends a stretch, so a line never
/// joins across a gap and never carries NaN to the drawing.
pub fn stretches(points: impl IntoIterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for (x, y) in points {
        if x.is_finite() && y.is_finite() {
            cur.push((x, y));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Thins a series (increasing x) to at most about `4 * buckets` points: in each of
/// `buckets` equal x intervals it keeps the first, lowest, highest and last point, so that
/// a line drawn through the result covers the same pixels as the full series.
pub fn thin(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 4 * buckets.max(1) {
        return points.to_vec();
    }
    let (x0, x1) = (points[0].0, points[points.len() - 1].0);
    let width = (x1 - x0) / buckets as f64;
    if width <= 0.0 || !width.is_finite() {
        return points.to_vec();
    }
    let mut out = Vec::new();
    let mut start = 0;
    while start < points.len() {
        let b = (((points[start].0 - x0) / width).floor() as usize).min(buckets - 1);
        let mut end = start + 1;
        while end < points.len()
            && (((points[end].0 - x0) / width).floor() as usize).min(buckets - 1) == b
        {
            end += 1;
        }
        let seg = &points[start..end];
        let lo = (0..seg.len())
            .min_by(|&a, &c| seg[a].1.total_cmp(&seg[c].1))
            .unwrap_or(0);
        let hi = (0..seg.len())
            .max_by(|&a, &c| seg[a].1.total_cmp(&seg[c].1))
            .unwrap_or(0);
        let mut keep = vec![0, lo, hi, seg.len() - 1];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|i| seg[i]));
        start = end;
    }
    out
}

/// Thins a path whose x is not monotonic (a track) to at most about `max` points. Consecutive
/// points that `pixel` maps to the same pixel are drawn as one: of each such run only the
/// first point is kept (and the path's last point), which leaves the drawing unchanged. If
/// more than `max` points remain (a path that goes round many times), each of `max / 6`
/// equal stretches of them keeps its first and last point and its extremes in x and in y.
pub fn thin_path(
    points: &[(f64, f64)],
    pixel: impl Fn((f64, f64)) -> (i32, i32),
    max: usize,
) -> Vec<(f64, f64)> {
    let mut kept: Vec<(f64, f64)> = Vec::new();
    let mut last_px = None;
    for (i, &p) in points.iter().enumerate() {
        let px = pixel(p);
        if last_px != Some(px) || i + 1 == points.len() {
            kept.push(p);
            last_px = Some(px);
        }
    }
    let buckets = (max / 6).max(1);
    if kept.len() <= max.max(6) {
        return kept;
    }
    let per = kept.len().div_ceil(buckets);
    let mut out = Vec::new();
    for seg in kept.chunks(per) {
        let by = |f: fn(&(f64, f64), &(f64, f64)) -> std::cmp::Ordering| {
            (0..seg.len())
                .min_by(|&a, &b| f(&seg[a], &seg[b]))
                .unwrap_or(0)
        };
        let mut keep = vec![
            0,
            seg.len() - 1,
            by(|a, b| a.0.total_cmp(&b.0)),
            by(|a, b| b.0.total_cmp(&a.0)),
            by(|a, b| a.1.total_cmp(&b.1)),
            by(|a, b| b.1.total_cmp(&a.1)),
        ];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|i| seg[i]));
    }
    out
}

/// Thins a scatter of points to about `target` when it has more: every s-th point (s chosen
/// for `target / 2` of them, a uniform sample of the cloud) and, in each of `target / 4`
/// equal x intervals, the points with the lowest and the highest y, so that outliers still
/// show. Points keep their order.
pub fn thin_dots(points: &[(f64, f64)], target: usize) -> Vec<(f64, f64)> {
    let target = target.max(8);
    if points.len() <= target {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    let every = points.len().div_ceil(target / 2);
    for k in keep.iter_mut().step_by(every) {
        *k = true;
    }
    let buckets = target / 4;
    if let Some(x) = Range::of(points.iter().map(|p| p.0)) {
        let width = x.span() / buckets as f64;
        let mut lo: Vec<Option<usize>> = vec![None; buckets];
        let mut hi: Vec<Option<usize>> = vec![None; buckets];
        for (i, p) in points.iter().enumerate() {
            if !(p.0.is_finite() && p.1.is_finite()) {
                continue;
            }
            let b = if width > 0.0 {
                (((p.0 - x.lo) / width) as usize).min(buckets - 1)
            } else {
                0
            };
            if lo[b].is_none_or(|j| p.1 < points[j].1) {
                lo[b] = Some(i);
            }
            if hi[b].is_none_or(|j| p.1 > points[j].1) {
                hi[b] = Some(i);
            }
        }
        for i in lo.into_iter().chain(hi).flatten() {
            keep[i] = true;
        }
    }
    points
        .iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

/// Draws a line through every finite stretch of `points`, thinned to the panel width.
pub fn line<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: impl IntoIterator<Item = (f64, f64)>,
    style: ShapeStyle,
) -> Result<(), PlotError> {
    stretched(chart, points, style, None)
}

/// Dash length and gap of dashed lines, pixels.
const DASH: (u32, u32) = (9, 6);

/// Draws a dashed line through every finite stretch of `points`.
pub fn dashed<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: impl IntoIterator<Item = (f64, f64)>,
    style: ShapeStyle,
) -> Result<(), PlotError> {
    stretched(chart, points, style, Some(DASH))
}

/// Moves a point that lies far outside the panel (a spike cell of 1e308) to just outside
/// it, so that its pixel coordinate stays a small integer; points inside are unchanged.
fn clipper<DB: DrawingBackend>(chart: &Chart<'_, DB>) -> impl Fn((f64, f64)) -> (f64, f64) {
    let (x, y) = (chart.x_range(), chart.y_range());
    let (wx, wy) = (x.end - x.start, y.end - y.start);
    move |(px, py)| {
        (
            px.clamp(x.start - wx, x.end + wx),
            py.clamp(y.start - wy, y.end + wy),
        )
    }
}

/// Solid (`dash` None) or dashed (dash length, gap in pixels) lines through the finite
/// stretches of `points`, thinned to the panel width.
fn stretched<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: impl IntoIterator<Item = (f64, f64)>,
    style: ShapeStyle,
    dash: Option<(u32, u32)>,
) -> Result<(), PlotError> {
    let (width, height) = chart.plotting_area().dim_in_pixel();
    let width = width.max(1) as usize;
    let clip = clipper(chart);
    for s in stretches(points.into_iter().map(&clip)) {
        let pts = if s.len() <= 4 * width || s.windows(2).all(|w| w[1].0 >= w[0].0) {
            thin(&s, width)
        } else {
            thin_path(&s, |p| chart.backend_coord(&p), 4 * width)
        };
        // each dash is drawn on its own: a path that goes round many times (a long turning
        // run's track) would take a dash per 15 pixels of its length, and where it covers
        // itself that often its dashes fill each other's gaps anyway: draw it solid
        let length = pixel_length(&pts, |p| chart.backend_coord(&p));
        let solid = length > DASHED_MAX_PANELS * (width + height as usize) as f64;
        match dash {
            Some((size, gap)) if !solid => {
                chart.draw_series(DashedLineSeries::new(pts, size, gap, style))?
            }
            _ => chart.draw_series(LineSeries::new(pts, style))?,
        };
    }
    Ok(())
}

/// A dashed path longer than this many times the panel's width plus height is drawn solid.
const DASHED_MAX_PANELS: f64 = 50.0;

/// Length in pixels of a path.
fn pixel_length(points: &[(f64, f64)], pixel: impl Fn((f64, f64)) -> (i32, i32)) -> f64 {
    points
        .windows(2)
        .map(|w| {
            let (a, b) = (pixel(w[0]), pixel(w[1]));
            f64::from(a.0 - b.0).hypot(f64::from(a.1 - b.1))
        })
        .sum()
}

/// A horizontal line across the panel at `y` (nothing when `y` is outside it).
pub fn hline<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x: Range,
    y: f64,
    style: ShapeStyle,
    dash: bool,
) -> Result<(), PlotError> {
    if !y.is_finite() {
        return Ok(());
    }
    stretched(chart, [(x.lo, y), (x.hi, y)], style, dash.then_some(DASH))
}

/// A shaded band between `lower` and `upper` over `x` (all the same length), clamped to the
/// vertical range `y` and split at non-finite values.
pub fn band<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    y: Range,
    colour: RGBColor,
) -> Result<(), PlotError> {
    let width = chart.plotting_area().dim_in_pixel().0 as usize;
    let ok = |i: usize| x[i].is_finite() && lower[i].is_finite() && upper[i].is_finite();
    let mut i = 0;
    while i < x.len() {
        if !ok(i) {
            i += 1;
            continue;
        }
        let start = i;
        while i < x.len() && ok(i) {
            i += 1;
        }
        let lo: Vec<(f64, f64)> = (start..i).map(|k| (x[k], y.clamp(lower[k]))).collect();
        let hi: Vec<(f64, f64)> = (start..i).map(|k| (x[k], y.clamp(upper[k]))).collect();
        let mut poly = thin(&hi, width.max(1));
        poly.extend(thin(&lo, width.max(1)).into_iter().rev());
        chart.draw_series(std::iter::once(Polygon::new(
            poly,
            colour.mix(0.22).filled(),
        )))?;
    }
    Ok(())
}

/// A vertical error bar at `x` from `lo` to `hi` with caps `cap` pixels wide.
pub fn error_bar<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x: f64,
    lo: f64,
    hi: f64,
    style: ShapeStyle,
) -> Result<(), PlotError> {
    if !(x.is_finite() && lo.is_finite() && hi.is_finite()) {
        return Ok(());
    }
    let cap = 5;
    let clip = clipper(chart);
    let ((x, lo), (_, hi)) = (clip((x, lo)), clip((x, hi)));
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(x, lo), (x, hi)],
        style,
    )))?;
    for y in [lo, hi] {
        chart.draw_series(std::iter::once(
            EmptyElement::at((x, y)) + PathElement::new(vec![(-cap, 0), (cap, 0)], style),
        ))?;
    }
    Ok(())
}

/// A note in the top left corner of a chart's plotting area.
pub fn note<DB: DrawingBackend>(chart: &Chart<'_, DB>, lines: &[String]) -> Result<(), PlotError> {
    style::corner_note(&chart.plotting_area().strip_coord_spec(), lines)
}

/// Measured data, drawn light under the lines that are compared with them: a thin light
/// line where the samples are denser than the panel's pixel columns (their noise then shows
/// as a light band, thinned to the pixels), else light points.
pub fn data<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: &[(f64, f64)],
    colour: RGBColor,
) -> Result<(), PlotError> {
    let width = chart.plotting_area().dim_in_pixel().0 as usize;
    if points.len() > width {
        line(chart, points.iter().copied(), colour.stroke_width(1))
    } else {
        let (x, y) = (chart.x_range(), chart.y_range());
        let inside = points
            .iter()
            .filter(|p| x.contains(&p.0) && (y.start..=y.end).contains(&p.1));
        dots(chart, inside.copied(), 2, colour.filled())
    }
}

/// Filled dots (or rings) at the finite points; more than two per pixel column of the
/// panel are thinned ([`thin_dots`]).
pub fn dots<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: impl IntoIterator<Item = (f64, f64)>,
    radius: i32,
    style: ShapeStyle,
) -> Result<(), PlotError> {
    let width = chart.plotting_area().dim_in_pixel().0.max(1) as usize;
    let clip = clipper(chart);
    let finite: Vec<(f64, f64)> = points
        .into_iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(&clip)
        .collect();
    chart.draw_series(
        thin_dots(&finite, 2 * width)
            .into_iter()
            .map(|p| Circle::new(p, radius, style)),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_ignore_non_finite_values() {
        let r = Range::of([1.0, f64::NAN, -2.0, f64::INFINITY]).unwrap();
        assert_eq!(r, Range::new(-2.0, 1.0));
        assert!(Range::of([f64::NAN]).is_none());
        let e = Range::require([f64::NAN], "u of run 'a'").unwrap_err();
        assert!(e.to_string().contains("u of run 'a'"), "{e}");
        assert_eq!(Range::new(2.0, 2.0).pad(0.1), Range::new(1.8, 2.2));
        assert_eq!(Range::new(0.0, 0.0).pad(0.1), Range::new(-1.0, 1.0));
        assert_eq!(Range::new(-1.0, 3.0).symmetric(), Range::new(-3.0, 3.0));
    }

    #[test]
    fn stretches_break_at_gaps() {
        let s = stretches([(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (3.0, 4.0)]);
        assert_eq!(s, vec![vec![(0.0, 1.0)], vec![(2.0, 3.0), (3.0, 4.0)]]);
    }

    #[test]
    fn thinning_keeps_the_extremes() {
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|k| {
                let t = k as f64 * 1e-3;
                (t, (7.0 * t).sin() + if k == 4321 { 5.0 } else { 0.0 })
            })
            .collect();
        let th = thin(&pts, 100);
        assert!(th.len() <= 400 && th.len() >= 100, "{}", th.len());
        assert_eq!(th.first(), pts.first());
        assert_eq!(th.last(), pts.last());
        // the spike survives
        assert!(th.iter().any(|p| p.1 > 4.0));
        let max = |v: &[(f64, f64)]| v.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert_eq!(max(&th), max(&pts));
        // x stays increasing
        assert!(th.windows(2).all(|w| w[1].0 >= w[0].0));
    }

    #[test]
    fn scatters_are_thinned_keeping_the_outliers() {
        let few: Vec<(f64, f64)> = (0..100).map(|k| (k as f64, 1.0)).collect();
        assert_eq!(thin_dots(&few, 400), few);
        let pts: Vec<(f64, f64)> = (0..300_000)
            .map(|k| {
                let y = (k as f64 * 0.7).sin() + if k == 77_777 { 9.0 } else { 0.0 };
                (k as f64 * 0.01, if k == 5 { f64::NAN } else { y })
            })
            .collect();
        let th = thin_dots(&pts, 2000);
        assert!(th.len() <= 2000 && th.len() >= 1000, "{}", th.len());
        assert!(th.iter().any(|p| p.1 > 9.0), "the outlier survives");
        assert!(th.iter().any(|p| p.1 < -0.99), "the low side survives");
        assert!(th.windows(2).all(|w| w[1].0 > w[0].0), "order kept");
    }

    #[test]
    fn paths_are_thinned_to_their_pixels_and_bounded() {
        let pixel = |p: (f64, f64)| ((p.0 * 100.0).round() as i32, (p.1 * 100.0).round() as i32);
        // a slow circle: many samples per pixel; drawing is unchanged
        let circle: Vec<(f64, f64)> = (0..20_000)
            .map(|k| {
                let a = k as f64 * 1e-4 * std::f64::consts::TAU;
                (a.cos(), a.sin())
            })
            .collect();
        let th = thin_path(&circle, pixel, 4000);
        assert!(th.len() < 4000, "{}", th.len());
        assert_eq!(th.first(), circle.first());
        assert_eq!(th.last(), circle.last());
        let px: Vec<_> = th.iter().map(|p| pixel(*p)).collect();
        let all: std::collections::BTreeSet<_> = circle.iter().map(|p| pixel(*p)).collect();
        assert!(px.iter().all(|p| all.contains(p)));
        // 400 laps of a drifting circle: bounded, with the extremes of every stretch
        let laps: Vec<(f64, f64)> = (0..400_000)
            .map(|k| {
                let a = k as f64 * 1e-3 * std::f64::consts::TAU;
                (a.cos() + k as f64 * 1e-6, a.sin())
            })
            .collect();
        let th = thin_path(&laps, pixel, 4000);
        assert!(th.len() <= 4000, "{}", th.len());
        let right = laps.iter().map(|p| p.0).fold(f64::MIN, f64::max);
        assert_eq!(th.iter().map(|p| p.0).fold(f64::MIN, f64::max), right);
    }

    #[test]
    fn equal_aspect_gives_one_scale() {
        let (x, y) = equal_aspect(Range::new(0.0, 10.0), Range::new(0.0, 2.0), (500, 500));
        assert!((x.span() - 10.0).abs() < 1e-12);
        assert!((y.span() - 10.0).abs() < 1e-12);
        assert!((y.lo + y.hi - 2.0).abs() < 1e-12, "centred");
        let (x, y) = equal_aspect(Range::new(0.0, 1.0), Range::new(0.0, 4.0), (800, 400));
        assert!((x.span() / 800.0 - y.span() / 400.0).abs() < 1e-12);
        assert!(x.span() >= 1.0 && y.span() >= 4.0);
    }

    #[test]
    fn a_huge_range_stays_finite_for_plotters() {
        let r = Range::of([0.0, 1e308, -1e308]).unwrap().pad(0.05);
        let s = r.span_range();
        assert!((s.end - s.start).is_finite());
        let keys = plotters::coord::types::RangedCoordf64::from(s).key_points(10);
        assert!(!keys.is_empty() && keys.len() <= 10);
    }

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(&0.30000000000000004), "0.3");
        assert_eq!(tick(&-12.0), "\u{2212}12");
        assert_eq!(tick(&0.0025), "0.0025");
        assert_eq!(tick(&-5.0e-4), "\u{2212}0.0005");
        assert_eq!(tick(&1.5e-6), "1.5e\u{2212}6");
        assert_eq!(tick(&250.0), "250");
    }
}
