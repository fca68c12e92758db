//! The estimator the stage does not use, kept to show why.

use super::STAGE;
use crate::base::error::{Error, Result};

/// Diagnostic only, and biased: X_udot from regressing the force Xuu u|u| + X_prop on a
/// central-difference u_dot through the origin, (m - Xud) = sum(F u_dot) / sum(u_dot^2).
/// Noise in u becomes noise of size sqrt(2) sigma_u / (2 dt) in u_dot, which shrinks the
/// fitted slope (regression dilution; Fuller 1987, section 1.1); since X_udot is the small
/// difference m - slope, a few per cent of dilution flips its sign. Kept to show why the
/// stage uses the integral form; `force[i]` is the total force at sample i.
pub fn naive_xud(time: &[f64], u: &[f64], force: &[f64], mass: f64) -> Result<f64> {
    let n = time.len();
    if n < 3 || u.len() != n || force.len() != n {
        return Err(Error::numerical(
            STAGE,
            "naive_xud needs time, u and force of equal length (at least 3 samples)",
        ));
    }
    let (mut sfu, mut suu) = (0.0, 0.0);
    for i in 1..n - 1 {
        // central difference u_dot = (u[i+1] - u[i-1]) / (t[i+1] - t[i-1])
        let ud = (u[i + 1] - u[i - 1]) / (time[i + 1] - time[i - 1]);
        sfu += force[i] * ud;
        suu += ud * ud;
    }
    if suu == 0.0 {
        return Err(Error::numerical(STAGE, "naive_xud: u does not change"));
    }
    Ok(mass - sfu / suu)
}
