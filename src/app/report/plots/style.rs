//! The look shared by every figure: the embedded font, the colours, the text sizes, the
//! title and the legend strip drawn above the panels.

use super::PlotError;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle};
use std::sync::OnceLock;

/// DejaVu Sans, embedded so that text renders the same on machines without system fonts
/// (licence in assets/DejaVuSans-LICENSE.txt).
pub const FONT_BYTES: &[u8] = include_bytes!("../../../../assets/DejaVuSans.ttf");

/// The family name the figures use; SVG viewers fall back to their own sans-serif face.
pub const FONT: &str = "sans-serif";

/// Registers the embedded font once.
pub fn ensure_font() -> Result<(), PlotError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PlotError::new("the embedded font cannot be read"))
    }
}

/// Okabe-Ito colours (distinguishable with the common colour-vision deficiencies).
pub mod colour {
    use plotters::style::RGBColor;
    /// Data points of a stage's fit (polar, surge).
    pub const DATA: RGBColor = RGBColor(40, 40, 40);
    /// Measured or CFD histories, drawn light under the model and the smoothed estimate.
    pub const MEASURED: RGBColor = RGBColor(165, 165, 165);
    /// Fitted or estimated quantities.
    pub const BLUE: RGBColor = RGBColor(0, 114, 178);
    /// The model re-simulated open loop.
    pub const VERMILLION: RGBColor = RGBColor(213, 94, 0);
    /// Reference (published) values.
    pub const GREEN: RGBColor = RGBColor(0, 158, 115);
    /// Fossen's analytic values.
    pub const ORANGE: RGBColor = RGBColor(230, 159, 0);
    /// A further series.
    pub const PURPLE: RGBColor = RGBColor(204, 121, 167);
    /// A further series.
    pub const SKY: RGBColor = RGBColor(86, 180, 233);
    /// Limits (the IMO criteria).
    pub const RED_LIMIT: RGBColor = RGBColor(178, 24, 43);
    /// Grid lines.
    pub const GRID: RGBColor = RGBColor(225, 225, 225);
    /// Annotations and bounds.
    pub const GREY: RGBColor = RGBColor(120, 120, 120);
    /// Series colours in order, for groups (speeds, runs).
    pub const SERIES: [RGBColor; 5] = [BLUE, VERMILLION, GREEN, PURPLE, ORANGE];
}

/// Text sizes in pixels.
pub mod size {
    /// Figure title.
    pub const TITLE: f64 = 24.0;
    /// Panel title.
    pub const PANEL: f64 = 19.0;
    /// Axis descriptions.
    pub const AXIS: f64 = 18.0;
    /// Tick labels.
    pub const TICK: f64 = 15.0;
    /// Legend entries and annotations.
    pub const LEGEND: f64 = 16.0;
}

/// A text style of the embedded font.
pub fn text(px: f64) -> TextStyle<'static> {
    (FONT, px).into_font().color(&BLACK)
}

/// A text style anchored at `h`, `v`.
pub fn anchored(px: f64, h: HPos, v: VPos) -> TextStyle<'static> {
    text(px).pos(Pos::new(h, v))
}

/// Width of `s` in pixels at size `px`.
pub fn text_width(s: &str, px: f64) -> u32 {
    (FONT, px).into_font().box_size(s).map_or(0, |b| b.0)
}

/// The largest size not above `px` at which `s` fits in `width` pixels.
pub fn fitting_size(s: &str, px: f64, width: u32) -> f64 {
    let w = text_width(s, px);
    if w <= width || w == 0 {
        px
    } else {
        (px * width as f64 / w as f64).floor().max(8.0)
    }
}

/// How a legend entry is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A solid line.
    Line(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A shaded band.
    Band(RGBColor),
    /// A filled dot.
    Dot(RGBColor),
    /// A hollow circle.
    Ring(RGBColor),
    /// A vertical error bar.
    Bar(RGBColor),
}

/// One legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    /// Its mark.
    pub mark: Mark,
    /// Its text.
    pub label: String,
}

impl Key {
    /// A legend entry.
    pub fn new(mark: Mark, label: impl Into<String>) -> Self {
        Key {
            mark,
            label: label.into(),
        }
    }
}

const KEY_SAMPLE: i32 = 34;
const KEY_GAP: i32 = 28;
const KEY_ROW: i32 = 26;
const SIDE: i32 = 24;

/// Places the legend entries in rows across `width`: (row, x) of each.
fn key_layout(keys: &[Key], width: u32) -> Vec<(i32, i32)> {
    let mut out = Vec::with_capacity(keys.len());
    let (mut row, mut x) = (0, SIDE);
    for k in keys {
        let w = KEY_SAMPLE + 8 + text_width(&k.label, size::LEGEND) as i32;
        if x > SIDE && x + w > width as i32 - SIDE {
            row += 1;
            x = SIDE;
        }
        out.push((row, x));
        x += w + KEY_GAP;
    }
    out
}

