//! Process noise from the data: what the model does not explain along the measured path.
//!
//! A model that misses part of the forces on a real vehicle (a form it does not have, an
//! asymmetry, a coefficient held at a published value that the basin's ship does not have)
//! leaves the measured velocities moving in ways its equations cannot; measured positions and
//! angles that the measured velocities and rates do not integrate to do the same for the
//! kinematics. With no process noise the filter can only bend the coefficients to follow
//! them, and its sigmas say nothing of the misfit. Process noise is, by definition, the part
//! of the state's rate the model does not give: x_dot = f(x, u, c) + w. Along a run whose
//! states are all measured, its low-frequency power is measured directly: over a stretch of
//! T seconds the mean rate from the measurements, (x(t+T) - x(t)) / T, less the model's mean
//! rate along the measured states, is the mean of w over T, whose variance for white noise of
//! spectral density q is q / T (Jazwinski 1970, "Stochastic processes and filtering theory",
//! section 4.4; the batch-means estimate of a spectral density at zero frequency, Priestley
//! 1981, section 7.5). The measurement noise adds (R_start + R_end) / T^2 to each stretch's
//! squared mean rate, which is taken off. Stretches are long (a twentieth of the run) so that
//! both the measurement noise and the rounding of the data average out.

use super::identify::RunData;
use crate::model::models::Model;

/// Stretches a run is cut into.
const STRETCHES: usize = 20;

/// Fewest samples a stretch needs.
const MIN_STRETCH: usize = 10;

/// An interval longer than this many median sampling intervals is a gap.
const GAP: f64 = 3.0;

/// Standard errors by which the mean excess must exceed 0 to count as process noise.
const SIGNIFICANT: f64 = 2.0;

/// The process noise spectral density (SI^2/s) of each state `adaptable` marks, from the
/// model's misfit along `run`'s measured states with the completed coefficient vector `c`;
/// None when the run does not measure every state or is too short.
pub fn from_misfit<M: Model>(
    model: &M,
    c: &[f64],
    run: &RunData,
    adaptable: &[bool],
) -> Option<Vec<f64>> {
    let nx = model.nx();
    let m = run.measured.len();
    // where each state is measured
    let column: Vec<usize> = (0..nx)
        .map(|j| run.measured.iter().position(|&s| s == j))
        .collect::<Option<Vec<usize>>>()?;
    let k_len = run.len();
    let len = (k_len / STRETCHES).max(MIN_STRETCH);
    if k_len < 2 * len || !model.outputs().is_empty() {
        return None;
    }
    let state = |k: usize| -> Vec<f64> { column.iter().map(|&a| run.y[k * m + a]).collect() };
    let variance =
        |k: usize, a: usize| run.r[a] + run.rounding.get(k * m + a).copied().unwrap_or(0.0);
    let rate = |k: usize, out: &mut [f64], u: &mut [f64]| {
        run.inputs.at(run.times[k], u);
        model.derivatives(&state(k), u, c, out);
    };
    let mut u = vec![0.0; run.inputs.len()];
    let (mut f0, mut f1) = (vec![0.0; nx], vec![0.0; nx]);
    let mut excess: Vec<Vec<f64>> = vec![Vec::new(); nx];
    let mut stretches = 0usize;
    let mut duration = 0.0;
    let step = crate::numerics::sampling::median_interval(&run.times)?;
    for start in (0..k_len - len).step_by(len) {
        let end = start + len;
        let t = run.times[end] - run.times[start];
        // a stretch with a missing sample (an excluded outlier) is left out, and one across a
        // gap in the time axis: the model's rate cannot be averaged over the gap from its ends
        let gap = (start..end).any(|k| run.times[k + 1] - run.times[k] > GAP * step);
        if t.is_nan()
            || t <= 0.0
            || gap
            || (start..=end).any(|k| state(k).iter().any(|v| !v.is_finite()))
        {
            continue;
        }
        // the model's mean rate over the stretch (trapezoidal)
        let mut mean = vec![0.0; nx];
        rate(start, &mut f0, &mut u);
        for k in start..end {
            rate(k + 1, &mut f1, &mut u);
            let h = run.times[k + 1] - run.times[k];
            for j in 0..nx {
                mean[j] += 0.5 * h * (f0[j] + f1[j]) / t;
            }
            std::mem::swap(&mut f0, &mut f1);
        }
        if mean.iter().any(|v| !v.is_finite()) {
            continue;
        }
        let (x0, x1) = (state(start), state(end));
        // the measurement noise of the states the model's rate is evaluated at, averaged
        // over the stretch's samples: sum_l (df_j/dx_l)^2 R_l / (samples)
        let mid = (start + end) / 2;
        let through_f = propagated(model, c, &state(mid), &mut u, run, mid, &|l| {
            variance(mid, column[l])
        });
        let samples = (end - start) as f64;
        for j in 0..nx {
            let e = (x1[j] - x0[j]) / t - mean[j];
            let noise = (variance(start, column[j]) + variance(end, column[j])) / (t * t)
                + through_f[j] / samples;
            excess[j].push((e * e - noise) * t);
        }
        stretches += 1;
        duration += t;
    }
    if stretches < 2 || duration.is_nan() || duration <= 0.0 {
        return None;
    }
    Some(
        (0..nx)
            .map(|j| {
                if adaptable.get(j).copied().unwrap_or(false) {
                    significant_mean(&excess[j])
                } else {
                    0.0
                }
            })
            .collect(),
    )
}

