//! Numbers written for people: four significant digits, fixed decimals without trailing
//! zeros, proportions.

/// `v` with `decimals` decimals, trailing zeros (and a bare decimal point) removed:
/// 0.2500 -> "0.25", 3.0000 -> "3"; integers written without decimals keep their zeros.
pub fn fixed_trimmed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Significant-figure formatting used in every table: 4 significant digits, plain for
/// moderate magnitudes.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..6).contains(&mag) {
        let decimals = (3 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// `v` (> 0) rounded to two significant digits.
fn two_digits(v: f64) -> f64 {
    let step = 10f64.powi(v.log10().floor() as i32 - 1);
    (v / step).round() * step
}

/// A fraction as a percentage with two significant digits (0.1637 -> "16 %", 0.0052 ->
/// "0.52 %", 8.43 -> "840 %").
pub fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction.abs();
    if !p.is_finite() || p == 0.0 {
        return format!("{p} %");
    }
    let p = two_digits(p);
    let decimals = (1 - p.log10().floor() as i32).max(0) as usize;
    format!("{} %", fixed_trimmed(p, decimals))
}

/// How large `ratio` (>= 0) is next to the thing it is a ratio of, to be followed by that
/// thing: up to 10, a percentage ("16 % of" the value); beyond, a factor with two significant
/// digits ("13 times", "1.3e9 times" the value, rather than "131003125175 % of" it).
pub fn proportion(ratio: f64) -> String {
    let r = ratio.abs();
    if r <= 10.0 || !r.is_finite() {
        format!("{} of", percent(r))
    } else if r < 1000.0 {
        format!("{} times", two_digits(r))
    } else {
        format!("{r:.1e} times")
    }
}

/// A number as a configuration problem shows it: plain between 1e-3 and 1e6, else in
/// exponent form (`1e300`, not three hundred digits).
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `v` to four significant digits, written as [`short`] writes it: 55.56, 100, 1e6.
pub fn short_four(v: f64) -> String {
    short(format!("{v:.3e}").parse().unwrap_or(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_significant_figures() {
        assert_eq!(short_four(55.5555), "55.56");
        assert_eq!(short_four(100.0), "100");
        assert_eq!(short_four(1e6), "1e6");
        assert_eq!(num(-23.6261), "-23.63");
        assert_eq!(num(-1.16404), "-1.164");
        assert_eq!(num(0.0017), "0.001700");
        assert_eq!(num(13.43), "13.43");
        assert_eq!(num(1234.5), "1234");
        assert_eq!(num(2.5e-7), "2.500e-7");
    }

    #[test]
    fn ratios_read_sensibly_at_any_size() {
        assert_eq!(proportion(0.1637), "16 % of");
        assert_eq!(proportion(0.8443), "84 % of");
        assert_eq!(proportion(0.0052), "0.52 % of");
        assert_eq!(proportion(0.0123), "1.2 % of");
        assert_eq!(proportion(8.43), "840 % of");
        assert_eq!(proportion(10.0), "1000 % of");
        assert_eq!(proportion(12.6), "13 times");
        assert_eq!(proportion(1310031251.75), "1.3e9 times");
        assert_eq!(percent(0.0), "0 %");
    }

    #[test]
    fn trailing_zeros_go_integer_zeros_stay() {
        assert_eq!(fixed_trimmed(0.25, 4), "0.25");
        assert_eq!(fixed_trimmed(3.0, 4), "3");
        assert_eq!(fixed_trimmed(250.0, 0), "250");
        assert_eq!(fixed_trimmed(-0.0005, 6), "-0.0005");
    }
}
