//! Rauch-Tung-Striebel fixed-interval smoother over a filter pass (Simon 2006, section 9.4.2):
//! G_k = P_k|k Phi_k+1^T P_k+1|k^-1 and x_k|N = x_k|k + G_k (x_k+1|N - x_k+1|k).
//!
//! The backward sweep needs, at every sample, the prior and posterior covariances and the
//! transition matrix: three n x n matrices, 3.5 kB per sample for 12 states, 3.5 GB for a
//! million samples. Instead of keeping them, the pass is smoothed in segments
//! ([`smooth_segments`]): the caller saves the filter's whole state at the start of every
//! segment (a checkpoint) during the forward pass, and the backward sweep re-runs the filter
//! from each checkpoint over its segment, last segment first, keeping the dense trace of one
//! segment at a time (checkpointing, Griewank & Walther 2008, "Evaluating Derivatives",
//! ch. 12). With segments of about sqrt(K) samples the memory is O(sqrt(K)) matrices instead
//! of O(K), for the cost of one more filter pass. The re-run repeats the forward pass's
//! arithmetic exactly, so the smoothed states are the same to the last bit as those of a
//! sweep over a full trace.
//!
//! The smoothed covariance goes with each smoothed state (Simon 2006, eq. 9.115; Rauch, Tung
//! & Striebel 1965): P_k|N = P_k|k + G_k (P_k+1|N - P_k+1|k) G_k^T, computed in the same
//! order of operations as a sweep over a full trace, so that it too is the same to the last
//! bit.

use crate::numerics::linalg::{cholesky, cholesky_solve, matmul, matmul_bt, symmetrize};

/// The dense record of consecutive samples of a filter pass: what the backward step needs.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    /// State dimension.
    pub n: usize,
    /// Index in the pass of the first sample held.
    pub start: usize,
    /// Prior (predicted) state at each sample (len x n).
    pub x_prior: Vec<f64>,
    /// Prior covariance at each sample (len x n x n).
    pub p_prior: Vec<f64>,
    /// Transition matrix from the previous sample to this one (len x n x n; unused at the
    /// first sample of the pass).
    pub phi: Vec<f64>,
    /// Posterior (updated) state (len x n).
    pub x_post: Vec<f64>,
    /// Posterior covariance (len x n x n).
    pub p_post: Vec<f64>,
}

impl Trace {
    /// An empty trace for n states.
    pub fn new(n: usize) -> Self {
        Trace {
            n,
            ..Default::default()
        }
    }

    /// Empties the trace; the next sample pushed is sample `start` of the pass.
    pub fn restart(&mut self, start: usize) {
        self.start = start;
        for v in [
            &mut self.x_prior,
            &mut self.p_prior,
            &mut self.phi,
            &mut self.x_post,
            &mut self.p_post,
        ] {
            v.clear();
        }
    }

    /// Records the prediction of the next sample: prior state, covariance and the transition
    /// matrix from the sample before (`None` at the first sample of a pass).
    pub fn push_prior(&mut self, x: &[f64], p: &[f64], phi: Option<&[f64]>) {
        self.x_prior.extend_from_slice(x);
        self.p_prior.extend_from_slice(p);
        match phi {
            Some(phi) => self.phi.extend_from_slice(phi),
            None => self.phi.resize(self.phi.len() + self.n * self.n, 0.0),
        }
    }

    /// Records the update of the sample last predicted.
    pub fn push_post(&mut self, x: &[f64], p: &[f64]) {
        self.x_post.extend_from_slice(x);
        self.p_post.extend_from_slice(p);
    }

    /// Number of samples held.
    pub fn len(&self) -> usize {
        self.x_post.len() / self.n.max(1)
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.x_post.is_empty()
    }

    fn x_prior(&self, k: usize) -> &[f64] {
        let i = k - self.start;
        &self.x_prior[i * self.n..(i + 1) * self.n]
    }

    fn x_post(&self, k: usize) -> &[f64] {
        let i = k - self.start;
        &self.x_post[i * self.n..(i + 1) * self.n]
    }

    fn matrix<'a>(&self, v: &'a [f64], k: usize) -> &'a [f64] {
        let (i, nn) = (k - self.start, self.n * self.n);
        &v[i * nn..(i + 1) * nn]
    }
}

/// Why smoothing failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SmoothError<E> {
    /// Re-running the filter over a segment failed.
    Filter(E),
    /// The predicted covariance at this sample is not positive definite.
    NotPositiveDefinite(usize),
}

/// Work space of one backward step.
struct Backward {
    n: usize,
    l: Vec<f64>,
    b: Vec<f64>,
    g: Vec<f64>,
    col: Vec<f64>,
    d: Vec<f64>,
    tmp: Vec<f64>,
}

