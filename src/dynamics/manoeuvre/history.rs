//! A manoeuvre's history (time, heading, and the track, velocities and rudder where the run
//! has them), checked once, with the interpolation the measures share.

use std::f64::consts::PI;

/// Why a history cannot be analysed: it names the series and the sample.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HistoryError {
    /// Fewer than two samples.
    #[error("a manoeuvre history needs at least 2 samples, got {0}")]
    TooShort(usize),
    /// A series has another length than the time.
    #[error("series '{series}' has {found} samples where the time has {expected}")]
    Length {
        /// The series.
        series: &'static str,
        /// Its length.
        found: usize,
        /// The time's length.
        expected: usize,
    },
    /// A value is NaN or infinite.
    #[error("series '{series}', sample {index} (1-based): expected a finite number, got {value}")]
    NotFinite {
        /// The series.
        series: &'static str,
        /// 1-based sample index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Times do not increase strictly.
    #[error("time, sample {index} (1-based): {value} s does not follow {previous} s; times must increase")]
    TimeOrder {
        /// 1-based sample index.
        index: usize,
        /// The time there.
        value: f64,
        /// The time before.
        previous: f64,
    },
    /// A measure needs a series the history lacks.
    #[error("{what} needs the {series}, which the history does not have")]
    Lacks {
        /// The measure.
        what: &'static str,
        /// The series it needs.
        series: &'static str,
    },
    /// The execute (the rudder order) cannot be found or lies outside the run.
    #[error("{0}")]
    Execute(String),
}

/// A manoeuvre's history in SI units (s, m, rad, m/s) on one time base. The heading is
/// unwrapped on construction (a jump of more than 180 deg between two samples is read as a
/// wrap through +-180 deg or 0/360 deg).
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    time: Vec<f64>,
    heading: Vec<f64>,
    track: Option<(Vec<f64>, Vec<f64>)>,
    velocity: Option<(Vec<f64>, Vec<f64>)>,
    rudder: Option<Vec<f64>>,
}

fn check_finite(series: &'static str, v: &[f64]) -> Result<(), HistoryError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(HistoryError::NotFinite {
            series,
            index: i + 1,
            value: v[i],
        }),
        None => Ok(()),
    }
}

impl History {
    /// A history of time (s, strictly increasing) and heading psi (rad, earth frame x north,
    /// y east: positive clockwise seen from above).
    pub fn new(time: Vec<f64>, heading: Vec<f64>) -> Result<Self, HistoryError> {
        if time.len() < 2 {
            return Err(HistoryError::TooShort(time.len()));
        }
        check_finite("time", &time)?;
        for i in 1..time.len() {
            if time[i] <= time[i - 1] {
                return Err(HistoryError::TimeOrder {
                    index: i + 1,
                    value: time[i],
                    previous: time[i - 1],
                });
            }
        }
        let mut h = History {
            time,
            heading: Vec::new(),
            track: None,
            velocity: None,
            rudder: None,
        };
        let heading = h.series("heading", heading)?;
        h.heading = unwrap(&heading);
        Ok(h)
    }

    fn series(&self, name: &'static str, v: Vec<f64>) -> Result<Vec<f64>, HistoryError> {
        if v.len() != self.time.len() {
            return Err(HistoryError::Length {
                series: name,
                found: v.len(),
                expected: self.time.len(),
            });
        }
        check_finite(name, &v)?;
        Ok(v)
    }

    /// The history with its heading replaced by `f(time, heading)` (e.g. a smoothed heading),
    /// checked as [`History::new`] checks it.
    pub fn map_heading(
        mut self,
        f: impl FnOnce(&[f64], &[f64]) -> Vec<f64>,
    ) -> Result<Self, HistoryError> {
        let heading = f(&self.time, &self.heading);
        self.heading = self.series("heading", heading)?;
        Ok(self)
    }

    /// Adds the track: earth-frame positions x (north) and y (east), m.
    pub fn with_track(mut self, x: Vec<f64>, y: Vec<f64>) -> Result<Self, HistoryError> {
        self.track = Some((self.series("x", x)?, self.series("y", y)?));
        Ok(self)
    }

    /// Adds the body-frame velocities u (surge) and v (sway), m/s.
    pub fn with_velocity(mut self, u: Vec<f64>, v: Vec<f64>) -> Result<Self, HistoryError> {
        self.velocity = Some((self.series("u", u)?, self.series("v", v)?));
        Ok(self)
    }

