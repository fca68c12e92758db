//! Parameters of the disturbance model by the innovations' likelihood.
//!
//! A coefficient of the disturbance model (the wave-yaw model's peak frequency w0 and
//! damping, [`CoefDef::disturbance`]) sets how the filter splits the measurements between
//! the vehicle's response and the disturbance, so it enters the Kalman gain. Appended to the
//! state, the extended Kalman filter ignores the gain's dependence on it and its estimate is
//! biased (Ljung 1979, "Asymptotic behavior of the extended Kalman filter as a parameter
//! estimator for linear systems", IEEE TAC 24(1)): on independently generated
//! Nomoto runs the appended w0 went wrong in about one seed in ten and took K and T with it.
//! The prediction-error (maximum-likelihood) method estimates it instead (Ljung 1999, System
//! Identification, 2nd ed., section 7.4 and chapter 9; Maybeck 1982, Stochastic Models,
//! Estimation and Control, vol. 2, chapter 10): with the coefficient held at a value, the
//! filter's innovations e_k with covariances S_k give
//!
//! ```text
//! V(theta) = sum_k ( e_k^T S_k^-1 e_k + ln det S_k )   (-2 ln L less a constant)
//! ```
//!
//! and the estimate minimises V over theta, each value's vehicle coefficients estimated by
//! the filter as before (the profile likelihood). Its covariance is 2 H^-1, H the Hessian
//! of V (Ljung 1999, chapter 9: the inverse Fisher information); the vehicle coefficients'
//! covariance adds G cov(theta) G^T, G their derivative along the profile (the delta
//! method), so that the uncertainty of the disturbance model reaches them.

use super::identify::{self, Identification, RunData, Setup};
use crate::model::models::{CoefDef, Model};
use crate::numerics::estimation::FilterKind;

/// A profiled coefficient is held in the filter at a prior sigma this many times its
/// configured one (with no random walk): the filter's gain for it is nil.
const HELD: f64 = 1e-6;

/// The search ends when a step in ln(theta) is below this.
const TOLERANCE: f64 = 2e-3;

/// First step of the search in ln(theta) (10 %), doubled until the minimum is bracketed.
const FIRST_STEP: f64 = 0.1;

/// The search stays within this factor of its start (either way).
const REACH: f64 = 100.0;

/// Step in ln(theta) of the Hessian's central differences.
const CURVATURE_STEP: f64 = 0.02;

/// A minimum this far (in ln(theta)) from the search's start moves the start there once.
const RECENTRE: f64 = 0.05;

/// V and the estimates (SI) at one trial value of the profiled coefficients; None where the
/// filter fails.
type Trial = Option<(f64, Vec<f64>)>;

/// Coordinate sweeps over several profiled coefficients.
const SWEEPS: usize = 4;

/// The maximum-likelihood values of the profiled coefficients and what they give the others.
#[derive(Debug, Clone)]
pub struct Profile {
    /// Positions in [`Setup::est`] of the profiled coefficients.
    pub at: Vec<usize>,
    /// Their maximum-likelihood values (SI).
    pub values: Vec<f64>,
    /// Their covariance (np x np, row-major, SI): 2 H^-1 in ln(theta), scaled.
    pub covariance: Vec<f64>,
    /// Derivative of every estimate (nb, SI) along each profiled coefficient (nb x np,
    /// row-major, per unit of the coefficient).
    pub gradient: Vec<f64>,
    /// Identifications the search ran.
    pub evaluations: usize,
}

/// Why a profile could not be found; the appended (filter-state) estimate is used instead.
#[derive(Debug, Clone, PartialEq)]
pub enum NotProfiled {
    /// The continuous (Kalman-Bucy) filter has no discrete innovations to weigh.
    ContinuousFilter,
    /// The likelihood has no minimum inside the search's reach (the data do not determine
    /// the coefficient), or no curvature there.
    NotDetermined(String),
}

