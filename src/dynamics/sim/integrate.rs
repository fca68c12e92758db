//! Fixed-step classical RK4 integration of a model (Butcher 2008, section 32; the stepper is
//! [`crate::numerics::ode::Rk4`], shared with the hybrid EKF).

use super::InputSeries;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::Model;
use crate::numerics::ode::{self, Rk4};
use std::fmt;

/// A simulation that could not continue.
#[derive(Debug, Clone, PartialEq)]
pub struct SimError {
    /// Time at which it stopped, s.
    pub time: f64,
    /// Why.
    pub reason: String,
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "simulation stopped at t = {:.4} s: {}",
            self.time, self.reason
        )
    }
}

/// The model's coefficient vector from a coefficient set, with the model's relations applied.
/// Returns the names of free coefficients the set does not have.
pub fn complete_coefficients<M: Model>(
    model: &M,
    set: &CoefficientSet,
) -> Result<Vec<f64>, Vec<String>> {
    let names = model.coefficient_names();
    let mut c = vec![0.0; names.len()];
    let mut missing = Vec::new();
    for (i, n) in names.iter().enumerate() {
        match set.value(n) {
            Some(v) => c[i] = v,
            None if model.is_derived(n) || model.is_optional(n) => {}
            None => missing.push(n.to_string()),
        }
    }
    if !missing.is_empty() {
        return Err(missing);
    }
    model.relations().apply(&mut c);
    Ok(c)
}

/// Integrates the model from `x0` at `times[0]` and returns the state at every time in
/// `times` (row per time). `substeps` RK4 steps are taken per interval.
pub fn simulate<M: Model>(
    model: &M,
    coefficients: &[f64],
    x0: &[f64],
    inputs: &InputSeries,
    times: &[f64],
    substeps: usize,
) -> Result<Vec<Vec<f64>>, SimError> {
    let nx = model.nx();
    let mut out = Vec::with_capacity(times.len());
    let mut x = x0.to_vec();
    let mut u = vec![0.0; inputs.len()];
    let mut rk4 = Rk4::new(nx, nx);
    if let Some(&t0) = times.first() {
        model.check(&x, coefficients).map_err(|e| SimError {
            time: t0,
            reason: e.to_string(),
        })?;
        out.push(x.clone());
    }
    for w in times.windows(2) {
        for (t, h) in ode::substeps(w[0], w[1], substeps) {
            rk4.step(t, h, &mut x, |t, x, dx, _| {
                inputs.at(t, &mut u);
                model.derivatives(x, &u, coefficients, dx);
            });
        }
        model.check(&x, coefficients).map_err(|e| SimError {
            time: w[1],
            reason: e.to_string(),
        })?;
        out.push(x.clone());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::coefficients::{Coefficient, Source};
    use crate::model::models::Spheroid3;

    #[test]
    fn surge_run_approaches_terminal_speed() {
        let m = Spheroid3::paper_vehicle();
        let mut set = CoefficientSet::new();
        for n in m.coefficient_names() {
            set.insert(Coefficient::new(n, 0.0, None, Source::Config));
        }
        set.insert(Coefficient::new("Xuu", -1.33, None, Source::Config));
        set.insert(Coefficient::new("Xud", -1.164, None, Source::Config));
        let c = complete_coefficients(&m, &set).unwrap();
        let times: Vec<f64> = (0..=6000).map(|i| i as f64 * 0.01).collect();
        let xs = simulate(
            &m,
            &c,
            &[0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
            &InputSeries::constant(&[22.0]),
            &times,
            1,
        )
        .unwrap();
        let u_end = xs.last().unwrap()[0];
        // terminal speed sqrt(22 / 1.33)
        assert!((u_end - (22.0f64 / 1.33).sqrt()).abs() < 1e-3, "{u_end}");
    }

    #[test]
    fn missing_coefficients_are_named() {
        let m = Spheroid3::paper_vehicle();
        let mut set = CoefficientSet::new();
        set.insert(Coefficient::new("Xuu", -1.33, None, Source::Config));
        let missing = complete_coefficients(&m, &set).unwrap_err();
        assert!(missing.contains(&"Yvd".to_string()));
        assert!(
            !missing.contains(&"Xvr".to_string()),
            "derived ones are not asked for"
        );
    }
}
