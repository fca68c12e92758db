//! A candidate captive run as the captive stage fits it: a steady condition (static drift,
//! rudder, circular motion) as the mean of its force histories, a PMM run as the Fourier parts
//! of its forces over whole periods ([`crate::stages::captive::harmonic`]); the model's values
//! and their sensitivities to the coefficients by automatic differentiation of
//! [`Model::captive_forces`], each value's noise from the per-sample noise of its force
//! (white noise over N samples: a mean sigma / sqrt(N), a Fourier cosine or sine part
//! sigma sqrt(2 / N); Bendat & Piersol 2010, section 11.1).

use super::candidate::{Candidate, Kind};
use super::prior::{Operating, Prior};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::model::models::Model;
use crate::stages::captive::fit::Condition;
use crate::stages::captive::harmonic::{whole_periods, HarmonicMotion, MIN_PERIODS, PER_FORCE};
use nalgebra::DMatrix;

/// Default per-sample force noise as a share of the dynamic-pressure force
/// 0.5 rho U^2 A_ref (moments times the length): about what the bundled PMM and captive
/// exports carry (0.2 N on the spheroid's 64 N at 2 m/s, 2 N on the KVLCC2's 1.8 kN).
pub const FORCE_NOISE_SHARE: f64 = 0.003;

/// Default captive duration, s, and sample interval, s.
pub const DURATION: f64 = 10.0;
/// Default captive sample interval, s.
pub const DT: f64 = 0.01;

/// The reference scales of the default force noise: rho, A_ref, length.
#[derive(Debug, Clone, Copy)]
pub struct ForceScale {
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Reference area, m^2.
    pub area: f64,
    /// Length (moment arm of the moment noise), m.
    pub length: f64,
}

/// A captive candidate's measured values: the condition (at the model's prediction) with the
/// noise of each value.
pub fn condition<M: Model>(
    model: &M,
    prior: &Prior,
    op: &Operating,
    c: &Candidate,
    scale: ForceScale,
) -> Result<Condition> {
    if model.force_quantities().is_empty() {
        return Err(Error::Usage(format!(
            "candidate '{}': the {} model gives no captive forces",
            c.name,
            model.name()
        )));
    }
    let speed = c.speed.unwrap_or(op.speed);
    let nx = model.nx();
    let at = |q: Quantity| model.state_index(q);
    let mut u = op.u0.clone();
    if let Some(i) = model
        .input_quantities()
        .iter()
        .position(|q| *q == Quantity::Rudder)
    {
        u[i] = c.rudder_deg.to_radians();
    } else if c.rudder_deg != 0.0 {
        return Err(Error::Usage(format!(
            "candidate '{}': the {} model has no rudder",
            c.name,
            model.name()
        )));
    }
    let (iu, iv, ir) = match (at(Quantity::U), at(Quantity::V), at(Quantity::R)) {
        (Some(a), Some(b), Some(c)) => (a, b, c),
        _ => {
            return Err(Error::Usage(format!(
                "candidate '{}': the {} model has no u, v and r states",
                c.name,
                model.name()
            )))
        }
    };
    let beta = c.drift_deg.to_radians();
    let mut x = vec![0.0; nx];
    // drift angle beta = -atan(v / u) (Yasukawa & Yoshimura 2015, section 2.1)
    x[iu] = speed * beta.cos();
    x[iv] = -speed * beta.sin();
    x[ir] = c.yaw_rate_deg_s.to_radians();
    let harmonic = match c.kind {
        Kind::PmmSway | Kind::PmmYaw => {
            let mut states = vec![[0.0; 3]; nx];
            states[iu] = [speed, 0.0, 0.0];
            match c.kind {
                Kind::PmmSway => states[iv] = [0.0, 0.0, c.amplitude],
                _ => states[ir] = [0.0, 0.0, c.amplitude.to_radians()],
            }
            Some(HarmonicMotion {
                omega: 2.0 * std::f64::consts::PI * c.frequency_hz,
                states,
            })
        }
        _ => None,
    };
    let fit = fitted(model, c, speed, scale);
    let samples = fit.samples as f64;
    let per_sample: Vec<f64> = fit.noise.iter().map(|n| n.sigma).collect();
    let mut cond = Condition {
        x,
        u,
        f: Vec::new(),
        sigma: None,
        place: c.name.clone(),
        harmonic,
    };
    let m = per_sample.len()
        * if cond.harmonic.is_some() {
            PER_FORCE
        } else {
            1
        };
    let mut f = vec![0.0; m];
    cond.predict(model, &prior.base, &mut f);
    let sigma = (0..m)
        .map(|k| {
            let s = per_sample[cond.component(k)];
            let first = cond.harmonic.is_none() || k % PER_FORCE == 0;
            if first {
                s / samples.sqrt()
            } else {
                s * (2.0 / samples).sqrt()
            }
        })
        .collect();
    cond.f = f;
    cond.sigma = Some(sigma);
    Ok(cond)
}

