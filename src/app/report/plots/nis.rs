//! Innovation consistency of one fit run: the normalised innovation squared of every sample
//! against its two-sided 95 % chi-square bounds, and its running mean against the bounds of
//! a mean over that many samples.

use super::axes::{self, Axes, Range};
use super::style::{self, colour, Key, Mark};
use super::{FigureMeta, Plot, PlotError, Section};
use crate::base::numfmt::num;
use crate::numerics::estimation::nis::{self, NisSummary};
use crate::stages::hekf::{RunSummary, RunTraces};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Running mean of the finite values of `v` (NaN until the first finite one).
pub fn running_mean(v: &[f64]) -> Vec<f64> {
    let (mut s, mut n) = (0.0, 0usize);
    v.iter()
        .map(|x| {
            if x.is_finite() {
                s += x;
                n += 1;
            }
            if n == 0 {
                f64::NAN
            } else {
                s / n as f64
            }
        })
        .collect()
}

/// The 95 % bounds of a mean of `k` NIS values of `dof` degrees of freedom, at about
/// `n` sample counts spaced logarithmically from 1 to `k_max` (and at `k_max`), with the
/// variance `extra` an estimated measurement noise adds ([`nis::mean_bounds`]).
pub fn mean_bounds(dof: usize, k_max: usize, n: usize, extra: f64) -> Vec<(usize, [f64; 2])> {
    let mut ks: Vec<usize> = (0..n)
        .map(|i| {
            let f = i as f64 / (n.max(2) - 1) as f64;
            ((k_max as f64).powf(f).round() as usize).clamp(1, k_max.max(1))
        })
        .collect();
    ks.push(k_max.max(1));
    ks.dedup();
    ks.into_iter()
        .map(|k| (k, nis::mean_bounds(dof, k, extra)))
        .collect()
}

/// The NIS figure of one fit run.
pub struct NisPlot<'a> {
    index: usize,
    run: &'a RunSummary,
    summary: &'a NisSummary,
    traces: &'a RunTraces,
}

impl<'a> NisPlot<'a> {
    /// The figure of fit run number `index` (1-based), when it has NIS values.
    pub fn new(index: usize, run: &'a RunSummary, traces: &'a RunTraces) -> Option<Self> {
        let summary = run.nis.as_ref()?;
        (traces.nis.len() == traces.times.len() && traces.nis.iter().any(|v| v.is_finite()))
            .then_some(NisPlot {
                index,
                run,
                summary,
                traces,
            })
    }

    fn verdict(&self) -> String {
        let s = self.summary;
        format!(
            "mean NIS {} against 95 % bounds [{}, {}] for the mean: {}",
            num(s.mean),
            num(s.mean_bounds[0]),
            num(s.mean_bounds[1]),
            if s.consistent {
                "consistent"
            } else if s.mean > s.mean_bounds[1] {
                "too large: the innovations exceed what the noise model allows"
            } else {
                "too small: the noise model is more pessimistic than the innovations"
            }
        )
    }
}

