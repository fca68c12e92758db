//! The rudder's first excursion after the execute: put over to an angle and held until it
//! moves back (a zig-zag's reversal, the pull-out after a turning circle, any other rudder
//! order) or the run ends. A turning circle's measures are those of the turn with the rudder
//! held (MSC.137(76), annex, 4.2.2; ITTC 7.5-04-02-01, 2.2.1); a zig-zag's rudder angle is
//! the angle held and its check angle the heading change where the hold ends (4.2.6).

use super::history::{rudder_execute_sign, At, History, RUDDER_MOVE_MIN};

/// Share of the excursion a move back must exceed (at least [`RUDDER_MOVE_MIN`]) to end the
/// hold; a quarter of it is the band the rudder is "at" its extreme in.
const RELEASE_SHARE: f64 = 0.1;

/// The rudder's first excursion from its approach angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Hold {
    /// +1 when the rudder moves to larger angles, -1 to smaller (the run's sign convention).
    pub sign: f64,
    /// The first sample at the extreme (within a quarter of the release threshold).
    pub reached: usize,
    /// The last sample at the extreme before the rudder moves back by more than the
    /// threshold (the reversal or pull-out); None when it is held to the end of the run.
    pub released: Option<usize>,
    /// The angle held, rad, in the run's sign: the median of the samples from `reached` to
    /// the release (or the end).
    pub angle: f64,
}

impl Hold {
    /// The last sample of the hold.
    pub fn last(&self, len: usize) -> usize {
        self.released.unwrap_or(len - 1)
    }
}

/// The first excursion of `rudder` after the execute `exec`. The move back that ends it
/// exceeds [`RELEASE_SHARE`] of the excursion and at least 1 deg, so that sensor noise and
/// the steering gear's hunting are not read as orders.
pub(super) fn first_hold(rudder: &[f64], exec: At) -> Hold {
    let start = exec.of(rudder);
    let from = exec.next_index().min(rudder.len() - 1);
    let sign = rudder_execute_sign(rudder, from, start);
    let moved: Vec<f64> = rudder.iter().map(|d| sign * (d - start)).collect();
    let threshold = |top: f64| (RELEASE_SHARE * top).max(RUDDER_MOVE_MIN);
    let mut top = 0.0f64;
    let mut released = None;
    for i in from..moved.len() {
        let th = threshold(top);
        if top > th && moved[i] < top - th {
            released = (from..i).rev().find(|&j| moved[j] >= top - 0.25 * th);
            break;
        }
        top = top.max(moved[i]);
    }
    let band = top - 0.25 * threshold(top);
    let end = released.unwrap_or(moved.len() - 1);
    let reached = (from..=end).find(|&j| moved[j] >= band).unwrap_or(end);
    let mut held: Vec<f64> = rudder[reached..=end].to_vec();
    held.sort_by(f64::total_cmp);
    Hold {
        sign,
        reached,
        released,
        angle: held[held.len() / 2],
    }
}

/// The direction the rudder is put over at the execute at `execute_time` (s), in the
/// history's sign convention: +1 to larger angles, -1 to smaller; None without a rudder. The
/// first departure from the approach angle by more than 1 deg decides, not the first sample
/// off zero (an approach rudder trimmed the other way is not the test's order).
pub fn rudder_put_over(history: &History, execute_time: f64) -> Option<f64> {
    let rudder = history.rudder()?;
    Some(first_hold(rudder, history.at_time(execute_time)).sign)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deg(v: &[f64]) -> Vec<f64> {
        v.iter().map(|d| d.to_radians()).collect()
    }

    #[test]
    fn a_turn_with_a_pull_out_is_held_until_the_rudder_comes_back() {
        let r = deg(&[-1.0, -1.0, 10.0, 34.9, 35.0, 35.1, 35.0, 20.0, 0.0, 0.0]);
        let h = first_hold(&r, At::sample(1));
        assert_eq!((h.sign, h.reached, h.released), (1.0, 3, Some(6)));
        assert!((h.angle.to_degrees() - 35.0).abs() < 1e-12, "{h:?}");
        let held = deg(&[0.0, 0.0, -10.0, -20.0, -20.0]);
        let h = first_hold(&held, At::sample(1));
        assert_eq!((h.sign, h.reached, h.released), (-1.0, 3, None));
        assert!((h.angle.to_degrees() + 20.0).abs() < 1e-12);
    }
}
