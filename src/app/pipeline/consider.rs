//! An earlier stage's uncertainty carried through a fitting stage that holds some of its
//! coefficients fixed (the captive fit holds the polar's Y_uv,d while it fits the total
//! Y_uv and books the rest as Y_uv,l).
//!
//! For each earlier uncertainty direction that reaches a coefficient the stage holds fixed,
//! the stage is refitted with the fixed values moved by plus and minus one sigma along it,
//! and half the difference of its estimates, (beta(+) - beta(-)) / 2, is that direction's
//! share in them: linear error propagation by central differences, the "consider" analysis
//! of Bierman (1977, ch. 7), exact for a fit linear in the fixed coefficients. The stage's
//! sigmas then hold these shares as well as its own statistics, and the directions keep the
//! earlier labels, so that the correlation with the earlier stage is carried on.

use crate::model::coefficients::{Coefficient, CoefficientSet, Direction};
use std::collections::BTreeMap;

/// A stage's estimates along the earlier directions, and the directions whose refit failed.
#[derive(Debug, Default)]
pub struct Upstream {
    /// The estimates' one-sigma change along each earlier direction (its label kept).
    pub directions: Vec<Direction>,
    /// Labels of the directions whose refit failed.
    pub failed: Vec<String>,
}

impl Upstream {
    /// The estimates with these shares added to their variances.
    pub fn widen(&self, estimates: &mut [Coefficient]) {
        for c in estimates.iter_mut() {
            let extra: f64 = self
                .directions
                .iter()
                .filter_map(|d| d.deltas.get(&c.name))
                .map(|v| v * v)
                .sum();
            if extra > 0.0 {
                c.sigma = c.sigma.map(|s| (s * s + extra).sqrt());
            }
        }
    }
}

/// The change of `estimates` along every direction of `known` that reaches a coefficient
/// `known` holds and the stage does not estimate, by refitting (`refit`: the stage's
/// estimates from a moved set, None when the fit fails).
pub fn upstream(
    known: &CoefficientSet,
    estimates: &[Coefficient],
    refit: impl Fn(&CoefficientSet) -> Option<Vec<Coefficient>>,
) -> Upstream {
    let estimated = |n: &str| estimates.iter().any(|c| c.name == n);
    let mut out = Upstream::default();
    for d in &known.directions {
        let fixed: Vec<(&String, f64)> = d
            .deltas
            .iter()
            .filter(|(n, v)| !estimated(n) && known.get(n).is_some() && **v != 0.0)
            .map(|(n, v)| (n, *v))
            .collect();
        if fixed.is_empty() {
            continue;
        }
        let at = |sign: f64| {
            let mut moved = known.clone();
            for (n, v) in &fixed {
                if let Some(c) = known.get(n) {
                    let mut c = c.clone();
                    c.value += sign * v;
                    moved.insert(c);
                }
            }
            refit(&moved)
        };
        match (at(1.0), at(-1.0)) {
            (Some(plus), Some(minus)) => {
                let deltas: BTreeMap<String, f64> = estimates
                    .iter()
                    .filter_map(|c| {
                        let p = plus.iter().find(|x| x.name == c.name)?.value;
                        let m = minus.iter().find(|x| x.name == c.name)?.value;
                        Some((c.name.clone(), 0.5 * (p - m)))
                    })
                    .filter(|(_, v)| *v != 0.0 && v.is_finite())
                    .collect();
                if !deltas.is_empty() {
                    out.directions.push(Direction {
                        source: d.source.clone(),
                        deltas,
                    });
                }
            }
            _ => out.failed.push(d.source.clone()),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::coefficients::Source;

    /// A fit of a total t = a + b, with a held: b = t - a, so b moves one for one against a,
    /// and a coefficient the fit does not involve moves nothing.
    #[test]
    fn a_held_part_moves_the_fitted_rest_one_for_one() {
        let mut known = CoefficientSet::new();
        known.insert(Coefficient::new("Yuvd", 1.33, Some(0.02), Source::Polar));
        known.insert(Coefficient::new("Xuu", -1.33, Some(0.01), Source::Polar));
        known.merge_stage(
            Vec::new(),
            vec![
                Direction {
                    source: "polar drag 1".into(),
                    deltas: BTreeMap::from([("Yuvd".into(), 0.02), ("Xuu".into(), 0.001)]),
                },
                Direction {
                    source: "polar drag 2".into(),
                    deltas: BTreeMap::from([("Xuu".into(), 0.01)]),
                },
            ],
        );
        let total = -15.0;
        let fit = |set: &CoefficientSet| {
            Some(vec![Coefficient::new(
                "Yuvl",
                total - set.get("Yuvd")?.value,
                Some(0.05),
                Source::Captive,
            )])
        };
        let mut estimates = fit(&known).unwrap();
        let up = upstream(&known, &estimates, fit);
        assert!(up.failed.is_empty());
        assert_eq!(up.directions.len(), 1, "{:?}", up.directions);
        assert_eq!(up.directions[0].source, "polar drag 1");
        assert!((up.directions[0].deltas["Yuvl"] + 0.02).abs() < 1e-12);
        up.widen(&mut estimates);
        let s = estimates[0].sigma.unwrap();
        assert!((s - (0.05f64.powi(2) + 0.02f64.powi(2)).sqrt()).abs() < 1e-12);
    }

    /// A refit that fails is named, and no share is invented for it.
    #[test]
    fn a_failed_refit_is_named() {
        let mut known = CoefficientSet::new();
        known.insert(Coefficient::new("Yuvd", 1.33, Some(0.02), Source::Polar));
        known.merge_stage(
            Vec::new(),
            vec![Direction {
                source: "polar drag 1".into(),
                deltas: BTreeMap::from([("Yuvd".into(), 0.02)]),
            }],
        );
        let estimates = vec![Coefficient::new("Yuvl", -16.0, Some(0.05), Source::Captive)];
        let up = upstream(&known, &estimates, |_| None);
        assert_eq!(up.failed, vec!["polar drag 1".to_string()]);
        assert!(up.directions.is_empty());
    }
}
