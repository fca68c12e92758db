//! Numbers written for people: fixed decimals without trailing zeros.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trailing_zeros_go_integer_zeros_stay() {
        assert_eq!(fixed_trimmed(0.25, 4), "0.25");
        assert_eq!(fixed_trimmed(3.0, 4), "3");
        assert_eq!(fixed_trimmed(250.0, 0), "250");
        assert_eq!(fixed_trimmed(-0.0005, 6), "-0.0005");
    }
}