    /// Adds the rudder angle, rad, in whatever sign convention the run uses (the measures
    /// read the side of a turn from the heading, never from the rudder's sign).
    pub fn with_rudder(mut self, rudder: Vec<f64>) -> Result<Self, HistoryError> {
        self.rudder = Some(self.series("rudder", rudder)?);
        Ok(self)
    }

    /// Times, s.
    pub fn time(&self) -> &[f64] {
        &self.time
    }

    /// Heading, rad, unwrapped.
    pub fn heading(&self) -> &[f64] {
        &self.heading
    }

    /// The track (x, y), m, if the history has it.
    pub fn track(&self) -> Option<(&[f64], &[f64])> {
        self.track
            .as_ref()
            .map(|(x, y)| (x.as_slice(), y.as_slice()))
    }

    /// The rudder angle, rad, if the history has it.
    pub fn rudder(&self) -> Option<&[f64]> {
        self.rudder.as_deref()
    }

    /// The speed over ground at each sample from u and v, if the history has them.
    pub(super) fn speed(&self) -> Option<Vec<f64>> {
        self.velocity
            .as_ref()
            .map(|(u, v)| u.iter().zip(v).map(|(u, v)| u.hypot(*v)).collect())
    }

    /// The time of the execute: `given` if set (checked to lie in the run), otherwise the
    /// rudder order found in the rudder history ([`rudder_execute`]).
    pub(super) fn execute(
        &self,
        given: Option<f64>,
        what: &'static str,
    ) -> Result<At, HistoryError> {
        let (t0, t1) = (self.time[0], self.time[self.time.len() - 1]);
        match given {
            Some(t) if t >= t0 && t < t1 => Ok(self.at_time(t)),
            Some(t) => Err(HistoryError::Execute(format!(
                "{what}: the execute time {t} s is outside the run ({t0} s to {t1} s)"
            ))),
            None => {
                let rudder = self.rudder.as_deref().ok_or(HistoryError::Lacks {
                    what,
                    series: "rudder angle (or an execute time)",
                })?;
                rudder_execute(rudder).map(At::sample).ok_or_else(|| {
                    HistoryError::Execute(format!(
                        "{what}: the rudder never moves from its approach angle by more than {} deg, so the run has no execute",
                        RUDDER_MOVE_MIN.to_degrees()
                    ))
                })
            }
        }
    }

    /// The place in the run at time `t` (inside the run).
    pub(super) fn at_time(&self, t: f64) -> At {
        let i = self
            .time
            .partition_point(|&s| s <= t)
            .clamp(1, self.time.len() - 1)
            - 1;
        At {
            index: i,
            frac: ((t - self.time[i]) / (self.time[i + 1] - self.time[i])).clamp(0.0, 1.0),
        }
    }
}

/// A place in a run between two samples: `index` and the fraction of the way to the next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct At {
    pub index: usize,
    pub frac: f64,
}

impl At {
    /// Exactly at sample `i`.
    pub fn sample(i: usize) -> At {
        At {
            index: i,
            frac: 0.0,
        }
    }

    /// `series` interpolated linearly at this place.
    pub fn of(&self, series: &[f64]) -> f64 {
        let a = series[self.index];
        if self.frac == 0.0 || self.index + 1 >= series.len() {
            a
        } else {
            a + self.frac * (series[self.index + 1] - a)
        }
    }

    /// The first sample at or after this place.
    pub fn next_index(&self) -> usize {
        if self.frac == 0.0 {
            self.index
        } else {
            self.index + 1
        }
    }
}

/// The first place at or after `from` where `signal` reaches `level` from below, linearly
/// interpolated between the samples either side; None if it never does.
pub(super) fn first_reaching(signal: &[f64], level: f64, from: At) -> Option<At> {
    if from.of(signal) >= level {
        return Some(from);
    }
    let start = from.index + 1;
    (start..signal.len())
        .find(|&i| signal[i] >= level)
        .map(|i| At {
            index: i - 1,
            frac: (level - signal[i - 1]) / (signal[i] - signal[i - 1]),
        })
}

/// The heading with the 2 pi jumps of a wrapped angle removed.
fn unwrap(psi: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(psi.len());
    let mut offset = 0.0;
    for (i, &p) in psi.iter().enumerate() {
        if i > 0 {
            let d = p - psi[i - 1];
            offset -= 2.0 * PI * ((d / (2.0 * PI)).round());
        }
        out.push(p + offset);
    }
    out
}

