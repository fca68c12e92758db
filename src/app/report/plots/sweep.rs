//! The figures of a turning-circle sweep (`hydroid simulate` with `[sweep]`): the tracks of
//! every case on one plot, and the tactical and steady turning diameters against the rudder
//! angle and against the approach speed, in ship lengths.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::simulate::sweep::{Case, SweepResult, Varies};
use crate::dynamics::manoeuvre::Side;
use plotters::coord::Shift;
use plotters::prelude::*;

/// One figure of a sweep.
#[derive(Debug, Clone)]
pub enum SweepPlot<'a> {
    /// The tracks of the cases varying one parameter.
    Tracks {
        /// Which cases.
        varies: Varies,
        /// The sweep.
        result: &'a SweepResult,
    },
    /// Tactical and steady diameters against the varied parameter.
    Diameters {
        /// Which cases.
        varies: Varies,
        /// The sweep.
        result: &'a SweepResult,
    },
}

/// The figures the sweep's cases support (a family only when it has cases).
pub fn figures(result: &SweepResult) -> Vec<SweepPlot<'_>> {
    let mut out = Vec::new();
    for varies in [Varies::Rudder, Varies::Speed] {
        if result.cases.iter().any(|c| c.varies == varies) {
            out.push(SweepPlot::Tracks { varies, result });
            out.push(SweepPlot::Diameters { varies, result });
        }
    }
    out
}

fn word(v: Varies) -> &'static str {
    match v {
        Varies::Rudder => "rudder",
        Varies::Speed => "speed",
    }
}

fn cases(result: &SweepResult, varies: Varies) -> Vec<&Case> {
    result.cases.iter().filter(|c| c.varies == varies).collect()
}

/// Colours of the settings of a sweep (the report's series colours, then more).
const PALETTE: [RGBColor; 7] = [
    colour::BLUE,
    colour::VERMILLION,
    colour::GREEN,
    colour::PURPLE,
    colour::ORANGE,
    colour::SKY,
    colour::DATA,
];

impl Plot for SweepPlot<'_> {
    fn meta(&self) -> FigureMeta {
        match self {
            SweepPlot::Tracks { varies, .. } => FigureMeta {
                name: format!("tracks_{}", word(*varies)),
                title: format!("Turning circles at several {} settings", word(*varies)),
                caption: "Track of each turning circle from the rudder order, in ship \
                          lengths (x forward on the original course, y to starboard)."
                    .into(),
                section: Section::Resim,
                shows: Vec::new(),
            },
            SweepPlot::Diameters { varies, .. } => FigureMeta {
                name: format!("diameter_vs_{}", word(*varies)),
                title: format!("Turning diameters against the {}", word(*varies)),
                caption: "Tactical diameter (transfer at 180 deg heading change) and steady \
                          turning diameter, in ship lengths, for each side."
                    .into(),
                section: Section::Resim,
                shows: Vec::new(),
            },
        }
    }

    fn size(&self) -> (u32, u32) {
        (1100, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        match self {
            SweepPlot::Tracks { varies, result } => tracks(root, result, *varies),
            SweepPlot::Diameters { varies, result } => diameters(root, result, *varies),
        }
    }
}