/// What the captive stage fits of a candidate, as the plan assumed it (the table and
/// plan.json print it).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Fitted {
    /// The run's duration, s (given, or the default: [`duration`]).
    pub duration_s: f64,
    /// Samples the stage fits: every sample of a steady condition, those of a PMM run's whole
    /// periods only.
    pub samples: usize,
    /// A PMM run's whole periods (the stage leaves an incomplete last period out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periods: Option<usize>,
    /// Per-sample noise of each force component, in the model's order.
    pub noise: Vec<ForceNoise>,
}

/// One force component's per-sample noise as the plan assumed it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ForceNoise {
    /// The component's quantity key (`fx`, `fy`, `mz` ...).
    pub quantity: &'static str,
    /// Standard deviation per sample, SI.
    pub sigma: f64,
    /// Its SI unit (N, N m).
    pub unit: &'static str,
    /// True when it is the default share of the dynamic-pressure force
    /// ([`FORCE_NOISE_SHARE`]), not the candidate's `noise`.
    pub default: bool,
}

/// A captive candidate's duration, s: the given one; else [`DURATION`], and for a PMM run at
/// least [`MIN_PERIODS`] + 1 periods (a ship-scale PMM period is tens of seconds).
pub fn duration(c: &Candidate) -> f64 {
    c.duration_s.unwrap_or_else(|| {
        if c.kind.is_pmm() && c.frequency_hz > 0.0 {
            DURATION.max(((MIN_PERIODS + 1) as f64 / c.frequency_hz).ceil())
        } else {
            DURATION
        }
    })
}

/// The samples, periods and per-sample noise of candidate `c` at `speed`: a PMM run's whole
/// periods only, as the stage takes them (`harmonic::reduce`); each force's noise the
/// candidate's, else the default share of the dynamic-pressure force (times the length for a
/// moment).
pub fn fitted<M: Model>(model: &M, c: &Candidate, speed: f64, s: ForceScale) -> Fitted {
    let duration_s = duration(c);
    let dt = c.dt_s.unwrap_or(DT);
    let pmm = c.kind.is_pmm() && c.frequency_hz > 0.0;
    // the whole periods of the record, counted as the captive stage counts them
    let periods = pmm.then(|| whole_periods(duration_s, 1.0 / c.frequency_hz));
    let fitted_s = periods.map_or(duration_s, |n| n as f64 / c.frequency_hz);
    let samples = ((fitted_s / dt) + 1e-6).floor().max(1.0) as usize;
    let force = FORCE_NOISE_SHARE * 0.5 * s.rho * speed * speed * s.area;
    let noise = model
        .force_quantities()
        .iter()
        .map(|&q| {
            let moment = matches!(q, Quantity::Mx | Quantity::My | Quantity::Mz);
            let given = c.noise.get(q.key()).map(|n| n.si);
            ForceNoise {
                quantity: q.key(),
                sigma: given.unwrap_or(if moment { force * s.length } else { force }),
                unit: q.si_symbol(),
                default: given.is_none(),
            }
        })
        .collect();
    Fitted {
        duration_s,
        samples,
        periods,
        noise,
    }
}

/// The model's values of a condition at coefficients `theta` (the parameters of `prior`) and
/// their sensitivities (m x p) by automatic differentiation.
pub fn values_and_jacobian<M: Model>(
    model: &M,
    prior: &Prior,
    cond: &Condition,
    theta: &[f64],
) -> (Vec<f64>, DMatrix<f64>) {
    let (value, jac) = cond.values_and_jacobian(model, &prior.base, &prior.est, theta);
    (
        value,
        DMatrix::from_row_slice(cond.f.len(), theta.len(), &jac),
    )
}

/// Zeroes the sensitivities to the parameters `unused` marks: those the HEKF estimates from
/// its own prior in consider mode (`hekf.mode = "consider"`, docs/hekf.md), whose final
/// values take nothing from a captive run. The run's information then reaches them only
/// through their covariance with the coefficients the HEKF holds at the captive values (the
/// consider analysis's share of their sigmas; Bierman 1977, ch. 7).
pub fn drop_unused(j: &mut DMatrix<f64>, unused: &[bool]) {
    for (col, _) in unused.iter().enumerate().filter(|(_, u)| **u) {
        if col < j.ncols() {
            j.column_mut(col).fill(0.0);
        }
    }
}

/// The posterior covariance after a captive candidate, the information on the parameters
/// `unused` marks left out ([`drop_unused`]; none when empty).
pub fn posterior<M: Model>(
    model: &M,
    prior: &Prior,
    cond: &Condition,
    unused: &[bool],
) -> Result<DMatrix<f64>> {
    let theta = prior.values();
    let (_, mut j) = values_and_jacobian(model, prior, cond, &theta);
    drop_unused(&mut j, unused);
    let sigma = cond.sigma.clone().unwrap_or_default();
    let info = super::information::fisher(&j, &sigma);
    super::information::posterior(&prior.cov, &info).ok_or_else(|| {
        Error::numerical(
            "plan",
            format!("candidate '{}': singular update", cond.place),
        )
    })
}
