//! Speed bins (paper fig. 8: X_udot per speed band).

use super::estimate::{part, solve, Stack};
use super::regress::SegmentFit;
use super::{BinFit, DragFrom, SurgeConfig, DEFAULT_SPEED_BINS};
use crate::stages::spread::{spread, Spread};

/// Fits every speed bin on the stretches of runs inside it and compares the bins. Samples are
/// assigned by the fitted speed of the whole fit `whole`, so that the noise of u does not
/// decide which samples a bin keeps (selecting on the dependent variable would bias the fit).
pub(super) fn speed_bins(
    config: &SurgeConfig,
    stack: &Stack,
    mode: DragFrom,
    mass: f64,
    xuu: Option<(f64, Option<f64>)>,
    whole: &SegmentFit,
) -> (Vec<BinFit>, Option<Spread>) {
    let smooth: Vec<f64> = whole.fitted.concat();
    let edges = match &config.speed_bin_edges {
        Some(e) => e.clone(),
        None => {
            let n = config.speed_bins.unwrap_or(DEFAULT_SPEED_BINS).max(1);
            let lo = smooth.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = smooth.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (0..=n)
                .map(|i| lo + (hi - lo) * i as f64 / n as f64)
                .collect()
        }
    };
    let mut bins = Vec::new();
    for (b, w) in edges.windows(2).enumerate() {
        let last = b + 2 == edges.len();
        let inside = |v: f64| v >= w[0] && (v < w[1] || (last && v <= w[1]));
        let mut segs = Vec::new();
        for r in &stack.runs {
            let mut start = None;
            for i in r.clone() {
                match (inside(smooth[i]), start) {
                    (true, None) => start = Some(i),
                    (false, Some(s)) => {
                        segs.push(s..i);
                        start = None;
                    }
                    _ => {}
                }
            }
            if let Some(s) = start {
                segs.push(s..r.end);
            }
        }
        segs.retain(|s| s.len() >= config.min_bin_samples);
        let n_samples = segs.iter().map(|s| s.len()).sum();
        let (fit, note) = if segs.is_empty() {
            (
                None,
                Some(format!(
                    "no stretch of {} or more samples in this speed range",
                    config.min_bin_samples
                )),
            )
        } else {
            match solve(stack, mode, xuu, &segs)
                .map_err(|e| e.to_string())
                .and_then(|f| part(stack, mode, mass, xuu, &segs, &f))
            {
                Ok(p) => (Some(p), None),
                Err(m) => (None, Some(m)),
            }
        };
        bins.push(BinFit {
            u_min: w[0],
            u_max: w[1],
            n_samples,
            n_segments: segs.len(),
            fit,
            note,
        });
    }
    let bin_estimates: Vec<(f64, Option<f64>)> = bins
        .iter()
        .filter_map(|b| b.fit.as_ref())
        .map(|f| (f.xud.value, f.xud.sigma_statistical))
        .collect();
    (bins, spread("Xud", "kg", &bin_estimates))
}
