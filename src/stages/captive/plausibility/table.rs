//! Checks of a captive table that need no model: rows written more than once, forces that do
//! not respond to the motion (an F test against the model's regressors), a drift angle in
//! the wrong unit, and a prime system's length against the vehicle's.

use super::diagnosis::{Judge, DEG};
use super::words::Names;
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::model::models::Model;
use crate::stages::captive::fit::Condition;
use crate::stages::plausible::Finding;

/// The significance below which a force responds to the motion: an F test's p-value above
/// it says the force is no more related to the model's regressors than noise is.
pub const RESPONDS: f64 = 0.01;

/// Share of a table's rows that are copies from which they are warned about.
pub const COPIES_WARNED: f64 = 1.0 / 3.0;

fn finding(names: &Names, blocking: bool, message: String, meaning: &str) -> Finding {
    Finding::of(
        super::super::STAGE,
        &names.run,
        blocking,
        message,
        meaning.to_string(),
    )
}

/// Steady rows identical in every value (motion, inputs and forces) to an earlier row: one
/// measurement listed twice (a run in two test series, as the published KVLCC2 table lists
/// 18 of its 81 rows), a block pasted again, a table written twice. Measured forces never
/// repeat to every printed digit, so each copy is left out of the fit, which would
/// otherwise count it as a second measurement (sigmas too small by up to sqrt 2). A warning
/// when the copies are at least [`COPIES_WARNED`] of the rows (a table or a large block of
/// it written twice: a mistake). Returns the rows to keep and the finding.
pub(crate) fn duplicates(
    conditions: Vec<Condition>,
    names: &Names,
) -> (Vec<Condition>, Option<Finding>) {
    let same = |a: &Condition, b: &Condition| a.x == b.x && a.u == b.u && a.f == b.f;
    let mut keep: Vec<Condition> = Vec::with_capacity(conditions.len());
    let mut pairs = Vec::new();
    let n = conditions.len();
    for c in conditions {
        let steady = c.harmonic.is_none() && c.sigma.is_none();
        match keep.iter().find(|k| steady && same(k, &c)) {
            Some(first) => pairs.push(format!("{} = {}", line_of(&c.place), line_of(&first.place))),
            None => keep.push(c),
        }
    }
    if (pairs.len() as f64) < COPIES_WARNED * n as f64 {
        return (keep, None);
    }
    let shown = pairs.len().min(6);
    let message = format!(
        "in {}, {} of the {n} rows repeat an earlier row in every value: lines {}{}",
        names.file,
        pairs.len(),
        pairs[..shown].join(", "),
        if pairs.len() > shown { ", ..." } else { "" }
    );
    let meaning = "measured forces never repeat to every digit: the table (or a block of it) \
        is written twice. Each copy is left out of the fit, which would count it as a second \
        measurement and report sigmas too small; remove the copies from the file";
    (keep, Some(finding(names, false, message, meaning)))
}

/// `line 12` of a condition's place (`run line 12`), or the place.
fn line_of(place: &str) -> &str {
    place.rsplit_once(" line ").map_or(place, |(_, l)| l)
}

