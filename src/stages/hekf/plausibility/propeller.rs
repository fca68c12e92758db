//! The propeller speed against the vehicle's speed: the advance ratio J = u (1 - w) / (n D)
//! (Carlton 2012, Marine Propellers and Propulsion, ch. 6; Yasukawa & Yoshimura 2015, eq.
//! 13, with the wake fraction w = w_P0 in straight motion). A propeller driving its vehicle
//! works at J of about 0.1 (a tug, a slow turn) to 1.5 (a lightly loaded fast propeller); a
//! propeller speed read in rpm where the log has rps gives J 60 times too large, one read in
//! rps where the log has rpm 60 times too small. Judged only for a vehicle whose particulars
//! give the propeller diameter, and only for gross unit mistakes (the balance of the surge
//! equation is not judged here).

use super::{file, median_of, named, sig, Expectation, Finding};
use crate::base::quantity::Quantity;
use crate::io::record::Record;
use crate::stages::plausible::{propeller_unit, WORKING_ADVANCE};

/// The advance ratio's check.
pub(super) fn check(rec: &Record, expect: &Expectation) -> Option<Finding> {
    let diameter = expect.propeller_diameter?;
    let n = rec.rows();
    if n < 10 {
        return None;
    }
    let rps = |k: usize| rec.value_at(Quantity::Rpm, k);
    rps(0)?;
    let u = rec.channel(Quantity::U).filter(|u| u.len() == n)?;
    let v = rec.channel(Quantity::V).filter(|v| v.len() == n);
    let speed = |k: usize| u[k].hypot(v.map_or(0.0, |v| v[k]));
    // the samples at speed (at least half the run's 95th percentile of the speed: not a
    // start from rest, not a crash stop) with the propeller turning ahead
    let mut speeds: Vec<f64> = (0..n).map(speed).collect();
    let idx95 = (0.95 * (n.saturating_sub(1)) as f64) as usize;
    let fast = *speeds.select_nth_unstable_by(idx95, f64::total_cmp).1;
    let used: Vec<usize> = (0..n)
        .filter(|&k| speed(k) >= 0.5 * fast && rps(k).is_some_and(|r| r > 0.0))
        .collect();
    if used.len() < 10 || fast.is_nan() || fast <= 0.0 {
        return None;
    }
    let wake = expect.wake;
    let j = median_of(
        used.iter()
            .map(|&k| speed(k) * (1.0 - wake) / (rps(k).unwrap_or(f64::NAN) * diameter)),
    )?;
    let (blocking, meaning) = propeller_unit(j)?;
    let (u_typ, n_typ) = (
        median_of(used.iter().map(|&k| speed(k)))?,
        median_of(used.iter().map(|&k| rps(k).unwrap_or(f64::NAN)))?,
    );
    let seen = format!(
        "in {}, the propeller speed {} gives an advance ratio J = U (1 - w_P0) / (n D) of {} \
         (median over {} samples at speed: U = {} m/s, n = {} rev/s, D = {} m, w_P0 = {}); a \
         propeller driving its vehicle works at J of about {} to {}",
        file(rec),
        named(rec, Quantity::Rpm),
        sig(j),
        used.len(),
        sig(u_typ),
        sig(n_typ),
        sig(diameter),
        sig(wake),
        WORKING_ADVANCE.0,
        WORKING_ADVANCE.1
    );
    Some(Finding::new(rec, blocking, seen, meaning.to_string()))
}