/// The console warning when the disturbance coefficients (`names`) stay appended to the
/// state.
pub fn kept_warning(why: &NotProfiled, names: &[&str]) -> crate::base::warning::Warning {
    let reason = match why {
        NotProfiled::ContinuousFilter => {
            "the continuous filter (hekf.filter = \"continuous\") has no discrete innovations \
             to weigh"
                .to_string()
        }
        NotProfiled::NotDetermined(why) => why.clone(),
    };
    crate::base::warning::Warning::new(
        super::STAGE,
        format!(
            "{} not found by the innovations' likelihood ({reason}): estimated as a filter \
             state instead",
            names.join(", ")
        ),
        "a disturbance-model parameter estimated as a filter state can be biased, and its \
         bias reaches the vehicle's coefficients: hold it at a known value (the sea's \
         encounter frequency) or give a longer run",
    )
}

/// Positions in `setup.est` of the coefficients of the disturbance model.
pub fn profiled<M: Model>(model: &M, setup: &Setup) -> Vec<usize> {
    let defs: &[CoefDef] = model.coefficients();
    (0..setup.est.len())
        .filter(|&j| defs[setup.est[j]].disturbance)
        .collect()
}

/// `setup` with the coefficients at positions `at` held at `values` (SI).
pub fn held(setup: &Setup, at: &[usize], values: &[f64]) -> Setup {
    let mut s = setup.clone();
    let nx = s.q.len() - s.est.len();
    for (&j, &v) in at.iter().zip(values) {
        s.initial[j] = v;
        s.prior_sigma[j] *= HELD;
        s.q[nx + j] = 0.0;
    }
    s
}

/// What [`search`] found.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// No disturbance coefficient is estimated: identify with the setup as it is.
    Nothing,
    /// Identify with this setup (the profiled coefficients held at their maximum-likelihood
    /// values), then widen with [`widen`].
    Profiled(Box<Setup>, Profile),
    /// The likelihood could not be searched: the coefficients stay appended to the state.
    Kept(NotProfiled),
}

/// The maximum-likelihood values of the disturbance coefficients `setup` estimates
/// ([`profiled`]). The search's identifications are one pass each from the estimate of a
/// full identification at the search's start (the pass later passes make, with the same
/// prior: `sensitivity::one_pass_setup`), which makes V a smooth function of theta at a
/// third of the cost; when the minimum is more than [`RECENTRE`] away from that start, the
/// start moves there once and the search repeats.
pub fn search<M: Model>(model: &M, setup: &Setup, runs: &[RunData]) -> Outcome {
    let at = profiled(model, setup);
    if at.is_empty() {
        return Outcome::Nothing;
    }
    if setup.filter == FilterKind::Continuous {
        return Outcome::Kept(NotProfiled::ContinuousFilter);
    }
    let mut u: Vec<f64> = at
        .iter()
        .map(|&j| {
            let x = setup.initial[j];
            if x > 0.0 && x.is_finite() {
                x.ln()
            } else {
                setup.prior_sigma[j].ln()
            }
        })
        .collect();
    let mut evaluations = 0;
    let exp = |u: &[f64]| -> Vec<f64> { u.iter().map(|x| x.exp()).collect() };
    let mut recentred = false;
    loop {
        evaluations += 1;
        let Ok((start, q, _)) = identify::profile_point(model, &held(setup, &at, &exp(&u)), runs)
        else {
            return Outcome::Kept(NotProfiled::NotDetermined(
                "the filter fails at the start value".into(),
            ));
        };
        let warm = Setup {
            run_q: q,
            ..super::sensitivity::one_pass_setup(setup, &start.values, &start.sigmas)
        };
        let mut v = |w: &[f64]| -> Trial {
            evaluations += 1;
            identify::profile_point(model, &held(&warm, &at, &exp(w)), runs)
                .ok()
                .filter(|(_, _, v)| v.is_finite())
                .map(|(e, _, v)| (v, e.values))
        };
        let from = u.clone();
        let lowest = match descend(&mut |w| v(w).map_or(f64::INFINITY, |p| p.0), &mut u) {
            Ok(lowest) => lowest,
            Err(why) => return Outcome::Kept(NotProfiled::NotDetermined(why)),
        };
        let moved = u
            .iter()
            .zip(&from)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if !recentred && moved > RECENTRE {
            recentred = true;
            continue;
        }
        return match curvature(&mut v, &u, lowest, setup.est.len()) {
            Ok((covariance, gradient)) => {
                let values = exp(&u);
                let held_setup = held(setup, &at, &values);
                Outcome::Profiled(
                    Box::new(held_setup),
                    Profile {
                        at,
                        values,
                        covariance,
                        gradient,
                        evaluations,
                    },
                )
            }
            Err(why) => Outcome::Kept(NotProfiled::NotDetermined(why)),
        };
    }
}

