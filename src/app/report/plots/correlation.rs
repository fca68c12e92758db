//! The correlation matrix of the HEKF estimates as a heat map with the values in the cells.

use super::style::{self, anchored, colour, size};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::app::results::CORRELATED;
use crate::model::coefficients::Correlation;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use plotters::style::FontTransform;

/// Diverging colour of a correlation: blue for -1, white for 0, red for +1.
pub fn heat(rho: f64) -> RGBColor {
    let t = rho.clamp(-1.0, 1.0);
    let (end, f) = if t < 0.0 {
        ((33.0, 102.0, 172.0), -t)
    } else {
        ((178.0, 24.0, 43.0), t)
    };
    let mix = |e: f64| (255.0 + (e - 255.0) * f).round() as u8;
    RGBColor(mix(end.0), mix(end.1), mix(end.2))
}

/// The heat map.
pub struct CorrelationMap<'a> {
    c: &'a Correlation,
}

impl<'a> CorrelationMap<'a> {
    /// The figure, for two or more estimates with finite correlations.
    pub fn new(c: &'a Correlation) -> Option<Self> {
        let n = c.names.len();
        let square = c.matrix.len() == n && c.matrix.iter().all(|r| r.len() == n);
        let finite = c.matrix.iter().flatten().all(|v| v.is_finite());
        (n >= 2 && square && finite).then_some(CorrelationMap { c })
    }

    fn cell(&self) -> i32 {
        (660 / self.c.names.len() as i32).clamp(44, 110)
    }
}

const LEFT: i32 = 150;
const TOP: i32 = 70;
const BAR: i32 = 170;

impl Plot for CorrelationMap<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "hekf_correlation".into(),
            title: "Correlation of the HEKF estimates".into(),
            caption: format!(
                "Correlation coefficients of the estimated coefficients from the filter's \
                 covariance after the last pass. Outlined cells: |ρ| > {CORRELATED}, pairs that \
                 this data set cannot separate (a change of one is largely compensated by the \
                 other)."
            ),
            section: Section::Hekf,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        let n = self.c.names.len() as i32;
        let side = n * self.cell();
        ((LEFT + side + BAR) as u32, (TOP + side + 90) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let area = style::frame(root, "Correlation of the HEKF estimates (last pass)", &[])?;
        let n = self.c.names.len();
        let cell = self.cell();
        let side = cell * n as i32;
        let (x0, y0) = (LEFT, 16);
        let txt = (cell as f64 / 4.4).clamp(12.0, size::LEGEND + 4.0);
        for (i, row) in self.c.matrix.iter().enumerate() {
            for (j, rho) in row.iter().enumerate() {
                let (x, y) = (x0 + j as i32 * cell, y0 + i as i32 * cell);
                area.draw(&Rectangle::new(
                    [(x, y), (x + cell, y + cell)],
                    heat(*rho).filled(),
                ))?;
                area.draw(&Rectangle::new(
                    [(x, y), (x + cell, y + cell)],
                    WHITE.stroke_width(1),
                ))?;
                if i != j && rho.abs() > CORRELATED {
                    area.draw(&Rectangle::new(
                        [(x + 3, y + 3), (x + cell - 3, y + cell - 3)],
                        BLACK.stroke_width(3),
                    ))?;
                }
                let ink = if rho.abs() > 0.6 { WHITE } else { BLACK };
                area.draw(&Text::new(
                    format!("{rho:+.2}").replace('-', "\u{2212}"),
                    (x + cell / 2, y + cell / 2),
                    anchored(txt, HPos::Center, VPos::Center).color(&ink),
                ))?;
            }
        }
        for (k, name) in self.c.names.iter().enumerate() {
            let mid = k as i32 * cell + cell / 2;
            area.draw(&Text::new(
                name.clone(),
                (x0 - 12, y0 + mid),
                anchored(size::AXIS, HPos::Right, VPos::Center),
            ))?;
            area.draw(&Text::new(
                name.clone(),
                (x0 + mid, y0 + side + 12),
                anchored(size::AXIS, HPos::Center, VPos::Top),
            ))?;
        }
        // colour bar
        let (bx, bw) = (x0 + side + 40, 26);
        let steps = 100;
        for s in 0..steps {
            let rho = 1.0 - 2.0 * (s as f64 + 0.5) / steps as f64;
            let ya = y0 + side * s / steps;
            let yb = y0 + side * (s + 1) / steps;
            area.draw(&Rectangle::new(
                [(bx, ya), (bx + bw, yb)],
                heat(rho).filled(),
            ))?;
        }
        area.draw(&Rectangle::new(
            [(bx, y0), (bx + bw, y0 + side)],
            colour::GREY.stroke_width(1),
        ))?;
        for v in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            let y = y0 + ((1.0 - v) / 2.0 * side as f64).round() as i32;
            area.draw(&PathElement::new(
                vec![(bx + bw, y), (bx + bw + 6, y)],
                colour::GREY.stroke_width(1),
            ))?;
            area.draw(&Text::new(
                super::axes::tick(&v),
                (bx + bw + 10, y),
                anchored(size::TICK, HPos::Left, VPos::Center),
            ))?;
        }
        area.draw(&Text::new(
            "correlation ρ (-)".to_string(),
            (bx + bw + 70, y0 + side / 2),
            anchored(size::AXIS, HPos::Center, VPos::Center).transform(FontTransform::Rotate270),
        ))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_run_from_blue_through_white_to_red() {
        assert_eq!(heat(0.0), RGBColor(255, 255, 255));
        assert_eq!(heat(1.0), RGBColor(178, 24, 43));
        assert_eq!(heat(-1.0), RGBColor(33, 102, 172));
        assert_eq!(heat(7.0), heat(1.0));
        let half = heat(0.5);
        assert!(half.0 > 178 && half.1 > 24 && half.1 < 255);
    }

    #[test]
    fn only_square_finite_matrices_are_drawn() {
        let ok = Correlation {
            names: vec!["a".into(), "b".into()],
            matrix: vec![vec![1.0, 0.5], vec![0.5, 1.0]],
        };
        assert!(CorrelationMap::new(&ok).is_some());
        let mut nan = ok.clone();
        nan.matrix[0][1] = f64::NAN;
        assert!(CorrelationMap::new(&nan).is_none());
        let ragged = Correlation {
            names: ok.names.clone(),
            matrix: vec![vec![1.0]],
        };
        assert!(CorrelationMap::new(&ragged).is_none());
    }
}
