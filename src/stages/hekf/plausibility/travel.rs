//! The positions against the velocities: the distance travelled against the speed's
//! integral (the units of positions, velocities and time), the path against the velocities
//! rotated by the heading (frames, signs, swapped columns), and u against v where the
//! vehicle holds a straight course.
//!
//! x_dot + i y_dot = (u + i v) e^(i psi) (Fossen 2011, eq. 2.40 in the horizontal plane):
//! over a window the positions' increment is the integral of the rotated velocity, and its
//! length the integral of the speed sqrt(u^2 + v^2) when the heading turns little (a chord
//! of an arc of 20 deg is 98.5 % of the arc). The speed needs no heading and no frame, so a
//! factor between the two is a unit (or the time's unit), whatever else is wrong.

use super::{
    approach, complex_gain, factor, file, increment, integral, median_of, named, sig,
    window_lengths, windows, Finding, GAIN_TOLERANCE, GOOD_FIT, TRAVEL_FACTORS,
};
use crate::base::quantity::Quantity;
use crate::io::record::Record;

/// What a factor between distance and speed points at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Suspect {
    /// The time axis: every rate of the run is off by the same factor.
    Time,
    /// The positions or the velocities.
    Other,
}

/// Largest heading change within a window whose chord is compared with the speed's
/// integral (the chord of a 20 deg arc is 98.5 % of its length).
const MAX_TURN: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// The gain of chord on arc over windows of `len` samples that turn less than [`MAX_TURN`].
fn speed_fit(rec: &Record, len: usize) -> Option<((f64, f64), f64, usize)> {
    let times = rec.time()?;
    let (x, y) = (rec.channel(Quantity::X)?, rec.channel(Quantity::Y)?);
    let u = rec.channel(Quantity::U)?;
    let v = rec.channel(Quantity::V);
    let psi = rec.channel(Quantity::Yaw);
    let speed = |k: usize| u[k].hypot(v.map_or(0.0, |v| v[k]));
    let (measured, predicted): (Vec<Complex>, Vec<Complex>) = windows(times, len)
        .into_iter()
        .filter(|&(a, b)| psi.is_none_or(|p| (p[b] - p[a]).abs() < MAX_TURN))
        .map(|w| {
            let chord = (x[w.1] - x[w.0]).hypot(y[w.1] - y[w.0]);
            ((chord, 0.0), (integral(times, w, speed), 0.0))
        })
        .unzip();
    let (g, rel) = complex_gain(&measured, &predicted)?;
    Some((g, rel, measured.len()))
}

/// The distance travelled against the speed's integral. Windows grow (doubling) until the
/// relation holds, so that position noise or a coarse printed resolution cannot decide; a
/// consistent factor over the longest windows is named.
pub(super) fn speed(rec: &Record) -> Option<(Finding, Suspect)> {
    let times = rec.time()?;
    let mut last = None;
    for len in window_lengths(times) {
        let Some(((g, _), rel, n)) = speed_fit(rec, len) else {
            break;
        };
        if (g - 1.0).abs() < GAIN_TOLERANCE && rel < GOOD_FIT {
            return None;
        }
        last = Some((g, rel, n, len));
    }
    let (g, rel, n, len) = last?;
    if rel >= GOOD_FIT {
        // no consistent factor: the path check says what disagrees
        return None;
    }
    let dt = crate::numerics::sampling::median_interval(times).unwrap_or(0.0);
    let seen = format!(
        "in {}, the positions {} and {} travel {} times the distance the speed from {} and {} \
         gives between the same time stamps of {} ({n} windows of {} s; median relative \
         residual {:.0} %)",
        file(rec),
        named(rec, Quantity::X),
        named(rec, Quantity::Y),
        sig(g),
        named(rec, Quantity::U),
        named(rec, Quantity::V),
        named(rec, Quantity::Time),
        sig(len as f64 * dt),
        100.0 * rel
    );
    Some(match factor(g, TRAVEL_FACTORS) {
        Some(f) => {
            let suspect = if (f.gain - 60.0).abs() < 1.0 || (f.gain * 60.0 - 1.0).abs() < 0.01 {
                Suspect::Time
            } else {
                Suspect::Other
            };
            let words = thousand(rec, f.gain).unwrap_or_else(|| f.words.to_string());
            (Finding::new(rec, true, seen, words), suspect)
        }
        None => (
            Finding::new(
                rec,
                false,
                seen,
                "positions and speeds disagree by a factor that is no common unit: check the \
                 units of x, y, u, v and time"
                    .to_string(),
            ),
            Suspect::Other,
        ),
    })
}

