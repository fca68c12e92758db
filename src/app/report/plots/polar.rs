//! Static polars: C_D, C_L and C_M against the drift angle, the points of each speed, the
//! pooled fit (and each speed's own fit), with the residuals of the pooled fit below.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::stages::polar::{ChannelFit, PolarFit, PolarPoint, PolarResult};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One of the three fitted channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// C_D.
    Drag,
    /// C_L.
    Lift,
    /// C_M.
    Moment,
}

impl Channel {
    const ALL: [Channel; 3] = [Channel::Drag, Channel::Lift, Channel::Moment];

    fn symbol(self) -> &'static str {
        match self {
            Channel::Drag => "C_D",
            Channel::Lift => "C_L",
            Channel::Moment => "C_M",
        }
    }

    fn title(self) -> &'static str {
        match self {
            Channel::Drag => "drag C_D = −X / (q∞ A_ref)",
            Channel::Lift => "side force C_L = Y / (q∞ A_ref)",
            Channel::Moment => "yaw moment C_M = N / (q∞ A_ref L_ref)",
        }
    }

    fn of(self, p: &PolarPoint) -> (f64, Option<f64>) {
        match self {
            Channel::Drag => (p.cd, p.cd_se),
            Channel::Lift => (p.cl, p.cl_se),
            Channel::Moment => (p.cm, p.cm_se),
        }
    }

    fn fit(self, f: &PolarFit) -> &ChannelFit {
        match self {
            Channel::Drag => &f.drag,
            Channel::Lift => &f.lift,
            Channel::Moment => &f.moment,
        }
    }
}

/// The power of alpha each named constant multiplies.
fn power(name: &str) -> Option<i32> {
    match name {
        "c" | "intercept" => Some(0),
        "b" | "slope" => Some(1),
        "a" => Some(2),
        "cubic" => Some(3),
        _ => None,
    }
}

/// The fitted channel at `alpha` (rad).
pub fn eval(fit: &ChannelFit, alpha: f64) -> Option<f64> {
    fit.names
        .iter()
        .zip(&fit.values)
        .map(|(n, v)| power(n).map(|p| v * alpha.powi(p)))
        .sum()
}

/// The fitted formula in words, e.g. `C_D = 0.293 α² − 0.0273 α + 0.0826`.
fn formula(symbol: &str, fit: &ChannelFit) -> String {
    let mut terms: Vec<(i32, f64)> = fit
        .names
        .iter()
        .zip(&fit.values)
        .filter_map(|(n, v)| Some((power(n)?, *v)))
        .filter(|t| t.1 != 0.0)
        .collect();
    if terms.is_empty() {
        terms.push((0, 0.0));
    }
    terms.sort_by_key(|t| -t.0);
    let mut s = format!("{symbol} =");
    for (i, (p, v)) in terms.iter().enumerate() {
        let sign = if *v < 0.0 { "−" } else { "+" };
        let mag = crate::base::numfmt::num(v.abs());
        let a = match p {
            0 => String::new(),
            1 => " α".into(),
            2 => " α²".into(),
            _ => " α³".into(),
        };
        if i == 0 {
            s.push_str(&format!(" {}{mag}{a}", if *v < 0.0 { "−" } else { "" }));
        } else {
            s.push_str(&format!(" {sign} {mag}{a}"));
        }
    }
    s.push_str("  (α in rad)");
    s
}

struct Group<'a> {
    label: String,
    speed: Option<f64>,
    colour: RGBColor,
    fit: Option<&'a PolarFit>,
}

/// The polar figure.
pub struct PolarFits<'a> {
    r: &'a PolarResult,
    groups: Vec<Group<'a>>,
    word: &'static str,
}

