//! Admissible ranges inside the filter (docs/hekf.md, "Admissible ranges"): a coefficient
//! whose range the model declares ([`crate::model::models::Range`]: a frequency is positive, a
//! diagonal added mass has its convention's sign) is kept in it by estimate projection
//! (Simon 2010, "Kalman filtering with state constraints: a survey of linear and nonlinear
//! algorithms", IET Control Theory & Applications 4(8), "estimate projection"; Simon & Chia
//! 2002, "Kalman filtering with state equality constraints", IEEE Trans. AES 38(1)):
//! after a measurement update leaves a coefficient outside its range, the augmented state is
//! moved to the nearest point on the bound in the metric of the filter's covariance,
//!
//! ```text
//! x~ = x^ - W^-1 D^T (D W^-1 D^T)^-1 (D x^ - d),   W = P^-1   (Simon 2010)
//! ```
//!
//! with `D = e_i^T` for the augmented state `i` of the coefficient and `d` its bound, so that
//! the states and coefficients correlated with it move with it as the data say they should.
//! The covariance is left as it is: the projected estimate's error covariance is no larger
//! than the unconstrained one's (Simon & Chia 2002), so P stays a conservative
//! bound, and the reduced covariance `P - P D^T (D P D^T)^-1 D P` would be singular along the
//! bound and keep the coefficient there when later data pull it back inside. Where no bound
//! is reached the filter is the unconstrained one, to the last bit. A cold first pass that
//! more passes follow runs unprojected, as it runs ungated, and only its end is brought into
//! range ([`Bounds::clamp`]; docs/hekf.md, "The first pass").

use crate::base::warning::Warning;
use crate::model::models::{CoefDef, Range};

/// An open bound (`w0 > 0`) is held this share of the coefficient's expected size inside
/// the range: a wave period of hours for w0, where the wave model is a double integrator.
pub const OPEN_MARGIN: f64 = 1e-3;

/// Share of a pass's last run at whose end a projection counts as "at the bound".
const END_SHARE: f64 = 0.05;

/// The ranges of the estimated coefficients in the filter's scaled units (z = beta / s).
#[derive(Debug, Clone, Default)]
pub struct Bounds {
    /// Number of dynamic states before the coefficients in the augmented state.
    nx: usize,
    /// Per estimated coefficient, the lowest and highest admissible z (the open bounds
    /// moved inside by [`OPEN_MARGIN`]); infinite where unbounded.
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Whether any coefficient is bounded.
    any: bool,
}

impl Bounds {
    /// The bounds of coefficients with `ranges` (SI; empty: none) scaled by `scale`, after
    /// `nx` dynamic states.
    pub fn new(ranges: &[Range], scale: &[f64], nx: usize) -> Self {
        let mut lo = vec![f64::NEG_INFINITY; scale.len()];
        let mut hi = vec![f64::INFINITY; scale.len()];
        for (j, (r, &s)) in ranges.iter().zip(scale).enumerate() {
            let (a, b) = admissible(r, s);
            // z = beta / s with s > 0 (an expected size); a negative s swaps the bounds
            let (za, zb) = (a / s, b / s);
            lo[j] = za.min(zb);
            hi[j] = za.max(zb);
        }
        let any = lo.iter().chain(&hi).any(|v| v.is_finite());
        Bounds { nx, lo, hi, any }
    }

    /// Whether any coefficient is bounded.
    pub fn any(&self) -> bool {
        self.any
    }

    /// Number of estimated coefficients.
    pub fn coefficients(&self) -> usize {
        self.lo.len()
    }

    /// Projects the augmented state `x` (covariance `p`, n x n) onto the ranges; `hit[j]`
    /// is set for each coefficient that had left its range. One projection per coefficient
    /// outside (the others follow through their correlation and are checked again), at
    /// most as many rounds as coefficients; a coefficient still outside after them is set
    /// to its bound alone.
    pub fn project(&self, x: &mut [f64], p: &[f64], hit: &mut [bool]) {
        let n = x.len();
        let nb = self.lo.len();
        for _round in 0..nb.max(1) {
            let mut moved = false;
            for j in 0..nb {
                let i = self.nx + j;
                let Some(d) = self.target(j, x[i]) else {
                    continue;
                };
                hit[j] = true;
                moved = true;
                let pii = p[i * n + i];
                let delta = x[i] - d;
                if pii > 0.0 && pii.is_finite() {
                    // x~ = x^ - P e_i (e_i^T P e_i)^-1 (x_i - d)  (Simon 2010)
                    for (k, xk) in x.iter_mut().enumerate() {
                        *xk -= p[k * n + i] / pii * delta;
                    }
                }
                x[i] = d;
            }
            if !moved {
                return;
            }
        }
        for j in 0..nb {
            if let Some(d) = self.target(j, x[self.nx + j]) {
                hit[j] = true;
                x[self.nx + j] = d;
            }
        }
    }