/// Minimises `f` over `u` by coordinate sweeps of [`minimise`] (at most [`SWEEPS`]); the
/// minimum of `f`, at the `u` it leaves.
fn descend(f: &mut dyn FnMut(&[f64]) -> f64, u: &mut [f64]) -> Result<f64, String> {
    let mut f0 = f(u);
    if !f0.is_finite() {
        return Err("the filter fails at the start value".into());
    }
    for _ in 0..SWEEPS {
        let mut moved: f64 = 0.0;
        for i in 0..u.len() {
            let start = u[i];
            let mut along = |x: f64| {
                let mut w = u.to_vec();
                w[i] = x;
                f(&w)
            };
            let (x, fx) = minimise(&mut along, start, f0)?;
            moved = moved.max((x - start).abs());
            u[i] = x;
            f0 = fx;
        }
        if moved < TOLERANCE || u.len() == 1 {
            break;
        }
    }
    Ok(f0)
}

/// The minimum of `f` from `x0` (where it is `f0`): bracketed by steps doubling from
/// [`FIRST_STEP`], then refined by parabolas through the bracket, with golden-section steps
/// where a parabola fails (Brent 1973, Algorithms for Minimization without Derivatives,
/// chapter 5).
fn minimise(f: &mut dyn FnMut(f64) -> f64, x0: f64, f0: f64) -> Result<(f64, f64), String> {
    let mut step = FIRST_STEP;
    let mut f1 = f(x0 + step);
    if f1.is_nan() || f1 > f0 {
        let fm = f(x0 - step);
        if fm.partial_cmp(&f0) != Some(std::cmp::Ordering::Less) {
            return Ok(refine(f, [(x0 - step, fm), (x0, f0), (x0 + step, f1)]));
        }
        step = -step;
        f1 = fm;
    }
    let (mut a, mut b) = ((x0, f0), (x0 + step, f1));
    let reach = REACH.ln();
    loop {
        step *= 2.0;
        // the last step ends at the reach
        let last = (b.0 + step - x0).abs() >= reach;
        let x = if last {
            x0 + reach * step.signum()
        } else {
            b.0 + step
        };
        let c = (x, f(x));
        if c.1.partial_cmp(&b.1) != Some(std::cmp::Ordering::Less) {
            let mut t = [a, b, c];
            t.sort_by(|p, q| p.0.total_cmp(&q.0));
            return Ok(refine(f, t));
        }
        if last {
            return Err(format!(
                "the likelihood still rises towards {} times the start value",
                crate::base::numfmt::num((x - x0).exp())
            ));
        }
        (a, b) = (b, c);
    }
}

