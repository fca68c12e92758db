//! Number formatting shared by the report's sections.

use crate::base::numfmt::num;

/// A number, or `-` when absent or not finite.
pub fn opt(v: Option<f64>) -> String {
    v.filter(|x| x.is_finite()).map_or_else(|| "-".into(), num)
}

/// `value ± sigma` (just the value without a sigma).
pub fn pm(value: f64, sigma: Option<f64>) -> String {
    match sigma.filter(|s| s.is_finite()) {
        Some(s) => format!("{} ± {}", num(value), num(s)),
        None => num(value),
    }
}

/// A percentage with one decimal.
pub fn pct(fraction: f64) -> String {
    format!("{:.1} %", 100.0 * fraction)
}

/// A p-value: three decimals, or scientific below 0.001, and a bound below double precision.
pub fn p_value(p: f64) -> String {
    if p >= 1e-3 {
        format!("{p:.3}")
    } else if p >= 1e-15 {
        format!("{p:.1e}")
    } else {
        "< 1e-15".into()
    }
}

/// The name serde gives a unit variant (`"inverse_variance"`).
pub fn serde_name<T: serde::Serialize>(v: &T) -> String {
    match serde_json::to_value(v) {
        Ok(serde_json::Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(_) => "?".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        assert_eq!(opt(None), "-");
        assert_eq!(opt(Some(f64::NAN)), "-");
        assert_eq!(opt(Some(1.5)), "1.500");
        assert_eq!(pm(-23.84, Some(0.3798)), "-23.84 ± 0.3798");
        assert_eq!(pm(2.0, None), "2.000");
        assert_eq!(pct(0.3053), "30.5 %");
        assert_eq!(p_value(0.3634), "0.363");
        assert_eq!(p_value(2.5e-6), "2.5e-6");
        assert_eq!(p_value(0.0), "< 1e-15");
        assert_eq!(
            serde_name(&crate::stages::surge::DragFrom::Coefficients),
            "coefficients"
        );
    }
}