    /// Brings the coefficients `v` (a pass's start) into their ranges, each outside to its
    /// nearest bound, the others untouched: scaled (z) values, or SI values with `scale`.
    pub fn clamp(&self, v: &mut [f64], scale: Option<&[f64]>) {
        for (j, x) in v.iter_mut().enumerate() {
            let s = scale.map_or(1.0, |s| s[j]);
            if let Some(d) = self.target(j, *x / s) {
                *x = d * s;
            }
        }
    }

    /// The bound scaled coefficient `j` at `z` is projected to, when `z` lies outside.
    fn target(&self, j: usize, z: f64) -> Option<f64> {
        if z < self.lo[j] {
            Some(self.lo[j])
        } else if z > self.hi[j] {
            Some(self.hi[j])
        } else {
            None
        }
    }
}

/// The admissible interval of `r` for a coefficient of expected size `s` (SI): the closed
/// range, or the open one's bounds moved inside by [`OPEN_MARGIN`] of `s`.
fn admissible(r: &Range, s: f64) -> (f64, f64) {
    if !r.open {
        return (r.lo, r.hi);
    }
    let m = OPEN_MARGIN * s.abs();
    let (mut a, mut b) = (r.lo + m, r.hi - m);
    if a > b {
        // a range narrower than two margins: its middle
        let mid = 0.5 * (r.lo + r.hi);
        (a, b) = (mid, mid);
    }
    (a, b)
}

/// What the projection did to each estimated coefficient in one run of a pass.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BoundLog {
    /// Samples at which the coefficient was projected onto its bound.
    pub hits: Vec<usize>,
    /// The last such sample.
    pub last: Vec<Option<usize>>,
    /// Samples in the run.
    pub samples: usize,
    /// Work space: the coefficients hit at the current sample.
    hit: Vec<bool>,
}

impl BoundLog {
    /// An empty log for `nb` coefficients over a run of `samples` samples.
    pub fn new(nb: usize, samples: usize) -> Self {
        BoundLog {
            hits: vec![0; nb],
            last: vec![None; nb],
            samples,
            hit: vec![false; nb],
        }
    }

    /// Keeps the filter's state `x` (covariance `p`) in `bounds` after the update at sample
    /// `k` ([`Bounds::project`]) and records which coefficients it held.
    pub fn project(&mut self, bounds: &Bounds, k: usize, x: &mut [f64], p: &[f64]) {
        if !bounds.any() {
            return;
        }
        let mut hit = std::mem::take(&mut self.hit);
        hit.fill(false);
        bounds.project(x, p, &mut hit);
        self.record(k, &hit);
        self.hit = hit;
    }

    /// Records the coefficients `hit` at sample `k`.
    pub fn record(&mut self, k: usize, hit: &[bool]) {
        for (j, _) in hit.iter().enumerate().filter(|(_, h)| **h) {
            self.hits[j] += 1;
            self.last[j] = Some(k);
        }
    }

    /// Whether coefficient `j` was held at its bound at the end of the run (in its last
    /// `END_SHARE` of samples, at least the last one).
    pub fn at_end(&self, j: usize) -> bool {
        let tail = ((self.samples as f64 * END_SHARE) as usize).max(1);
        self.last[j].is_some_and(|k| k + tail >= self.samples)
    }
}

/// Per estimated coefficient, what the bounds did over the identification.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BoundSummary {
    /// Projections in the last pass (all runs).
    pub hits: usize,
    /// Samples in the last pass (all runs).
    pub samples: usize,
    /// Whether the last pass ended with it at its bound.
    pub at_end: bool,
    /// Passes that ended with it at its bound.
    pub passes_at_end: usize,
    /// Projections over all passes.
    pub total_hits: usize,
}

/// A tuning note for each coefficient the filter held at its bound at some samples but that
/// ended inside its range (`names`, `defs` of the estimated coefficients): the estimate is
/// the filter's own, the bound only kept it admissible on the way.
pub fn notes(names: &[&str], defs: &[&CoefDef], summary: &[BoundSummary]) -> Vec<String> {
    names
        .iter()
        .zip(defs)
        .zip(summary)
        .filter(|(_, s)| s.total_hits > 0 && !s.at_end)
        .map(|((n, d), s)| {
            format!(
                "{n}: held at the bound of its admissible range ({}) at {} samples over the \
                 passes ({} in the last), inside it at the end",
                d.range.describe(d.unit),
                s.total_hits,
                s.hits
            )
        })
        .collect()
}