/// Narrows a bracket (x ascending, the middle lowest) to the minimum.
fn refine(f: &mut dyn FnMut(f64) -> f64, mut t: [(f64, f64); 3]) -> (f64, f64) {
    const GOLDEN: f64 = 0.381_966_011_250_105_1;
    for _ in 0..60 {
        let [(x1, f1), (x2, f2), (x3, f3)] = t;
        if x3 - x1 < 2.0 * TOLERANCE {
            break;
        }
        // the vertex of the parabola through the three points
        let (p, q) = ((x2 - x1) * (f2 - f3), (x2 - x3) * (f2 - f1));
        let vertex = x2 - 0.5 * ((x2 - x1) * p - (x2 - x3) * q) / (p - q);
        let wide = if x3 - x2 > x2 - x1 { x3 } else { x1 };
        let mut x = if vertex.is_finite() && vertex > x1 && vertex < x3 {
            vertex
        } else {
            x2 + GOLDEN * (wide - x2)
        };
        if (x - x2).abs() < 0.5 * TOLERANCE {
            // a step below the tolerance: the minimum is found when V rises either side
            x = x2 + 0.5 * TOLERANCE * (wide - x2).signum();
        }
        let fx = f(x);
        t = if fx < f2 {
            if x < x2 {
                [(x1, f1), (x, fx), (x2, f2)]
            } else {
                [(x2, f2), (x, fx), (x3, f3)]
            }
        } else if x < x2 {
            [(x, fx), (x2, f2), (x3, f3)]
        } else {
            [(x1, f1), (x2, f2), (x, fx)]
        };
        if (x - x2).abs() <= 0.5 * TOLERANCE + f64::EPSILON {
            break;
        }
    }
    t[1]
}

/// The covariance of the profiled coefficients (SI) and every estimate's derivative along
/// them, from central differences of V and of the estimates about the minimum `u` (where V
/// is `f0`, as the search found it).
fn curvature(
    v: &mut dyn FnMut(&[f64]) -> Trial,
    u: &[f64],
    f0: f64,
    nb: usize,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let np = u.len();
    let h = CURVATURE_STEP;
    let fail = || "the filter fails beside the likelihood's minimum".to_string();
    let mut at = |d: &[(usize, f64)]| {
        let mut w = u.to_vec();
        for &(i, s) in d {
            w[i] += s * h;
        }
        v(&w).ok_or_else(fail)
    };
    let mut hess = nalgebra::DMatrix::<f64>::zeros(np, np);
    let mut gradient = vec![0.0; nb * np];
    for i in 0..np {
        let (fp, ep) = at(&[(i, 1.0)])?;
        let (fm, em) = at(&[(i, -1.0)])?;
        hess[(i, i)] = (fp - 2.0 * f0 + fm) / (h * h);
        let theta = u[i].exp();
        for b in 0..nb {
            gradient[b * np + i] = (ep[b] - em[b]) / (2.0 * h * theta);
        }
        for k in 0..i {
            let pp = at(&[(i, 1.0), (k, 1.0)])?.0;
            let pm = at(&[(i, 1.0), (k, -1.0)])?.0;
            let mp = at(&[(i, -1.0), (k, 1.0)])?.0;
            let mm = at(&[(i, -1.0), (k, -1.0)])?.0;
            hess[(i, k)] = (pp - pm - mp + mm) / (4.0 * h * h);
            hess[(k, i)] = hess[(i, k)];
        }
    }
    // cov(ln theta) = 2 H^-1 (V is -2 ln L); in SI, scaled by theta on both sides
    let inverse = hess
        .cholesky()
        .ok_or_else(|| "the likelihood has no curvature at its minimum".to_string())?
        .inverse();
    let mut covariance = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            covariance[i * np + k] = 2.0 * inverse[(i, k)] * u[i].exp() * u[k].exp();
        }
    }
    Ok((covariance, gradient))
}