impl Backward {
    fn new(n: usize) -> Self {
        Backward {
            n,
            l: vec![0.0; n * n],
            b: vec![0.0; n * n],
            g: vec![0.0; n * n],
            col: vec![0.0; n],
            d: vec![0.0; n * n],
            tmp: vec![0.0; n * n],
        }
    }

    /// P_k|N (into `out`) from the gain of the last [`Backward::step`] at sample k and
    /// P_k+1|N (`next`): P_k|k + G (P_k+1|N - P_k+1|k) G^T, symmetrised (Simon 2006,
    /// eq. 9.115).
    fn covariance(&mut self, tr: &Trace, k: usize, next: &[f64], out: &mut [f64]) {
        let n = self.n;
        let prior = tr.matrix(&tr.p_prior, k + 1);
        for ((d, a), b) in self.d.iter_mut().zip(next).zip(prior) {
            *d = a - b;
        }
        matmul(&self.g, &self.d, n, n, n, &mut self.tmp);
        matmul_bt(&self.tmp, &self.g, n, n, n, &mut self.d);
        for ((o, p), dv) in out.iter_mut().zip(tr.matrix(&tr.p_post, k)).zip(&self.d) {
            *o = p + dv;
        }
        symmetrize(out, n);
    }

    /// x_k|N (into `out`) from the trace at sample k and k + 1 and x_k+1|N (`next`). Fails
    /// with k + 1 when P_k+1|k is not positive definite.
    fn step(&mut self, tr: &Trace, k: usize, next: &[f64], out: &mut [f64]) -> Result<(), usize> {
        let n = self.n;
        // G^T = P_prior(k+1)^-1 Phi(k+1) P_post(k)
        self.l.copy_from_slice(tr.matrix(&tr.p_prior, k + 1));
        cholesky(&mut self.l, n).map_err(|_| k + 1)?;
        matmul(
            tr.matrix(&tr.phi, k + 1),
            tr.matrix(&tr.p_post, k),
            n,
            n,
            n,
            &mut self.b,
        );
        for j in 0..n {
            for i in 0..n {
                self.col[i] = self.b[i * n + j];
            }
            cholesky_solve(&self.l, n, &mut self.col);
            for i in 0..n {
                self.g[j * n + i] = self.col[i]; // G = (G^T)^T
            }
        }
        let (x_post, x_prior) = (tr.x_post(k), tr.x_prior(k + 1));
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s += self.g[i * n + j] * (next[j] - x_prior[j]);
            }
            out[i] = x_post[i] + s;
        }
        Ok(())
    }
}

/// Smooths a pass of `len` samples of an `n`-state filter in segments of `segment` samples
/// (module docs). `rerun(start, end, trace)` must fill `trace` (restarted at `start`) with
/// samples `start..end` of the pass exactly as the forward pass computed them, by re-running
/// the filter from its checkpoint at `start` (a multiple of `segment`). `emit(k, x, p)`
/// receives the smoothed state and covariance (n x n) of every sample, last sample first.
pub fn smooth_segments<E>(
    n: usize,
    len: usize,
    segment: usize,
    mut rerun: impl FnMut(usize, usize, &mut Trace) -> Result<(), E>,
    mut emit: impl FnMut(usize, &[f64], &[f64]),
) -> Result<(), SmoothError<E>> {
    if len == 0 {
        return Ok(());
    }
    let segment = segment.max(1);
    let mut trace = Trace::new(n);
    let mut back = Backward::new(n);
    let mut next = vec![0.0; n];
    let mut cur = vec![0.0; n];
    let mut next_p = vec![0.0; n * n];
    let mut cur_p = vec![0.0; n * n];
    let last_start = (len - 1) / segment * segment;
    for start in (0..=last_start).rev().step_by(segment) {
        // one sample into the next segment: its prior and transition close this segment
        let end = (start + segment + 1).min(len);
        trace.restart(start);
        rerun(start, end, &mut trace).map_err(SmoothError::Filter)?;
        for k in (start..(start + segment).min(len)).rev() {
            if k + 1 == len {
                cur.copy_from_slice(trace.x_post(k));
                cur_p.copy_from_slice(trace.matrix(&trace.p_post, k));
            } else {
                back.step(&trace, k, &next, &mut cur)
                    .map_err(SmoothError::NotPositiveDefinite)?;
                back.covariance(&trace, k, &next_p, &mut cur_p);
            }
            emit(k, &cur, &cur_p);
            std::mem::swap(&mut next, &mut cur);
            std::mem::swap(&mut next_p, &mut cur_p);
        }
    }
    Ok(())
}