/// What an estimate at its bound means when the model says nothing more.
const GENERAL_MEANING: &str = "the data pull the estimate beyond what physics admits for it: \
    the runs hardly excite its term, or the model misses something the runs contain (a fixed \
    coefficient, an input, a sign convention); the value and sigma reported are those at the \
    bound, not an estimate";

/// A warning for each estimated coefficient (`defs`, with the `summary` of what its range
/// did) that ended the identification pressed against its bound.
pub fn warnings(defs: &[&CoefDef], summary: &[BoundSummary]) -> Vec<Warning> {
    defs.iter()
        .zip(summary)
        .filter(|(_, s)| s.at_end)
        .map(|(d, s)| {
            Warning::new(
                "hekf",
                format!(
                    "{} ended at the bound of its admissible range ({}): the filter held it \
                     there at {} of the last pass's {} samples",
                    d.name,
                    d.range.describe(d.unit),
                    s.hits,
                    s.samples
                ),
                format!(
                    "{}; {GENERAL_MEANING}",
                    d.at_bound.unwrap_or("an estimate at its bound")
                ),
            )
        })
        .collect()
}

/// The sentence a divergence's error gets when the filter had held coefficients at their
/// bounds in the failing run (`held`: index into `defs` and samples), empty when it had not.
pub fn divergence_note(defs: &[&CoefDef], held: &[(usize, usize)]) -> String {
    if held.is_empty() {
        return String::new();
    }
    let list: Vec<String> = held
        .iter()
        .map(|&(j, k)| {
            format!(
                "{} at its bound ({}) at {k} samples",
                defs[j].name,
                defs[j].range.describe(defs[j].unit)
            )
        })
        .collect();
    format!(
        " Before it failed, the filter had held {} of this run: the estimate kept hitting its \
         admissible range and the filter could not converge with it there ({}).",
        list.join(", "),
        held.iter()
            .find_map(|&(j, _)| defs[j].at_bound)
            .unwrap_or(GENERAL_MEANING)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positive() -> Range {
        Range {
            lo: 0.0,
            hi: f64::INFINITY,
            open: true,
        }
    }

    /// A state inside its range is left alone, to the last bit.
    #[test]
    fn inside_the_range_nothing_moves() {
        let b = Bounds::new(&[positive()], &[0.8], 1);
        let mut x = [0.3, 0.5];
        let p = [1.0, 0.4, 0.4, 1.0];
        let mut hit = [false];
        b.project(&mut x, &p, &mut hit);
        assert_eq!(x, [0.3, 0.5]);
        assert!(!hit[0]);
    }

    /// The projection of a two-state Gaussian onto x1 = d in the metric of P^-1 is the
    /// conditional mean: x0 moves by P01 / P11 (d - x1) (Simon 2010), x1 lands on
    /// the bound (the open bound's margin inside it), and P is not changed.
    #[test]
    fn the_projection_is_the_conditional_mean_on_the_bound() {
        let b = Bounds::new(&[positive()], &[0.8], 1);
        let mut x = [0.3, -0.2];
        let p = [2.0, 0.6, 0.6, 0.5];
        let mut hit = [false];
        b.project(&mut x, &p, &mut hit);
        let d = OPEN_MARGIN * 0.8 / 0.8;
        assert!(hit[0]);
        assert_eq!(x[1], d);
        let expected = 0.3 + 0.6 / 0.5 * (d - -0.2);
        assert!((x[0] - expected).abs() < 1e-15, "{} vs {expected}", x[0]);
    }

    /// Monte Carlo: among draws of the Gaussian N(x^, P) whose coefficient lies within a
    /// thin slab at the bound, the state's mean is the projected state (the projection is
    /// the most probable state on the bound).
    #[test]
    fn the_projection_matches_monte_carlo_conditioning() {
        use rand::{rngs::StdRng, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let (x0, z0) = (1.0, -0.5);
        let (p00, p01, p11): (f64, f64, f64) = (1.0, -0.7, 0.64);
        let b = Bounds::new(
            &[Range {
                lo: 0.0,
                hi: f64::INFINITY,
                open: false,
            }],
            &[1.0],
            1,
        );
        let mut x = [x0, z0];
        b.project(&mut x, &[p00, p01, p01, p11], &mut [false]);
        // draws by the Cholesky factor of P
        let l11 = (p11 - p01 * p01 / p00).sqrt();
        let (l00, l10) = (p00.sqrt(), p01 / p00.sqrt());
        let normal = Normal::new(0.0, 1.0).unwrap();
        let mut rng = StdRng::seed_from_u64(7);
        let (mut sum, mut count) = (0.0, 0usize);
        for _ in 0..2_000_000 {
            let (e0, e1) = (normal.sample(&mut rng), normal.sample(&mut rng));
            let a = x0 + l00 * e0;
            let z = z0 + l10 * e0 + l11 * e1;
            if z.abs() < 0.01 {
                sum += a;
                count += 1;
            }
        }
        let mc = sum / count as f64;
        // the mean over the slab has a standard error of about sqrt(P00 - P01^2/P11 / n)
        let se = ((p00 - p01 * p01 / p11) / count as f64).sqrt();
        assert!(
            (mc - x[0]).abs() < 4.0 * se + 1e-3,
            "{mc} vs {} ({count})",
            x[0]
        );
    }

    /// Two correlated coefficients: projecting one may push the other out; the rounds end
    /// with both inside.
    #[test]
    fn every_bounded_coefficient_ends_inside() {
        let closed = Range {
            lo: 0.0,
            hi: f64::INFINITY,
            open: false,
        };
        let b = Bounds::new(&[closed, closed], &[1.0, 1.0], 0);
        let mut x = [-1.0, 0.1];
        let p = [1.0, 0.9, 0.9, 1.0];
        let mut hit = [false; 2];
        b.project(&mut x, &p, &mut hit);
        assert!(x[0] >= 0.0 && x[1] >= 0.0, "{x:?}");
        assert!(hit[0]);
    }

    /// A pass's start outside its range goes to the bound; one inside stays to the bit.
    #[test]
    fn a_start_outside_is_brought_to_its_bound() {
        let b = Bounds::new(&[positive(), Range::ANY], &[0.8, 2.0], 4);
        let mut si = [-0.3, -7.1];
        b.clamp(&mut si, Some(&[0.8, 2.0]));
        assert!(
            (si[0] - OPEN_MARGIN * 0.8).abs() < 1e-15 && si[1] == -7.1,
            "{si:?}"
        );
        let mut z = [0.3 / 0.8, 1.0];
        b.clamp(&mut z, None);
        assert_eq!(z, [0.3 / 0.8, 1.0]);
    }

    #[test]
    fn a_run_ending_at_its_bound_is_told_from_one_that_left_it() {
        let mut log = BoundLog::new(2, 1000);
        log.record(10, &[true, true]);
        log.record(990, &[true, false]);
        assert!(log.at_end(0) && !log.at_end(1));
        assert_eq!(log.hits, [2, 1]);
    }

    /// A divergence after the filter held w0 at its bound says so, with the range and what
    /// it means; one where nothing was held adds nothing; a coefficient at its bound at the
    /// end of the last pass is a warning naming it.
    #[test]
    fn a_bound_is_named_in_the_divergence_and_the_warning() {
        use crate::model::models::nomoto_wave::{COEFFICIENTS, K, W0};
        let defs = [&COEFFICIENTS[K], &COEFFICIENTS[W0]];
        let note = divergence_note(&defs, &[(1, 412)]);
        assert!(
            note.contains("w0 at its bound (> 0 rad/s) at 412 samples")
                && note.contains("kept hitting its admissible range")
                && note.contains("no waves in the data"),
            "{note}"
        );
        assert!(divergence_note(&defs, &[]).is_empty());
        let summary = [
            BoundSummary::default(),
            BoundSummary {
                hits: 30,
                samples: 600,
                at_end: true,
                passes_at_end: 3,
                total_hits: 90,
            },
        ];
        let w = warnings(&defs, &summary);
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("w0 ended at the bound") && w[0].message.contains("30 of"));
        assert!(
            w[0].meaning.contains("no waves in the data"),
            "{}",
            w[0].meaning
        );
    }

    #[test]
    fn ranges_read_in_words() {
        assert_eq!(positive().describe("rad/s"), "> 0 rad/s");
        let neg = Range {
            lo: f64::NEG_INFINITY,
            hi: 0.0,
            open: false,
        };
        assert_eq!(neg.describe("kg"), "<= 0 kg");
        assert_eq!(Range::ANY.describe("kg"), "any");
    }
}
