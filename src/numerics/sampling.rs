//! The time axis of a run: its regular sampling interval and the gaps in it.

/// An interval longer than this many regular intervals is a gap.
pub const GAP_FACTOR: f64 = 1.5;

/// The median sampling interval (which a few gaps do not move), or None for fewer than two
/// samples.
pub fn median_interval(times: &[f64]) -> Option<f64> {
    if times.len() < 2 {
        return None;
    }
    let mut d: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = d.len() / 2;
    let (_, m, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// A gap: the interval after sample `after` is longer than [`GAP_FACTOR`] regular intervals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Index of the sample before the gap.
    pub after: usize,
    /// Time of that sample, s.
    pub start: f64,
    /// Length of the interval, s.
    pub length: f64,
}

/// Every gap of a time axis.
pub fn gaps(times: &[f64]) -> Vec<Gap> {
    let Some(dt) = median_interval(times) else {
        return Vec::new();
    };
    times
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[1] - w[0] > GAP_FACTOR * dt)
        .map(|(k, w)| Gap {
            after: k,
            start: w[0],
            length: w[1] - w[0],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gap_is_found_where_it_is_and_does_not_move_the_interval() {
        let mut t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
        for v in t.iter_mut().skip(50) {
            *v += 2.0;
        }
        assert!((median_interval(&t).unwrap() - 0.01).abs() < 1e-12);
        let g = gaps(&t);
        assert_eq!(g.len(), 1);
        assert_eq!(g[0].after, 49);
        assert!((g[0].start - 0.49).abs() < 1e-12 && (g[0].length - 2.01).abs() < 1e-9);
        assert!(gaps(&t[..50]).is_empty());
        assert_eq!(median_interval(&[1.0]), None);
    }
}