/// The words for positions read 1000 times too large (`gain` 1000) or too small (1/1000),
/// from the unit they were read in: the file's unit is the one a thousand times smaller
/// (larger). None for a gain that is no factor of 1000, or a unit without such a neighbour.
fn thousand(rec: &Record, gain: f64) -> Option<String> {
    const LADDER: [(&str, &str); 3] =
        [("mm", "millimetres"), ("m", "metres"), ("km", "kilometres")];
    let read = rec.units.get(&Quantity::X).map_or("m", String::as_str);
    let at = LADDER.iter().position(|(u, _)| *u == read)?;
    let file_at = match gain {
        g if (g / 1e3 - 1.0).abs() < 0.03 => at.checked_sub(1)?,
        g if (g * 1e3 - 1.0).abs() < 0.03 => at + 1,
        _ => return None,
    };
    let (unit, words) = LADDER.get(file_at)?;
    Some(format!(
        "the positions look like {words} read as {}: give `unit = \"{unit}\"` in the x and y \
         column entries",
        LADDER[at].1
    ))
}

/// The meaning of u and v swapped.
const SWAPPED: &str = "u and v look swapped (the column mapped to u holds the sway velocity, \
    the one mapped to v the surge velocity): exchange the columns of the u and v entries";

/// A complex number as (real, imaginary): a horizontal vector, x + i y.
type Complex = (f64, f64);

type Predict<'a> = Box<dyn Fn(usize) -> Complex + 'a>;

/// The channels the path check relates.
struct Path<'a> {
    times: &'a [f64],
    x: &'a [f64],
    y: &'a [f64],
    psi: &'a [f64],
    u: &'a [f64],
    v: &'a [f64],
}

impl<'a> Path<'a> {
    fn of(rec: &'a Record) -> Option<Self> {
        Self::with_heading(rec, rec.channel(Quantity::Yaw)?)
    }

    /// The path of a run with the heading `psi` instead of its yaw column.
    fn with_heading(rec: &'a Record, psi: &'a [f64]) -> Option<Self> {
        let path = Path {
            times: rec.time()?,
            x: rec.channel(Quantity::X)?,
            y: rec.channel(Quantity::Y)?,
            psi,
            u: rec.channel(Quantity::U)?,
            v: rec.channel(Quantity::V)?,
        };
        let n = path.times.len();
        [path.x, path.y, path.psi, path.u, path.v]
            .iter()
            .all(|c| c.len() == n)
            .then_some(path)
    }

    /// (a + i b) e^(i heading psi_k): a body vector in the earth frame (`heading` -1 for the
    /// opposite sign convention).
    fn rotate(&self, k: usize, (a, b): (f64, f64), heading: f64) -> (f64, f64) {
        let (s, c) = (heading * self.psi[k]).sin_cos();
        (a * c - b * s, a * s + b * c)
    }

    /// x(t1) - x(t0) + i (y(t1) - y(t0)) = integral of the predicted earth velocity, over
    /// windows of `len` samples: the complex gain and its median relative residual.
    fn fit(&self, len: usize, predict: &dyn Fn(usize) -> (f64, f64)) -> Option<((f64, f64), f64)> {
        let (measured, p): (Vec<Complex>, Vec<Complex>) =
            self.increments(len, predict).into_iter().unzip();
        complex_gain(&measured, &p)
    }

    /// Over windows of `len` samples: the positions' increment x(t1) - x(t0) + i (y(t1) -
    /// y(t0)) and the integral of the predicted earth velocity.
    fn increments(
        &self,
        len: usize,
        predict: &dyn Fn(usize) -> Complex,
    ) -> Vec<(Complex, Complex)> {
        windows(self.times, len)
            .into_iter()
            .map(|w| {
                let re = increment(self.times, w, self.x, |k| predict(k).0);
                let im = increment(self.times, w, self.y, |k| predict(k).1);
                ((re.0, im.0), (re.1, im.1))
            })
            .collect()
    }

    /// The body velocity (u, v) at sample k rotated by the heading into the earth frame
    /// (Fossen 2011, eq. 2.40).
    fn earth_velocity(&self, k: usize) -> Complex {
        self.rotate(k, (self.u[k], self.v[k]), 1.0)
    }

