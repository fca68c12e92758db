//! Magnitude limits of a motion a user describes by hand: a manoeuvre of `hydroid simulate`,
//! a candidate run of `hydroid plan`, the speed of an autopilot's plant. Beyond them a value
//! is a unit or typing mistake (a speed in km/h written as m/s, a frequency in rad/s written
//! as Hz, degrees written as radians), not a run a towing tank, a planar motion mechanism or a
//! solver makes. Each check returns the message (the value with its unit, the limit and the
//! likely mistake) for the caller to place at its key; None when the value is plausible.
//! The magnitude of any one quantity is [`Quantity::plausible_bound`]'s, as for every key of
//! a configuration.

use crate::base::numfmt::{fixed_trimmed, num, short, short_four};
use crate::base::quantity::Quantity;
use std::f64::consts::PI;

/// Fastest carriage or approach speed, m/s: 50 m/s (97 kn), beyond any towing carriage
/// (the fastest run at about 15 m/s) and any ship or underwater vehicle hydroid models.
pub const MAX_SPEED: f64 = 50.0;

/// Largest non-dimensional yaw (or roll, pitch) rate r' = r L / U of a captive or PMM run:
/// a turning circle of a quarter length's radius. Captive tests reach r' of about 1
/// (ITTC 7.5-02-06-02).
pub const MAX_RATE_PRIME: f64 = 2.0;

/// Largest non-dimensional PMM frequency omega' = omega L / U: PMM tests run at omega' of
/// about 0.5 to 6 (ITTC 7.5-02-06-04); beyond 20 the vehicle moves less than a third of its
/// length per period.
pub const MAX_OMEGA_PRIME: f64 = 20.0;

/// Fewest samples per period of an oscillation: its Fourier parts are then read without
/// aliasing (Nyquist asks for more than 2; 20 keep the waveform).
pub const SAMPLES_PER_PERIOD: f64 = 20.0;

/// A carriage, towing or approach speed `u` (m/s) beyond [`MAX_SPEED`], or not positive.
pub fn speed(u: f64) -> Option<String> {
    if !(u.is_finite() && u > 0.0) {
        return Some(format!("must be a positive speed in m/s, got {}", short(u)));
    }
    (u > MAX_SPEED).then(|| {
        format!(
            "{} m/s ({} kn) is faster than any towing carriage or vessel (at most {MAX_SPEED} \
             m/s): a speed in km/h or kn written as m/s?",
            short_four(u),
            short_four(u * 3600.0 / 1852.0)
        )
    })
}

/// A value `si` of quantity `q` beyond the magnitude any hand-written value of it can have
/// ([`Quantity::plausible_bound`]); `shown` is the value as the user wrote it (with its unit).
pub fn magnitude(q: Quantity, si: f64, shown: &str) -> Option<String> {
    if !si.is_finite() {
        return Some(format!("must be a finite number, got {shown}"));
    }
    match q.plausible_bound() {
        Some((bound, what)) if si.abs() > bound => Some(format!(
            "{shown} is beyond any plausible {q}: at most {what} in magnitude; a unit or \
             typing mistake?"
        )),
        _ => None,
    }
}

/// The amplitude `a` (m/s) of an oscillating translation (PMM pure sway v, heave w, surge u)
/// against the carriage speed `u`: more than U is a drift angle beyond 45 deg.
pub fn translation_amplitude(a: f64, u: f64) -> Option<String> {
    (a.abs() > u).then(|| {
        format!(
            "{} m/s is more than the speed U = {} m/s (a drift angle of more than 45 deg at \
             the peak; PMM sway runs stay within about 0.3 U): is the amplitude in m/s?",
            short(a.abs()),
            short(u)
        )
    })
}

/// An angular rate `rate` (rad/s) against the speed `u` (m/s) and the length `length` (m):
/// r' = r L / U beyond [`MAX_RATE_PRIME`]. `shown` is the rate as written.
pub fn rate_prime(rate: f64, length: f64, u: f64, shown: &str) -> Option<String> {
    let prime = rate.abs() * length / u;
    (prime > MAX_RATE_PRIME).then(|| {
        format!(
            "{shown} is r' = r L / U = {} at U = {} m/s and L = {} m: beyond {MAX_RATE_PRIME} \
             (a turn of a quarter length's radius; captive runs reach about 1): degrees for \
             radians, or the wrong speed?",
            num(prime),
            short(u),
            short(length)
        )
    })
}