/// Adds the profiled coefficients' uncertainty to `id`'s covariance and last sigmas: the
/// profiled coefficients get theirs, the others G cov(theta) G^T (the delta method), and a
/// tuning note says how the values were found.
pub fn widen(id: &mut Identification, p: &Profile, names: &[String]) {
    let nb = names.len();
    let np = p.at.len();
    // d estimate / d theta, exactly 1 for a profiled coefficient along itself
    let mut g = p.gradient.clone();
    for (i, &j) in p.at.iter().enumerate() {
        for k in 0..np {
            g[j * np + k] = f64::from(u8::from(i == k));
        }
    }
    for a in 0..nb {
        for b in 0..nb {
            let mut add = 0.0;
            for i in 0..np {
                for k in 0..np {
                    add += g[a * np + i] * p.covariance[i * np + k] * g[b * np + k];
                }
            }
            id.covariance[a * nb + b] += add;
        }
    }
    if let Some(last) = id.passes.last_mut() {
        for (a, s) in last.sigmas.iter_mut().enumerate() {
            *s = id.covariance[a * nb + a].max(0.0).sqrt();
        }
    }
    let found: Vec<String> =
        p.at.iter()
            .enumerate()
            .map(|(i, &j)| {
                format!(
                    "{} = {} +- {}",
                    names[j],
                    crate::base::numfmt::num(p.values[i]),
                    crate::base::numfmt::num(p.covariance[i * np + i].sqrt())
                )
            })
            .collect();
    id.calibration.push(format!(
        "disturbance model by the innovations' likelihood (prediction-error method, {} \
         identifications): {}, held in the filter; the sigma from the likelihood's curvature, \
         carried into the other estimates along the profile",
        p.evaluations,
        found.join(", ")
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_of_a_parabola_is_found_from_either_side() {
        for start in [-2.0, 0.3, 1.9, 4.0] {
            let mut calls = 0;
            let mut f = |x: f64| {
                calls += 1;
                3.0 * (x - 1.234).powi(2) + 7.0
            };
            let f0 = f(start);
            let (x, fx) = minimise(&mut f, start, f0).unwrap();
            assert!((x - 1.234).abs() < TOLERANCE, "{start}: {x}");
            assert!((fx - 7.0).abs() < 1e-5);
            assert!(calls < 25, "{calls} calls from {start}");
        }
    }

    #[test]
    fn a_likelihood_that_keeps_falling_is_not_determined() {
        let mut f = |x: f64| -x;
        assert!(minimise(&mut f, 0.0, 0.0).is_err());
    }

    #[test]
    fn a_failing_filter_beside_the_start_is_stepped_over() {
        // infinite (the filter diverged) above 0.5, minimum at 0.2
        let mut f = |x: f64| {
            if x > 0.5 {
                f64::INFINITY
            } else {
                (x - 0.2).powi(2)
            }
        };
        let f0 = f(0.45);
        let (x, _) = minimise(&mut f, 0.45, f0).unwrap();
        assert!((x - 0.2).abs() < TOLERANCE, "{x}");
    }

    #[test]
    fn two_coupled_parameters_and_their_covariance() {
        // V = 2 ln L of a Gaussian with covariance C: V = d^T C^-1 d
        let (c11, c12, c22) = (0.04, 0.01, 0.09);
        let det = c11 * c22 - c12 * c12;
        let (i11, i12, i22) = (c22 / det, -c12 / det, c11 / det);
        let m = [0.5f64.ln(), 2.0f64.ln()];
        let vf = |u: &[f64]| {
            let d = [u[0] - m[0], u[1] - m[1]];
            i11 * d[0] * d[0] + 2.0 * i12 * d[0] * d[1] + i22 * d[1] * d[1]
        };
        let mut u = vec![0.0, 0.0];
        descend(&mut |u| vf(u), &mut u).unwrap();
        assert!(
            (u[0] - m[0]).abs() < 0.01 && (u[1] - m[1]).abs() < 0.01,
            "{u:?}"
        );
        let mut v = |w: &[f64]| Some((vf(w), vec![w[0] + 3.0 * w[1]]));
        let (cov, g) = curvature(&mut v, &m, vf(&m), 1).unwrap();
        // cov(theta) = 2 H^-1 scaled; H = 2 C^-1, so cov(ln theta) = C
        let theta = [0.5, 2.0];
        assert!((cov[0] - c11 * theta[0] * theta[0]).abs() < 1e-9, "{cov:?}");
        assert!((cov[1] - c12 * theta[0] * theta[1]).abs() < 1e-9);
        assert!((cov[3] - c22 * theta[1] * theta[1]).abs() < 1e-9);
        // the estimate e = ln th1 + 3 ln th2: de/dth1 = 1/th1, de/dth2 = 3/th2
        assert!(
            (g[0] - 1.0 / theta[0]).abs() < 1e-3 && (g[1] - 1.5).abs() < 1e-3,
            "{g:?}"
        );
    }
}