/// Samples per segment for a pass of `len` samples: about sqrt(len), which balances the
/// checkpoints (len / segment filter states) against one segment's dense trace.
pub fn segment_length(len: usize) -> usize {
    ((len as f64).sqrt().ceil() as usize).max(16)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::numerics::linalg::{matmul_bt, symmetrize};
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// The smoother as it was before segments: one backward sweep over a full trace, states
    /// and covariances (the reference the segmented sweep must reproduce bit for bit).
    pub(crate) fn dense_smooth(tr: &Trace) -> Result<(Vec<f64>, Vec<f64>), usize> {
        let n = tr.n;
        let kk = tr.len();
        let nn = n * n;
        let mut xs = tr.x_post.clone();
        let mut ps = tr.p_post.clone();
        let mut l = vec![0.0; nn];
        let mut b = vec![0.0; nn];
        let mut g = vec![0.0; nn];
        let mut d = vec![0.0; nn];
        let mut tmp = vec![0.0; nn];
        let mut col = vec![0.0; n];
        for k in (0..kk.saturating_sub(1)).rev() {
            l.copy_from_slice(&tr.p_prior[(k + 1) * nn..(k + 2) * nn]);
            cholesky(&mut l, n).map_err(|_| k + 1)?;
            matmul(
                &tr.phi[(k + 1) * nn..(k + 2) * nn],
                &tr.p_post[k * nn..(k + 1) * nn],
                n,
                n,
                n,
                &mut b,
            );
            for j in 0..n {
                for i in 0..n {
                    col[i] = b[i * n + j];
                }
                cholesky_solve(&l, n, &mut col);
                for i in 0..n {
                    g[j * n + i] = col[i];
                }
            }
            for i in 0..n {
                let mut s = 0.0;
                for j in 0..n {
                    s += g[i * n + j] * (xs[(k + 1) * n + j] - tr.x_prior[(k + 1) * n + j]);
                }
                xs[k * n + i] += s;
            }
            for i in 0..nn {
                d[i] = ps[(k + 1) * nn + i] - tr.p_prior[(k + 1) * nn + i];
            }
            matmul(&g, &d, n, n, n, &mut tmp);
            matmul_bt(&tmp, &g, n, n, n, &mut d);
            let pk = &mut ps[k * nn..(k + 1) * nn];
            for (p, dv) in pk.iter_mut().zip(&d) {
                *p += dv;
            }
            symmetrize(pk, n);
        }
        Ok((xs, ps))
    }

    /// Smooths a full trace in segments, the re-run copying samples out of it: the states.
    fn segmented(full: &Trace, segment: usize) -> Result<Vec<f64>, SmoothError<()>> {
        segmented_with_covariance(full, segment).map(|(xs, _)| xs)
    }

    /// Smooths a full trace in segments: the states and the covariances.
    fn segmented_with_covariance(
        full: &Trace,
        segment: usize,
    ) -> Result<(Vec<f64>, Vec<f64>), SmoothError<()>> {
        let (n, nn) = (full.n, full.n * full.n);
        let mut xs = vec![f64::NAN; full.len() * n];
        let mut ps = vec![f64::NAN; full.len() * nn];
        smooth_segments(
            n,
            full.len(),
            segment,
            |a, b, tr: &mut Trace| {
                for k in a..b {
                    tr.push_prior(
                        &full.x_prior[k * n..(k + 1) * n],
                        &full.p_prior[k * nn..(k + 1) * nn],
                        (k > 0).then(|| &full.phi[k * nn..(k + 1) * nn]),
                    );
                    tr.push_post(
                        &full.x_post[k * n..(k + 1) * n],
                        &full.p_post[k * nn..(k + 1) * nn],
                    );
                }
                Ok(())
            },
            |k, x, p| {
                xs[k * n..(k + 1) * n].copy_from_slice(x);
                ps[k * nn..(k + 1) * nn].copy_from_slice(p);
            },
        )?;
        Ok((xs, ps))
    }

    /// A Kalman filter over a random stable linear system: its full trace.
    fn random_pass(n: usize, len: usize, seed: u64) -> Trace {
        let mut rng = StdRng::seed_from_u64(seed);
        let nn = n * n;
        let mut phi = vec![0.0; nn];
        for i in 0..n {
            for j in 0..n {
                phi[i * n + j] =
                    if i == j { 0.95 } else { 0.0 } + 0.05 * rng.random_range(-1.0..1.0);
            }
        }
        let mut x = vec![0.0; n];
        let mut p = vec![0.0; nn];
        for i in 0..n {
            p[i * n + i] = 1.0;
        }
        let mut tr = Trace::new(n);
        let mut tmp = vec![0.0; nn];
        for k in 0..len {
            if k > 0 {
                let mut xn = vec![0.0; n];
                matmul(&phi, &x, n, n, 1, &mut xn);
                x = xn;
                matmul(&phi, &p, n, n, n, &mut tmp);
                matmul_bt(&tmp, &phi, n, n, n, &mut p);
                for i in 0..n {
                    p[i * n + i] += 0.01;
                }
            }
            tr.push_prior(&x, &p, (k > 0).then_some(phi.as_slice()));
            // scalar measurements of every state, r = 0.1, one at a time
            for j in 0..n {
                let y = (k as f64 * 0.1 + j as f64).sin() + 0.3 * rng.random_range(-1.0..1.0);
                let s = p[j * n + j] + 0.1;
                let kg: Vec<f64> = (0..n).map(|i| p[i * n + j] / s).collect();
                let nu = y - x[j];
                for i in 0..n {
                    x[i] += kg[i] * nu;
                }
                let pj: Vec<f64> = (0..n).map(|i| p[j * n + i]).collect();
                for a in 0..n {
                    for b in 0..n {
                        p[a * n + b] -= kg[a] * pj[b];
                    }
                }
                symmetrize(&mut p, n);
            }
            tr.push_post(&x, &p);
        }
        tr
    }

    #[test]
    fn smoothing_a_random_walk_pulls_the_past_towards_later_data() {
        // scalar random walk, Phi = 1, q = 1, r = 1: measurements 0 then 10
        let mut tr = Trace::new(1);
        let (mut x, mut p) = (0.0, 1.0);
        for (k, y) in [0.0, 10.0].iter().enumerate() {
            if k > 0 {
                p += 1.0;
            }
            tr.push_prior(&[x], &[p], (k > 0).then_some(&[1.0][..]));
            let kg = p / (p + 1.0);
            x += kg * (y - x);
            p *= 1.0 - kg;
            tr.push_post(&[x], &[p]);
        }
        // filtered x0 = 0 (p 0.5); prior x1 = 0 (p 1.5); posterior x1 = 6 (p 0.6)
        // G0 = 0.5/1.5 = 1/3; xs0 = 0 + (6 - 0)/3 = 2; ps0 = 0.5 + (0.6 - 1.5)/9 = 0.4
        for segment in [1, 2, 5] {
            let (xs, ps) = segmented_with_covariance(&tr, segment).unwrap();
            assert!((xs[0] - 2.0).abs() < 1e-12);
            assert!((xs[1] - 6.0).abs() < 1e-12);
            assert!((ps[0] - 0.4).abs() < 1e-12);
            assert!((ps[1] - 0.6).abs() < 1e-12);
        }
        let (xs, ps) = dense_smooth(&tr).unwrap();
        assert!((xs[0] - 2.0).abs() < 1e-12);
        assert!((ps[0] - 0.4).abs() < 1e-12);
    }

    #[test]
    fn segments_reproduce_the_full_sweep_bit_for_bit() {
        let tr = random_pass(5, 101, 3);
        let (dense, dense_p) = dense_smooth(&tr).unwrap();
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
        for segment in [1, 2, 7, 10, 100, 101, 500, segment_length(101)] {
            let (xs, ps) = segmented_with_covariance(&tr, segment).unwrap();
            assert!(same(&xs, &dense), "segment {segment}");
            assert!(same(&ps, &dense_p), "covariance, segment {segment}");
        }
        // the smoothed variances lie at or below the filtered ones (the smoother adds the
        // later data's information), and equal them at the last sample
        let (n, nn, last) = (5, 25, tr.len() - 1);
        for k in 0..tr.len() {
            for i in 0..n {
                let (s, f) = (dense_p[k * nn + i * n + i], tr.p_post[k * nn + i * n + i]);
                assert!(s <= f * (1.0 + 1e-12), "sample {k}, state {i}: {s} > {f}");
                assert!(k < last || s == f);
            }
        }
        assert!((0..last).any(|k| dense_p[k * nn] < 0.99 * tr.p_post[k * nn]));
    }

    #[test]
    fn a_bad_predicted_covariance_names_its_sample() {
        let mut tr = random_pass(3, 40, 5);
        let nn = 9;
        for v in &mut tr.p_prior[17 * nn..18 * nn] {
            *v = -1.0;
        }
        assert_eq!(dense_smooth(&tr).unwrap_err(), 17);
        assert_eq!(
            segmented(&tr, 6).unwrap_err(),
            SmoothError::NotPositiveDefinite(17)
        );
    }

    #[test]
    fn a_failed_rerun_stops_the_sweep() {
        let r = smooth_segments(2, 10, 4, |_, _, _| Err("diverged"), |_, _, _| {});
        assert_eq!(r, Err(SmoothError::Filter("diverged")));
        assert_eq!(
            smooth_segments(2, 0, 4, |_, _, _| Err(()), |_, _, _| {}),
            Ok(())
        );
    }
}