    /// Whether the positions follow the velocities rotated by the heading as closely as the
    /// channels' own noise allows over windows of `len` samples: the median misfit of the
    /// increments within twice what white noise alone gives. An increment's error is the two
    /// position errors (variance 2 (sx^2 + sy^2)) plus the trapezoid sum of the velocity and
    /// heading errors over its n samples (n dt^2 (su^2 + sv^2 + |V|^2 spsi^2)); its size is
    /// Rayleigh-distributed with the median sqrt(ln 2 T) for a total variance T (Papoulis
    /// 2002, sec. 6-3). GNSS positions of a slow vehicle (metres of noise, a metre or two of
    /// travel per window) cannot be judged: no finding, rather than a wrong one.
    fn within_noise(&self, len: usize) -> bool {
        let noise = |y: &[f64]| crate::numerics::signal::noise_sigma(y).unwrap_or(0.0);
        let (sx, sy, su, sv) = (noise(self.x), noise(self.y), noise(self.u), noise(self.v));
        let spsi = noise(self.psi);
        let Some(dt) = crate::numerics::sampling::median_interval(self.times) else {
            return false;
        };
        let speed2 = median_of((0..self.u.len()).map(|k| self.u[k].powi(2) + self.v[k].powi(2)));
        let n = len as f64;
        let total = 2.0 * (sx * sx + sy * sy)
            + n * dt * dt * (su * su + sv * sv + speed2.unwrap_or(0.0) * spsi * spsi);
        let expected = (std::f64::consts::LN_2 * total).sqrt();
        let misfit = median_of(
            self.increments(len, &|k| self.earth_velocity(k))
                .into_iter()
                .map(|(m, p)| (m.0 - p.0).hypot(m.1 - p.1)),
        );
        misfit.is_some_and(|m| expected > 0.0 && m <= 2.0 * expected)
    }

    /// The mix-ups a user may have made, each as the earth velocity it predicts and what it
    /// means.
    fn mix_ups(&self) -> [(Predict<'_>, &'static str); 6] {
        let (u, v) = (self.u, self.v);
        [
            (
                Box::new(move |k| (u[k], v[k])),
                "the velocity columns hold earth-frame velocities (dx/dt, dy/dt), not body \
                 velocities: set `velocity_frame = \"earth\"` for this run",
            ),
            // body velocities declared earth-frame: the loader rotated them by -psi, so the
            // columns as logged are the record's u, v rotated by +psi, and the earth velocity
            // those body velocities give is that rotated by +psi again
            (
                Box::new(move |k| {
                    let logged = self.rotate(k, (u[k], v[k]), 1.0);
                    self.rotate(k, logged, 1.0)
                }),
                "the velocity columns hold body velocities, but the run declares them \
                 earth-frame (`velocity_frame = \"earth\"`): remove it (or set \"body\")",
            ),
            (
                Box::new(move |k| self.rotate(k, (u[k], v[k]), -1.0)),
                "the heading has the opposite sign convention to the positions (e.g. clockwise \
                 while x-y is counter-clockwise): flip it with `scale = -1` in its column entry",
            ),
            (
                Box::new(move |k| self.rotate(k, (u[k], -v[k]), 1.0)),
                "the sway velocity has the opposite sign convention (positive to port): flip it \
                 with `scale = -1` in its column entry",
            ),
            // swapped in a body-frame file ...
            (
                Box::new(move |k| self.rotate(k, (v[k], u[k]), 1.0)),
                SWAPPED,
            ),
            // ... and in an earth-frame file, rotated into the body frame after the swap
            (
                Box::new(move |k| {
                    let (e, n) = self.rotate(k, (u[k], v[k]), 1.0);
                    (n, e)
                }),
                SWAPPED,
            ),
        ]
    }
}