fn tracks<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    result: &SweepResult,
    varies: Varies,
) -> Result<(), PlotError> {
    let l = result.length;
    let shown = cases(result, varies);
    // one colour per setting of the varied parameter; starboard solid, port dashed
    let setting = |c: &Case| match varies {
        Varies::Rudder => format!("{:.1} deg", c.rudder.abs().to_degrees()),
        Varies::Speed => format!("{} m/s", crate::base::numfmt::num(c.speed)),
    };
    let mut settings: Vec<String> = Vec::new();
    for c in &shown {
        let k = setting(c);
        if !settings.contains(&k) {
            settings.push(k);
        }
    }
    let colour_of = |c: &Case| {
        let i = settings.iter().position(|k| *k == setting(c)).unwrap_or(0);
        PALETTE[i % PALETTE.len()]
    };
    let mut keys: Vec<Key> = settings
        .iter()
        .enumerate()
        .map(|(i, k)| Key::new(Mark::Line(PALETTE[i % PALETTE.len()]), k.clone()))
        .collect();
    if shown.iter().any(|c| c.turn.side == Side::Port) {
        keys.push(Key::new(Mark::Line(colour::GREY), "to starboard"));
        keys.push(Key::new(Mark::Dashed(colour::GREY), "to port"));
    }
    let fixed = match (varies, shown.first()) {
        (Varies::Rudder, Some(c)) => format!(" at {} m/s", crate::base::numfmt::num(c.speed)),
        (Varies::Speed, Some(c)) => {
            format!(" with {:.1} deg rudder", c.rudder.abs().to_degrees())
        }
        _ => String::new(),
    };
    let body = style::frame(
        root,
        &format!("Turning circles, {} varied{fixed}", word(varies)),
        &keys,
    )?;
    // each track from its execute point, in the frame of the original course
    let paths: Vec<Vec<(f64, f64)>> = shown
        .iter()
        .map(|c| {
            let (x, y) = &c.track;
            let (x0, y0) = (
                x.first().copied().unwrap_or(0.0),
                y.first().copied().unwrap_or(0.0),
            );
            // rotated so that the approach course points up the page
            let (s, k) = c.turn.approach_heading.sin_cos();
            x.iter()
                .zip(y)
                .map(|(a, b)| {
                    let (dx, dy) = (a - x0, b - y0);
                    ((-dx * s + dy * k) / l, (dx * k + dy * s) / l)
                })
                .collect()
        })
        .collect();
    let all = || paths.iter().flatten();
    let east = Range::require(all().map(|p| p.0), "track y")?.pad(0.05);
    let north = Range::require(all().map(|p| p.1), "track x")?.pad(0.05);
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
    let mut chart = axes::panel(
        &body,
        &Axes::new(
            east,
            north,
            "y / L (to starboard)",
            "x / L (original course)",
        ),
    )?;
    for (c, p) in shown.iter().zip(&paths) {
        let style = colour_of(c).stroke_width(2);
        if c.turn.side == Side::Port {
            axes::dashed(&mut chart, p.iter().copied(), style)?;
        } else {
            axes::line(&mut chart, p.iter().copied(), style)?;
        }
    }
    Ok(())
}

/// A labelled line of points.
type Series = (String, Mark, Vec<(f64, f64)>);

fn diameters<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    result: &SweepResult,
    varies: Varies,
) -> Result<(), PlotError> {
    let l = result.length;
    let shown = cases(result, varies);
    let x_of = |c: &Case| match varies {
        Varies::Rudder => c.rudder.abs().to_degrees(),
        Varies::Speed => c.speed,
    };
    let mut series: Vec<Series> = Vec::new();
    for side in [Side::Starboard, Side::Port] {
        let of_side: Vec<&&Case> = shown.iter().filter(|c| c.turn.side == side).collect();
        if of_side.is_empty() {
            continue;
        }
        let (tactical, steady) = if side == Side::Starboard {
            (colour::BLUE, colour::SKY)
        } else {
            (colour::VERMILLION, colour::ORANGE)
        };
        let pts = |get: fn(&Case) -> Option<f64>| {
            let mut v: Vec<(f64, f64)> = of_side
                .iter()
                .filter_map(|c| get(c).map(|d| (x_of(c), d / l)))
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v
        };
        series.push((
            format!("tactical diameter, {side}"),
            Mark::Line(tactical),
            pts(|c| c.turn.tactical_diameter.value()),
        ));
        series.push((
            format!("steady diameter, {side}"),
            Mark::Dashed(steady),
            pts(|c| c.turn.steady_diameter.value()),
        ));
    }
    let keys: Vec<Key> = series
        .iter()
        .map(|(n, m, _)| Key::new(*m, n.clone()))
        .collect();
    let body = style::frame(
        root,
        &format!("Turning diameters against the {}", word(varies)),
        &keys,
    )?;
    let all = || series.iter().flat_map(|s| s.2.iter());
    let x = Range::require(all().map(|p| p.0), "varied parameter")?.pad(0.08);
    let y = Range::require(all().map(|p| p.1), "diameters")?
        .include(0.0)
        .pad(0.06);
    let x_desc = match varies {
        Varies::Rudder => "rudder angle (deg)",
        Varies::Speed => "approach speed (m/s)",
    };
    let mut chart = axes::panel(&body, &Axes::new(x, y, x_desc, "diameter / L"))?;
    for (_, mark, pts) in &series {
        let (c, dashed) = match mark {
            Mark::Dashed(c) => (*c, true),
            Mark::Line(c) => (*c, false),
            _ => continue,
        };
        if dashed {
            axes::dashed(&mut chart, pts.iter().copied(), c.stroke_width(2))?;
        } else {
            axes::line(&mut chart, pts.iter().copied(), c.stroke_width(3))?;
        }
        axes::dots(&mut chart, pts.iter().copied(), 5, c.filled())?;
    }
    Ok(())
}