impl<'a> PolarFits<'a> {
    /// The figure of a polar result; an error when a fit has a constant it cannot draw.
    /// `word` says what the points are ("CFD", "measured").
    pub fn new(r: &'a PolarResult, word: &'static str) -> crate::Result<Self> {
        for c in Channel::ALL {
            if let Some(n) = c.fit(&r.pooled).names.iter().find(|n| power(n).is_none()) {
                return Err(crate::Error::numerical(
                    "report",
                    format!(
                        "figure 'polar': unknown constant '{n}' in the {} fit",
                        c.symbol()
                    ),
                ));
            }
        }
        let groups = if r.per_speed.is_empty() {
            vec![Group {
                label: format!("{word} points"),
                speed: None,
                colour: colour::SERIES[0],
                fit: None,
            }]
        } else {
            r.per_speed
                .iter()
                .enumerate()
                .map(|(i, s)| Group {
                    label: format!("U = {} m/s (Re = {:.2e})", axes::tick(&s.speed), s.reynolds),
                    speed: Some(s.speed),
                    colour: colour::SERIES[i % colour::SERIES.len()],
                    fit: s.fit.as_ref(),
                })
                .collect()
        };
        Ok(PolarFits { r, groups, word })
    }

    /// The group a point belongs to: the nearest speed.
    fn group_of(&self, p: &PolarPoint) -> usize {
        match p.speed {
            Some(u) => (0..self.groups.len())
                .min_by(|&a, &b| {
                    let d = |g: usize| {
                        self.groups[g]
                            .speed
                            .map_or(f64::INFINITY, |s| (s - u).abs())
                    };
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0),
            None => 0,
        }
    }

    fn alpha_range(&self) -> Result<Range, PlotError> {
        Range::require(
            self.r.points.iter().map(|p| p.alpha),
            "polar angles of attack",
        )
    }

    fn keys(&self) -> Vec<Key> {
        let mut keys: Vec<Key> = self
            .groups
            .iter()
            .map(|g| Key::new(Mark::Dot(g.colour), g.label.clone()))
            .collect();
        keys.push(Key::new(
            Mark::Line(colour::DATA),
            "pooled fit (all speeds)",
        ));
        if self.groups.iter().filter(|g| g.fit.is_some()).count() > 1 {
            keys.push(Key::new(
                Mark::Dashed(colour::GREY),
                "fit of one speed (its colour)",
            ));
        }
        if self.r.points.iter().any(|p| !p.used) {
            keys.push(Key::new(
                Mark::Ring(colour::GREY),
                "outside α_max: not fitted",
            ));
        }
        if self.r.points.iter().any(|p| p.cd_se.is_some()) {
            keys.push(Key::new(Mark::Bar(colour::GREY), "±2 SE of a steady mean"));
        }
        keys
    }

    fn draw_channel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        ch: Channel,
        alpha: Range,
    ) -> Result<(), PlotError> {
        let deg = f64::to_degrees;
        let pooled = ch.fit(&self.r.pooled);
        let n = 200;
        let curve = |fit: &ChannelFit| -> Vec<(f64, f64)> {
            (0..=n)
                .map(|k| {
                    let a = alpha.lo + alpha.span() * k as f64 / n as f64;
                    (deg(a), eval(fit, a).unwrap_or(f64::NAN))
                })
                .collect()
        };
        let pooled_curve = curve(pooled);
        let values = self.r.points.iter().flat_map(|p| {
            let (v, se) = ch.of(p);
            let e = 2.0 * se.unwrap_or(0.0);
            [v - e, v + e]
        });
        let y = Range::require(values, ch.symbol())?
            .union(Range::require(
                pooled_curve.iter().map(|p| p.1),
                "the pooled fit",
            )?)
            .pad(0.08)
            .headroom(0.18);
        let x = Range::new(deg(alpha.lo), deg(alpha.hi)).pad(0.04);
        let (top, bottom) = area.split_vertically(area.dim_in_pixel().1 * 64 / 100);
        let y_desc = format!("{} (-)", ch.symbol());
        let mut chart = axes::panel(&top, &Axes::new(x, y, "", &y_desc).title(ch.title()))?;
        // each speed's own fit, then the pooled fit, then the points on top
        if self.groups.iter().filter(|g| g.fit.is_some()).count() > 1 {
            for g in &self.groups {
                if let Some(f) = g.fit {
                    axes::dashed(&mut chart, curve(ch.fit(f)), g.colour.stroke_width(2))?;
                }
            }
        }
        axes::line(&mut chart, pooled_curve, colour::DATA.stroke_width(2))?;
        for p in &self.r.points {
            let g = &self.groups[self.group_of(p)];
            let (v, se) = ch.of(p);
            let a = p.alpha_deg;
            if let Some(se) = se {
                axes::error_bar(
                    &mut chart,
                    a,
                    v - 2.0 * se,
                    v + 2.0 * se,
                    g.colour.stroke_width(1),
                )?;
            }
            let style = if p.used {
                g.colour.filled()
            } else {
                colour::GREY.stroke_width(2)
            };
            axes::dots(&mut chart, [(a, v)], 5, style)?;
        }
        let mut note = vec![formula(ch.symbol(), pooled)];
        if let (Some(r2), Some(s)) = (pooled.r_squared, pooled.residual_std) {
            note.push(format!(
                "R² = {:.5}, residual SD = {}",
                r2,
                crate::base::numfmt::num(s)
            ));
        }
        axes::note(&chart, &note)?;

        // residuals of the pooled fit
        let res: Vec<(usize, f64, f64)> = self
            .r
            .points
            .iter()
            .filter(|p| p.used)
            .filter_map(|p| {
                let f = eval(pooled, p.alpha)?;
                Some((self.group_of(p), p.alpha_deg, ch.of(p).0 - f))
            })
            .collect();
        let ry = Range::of(res.iter().map(|r| r.2))
            .unwrap_or(Range::new(-1.0, 1.0))
            .symmetric()
            .pad(0.15);
        let ry_desc = format!("{} residual (-)", ch.symbol());
        let mut rchart = axes::panel(&bottom, &Axes::new(x, ry, "drift angle α (deg)", &ry_desc))?;
        axes::hline(&mut rchart, x, 0.0, colour::GREY.stroke_width(1), false)?;
        for (g, a, r) in res {
            axes::dots(&mut rchart, [(a, r)], 4, self.groups[g].colour.filled())?;
        }
        Ok(())
    }
}