impl Plot for NisPlot<'_> {
    fn meta(&self) -> FigureMeta {
        let s = self.summary;
        FigureMeta {
            name: format!("nis_fit_{}", self.index),
            title: format!("NIS of fit run {}: {}", self.index, self.run.name),
            caption: format!(
                "Normalised innovation squared ν'S⁻¹ν of each sample of '{}' in the last pass \
                 ({} measurements, so χ² with {} degrees of freedom for a consistent filter), \
                 against its two-sided 95 % bounds [{}, {}]: {:.1} % of the samples are \
                 outside (5 % expected). Below, the running mean against the 95 % bounds of a \
                 mean of that many samples; {}.",
                self.run.name,
                s.dof,
                s.dof,
                num(s.sample_bounds[0]),
                num(s.sample_bounds[1]),
                100.0 * s.fraction_outside,
                self.verdict()
            ),
            section: Section::Hekf,
            shows: Vec::new(),
        }
    }

    fn size(&self) -> (u32, u32) {
        (1400, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let s = self.summary;
        let keys = vec![
            Key::new(Mark::Dot(colour::BLUE), "NIS of a sample"),
            Key::new(Mark::Dashed(colour::VERMILLION), "95 % bounds (χ²)"),
            Key::new(
                Mark::Line(colour::GREY),
                format!("expected value {} (= dof)", s.dof),
            ),
            Key::new(Mark::Line(colour::BLUE), "running mean"),
        ];
        let body = style::frame(
            root,
            &format!(
                "Innovation consistency (NIS), fit run {}: {}",
                self.index, self.run.name
            ),
            &keys,
        )?;
        let t = &self.traces.times;
        let nis = &self.traces.nis;
        let x = Range::require(t.iter().copied(), "NIS times")?;
        let positive = Range::of(nis.iter().copied().filter(|v| *v > 0.0));
        let lo = positive
            .map_or(s.sample_bounds[0], |r| r.lo)
            .min(s.sample_bounds[0] / 3.0)
            .max(s.sample_bounds[0] / 1e3);
        let hi = positive
            .map_or(s.sample_bounds[1], |r| r.hi)
            .max(s.sample_bounds[1] * 3.0);
        let y = Range::new(lo.log10(), hi.log10()).pad(0.03);
        let (top, bottom) = body.split_vertically(body.dim_in_pixel().1 * 55 / 100);
        let mut chart = axes::panel(&top, &Axes::new(x, y, "", "NIS (-), log scale").log_y())?;
        let log = |v: f64| y.clamp(v.max(lo).log10());
        axes::dots(
            &mut chart,
            t.iter()
                .zip(nis)
                .map(|(a, b)| (*a, if b.is_finite() { log(*b) } else { f64::NAN })),
            2,
            colour::BLUE.mix(0.6).filled(),
        )?;
        for b in s.sample_bounds {
            axes::hline(
                &mut chart,
                x,
                log(b),
                colour::VERMILLION.stroke_width(2),
                true,
            )?;
        }
        axes::hline(
            &mut chart,
            x,
            log(s.dof as f64),
            colour::GREY.stroke_width(2),
            false,
        )?;
        axes::note(
            &chart,
            &[format!(
                "{:.1} % of samples outside [{}, {}] (5 % expected)",
                100.0 * s.fraction_outside,
                num(s.sample_bounds[0]),
                num(s.sample_bounds[1])
            )],
        )?;

        let mean = running_mean(nis);
        let bounds = mean_bounds(s.dof, nis.len(), 120, s.noise_estimate_variance);
        let skip = nis.len() / 50; // the first samples' mean is one value: let the bounds show it
        let ym = Range::require(mean.iter().skip(skip).copied(), "running mean NIS")?
            .include(s.mean_bounds[0])
            .include(s.mean_bounds[1])
            .include(s.dof as f64)
            .pad(0.1);
        let mut m = axes::panel(
            &bottom,
            &Axes::new(x, ym, "time t (s)", "running mean of NIS (-)"),
        )?;
        let at = |k: usize| t[(k - 1).min(t.len() - 1)];
        for side in 0..2 {
            axes::dashed(
                &mut m,
                bounds.iter().map(|(k, b)| (at(*k), ym.clamp(b[side]))),
                colour::VERMILLION.stroke_width(2),
            )?;
        }
        axes::hline(&mut m, x, s.dof as f64, colour::GREY.stroke_width(2), false)?;
        axes::line(
            &mut m,
            t.iter().copied().zip(mean.iter().map(|v| ym.clamp(*v))),
            colour::BLUE.stroke_width(2),
        )?;
        axes::note(&m, &[self.verdict()])?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::estimation::nis::summarize;

    #[test]
    fn a_long_run_draws_a_small_figure_that_still_shows_an_outlier() {
        // 300,000 samples (the issue: a 28 MB SVG), one far outlier
        let k = 300_000;
        let times: Vec<f64> = (0..k).map(|i| i as f64 * 0.01).collect();
        let nis: Vec<f64> = (0..k)
            .map(|i| {
                if i == 123_457 {
                    5e4
                } else {
                    1.0 + 5.0 * ((i as f64 * 0.37).sin().powi(2))
                }
            })
            .collect();
        let run = RunSummary {
            name: "long".into(),
            file: "long.csv".into(),
            samples: k,
            duration: times[k - 1],
            mean_dt: 0.01,
            measured: vec!["u".into(), "v".into(), "r".into()],
            noise: Vec::new(),
            process_noise: Default::default(),
            nis: summarize(&nis, 3, 0.0),
            innovation_rms: Vec::new(),
            between: Default::default(),
            states: None,
            warnings: Vec::new(),
        };
        let traces = RunTraces {
            times,
            measured: run.measured.clone(),
            filtered: Vec::new(),
            smoothed: None,
            history: Vec::new(),
            nis,
            states: None,
        };
        let fig = super::super::render(&NisPlot::new(1, &run, &traces).unwrap(), None).unwrap();
        assert!(fig.svg.len() < 600_000, "{} bytes", fig.svg.len());
        // the outlier is drawn: one sample dot (radius 2; the legend's is larger) far above
        // all the others
        let mut cy: Vec<f64> = fig
            .svg
            .split("<circle")
            .skip(1)
            .filter(|c| c.contains("r=\"2\""))
            .filter_map(|c| c.split("cy=\"").nth(1)?.split('"').next()?.parse().ok())
            .collect();
        cy.sort_by(f64::total_cmp);
        assert!(cy.len() > 1000, "{} dots", cy.len());
        assert!(cy[0] + 100.0 < cy[1], "highest dots at {:?}", &cy[..5]);
    }

    #[test]
    fn running_mean_and_its_bounds() {
        assert_eq!(running_mean(&[2.0, 4.0, 6.0]), vec![2.0, 3.0, 4.0]);
        let m = running_mean(&[f64::NAN, 2.0, f64::INFINITY, 4.0]);
        assert!(m[0].is_nan());
        assert_eq!(&m[1..], &[2.0, 2.0, 3.0]);
        let b = mean_bounds(6, 2001, 50, 0.0);
        assert_eq!(b.first().unwrap().0, 1);
        assert_eq!(b.last().unwrap().0, 2001);
        assert!(b.windows(2).all(|w| w[1].0 > w[0].0));
        // the bounds of a single value are the per-sample bounds, and they narrow about dof
        let one = nis::chi2_bounds(6.0);
        assert!((b[0].1[0] - one[0]).abs() < 1e-12 && (b[0].1[1] - one[1]).abs() < 1e-12);
        let last = b.last().unwrap().1;
        assert!(
            last[0] < 6.0 && last[1] > 6.0 && last[1] - last[0] < 0.4,
            "{last:?}"
        );
        // an estimated noise widens the bounds, most where many samples made them narrow
        let wide = mean_bounds(6, 2001, 50, 0.01);
        let w = wide.last().unwrap().1;
        assert!(w[0] < last[0] && w[1] > last[1], "{w:?} against {last:?}");
        assert!(
            (wide[0].1[1] - one[1]).abs() < 0.05 * one[1],
            "{:?}",
            wide[0]
        );
    }
}
