//! Stage conflicts: two stages' estimates of one coefficient tested for agreement before the
//! later one replaces the earlier (docs/stages.md, "Stage conflicts").

use super::{Coefficient, CoefficientSet, Source};

/// Two estimates of one coefficient further apart than their sigmas allow.
#[derive(Debug, Clone, PartialEq)]
pub struct Conflict {
    /// The estimate already in the set (an earlier stage, or a relation over its values).
    pub earlier: Coefficient,
    /// The estimate that arrives.
    pub later: Coefficient,
    /// |later - earlier| / sqrt(sigma_earlier^2 + sigma_later^2).
    pub z: f64,
}

impl CoefficientSet {
    /// The coefficients of `incoming` that an earlier stage of this set (or a relation over
    /// the stages' values) also estimated, more than `limit` combined sigmas apart. Values
    /// without a sigma on either side (configured, analytic, held by a constraint) are not
    /// tested: nothing says how far apart they may be.
    pub fn conflicts(&self, incoming: &[Coefficient], limit: f64) -> Vec<Conflict> {
        incoming
            .iter()
            .filter_map(|later| {
                let earlier = self.get(&later.name)?;
                let measured = matches!(
                    earlier.source,
                    Source::Polar
                        | Source::Surge
                        | Source::Captive
                        | Source::Hekf
                        | Source::Symmetry
                );
                let combined = earlier.sigma?.hypot(later.sigma?);
                if !measured || combined.is_nan() || combined <= 0.0 {
                    return None;
                }
                let z = (later.value - earlier.value).abs() / combined;
                (z > limit).then(|| Conflict {
                    earlier: earlier.clone(),
                    later: later.clone(),
                    z,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(c: &[(&str, f64, Option<f64>, Source)]) -> CoefficientSet {
        let mut s = CoefficientSet::new();
        for (n, v, sg, src) in c {
            s.insert(Coefficient::new(n, *v, *sg, *src));
        }
        s
    }

    #[test]
    fn estimates_apart_by_more_than_the_limit_conflict() {
        let known = set(&[
            ("Nuv", 13.40, Some(0.055), Source::Polar),
            ("Yuv", -20.0, Some(0.1), Source::Polar),
            ("Xud", -1.0, None, Source::Config),
        ]);
        let incoming = [
            Coefficient::new("Nuv", -9.033, Some(0.004), Source::Captive),
            Coefficient::new("Yuv", -20.2, Some(0.1), Source::Captive),
            Coefficient::new("Xud", -3.0, Some(0.01), Source::Captive),
            Coefficient::new("Yvd", -3.0, Some(0.01), Source::Captive),
        ];
        let c = known.conflicts(&incoming, 3.0);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].later.name, "Nuv");
        // (13.40 + 9.033) / sqrt(0.055^2 + 0.004^2) = 406.8
        assert!((c[0].z - 406.8).abs() < 0.05, "{}", c[0].z);
    }

    #[test]
    fn values_without_a_sigma_are_not_tested() {
        let known = set(&[("Nuv", 1.0, Some(0.0), Source::Polar)]);
        let incoming = [Coefficient::new("Nuv", 2.0, Some(0.0), Source::Captive)];
        assert!(known.conflicts(&incoming, 3.0).is_empty());
    }
}