/// The positions against the velocities rotated by the heading `psi` (the rotation left
/// free: an offset of the heading's origin does not count), over the window length that
/// fits best: the gain's size and the median relative residual. None without positions and
/// velocities.
pub(super) fn heading_fit(rec: &Record, psi: &[f64]) -> Option<(f64, f64)> {
    let path = Path::with_heading(rec, psi)?;
    window_lengths(path.times)
        .into_iter()
        .filter_map(|len| path.fit(len, &|k| path.earth_velocity(k)))
        .map(|((gr, gi), rel)| (gr.hypot(gi), rel))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The positions against the velocities rotated by the heading. Windows grow (doubling)
/// until the relation holds; a misfit that the channels' noise explains is no finding;
/// otherwise over the longest windows the mix-ups a user may have made are tried.
pub(super) fn track(rec: &Record) -> Option<Finding> {
    let path = Path::of(rec)?;
    let holds = |(g, rel): ((f64, f64), f64)| {
        (g.0 - 1.0).abs() < GAIN_TOLERANCE && g.1.abs() < GAIN_TOLERANCE && rel < GOOD_FIT
    };
    let mut last = None;
    for len in window_lengths(path.times) {
        let Some(f) = path.fit(len, &|k| path.earth_velocity(k)) else {
            break;
        };
        if holds(f) {
            return None;
        }
        last = Some((len, f));
    }
    let (len, ((gr, gi), rel)) = last?;
    if path.within_noise(len) {
        return None;
    }
    let gain = gr.hypot(gi);
    let angle = gi.atan2(gr).to_degrees();
    let seen = format!(
        "in {}, the positions {} and {} do not move as {} and {} rotated by the heading {} \
         say: they move {} times as far, turned by {angle:.0} deg (median relative residual \
         {:.0} %)",
        file(rec),
        named(rec, Quantity::X),
        named(rec, Quantity::Y),
        named(rec, Quantity::U),
        named(rec, Quantity::V),
        named(rec, Quantity::Yaw),
        sig(gain),
        100.0 * rel
    );
    // a swap of u and v makes the sway the larger of the two (a vehicle moves along its x
    // axis); a heading offset (a rotation of the track) keeps the speed and the drift angle
    // of the columns: with the surge the larger, the swap is no explanation
    let swap_possible = median_of(path.v.iter().map(|v| v.abs()))
        .zip(median_of(path.u.iter().map(|u| u.abs())))
        .is_none_or(|(v, u)| v > u);
    // a mix-up that explains the data exactly comes first
    for (predict, words) in &path.mix_ups() {
        if *words == SWAPPED && !swap_possible {
            continue;
        }
        if path.fit(len, predict.as_ref()).is_some_and(holds) {
            return Some(Finding::new(rec, true, seen, words.to_string()));
        }
    }
    if rel < GOOD_FIT && angle.abs() >= 10.0 && (gain - 1.0).abs() < GAIN_TOLERANCE {
        return Some(Finding::new(
            rec,
            true,
            seen,
            format!(
                "the heading seems offset by {angle:.0} deg from the x axis of the positions \
                 (e.g. a compass heading from north with positions east-north): check which \
                 axis the heading is measured from"
            ),
        ));
    }
    Some(Finding::new(
        rec,
        false,
        seen,
        "positions, heading and velocities disagree and no simple mix-up explains it; the \
         filter will fit a compromise and the coefficients absorb the rest: check the units, \
         signs and frames of x, y, yaw, u and v"
            .to_string(),
    ))
}

/// Sway against surge where the vehicle holds a straight course (the approach, before the
/// heading or the rudder moves): a ship or an AUV on a straight course moves along its x
/// axis, so a sway far larger than the surge there is u and v swapped. Judged only when the
/// path check cannot (no positions or no heading), and a warning: a vehicle may move
/// sideways on purpose.
pub(super) fn sway_over_surge(rec: &Record) -> Option<Finding> {
    let track_judges = [Quantity::X, Quantity::Y, Quantity::Yaw]
        .iter()
        .all(|q| rec.channel(*q).is_some());
    if track_judges {
        return None;
    }
    let times = rec.time()?;
    let (u, v) = (rec.channel(Quantity::U)?, rec.channel(Quantity::V)?);
    let range = approach(rec)?;
    let range = range.start..range.end.min(u.len()).min(v.len()).min(times.len());
    if range.len() < 10 {
        return None;
    }
    let surge = median_of(u[range.clone()].iter().map(|x| x.abs()))?;
    let sway = median_of(v[range.clone()].iter().map(|x| x.abs()))?;
    let noise = crate::numerics::signal::noise_sigma(v).unwrap_or(0.0);
    if !(sway > 3.0 * surge && sway > 10.0 * noise) {
        return None;
    }
    Some(Finding::new(
        rec,
        false,
        format!(
            "in {}, while the vehicle holds its course (t = {} to {} s), the sway {} is {} \
             times the surge {} (median {} against {} m/s)",
            file(rec),
            sig(times[range.start]),
            sig(times[range.end - 1]),
            named(rec, Quantity::V),
            sig(sway / surge.max(f64::MIN_POSITIVE)),
            named(rec, Quantity::U),
            sig(sway),
            sig(surge)
        ),
        "a vehicle on a straight course moves along its x axis: u and v look swapped; \
         exchange the columns of the u and v entries (if this vehicle really moves sideways \
         here, ignore this)"
            .to_string(),
    ))
}