/// Draws the mark of a legend entry with its left end at `(x, y)`.
pub fn draw_mark<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    mark: Mark,
    (x, y): (i32, i32),
) -> Result<(), PlotError> {
    let w = KEY_SAMPLE;
    match mark {
        Mark::Line(c) => area.draw(&PathElement::new(
            vec![(x, y), (x + w, y)],
            c.stroke_width(3),
        ))?,
        Mark::Dashed(c) => area.draw(&DashedPathElement::new(
            vec![(x, y), (x + w, y)],
            7,
            5,
            c.stroke_width(3),
        ))?,
        Mark::Band(c) => area.draw(&Rectangle::new(
            [(x, y - 7), (x + w, y + 7)],
            c.mix(0.3).filled(),
        ))?,
        Mark::Dot(c) => area.draw(&Circle::new((x + w / 2, y), 5, c.filled()))?,
        Mark::Ring(c) => area.draw(&Circle::new((x + w / 2, y), 5, c.stroke_width(2)))?,
        Mark::Bar(c) => {
            let m = x + w / 2;
            let s = c.stroke_width(2);
            area.draw(&PathElement::new(vec![(m, y - 9), (m, y + 9)], s))?;
            area.draw(&PathElement::new(vec![(m - 5, y - 9), (m + 5, y - 9)], s))?;
            area.draw(&PathElement::new(vec![(m - 5, y + 9), (m + 5, y + 9)], s))?;
        }
    }
    Ok(())
}

/// Fills `root` white, writes the title at the top and the legend below it, and returns the
/// area left for the panels.
pub fn frame<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    keys: &[Key],
) -> Result<DrawingArea<DB, Shift>, PlotError> {
    root.fill(&WHITE)?;
    let (w, _) = root.dim_in_pixel();
    let px = fitting_size(title, size::TITLE, w.saturating_sub(2 * SIDE as u32));
    root.draw(&Text::new(
        title.to_string(),
        (w as i32 / 2, 12),
        anchored(px, HPos::Center, VPos::Top),
    ))?;
    let mut top = 12 + size::TITLE as i32 + 14;
    if !keys.is_empty() {
        let layout = key_layout(keys, w);
        for (k, (row, x)) in keys.iter().zip(&layout) {
            let y = top + row * KEY_ROW + KEY_ROW / 2;
            draw_mark(root, k.mark, (*x, y))?;
            root.draw(&Text::new(
                k.label.clone(),
                (x + KEY_SAMPLE + 8, y),
                anchored(size::LEGEND, HPos::Left, VPos::Center),
            ))?;
        }
        let rows = layout.last().map_or(0, |l| l.0 + 1);
        top += rows * KEY_ROW + 8;
    }
    Ok(root.split_vertically(top).1)
}

/// A note written in the top left corner of a panel's plotting area.
pub fn corner_note<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lines: &[String],
) -> Result<(), PlotError> {
    let h = size::LEGEND as i32 + 4;
    let w = lines
        .iter()
        .map(|l| text_width(l, size::LEGEND) as i32)
        .max()
        .unwrap_or(0);
    if w == 0 {
        return Ok(());
    }
    area.draw(&Rectangle::new(
        [(6, 6), (w + 18, 10 + h * lines.len() as i32)],
        WHITE.mix(0.85).filled(),
    ))?;
    for (i, l) in lines.iter().enumerate() {
        area.draw(&Text::new(
            l.clone(),
            (12, 9 + h * i as i32),
            anchored(size::LEGEND, HPos::Left, VPos::Top),
        ))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legend_wraps_when_the_row_is_full() {
        ensure_font().unwrap();
        let keys: Vec<Key> = (0..6)
            .map(|i| {
                Key::new(
                    Mark::Dot(colour::BLUE),
                    format!("a fairly long legend entry {i}"),
                )
            })
            .collect();
        let wide = key_layout(&keys, 4000);
        assert!(wide.iter().all(|(row, _)| *row == 0));
        let narrow = key_layout(&keys, 700);
        assert!(narrow.last().unwrap().0 >= 2, "{narrow:?}");
        // entries on one row never overlap
        for pair in narrow.windows(2) {
            if pair[0].0 == pair[1].0 {
                assert!(pair[1].1 > pair[0].1 + KEY_SAMPLE);
            }
        }
    }

    #[test]
    fn long_titles_shrink_to_fit() {
        ensure_font().unwrap();
        let s = "a title that is certainly far too long for a narrow figure of 300 pixels";
        let px = fitting_size(s, size::TITLE, 300);
        assert!(px < size::TITLE);
        assert!(text_width(s, px) <= 310);
        assert_eq!(fitting_size("short", size::TITLE, 300), size::TITLE);
    }
}
