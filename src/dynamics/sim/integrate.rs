//! Fixed-step classical RK4 integration of a model (Butcher 2008, section 32; the stepper is
//! [`crate::numerics::ode::Rk4`], shared with the hybrid EKF).

use super::inputs::InputSeries;
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
/// `times` (row per time). `substeps` RK4 steps are taken per interval. A held input is read
/// at each step's start (zero-order hold, [`InputSeries::in_step`]), so `times` should
/// include the input series' sample times for its jumps to fall on step boundaries.
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
            // each step lies in one sample interval: its held inputs are that interval's
            // (`InputSeries::in_step`), also at the step's end
            rk4.step(t, h, &mut x, |at, x, dx, _| {
                inputs.in_step(at, &mut u);
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
    use crate::dynamics::sim::inputs::Input;
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

    /// x_dot = T / m (surge1 without drag or added mass) with T held at its samples
    /// (zero-order hold): each sample interval of length h adds exactly h T_k / m to the
    /// speed, however many RK4 steps it takes; RK4 used to read T_k+1 in the last stage of an
    /// interval's last step, adding (T_k+1 - T_k) h / (6 m) too much with one step. An
    /// interpolated T adds the trapezoid h (T_k + T_k+1) / (2 m) (RK4 is exact for it).
    #[test]
    fn a_held_input_acts_over_its_own_interval() {
        use crate::model::models::{Surge1, Vehicle};
        let m = Surge1::build(&Vehicle::paper_spheroid()).unwrap();
        let c = m.coefficient_vector(&[("Xud", 0.0), ("Xuu", 0.0)]);
        let times = [0.0, 0.5, 1.0, 1.5];
        let thrust = vec![1.0, 7.0, -2.0, 4.0];
        for (input, gains) in [
            (Input::Held(thrust.clone()), [1.0, 7.0, -2.0]),
            (Input::Series(thrust.clone()), [4.0, 2.5, 1.0]),
        ] {
            let inputs = InputSeries {
                t: times.to_vec(),
                inputs: vec![input],
            };
            for substeps in [1, 4] {
                let xs = simulate(&m, &c, &[0.25, 0.0], &inputs, &times, substeps).unwrap();
                for (k, g) in gains.iter().enumerate() {
                    let want = xs[k][0] + 0.5 * g / m.mass;
                    assert!(
                        (xs[k + 1][0] - want).abs() < 1e-14,
                        "{:?}, {substeps} steps, interval {k}: {} for {want}",
                        inputs.inputs[0],
                        xs[k + 1][0]
                    );
                }
            }
        }
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