/// A PMM frequency `f` (Hz) against the speed `u` (m/s) and the length `length` (m):
/// omega' = 2 pi f L / U beyond [`MAX_OMEGA_PRIME`].
pub fn omega_prime(f: f64, length: f64, u: f64) -> Option<String> {
    let prime = 2.0 * PI * f * length / u;
    (prime > MAX_OMEGA_PRIME).then(|| {
        format!(
            "{} Hz is omega' = 2 pi f L / U = {} at U = {} m/s and L = {} m: beyond \
             {MAX_OMEGA_PRIME} (PMM runs are at 0.5 to 6): a frequency in rad/s written as \
             Hz?",
            short(f),
            num(prime),
            short(u),
            short(length)
        )
    })
}

/// An oscillation of `f` Hz sampled every `dt` s with fewer than [`SAMPLES_PER_PERIOD`]
/// samples a period (a motion above the Nyquist frequency 1 / (2 dt) cannot be told from a
/// slower one at all).
pub fn sampling(f: f64, dt: f64) -> Option<String> {
    let per_period = 1.0 / (f * dt);
    (per_period < SAMPLES_PER_PERIOD).then(|| {
        let nyquist = if per_period < 2.0 {
            format!(
                ", above the Nyquist frequency 1 / (2 dt) = {} Hz: the samples cannot tell it \
                 from a slower motion",
                short(0.5 / dt)
            )
        } else {
            String::new()
        };
        format!(
            "{} Hz sampled every {} s is {} samples a period{nyquist}; the sampling must \
             resolve the motion: at least {SAMPLES_PER_PERIOD} samples a period, dt at most \
             {} s",
            short(f),
            short(dt),
            fixed_trimmed(per_period, 2),
            short(1.0 / (SAMPLES_PER_PERIOD * f))
        )
    })
}

/// A run of `duration` s holding fewer than `min` whole periods of `f` Hz: the captive
/// stage fits the forces' Fourier parts over whole periods and refuses fewer than `min`.
pub fn whole_periods(f: f64, duration: f64, min: usize) -> Option<String> {
    let held = f * duration;
    (held + 1e-6 < min as f64).then(|| {
        format!(
            "{} s holds {} periods of the {} Hz oscillation ({} s each): the captive stage \
             fits the forces over at least {min} whole periods (an incomplete period is not \
             used); at least {} s",
            short(duration),
            short(held),
            short(f),
            short(1.0 / f),
            short((min as f64 / f * 100.0).ceil() / 100.0)
        )
    })
}

/// The number of samples of a run of `duration` s sampled every `dt` s beyond `max`
/// (`what`: whose limit it is).
pub fn sample_count(duration: f64, dt: f64, max: f64, what: &str) -> Option<String> {
    let n = duration / dt;
    (n > max).then(|| {
        format!(
            "duration {} s / dt {} s is {} samples, more than the {} {what}: a longer dt or a \
             shorter duration",
            short(duration),
            short(dt),
            short(n.round()),
            short(max)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_check_names_the_value_and_its_unit() {
        assert!(speed(2.0).is_none());
        let e = speed(1e6).unwrap();
        assert!(e.contains("1e6 m/s") && e.contains("50"), "{e}");
        assert!(speed(0.0).unwrap().contains("positive"));
        let e = magnitude(Quantity::Rudder, 95f64.to_radians(), "95 deg").unwrap();
        assert!(e.contains("95 deg") && e.contains("90 deg"), "{e}");
        assert!(magnitude(Quantity::Rudder, 0.5, "0.5").is_none());
        assert!(translation_amplitude(0.2, 2.0).is_none());
        assert!(translation_amplitude(10.0, 2.0).unwrap().contains("45 deg"));
        // 15 deg/s on a 1.2 m body at 2 m/s: r' 0.16
        assert!(rate_prime(15f64.to_radians(), 1.2, 2.0, "15 deg/s").is_none());
        let e = rate_prime(900f64.to_radians(), 1.2, 2.0, "900 deg/s").unwrap();
        assert!(e.contains("r' = r L / U = 9.425"), "{e}");
        assert!(omega_prime(0.5, 1.2, 2.0).is_none());
        assert!(omega_prime(50.0, 1.2, 2.0).unwrap().contains("rad/s"));
        let e = sampling(1000.0, 0.01).unwrap();
        assert!(e.contains("Nyquist") && e.contains("0.1 samples"), "{e}");
        assert!(sampling(0.5, 0.01).is_none());
        assert!(!sampling(10.0, 0.01).unwrap().contains("Nyquist"));
        assert!(whole_periods(0.01, 10.0, 2).unwrap().contains("100 s each"));
        // 1.9 periods are refused (the captive stage needs 2 whole ones), 2 are not
        assert!(whole_periods(0.19, 10.0, 2)
            .unwrap()
            .contains("at least 10.53 s"));
        assert!(whole_periods(0.2, 10.0, 2).is_none());
        assert!(sample_count(10.0, 1e-6, 2e5, "a candidate may make")
            .unwrap()
            .contains("1e7 samples"));
    }
}