/// The mean of the stretches' excesses when it exceeds [`SIGNIFICANT`] standard errors, else
/// 0: with no process noise the excesses scatter about 0 (the measurement noise's share is
/// taken off only in expectation), and a chance positive mean is not a misfit.
fn significant_mean(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    if n < 2.0 {
        return 0.0;
    }
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    if mean > SIGNIFICANT * (var / n).sqrt() {
        mean
    } else {
        0.0
    }
}

/// Per state j, sum_l (df_j/dx_l)^2 var(l) at the state `x` (sample `k` of `run`): the
/// variance the measurement noise of the states gives the model's rate (central differences
/// of one tenth of each state's noise sigma).
fn propagated<M: Model>(
    model: &M,
    c: &[f64],
    x: &[f64],
    u: &mut [f64],
    run: &RunData,
    k: usize,
    var: &dyn Fn(usize) -> f64,
) -> Vec<f64> {
    let nx = x.len();
    run.inputs.at(run.times[k], u);
    let mut out = vec![0.0; nx];
    let (mut plus, mut minus) = (vec![0.0; nx], vec![0.0; nx]);
    let mut xs = x.to_vec();
    for l in 0..nx {
        let v = var(l);
        let h = 0.1 * v.sqrt();
        if h.is_nan() || h <= 0.0 {
            continue;
        }
        xs[l] = x[l] + h;
        model.derivatives(&xs, u, c, &mut plus);
        xs[l] = x[l] - h;
        model.derivatives(&xs, u, c, &mut minus);
        xs[l] = x[l];
        for j in 0..nx {
            let d = (plus[j] - minus[j]) / (2.0 * h);
            if d.is_finite() {
                out[j] += d * d * v;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::sim::InputSeries;
    use crate::model::models::surge1::Surge1;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// A surge run of `Surge1`'s example driven by white process noise of density `q` and
    /// measured with noise `sigma`: x_dot = f(x) + w.
    fn run(q: f64, sigma: f64) -> (Surge1, Vec<f64>, RunData) {
        let model = Surge1::build(&Surge1::example_vehicle()).expect("builds");
        let ex = model.example();
        let c = model.coefficient_vector(ex.coefficients);
        let dt = 0.01;
        let n = 20_000;
        let mut rng = StdRng::seed_from_u64(7);
        let w = Normal::new(0.0, (q / dt).sqrt()).unwrap();
        let e = Normal::new(0.0, sigma).unwrap();
        let inputs = InputSeries::constant(&ex.inputs);
        let mut x = ex.state.clone();
        let mut y = Vec::new();
        let mut dx = vec![0.0; x.len()];
        for _ in 0..n {
            y.extend(x.iter().map(|v| v + e.sample(&mut rng)));
            // Euler in 20 sub-steps, the forcing held over the sample
            let wk: Vec<f64> = x.iter().map(|_| w.sample(&mut rng)).collect();
            for _ in 0..20 {
                model.derivatives(&x, &ex.inputs, &c, &mut dx);
                for ((xi, di), wi) in x.iter_mut().zip(&dx).zip(&wk) {
                    *xi += dt / 20.0 * (di + wi);
                }
            }
        }
        let nx = x.len();
        let data = RunData {
            name: "surge".into(),
            times: (0..n).map(|k| k as f64 * dt).collect(),
            measured: (0..nx).collect(),
            y,
            r: vec![sigma * sigma; nx],
            rounding: Vec::new(),
            inputs,
            x0: ex.state.clone(),
            p0: vec![0.0; nx * nx],
            lines: Vec::new(),
        };
        (model, c, data)
    }

    #[test]
    fn the_density_of_a_white_forcing_is_recovered() {
        let (model, c, data) = run(1e-4, 1e-3);
        let q = from_misfit(&model, &c, &data, &[true; 2]).unwrap();
        // the velocity and the position: both forced (the position through its own w)
        assert!((q[0] / 1e-4 - 1.0).abs() < 0.4, "{q:?}");
    }

    #[test]
    fn a_model_that_follows_the_data_needs_none() {
        let (model, c, data) = run(0.0, 1e-3);
        let q = from_misfit(&model, &c, &data, &[true; 2]).unwrap();
        // against 1e-4 of the forced run: the measurement noise is taken off
        assert!(q.iter().all(|v| *v < 1e-7), "{q:?}");
        // a state that is not adaptable gets none
        assert_eq!(
            from_misfit(&model, &c, &data, &[false; 2]).unwrap(),
            vec![0.0; 2]
        );
    }
}
