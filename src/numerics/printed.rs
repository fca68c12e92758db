//! What the digits of a printed column say: the resolution of each value, the step by which
//! a number written with a fixed count of decimals or of significant digits can change.
//!
//! A log printed with `%.2E` (three significant digits) rounds 785.3 m to 785 and 1234 m to
//! 1230: its resolution grows with the value. A column printed with a fixed count of decimals
//! (`%.3f`) has one resolution. Rounding to a step `d` adds an error spread evenly over
//! `(-d/2, d/2)` to each value, of variance `d^2 / 12` (Widrow & Kollar 2008, "Quantization
//! Noise", section 4.2), which a measurement noise model must include.

/// Values the digit counts are read from at most (evenly spaced over the column): enough to
/// meet every digit count a printing format produces, bounded for long columns.
const SAMPLE: usize = 20_000;

/// The digits a column is printed with. A printing format fixes either the decimals (`%.3f`,
/// fixed-width columns) or the significant digits (`%.2E`); which one is read from the
/// values: the count that most of them reach (a value falls short of it only when its last
/// digits are zeros, which its shortest form drops).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Digits {
    /// A fixed count of decimals.
    Decimals(i32),
    /// A fixed count of significant digits; `zero` is the step given to a printed zero (the
    /// step of the smallest value seen: anything smaller would have printed as itself).
    Significant { digits: i32, zero: f64 },
}

impl Digits {
    /// The digits of a column, read from up to [`SAMPLE`] of its finite non-zero values.
    pub fn of(values: &[f64]) -> Digits {
        let step = values.len().div_ceil(SAMPLE).max(1);
        let seen: Vec<(i32, i32)> = values
            .iter()
            .step_by(step)
            .filter(|v| v.is_finite() && **v != 0.0)
            .map(|&v| (decimals(v), significant(v).0))
            .collect();
        let d = seen.iter().map(|s| s.0).max().unwrap_or(0).min(17);
        let s = seen.iter().map(|s| s.1).max().unwrap_or(1).min(17);
        let reach_d = seen.iter().filter(|v| v.0 == d).count();
        let reach_s = seen.iter().filter(|v| v.1 == s).count();
        if reach_s > reach_d {
            let smallest = values
                .iter()
                .step_by(step)
                .filter(|v| v.is_finite() && **v != 0.0)
                .fold(f64::INFINITY, |m, v| m.min(v.abs()));
            let mut d = Digits::Significant {
                digits: s,
                zero: 0.0,
            };
            let zero = d.resolution(smallest);
            if let Digits::Significant { zero: z, .. } = &mut d {
                *z = zero;
            }
            d
        } else {
            Digits::Decimals(d)
        }
    }

    /// The resolution of value `v` printed with these digits: the step of its last digit.
    pub fn resolution(&self, v: f64) -> f64 {
        match *self {
            Digits::Decimals(d) => 10f64.powi(-d),
            Digits::Significant { digits: s, zero } => {
                if v == 0.0 || !v.is_finite() {
                    return zero;
                }
                let exponent = v.abs().log10().floor() as i32;
                // log10 of a power of ten can land just below the integer
                let exponent = if 10f64.powi(exponent + 1) <= v.abs() {
                    exponent + 1
                } else {
                    exponent
                };
                10f64.powi(exponent - s + 1)
            }
        }
    }
}

/// Digits after the decimal point in the shortest form of `v`.
fn decimals(v: f64) -> i32 {
    let s = format!("{}", v.abs());
    s.split('.').nth(1).map_or(0, str::len) as i32
}

/// Significant digits and decimal exponent of the shortest form of `v` (`{:e}` writes the
/// shortest mantissa that reads back: 1.35e-1, 1e1).
fn significant(v: f64) -> (i32, i32) {
    let s = format!("{:e}", v.abs());
    let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
    let digits = m.chars().filter(char::is_ascii_digit).count() as i32;
    (digits, e.parse::<i32>().unwrap_or(0))
}

/// The print resolution of each value of a column (see [`Digits`]).
pub fn resolutions(values: &[f64]) -> Vec<f64> {
    let d = Digits::of(values);
    values.iter().map(|&v| d.resolution(v)).collect()
}

/// The print resolution of each value when it is coarse enough to matter as noise: some
/// value's step is more than a part in 10^7 of the column's range (a log printed with a few
/// digits), else None (an export with 10 or more significant digits).
pub fn coarse_resolutions(values: &[f64]) -> Option<Vec<f64>> {
    let (lo, hi) = crate::numerics::signal::range(values.iter().copied().filter(|v| v.is_finite()));
    let span = (hi - lo).max(hi.abs().max(lo.abs()) * 1e-3);
    if span.is_nan() || span <= 0.0 {
        return None;
    }
    let res = resolutions(values);
    let largest = res.iter().fold(0.0f64, |m, &r| m.max(r));
    (largest > 1e-7 * span).then_some(res)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_significant_digits_have_a_step_that_grows_with_the_value() {
        let printed: Vec<f64> = ["1.35E-01", "8.11E+00", "1.00E+02", "7.85E+02", "1.23E+03"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        let r = resolutions(&printed);
        let want = [1e-3, 1e-2, 1.0, 1.0, 10.0];
        for (got, want) in r.iter().zip(want) {
            assert!((got / want - 1.0).abs() < 1e-12, "{r:?}");
        }
        assert!(coarse_resolutions(&printed).is_some());
    }

    #[test]
    fn fixed_decimals_have_one_step() {
        let printed: Vec<f64> = [".050000000", "2.931712300", "41.448000000", "-.000822800"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        let d = Digits::of(&printed);
        assert_eq!(d, Digits::Decimals(7));
        assert!((d.resolution(41.448) - 1e-7).abs() < 1e-19);
        // ten significant digits over a range of tens: too fine to matter
        let fine: Vec<f64> = (0..100)
            .map(|k| (k as f64 * 0.123_456_789_1).sin() * 10.0)
            .collect();
        assert!(coarse_resolutions(&fine).is_none());
    }
}