/// The forces that do not respond to the motion: each judged component of the steady rows
/// regressed on the model's regressors (its sensitivities to the estimated coefficients at
/// the expected ones, and the expected force itself) with an intercept; the F test of the
/// regression (Draper & Smith 1998, section 1.3) with a p-value above [`RESPONDS`] says the
/// force is no more related to the motion than noise is (a channel of noise, another gauge).
pub(crate) fn unresponsive<M: Model>(
    judge: &Judge<M>,
    conditions: &[Condition],
    est: &[usize],
    names: &Names,
) -> Option<Finding> {
    let steady: Vec<&Condition> = conditions.iter().filter(|c| c.harmonic.is_none()).collect();
    let theta: Vec<f64> = est.iter().map(|&i| judge.coefficients[i]).collect();
    let rows: Vec<(Vec<f64>, Vec<f64>)> = steady
        .iter()
        .map(|c| c.values_and_jacobian(judge.model, judge.coefficients, est, &theta))
        .collect();
    let forces = judge.model.force_quantities();
    let mut dead = Vec::new();
    for i in judge.judged() {
        let y: Vec<f64> = steady.iter().map(|c| c.f[i]).collect();
        let x: Vec<Vec<f64>> = rows
            .iter()
            .map(|(value, jac)| {
                std::iter::once(value[i])
                    .chain(jac[i * est.len()..(i + 1) * est.len()].iter().copied())
                    .collect()
            })
            .collect();
        if let Some((f, p)) = f_test(&x, &y) {
            if p > RESPONDS {
                dead.push(format!(
                    "{} (F = {}, p = {})",
                    forces[i].key(),
                    num(f),
                    num(p)
                ));
            }
        }
    }
    (!dead.is_empty()).then(|| {
        finding(
            names,
            false,
            format!(
                "in {}, {} of the {} steady rows {} not respond to the motion: regressed on \
                 the {} model's terms, no more of {} variance is explained than noise explains \
                 (F test, p above {RESPONDS})",
                names.file,
                dead.join(", "),
                steady.len(),
                if dead.len() == 1 { "does" } else { "do" },
                judge.model.name(),
                if dead.len() == 1 { "its" } else { "their" }
            ),
            "the force columns hold noise, or forces of another test or gauge (check which \
             columns are mapped to the forces); the coefficients fitted from them are noise \
             with sigmas that look meaningful",
        )
    })
}

/// The F statistic of the regression of `y` on the columns of `x` with an intercept
/// (columns without spread, or dependent on others, dropped) and its p-value; None with too
/// few rows.
fn f_test(x: &[Vec<f64>], y: &[f64]) -> Option<(f64, f64)> {
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    let n = y.len();
    let mean = y.iter().sum::<f64>() / n.max(1) as f64;
    let tss: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    // columns centred, kept while they add rank
    let k = x.first().map_or(0, Vec::len);
    let mut kept: Vec<Vec<f64>> = Vec::new();
    for j in 0..k {
        let col: Vec<f64> = x.iter().map(|r| r[j]).collect();
        let m = col.iter().sum::<f64>() / n as f64;
        let centred: Vec<f64> = col.iter().map(|v| v - m).collect();
        if centred
            .iter()
            .all(|v| v.abs() <= 1e-12 * m.abs().max(1e-300))
        {
            continue;
        }
        let mut trial = kept.clone();
        trial.push(centred);
        if rank_ok(&trial, n) {
            kept = trial;
        }
    }
    let p = kept.len();
    if p == 0 || n < p + 3 || tss <= 0.0 {
        return None;
    }
    let a = nalgebra::DMatrix::from_fn(n, p, |r, c| kept[c][r]);
    let yc = nalgebra::DVector::from_iterator(n, y.iter().map(|v| v - mean));
    let fit = crate::numerics::lsq::scaled_least_squares(&a, &yc, n - p - 1)?;
    let rss = fit.rss.min(tss);
    let f = ((tss - rss) / p as f64) / (rss.max(1e-300 * tss) / (n - p - 1) as f64);
    let dist = FisherSnedecor::new(p as f64, (n - p - 1) as f64).ok()?;
    Some((f, 1.0 - dist.cdf(f)))
}

/// Whether the columns are independent (a least-squares solve on them succeeds).
fn rank_ok(cols: &[Vec<f64>], n: usize) -> bool {
    let a = nalgebra::DMatrix::from_fn(n, cols.len(), |r, c| cols[c][r]);
    let y = nalgebra::DVector::from_element(n, 1.0);
    crate::numerics::lsq::scaled_least_squares(&a, &y, n.saturating_sub(cols.len()).max(1))
        .is_some()
}

