//! A circle fitted to points of a track: the algebraic least-squares fit of Kåsa
//! (I. Kåsa, "A circle fitting procedure and its error analysis", IEEE Trans. Instrum. Meas.
//! 25(1), 1976): minimise sum (x^2 + y^2 + D x + E y + F)^2, linear in D, E, F.

use nalgebra::{Matrix3, Vector3};

/// A fitted circle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Circle {
    /// Centre x, m.
    pub cx: f64,
    /// Centre y, m.
    pub cy: f64,
    /// Radius, m.
    pub radius: f64,
}

/// The circle through `x`, `y` in the least-squares sense; None for fewer than 3 points or
/// points on a line (or on one point). The points are centred on their mean first so that the normal
/// equations stay well conditioned far from the origin.
pub(super) fn fit_circle(x: &[f64], y: &[f64]) -> Option<Circle> {
    let n = x.len();
    if n < 3 {
        return None;
    }
    let mx = x.iter().sum::<f64>() / n as f64;
    let my = y.iter().sum::<f64>() / n as f64;
    let mut a = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    for (&xi, &yi) in x.iter().zip(y) {
        let (u, v) = (xi - mx, yi - my);
        let row = Vector3::new(u, v, 1.0);
        a += row * row.transpose();
        b -= row * (u * u + v * v);
    }
    // Points on a line make the normal equations singular (to rounding).
    let eig = a.symmetric_eigenvalues();
    if eig.min() <= 1e-12 * eig.max() {
        return None;
    }
    let p = a.cholesky()?.solve(&b);
    let (cu, cv) = (-p[0] / 2.0, -p[1] / 2.0);
    let r2 = cu * cu + cv * cv - p[2];
    (r2.is_finite() && r2 > 0.0).then(|| Circle {
        cx: cu + mx,
        cy: cv + my,
        radius: r2.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_an_arc_give_its_circle() {
        let (x, y): (Vec<f64>, Vec<f64>) = (0..20)
            .map(|i| {
                let a = 0.1 * i as f64;
                (1000.0 + 250.0 * a.cos(), -40.0 + 250.0 * a.sin())
            })
            .unzip();
        let c = fit_circle(&x, &y).unwrap();
        assert!((c.radius - 250.0).abs() < 1e-8, "{c:?}");
        assert!((c.cx - 1000.0).abs() < 1e-8 && (c.cy + 40.0).abs() < 1e-8);
    }

    #[test]
    fn points_on_a_line_have_no_circle() {
        assert!(fit_circle(&[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0]).is_none());
    }
}