impl Plot for PolarFits<'_> {
    fn meta(&self) -> FigureMeta {
        FigureMeta {
            name: "polar".into(),
            title: "Static polars: C_D, C_L, C_M against drift angle".into(),
            caption: format!(
                "Body-axis force and moment coefficients of the steady {} runs against the \
                 drift angle α = atan(v/u), with the constrained least-squares fit over all \
                 speeds (solid) that gives the coefficients{}; residuals of that fit below. \
                 Reference quantities: {}",
                self.word,
                if self.groups.len() > 1 {
                    ", and each speed's own fit (dashed)"
                } else {
                    ""
                },
                self.r.reference.statement
            ),
            section: Section::Polar,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1600, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let alpha = self.alpha_range()?;
        let body = style::frame(
            root,
            "Static polars: body-axis coefficients against drift angle",
            &self.keys(),
        )?;
        for (area, ch) in body.split_evenly((1, 3)).iter().zip(Channel::ALL) {
            self.draw_channel(area, ch, alpha)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(names: &[&str], values: &[f64]) -> ChannelFit {
        ChannelFit {
            channel: "drag".into(),
            model: String::new(),
            names: names.iter().map(|s| s.to_string()).collect(),
            units: vec![String::new(); names.len()],
            values: values.to_vec(),
            std_errors: vec![None; names.len()],
            covariance: None,
            active_constraints: vec![],
            binding_inequalities: vec![],
            n_points: 0,
            dof: 0,
            rss: 0.0,
            residual_std: None,
            r_squared: None,
            residuals: vec![],
        }
    }

    #[test]
    fn curves_follow_the_fitted_model() {
        let d = fit(&["a", "b", "c"], &[0.293, -0.0273, 0.0826]);
        let a = 0.2;
        let want = 0.293 * a * a - 0.0273 * a + 0.0826;
        assert!((eval(&d, a).unwrap() - want).abs() < 1e-15);
        let l = fit(&["intercept", "slope", "cubic"], &[0.0, -1.0, 0.5]);
        assert!((eval(&l, 0.3).unwrap() - (-0.3 + 0.5 * 0.027)).abs() < 1e-15);
        assert_eq!(eval(&fit(&["d"], &[1.0]), 0.1), None);
        assert_eq!(
            formula("C_D", &d),
            "C_D = 0.2930 α² − 0.02730 α + 0.08260  (α in rad)"
        );
        assert_eq!(formula("C_L", &l), "C_L = 0.5000 α³ − 1.000 α  (α in rad)");
        assert_eq!(
            formula("C_M", &fit(&["slope"], &[0.0])),
            "C_M = 0  (α in rad)"
        );
    }
}