/// A drift angle beyond 90 deg as read that a degree read as a radian explains (a
/// captive drift angle of 20 read as 20 rad is 1146 deg).
pub(crate) fn drift_unit(rec: &Record, names: &Names) -> Option<Finding> {
    let drift = rec.channel(Quantity::Drift)?;
    let largest = drift.iter().fold(0.0f64, |a, d| a.max(d.abs()));
    let right = std::f64::consts::FRAC_PI_2;
    (largest > right && largest / DEG <= right).then(|| {
        finding(
            names,
            true,
            format!(
                "in {}, the drift angle {} reaches {} deg",
                names.file,
                crate::stages::plausible::named(rec, Quantity::Drift),
                num(largest * DEG)
            ),
            &format!(
                "a captive drift angle stays within 90 deg: the drift angle looks like degrees \
                 read as radians: give `unit = \"deg\"` in {}.drift",
                names.key
            ),
        )
    })
}

/// The prime system's length against the vehicle's: a factor of 1000 (or 100) is a length
/// in mm (cm) given as m, and the reverse; otherwise beyond a factor of 2 a warning (r' = r L
/// / U and N' = N / (0.5 rho A L U^2) are then read with another length).
pub fn prime_length(prime: f64, length: f64) -> Option<Finding> {
    let ratio = prime / length;
    let near = |f: f64| (ratio / f - 1.0).abs() < 0.1;
    let unit = [(1000.0, "mm"), (100.0, "cm"), (1e-3, "km")]
        .into_iter()
        .find(|(f, _)| near(*f));
    let message = format!(
        "captive.prime.length = {} m is {} times vehicle.length = {} m",
        num(prime),
        num(ratio),
        num(length)
    );
    let (blocking, meaning) = match unit {
        Some((_, u)) => (
            true,
            format!(
                "the prime length looks like a length in {u} given as metres: give it with its \
                 unit (`length = \"{} {u}\"`) or in m; r' = r L / U and N' = N / (0.5 rho A L \
                 U^2) are read with it",
                num(prime)
            ),
        ),
        None if !(0.5..=2.0).contains(&ratio) => (
            false,
            "the prime system's length is usually the vehicle's (L_pp): check \
             captive.prime.length; r' = r L / U and N' = N / (0.5 rho A L U^2) are read with it"
                .to_string(),
        ),
        None => return None,
    };
    Some(Finding {
        warning: crate::base::warning::Warning::new(super::super::STAGE, message, meaning),
        blocking,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// Noise regressed on regressors it does not depend on is no regression (p above 0.01 on
    /// nine seeds in ten); a force that follows its regressors with 10 % noise is one (p
    /// below 1e-6 on every seed).
    #[test]
    fn the_f_test_tells_a_response_from_noise() {
        let mut noise_passed = 0;
        for seed in 0..20 {
            let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
            let e = Normal::new(0.0, 1.0).unwrap();
            let x: Vec<Vec<f64>> = (0..60)
                .map(|k| {
                    let a = (k as f64 * 0.3).sin();
                    vec![a, a * a * a, (k % 7) as f64]
                })
                .collect();
            let noise: Vec<f64> = x.iter().map(|_| e.sample(&mut rng)).collect();
            let (_, p) = f_test(&x, &noise).unwrap();
            noise_passed += usize::from(p > RESPONDS);
            let force: Vec<f64> = x
                .iter()
                .zip(&noise)
                .map(|(r, n)| 3.0 * r[0] - r[1] + 0.1 * n)
                .collect();
            let (f, p) = f_test(&x, &force).unwrap();
            assert!(p < 1e-6, "seed {seed}: F = {f}, p = {p}");
        }
        assert!(noise_passed >= 18, "{noise_passed} of 20");
    }

    #[test]
    fn a_prime_length_in_mm_or_cm_is_named() {
        let mm = prime_length(7000.0, 7.0).unwrap();
        assert!(
            mm.blocking && mm.warning.meaning.contains("in mm"),
            "{mm:?}"
        );
        let cm = prime_length(700.0, 7.0).unwrap();
        assert!(
            cm.blocking && cm.warning.meaning.contains("in cm"),
            "{cm:?}"
        );
        assert!(prime_length(7.0, 7.0).is_none());
        assert!(prime_length(6.8, 7.0).is_none());
        let off = prime_length(20.0, 7.0).unwrap();
        assert!(!off.blocking, "{off:?}");
    }
}
