//! The coefficient estimates and their sigmas over a filter pass, as the convergence figure
//! draws them. Up to [`KEEP_ALL`] samples every sample is kept; a longer pass keeps, in each
//! of [`BUCKETS`] equal stretches of samples, the first and the last sample and those where
//! an estimate or a sigma is lowest or highest (min/max-per-bucket decimation): a line drawn
//! through the kept samples covers the same pixels as one through all of them, peaks and
//! spikes included, and the history of a pass of any length takes at most
//! `BUCKETS * (2 + 4 nb)` rows.

/// Samples up to which a history keeps every sample.
pub const KEEP_ALL: usize = 4000;

/// Stretches of samples a longer history is thinned to.
pub const BUCKETS: usize = 500;

/// Estimates and sigmas of the estimated coefficients at the samples kept (module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct History {
    /// Time of each kept sample, s.
    pub times: Vec<f64>,
    /// Estimates (rows x nb, SI).
    pub values: Vec<f64>,
    /// Standard deviations (rows x nb, SI).
    pub sigmas: Vec<f64>,
}

impl History {
    /// Number of kept samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// Builds a [`History`] sample by sample, keeping a bounded number of them.
#[derive(Debug, Clone)]
pub struct HistoryBuilder {
    nb: usize,
    len: usize,
    /// Equal stretches of samples (0: keep every sample).
    buckets: usize,
    /// The stretch the candidates belong to.
    bucket: Option<usize>,
    /// Candidate rows of the current stretch, one per slot: first, last, then the lowest
    /// and the highest of each channel (estimates, then sigmas). A row is sample index, time
    /// and the 2 nb channels.
    slots: Vec<f64>,
    out: History,
}

impl HistoryBuilder {
    /// A builder for `nb` coefficients over a pass of `len` samples.
    pub fn new(nb: usize, len: usize) -> Self {
        let buckets = if len <= KEEP_ALL { 0 } else { BUCKETS };
        HistoryBuilder {
            nb,
            len,
            buckets,
            bucket: None,
            slots: vec![0.0; (2 + 4 * nb) * (2 + 2 * nb)],
            out: History::default(),
        }
    }

    fn row_len(&self) -> usize {
        2 + 2 * self.nb
    }

    /// Adds sample `k` (0-based, increasing) at time `t` with the estimates and sigmas.
    pub fn push(&mut self, k: usize, t: f64, values: &[f64], sigmas: &[f64]) {
        if self.buckets == 0 {
            self.out.times.push(t);
            self.out.values.extend_from_slice(values);
            self.out.sigmas.extend_from_slice(sigmas);
            return;
        }
        let b = k * self.buckets / self.len.max(1);
        let w = self.row_len();
        let nb = self.nb;
        let channel = |c: usize| if c < nb { values[c] } else { sigmas[c - nb] };
        let set = |slots: &mut [f64], slot: usize| {
            let r = &mut slots[slot * w..(slot + 1) * w];
            r[0] = k as f64;
            r[1] = t;
            r[2..2 + nb].copy_from_slice(values);
            r[2 + nb..].copy_from_slice(sigmas);
        };
        if self.bucket != Some(b) {
            self.flush();
            self.bucket = Some(b);
            for slot in 0..2 + 4 * nb {
                set(&mut self.slots, slot);
            }
            return;
        }
        set(&mut self.slots, 1);
        for c in 0..2 * nb {
            let v = channel(c);
            let (lo, hi) = (2 + 2 * c, 3 + 2 * c);
            if v < self.slots[lo * w + 2 + c] {
                set(&mut self.slots, lo);
            }
            if v > self.slots[hi * w + 2 + c] {
                set(&mut self.slots, hi);
            }
        }
    }

    /// Moves the kept rows of the current stretch to the output, in sample order.
    fn flush(&mut self) {
        if self.bucket.take().is_none() {
            return;
        }
        let (w, nb) = (self.row_len(), self.nb);
        let mut order: Vec<usize> = (0..2 + 4 * nb).collect();
        order.sort_by(|a, b| self.slots[a * w].total_cmp(&self.slots[b * w]));
        order.dedup_by(|a, b| self.slots[*a * w] == self.slots[*b * w]);
        for slot in order {
            let r = &self.slots[slot * w..(slot + 1) * w];
            self.out.times.push(r[1]);
            self.out.values.extend_from_slice(&r[2..2 + nb]);
            self.out.sigmas.extend_from_slice(&r[2 + nb..]);
        }
    }

    /// The history.
    pub fn finish(mut self) -> History {
        self.flush();
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(len: usize, f: impl Fn(usize) -> (f64, f64)) -> History {
        let mut b = HistoryBuilder::new(1, len);
        for k in 0..len {
            let (v, s) = f(k);
            b.push(k, k as f64 * 0.01, &[v], &[s]);
        }
        b.finish()
    }

    #[test]
    fn short_passes_keep_every_sample() {
        let h = build(KEEP_ALL, |k| (k as f64, 1.0 / (1.0 + k as f64)));
        assert_eq!(h.len(), KEEP_ALL);
        assert_eq!(h.values[17], 17.0);
        assert_eq!(h.times[17], 0.17);
    }

    #[test]
    fn long_passes_are_bounded_and_keep_the_extremes() {
        let len = 1_000_003;
        let spike = 654_321;
        let h = build(len, |k| {
            let v = (k as f64 * 1e-4).sin() + if k == spike { 50.0 } else { 0.0 };
            (v, 2.0 - k as f64 / len as f64)
        });
        assert!(h.len() <= BUCKETS * 6, "{} rows", h.len());
        assert!(h.len() >= 2 * BUCKETS);
        // first and last sample, the spike, increasing times
        assert_eq!(h.times[0], 0.0);
        assert_eq!(*h.times.last().unwrap(), (len - 1) as f64 * 0.01);
        let max = h.values.iter().copied().fold(f64::MIN, f64::max);
        assert!(max > 50.0, "the spike survives: {max}");
        assert!(h.times.windows(2).all(|w| w[1] > w[0]));
        assert_eq!(h.values.len(), h.len());
        assert_eq!(h.sigmas.len(), h.len());
    }
}