/// The smallest rudder movement read as a rudder order, rad (1 deg).
pub(super) const RUDDER_MOVE_MIN: f64 = PI / 180.0;

/// The sample of the rudder order (execute): the last sample at the approach rudder angle
/// before the rudder moves ("the position at which the rudder order is given", MSC.137(76),
/// annex, 4.2.3). The move is found where the rudder first leaves its first value by 10 % of
/// its largest excursion (at least 1 deg, so that sensor noise is not read as an order); from
/// there the rudder's path is followed back while its departure from the approach angle (the
/// median of the samples before the move) keeps falling, to where the movement starts: a
/// steering gear at 2.3 deg/s takes many samples to reach the move.
pub(super) fn rudder_execute(rudder: &[f64]) -> Option<usize> {
    let d0 = rudder[0];
    let range = rudder.iter().map(|d| (d - d0).abs()).fold(0.0, f64::max);
    let threshold = (0.1 * range).max(RUDDER_MOVE_MIN);
    let moved = rudder.iter().position(|d| (d - d0).abs() > threshold)?;
    let mut before = rudder[..moved].to_vec();
    before.sort_by(f64::total_cmp);
    let approach = before[before.len() / 2];
    let departure = |j: usize| (rudder[j] - approach).abs();
    let mut e = moved - 1;
    while e > 0 && departure(e - 1) < departure(e) {
        e -= 1;
    }
    Some(e)
}

/// The direction the rudder first moves in from `start` after sample `from`: the sign of its
/// first departure by more than 1 deg (+1 if it never departs).
pub(super) fn rudder_execute_sign(rudder: &[f64], from: usize, start: f64) -> f64 {
    rudder[from..]
        .iter()
        .find(|d| (*d - start).abs() > RUDDER_MOVE_MIN)
        .map_or(1.0, |d| if *d < start { -1.0 } else { 1.0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heading_wrapping_through_180_deg_is_unwrapped() {
        let h = History::new(vec![0.0, 1.0, 2.0], vec![3.0, -3.0, -2.9]).unwrap();
        let d = h.heading()[1] - h.heading()[0];
        assert!((d - (2.0 * PI - 6.0)).abs() < 1e-12, "{d}");
    }

    #[test]
    fn bad_histories_name_the_series_and_sample() {
        let e = History::new(vec![0.0, 1.0, 1.0], vec![0.0; 3]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "time, sample 3 (1-based): 1 s does not follow 1 s; times must increase"
        );
        let h = History::new(vec![0.0, 1.0], vec![0.0; 2]).unwrap();
        let e = h
            .clone()
            .with_track(vec![0.0, f64::NAN], vec![0.0; 2])
            .unwrap_err();
        assert!(e.to_string().starts_with("series 'x', sample 2"), "{e}");
        let e = h.with_rudder(vec![0.0]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "series 'rudder' has 1 samples where the time has 2"
        );
    }

    #[test]
    fn execute_is_the_last_sample_before_the_rudder_moves() {
        let d: Vec<f64> = [0.0, 0.0, 0.0, 5.0, 10.0, 10.0]
            .iter()
            .map(|d: &f64| d.to_radians())
            .collect();
        assert_eq!(rudder_execute(&d), Some(2));
        // a slow steering gear: the order is where the rudder leaves its (noisy) approach
        // angle, not where it has moved by the threshold
        let slow: Vec<f64> = [
            -1.16, -1.17, -1.16, -1.15, -1.16, -0.9, -0.3, 0.3, 0.9, 1.5, 2.1,
        ]
        .iter()
        .map(|d: &f64| d.to_radians())
        .collect();
        assert_eq!(rudder_execute(&slow), Some(4));
        assert_eq!(rudder_execute(&[0.001, -0.001, 0.0]), None);
    }

    #[test]
    fn reaching_a_level_interpolates_between_samples() {
        let s = [0.0, 1.0, 3.0];
        let at = first_reaching(&s, 2.0, At::sample(0)).unwrap();
        assert_eq!(
            at,
            At {
                index: 1,
                frac: 0.5
            }
        );
        assert!(first_reaching(&s, 4.0, At::sample(0)).is_none());
    }
}
