//! The identification loop: several passes of the hybrid EKF over one or more runs, each pass
//! restarting from the last estimate with the prior covariance, then a smoother pass.

use super::system::ModelSystem;
use crate::estimation::rts::Trace;
use crate::estimation::{Divergence, HybridEkf};
use crate::models::Model;
use crate::progress::Progress;
use crate::sim::InputSeries;

/// One run, ready for the filter.
#[derive(Debug, Clone)]
pub struct RunData {
    /// Name for messages and reports.
    pub name: String,
    /// Sample times, s.
    pub times: Vec<f64>,
    /// Indices of the measured states.
    pub measured: Vec<usize>,
    /// Measurements, K x m row-major (SI).
    pub y: Vec<f64>,
    /// Measurement noise variance of each measured state.
    pub r: Vec<f64>,
    /// Inputs over time.
    pub inputs: InputSeries,
    /// Initial state.
    pub x0: Vec<f64>,
    /// Initial state covariance (nx x nx).
    pub p0: Vec<f64>,
    /// 1-based file line of each sample (for messages).
    pub lines: Vec<usize>,
}

impl RunData {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// What the filter is told about the coefficients and the noise.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Full coefficient vector of the model with the fixed values.
    pub base: Vec<f64>,
    /// Indices of the estimated coefficients.
    pub est: Vec<usize>,
    /// Internal scale of each estimated coefficient (SI).
    pub scale: Vec<f64>,
    /// Initial value of each estimated coefficient (SI).
    pub initial: Vec<f64>,
    /// Prior standard deviation of each estimated coefficient (SI).
    pub prior_sigma: Vec<f64>,
    /// Process noise spectral density of the states (nx) and coefficients (nb, SI^2 / s).
    pub q: Vec<f64>,
    /// Filter passes.
    pub passes: usize,
    /// RK4 sub-steps per regular sample interval (for the report).
    pub substeps: usize,
    /// Longest RK4 step, s: every interval, a gap included, is integrated in steps no
    /// longer than this.
    pub max_step: f64,
    /// Run the smoother on the last pass.
    pub smoother: bool,
    /// Innovation gate in standard deviations (0: none).
    pub gate: f64,
    /// The first pass (0-based) the gate applies in: 1 from a cold start, whose first pass
    /// cannot predict the motion before the coefficients have converged; 0 when the passes
    /// start from a converged estimate.
    pub gate_from_pass: usize,
    /// Prior of passes after the first: at most this many times the previous pass's sigma
    /// (None: the configured prior every pass).
    pub repeat_prior_factor: Option<f64>,
}

/// Estimates after one pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PassEstimate {
    /// Coefficient values (SI), in `Setup::est` order.
    pub values: Vec<f64>,
    /// Standard deviations (SI).
    pub sigmas: Vec<f64>,
}

/// The filter's account of one run in one pass.
#[derive(Debug, Clone, Default)]
pub struct RunTrace {
    /// Sample times.
    pub times: Vec<f64>,
    /// Filtered states (K x nx).
    pub states: Vec<f64>,
    /// Smoothed states (K x nx), when the smoother ran.
    pub smoothed: Option<Vec<f64>>,
    /// Coefficient estimates over time (K x nb, SI).
    pub coefficients: Vec<f64>,
    /// Their standard deviations over time (K x nb, SI).
    pub sigmas: Vec<f64>,
    /// Innovations (K x m).
    pub innovations: Vec<f64>,
    /// Normalised innovation squared per sample.
    pub nis: Vec<f64>,
    /// Measurements the innovation gate rejected.
    pub rejected: Vec<Rejection>,
}

/// A measurement the innovation gate rejected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rejection {
    /// Sample index in the run.
    pub sample: usize,
    /// Index of the measured quantity (into `RunData::measured`).
    pub measurement: usize,
    /// Its innovation in standard deviations of the predicted spread.
    pub sigmas: f64,
}

/// Consecutive samples the gate may reject one quantity before the filter is taken to have
/// lost track of it (a burst of bad data or a model that cannot follow the run, not
/// isolated outliers).
pub const MAX_GATED_RUN: usize = 25;

/// Result of the identification.
#[derive(Debug, Clone)]
pub struct Identification {
    /// Estimates after each pass; the last is the answer.
    pub passes: Vec<PassEstimate>,
    /// Covariance of the estimated coefficients after the last pass (nb x nb, SI).
    pub covariance: Vec<f64>,
    /// Per pass, per run: the filter's trace.
    pub traces: Vec<Vec<RunTrace>>,
}

/// A failure, located by run and pass.
#[derive(Debug, Clone)]
pub struct IdentifyError {
    /// The run being filtered.
    pub run: String,
    /// The pass (1-based).
    pub pass: usize,
    /// What happened.
    pub divergence: Divergence,
}

/// Runs the passes.
pub fn identify<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    progress: &mut dyn Progress,
) -> Result<Identification, IdentifyError> {
    let nx = model.nx();
    let nb = setup.est.len();
    let n = nx + nb;
    let mut z: Vec<f64> = setup
        .initial
        .iter()
        .zip(&setup.scale)
        .map(|(v, s)| v / s)
        .collect();
    let mut pzz: Vec<f64> = setup
        .prior_sigma
        .iter()
        .zip(&setup.scale)
        .map(|(p, s)| (p / s).powi(2))
        .collect();
    let mut q = setup.q.clone();
    for j in 0..nb {
        q[nx + j] /= setup.scale[j] * setup.scale[j];
    }
    let mut passes = Vec::new();
    let mut traces = Vec::new();
    let mut covariance = vec![0.0; nb * nb];
    let total: usize = runs.iter().map(RunData::len).sum();
    for pass in 0..setup.passes {
        let smooth = setup.smoother && pass + 1 == setup.passes;
        let mut done = 0;
        let mut filter: Option<HybridEkf> = None;
        let mut pass_traces = Vec::new();
        for run in runs {
            let fail = |divergence| IdentifyError {
                run: run.name.clone(),
                pass: pass + 1,
                divergence,
            };
            let mut sys = ModelSystem::new(
                model,
                setup.base.clone(),
                &setup.est,
                &setup.scale,
                &run.inputs,
                &run.measured,
            );
            if let Some(f) = filter.as_mut() {
                f.restart_dynamic(&run.x0, &run.p0);
            } else {
                let mut x = run.x0.clone();
                x.extend_from_slice(&z);
                let mut p = vec![0.0; n * n];
                for i in 0..nx {
                    for j in 0..nx {
                        p[i * n + j] = run.p0[i * nx + j];
                    }
                }
                for j in 0..nb {
                    p[(nx + j) * n + nx + j] = pzz[j];
                }
                filter = Some(HybridEkf::new(n, nx, x, p, q.clone(), setup.max_step));
            }
            let f = filter.as_mut().expect("created above");
            f.gate = if pass >= setup.gate_from_pass {
                setup.gate
            } else {
                0.0
            };
            let mut gated_run = vec![0usize; run.measured.len()];
            let k_len = run.len();
            let m = run.measured.len();
            let mut tr = RunTrace {
                times: run.times.clone(),
                ..Default::default()
            };
            let mut smoother = smooth.then(|| Trace::new(n));
            let mut phi = vec![0.0; n * n];
            for k in 0..k_len {
                let t = run.times[k];
                if k > 0 {
                    let want_phi = smoother.is_some();
                    f.predict(
                        &mut sys,
                        run.times[k - 1],
                        t,
                        want_phi.then_some(phi.as_mut_slice()),
                    )
                    .map_err(fail)?;
                }
                if let Some(s) = smoother.as_mut() {
                    s.t.push(t);
                    s.x_prior.extend_from_slice(&f.x);
                    s.p_prior.extend_from_slice(&f.p);
                    if k == 0 {
                        s.phi.extend(std::iter::repeat_n(0.0, n * n));
                    } else {
                        s.phi.extend_from_slice(&phi);
                    }
                }
                let nis = f
                    .update(&mut sys, t, &run.y[k * m..(k + 1) * m], &run.r)
                    .map_err(fail)?;
                track_gate(f.rejected(), k, &mut gated_run, &mut tr.rejected)
                    .map_err(|a| fail(lost_track(model, run, a, k)))?;
                if let Some(s) = smoother.as_mut() {
                    s.x_post.extend_from_slice(&f.x);
                    s.p_post.extend_from_slice(&f.p);
                }
                tr.states.extend_from_slice(&f.x[..nx]);
                for j in 0..nb {
                    tr.coefficients.push(f.x[nx + j] * setup.scale[j]);
                    tr.sigmas
                        .push(f.p[(nx + j) * n + nx + j].max(0.0).sqrt() * setup.scale[j]);
                }
                tr.innovations.extend_from_slice(f.innovation());
                tr.nis.push(nis);
                done += 1;
                if done % 250 == 0 || done == total {
                    progress.filter(pass + 1, setup.passes, done, total);
                }
            }
            if let Some(&t_end) = run.times.last() {
                f.check_covariance(t_end).map_err(fail)?;
            }
            if let Some(s) = smoother {
                let (xs, _) = s.smooth().map_err(|k| {
                    fail(Divergence {
                        time: run.times[k],
                        reason: "the smoother met a predicted covariance that is not \
                                 positive definite"
                            .into(),
                    })
                })?;
                let mut states = Vec::with_capacity(k_len * nx);
                for k in 0..k_len {
                    states.extend_from_slice(&xs[k * n..k * n + nx]);
                }
                tr.smoothed = Some(states);
            }
            pass_traces.push(tr);
        }
        let f = filter.expect("at least one run");
        z.copy_from_slice(&f.x[nx..]);
        let values: Vec<f64> = z.iter().zip(&setup.scale).map(|(v, s)| v * s).collect();
        let sigmas: Vec<f64> = (0..nb)
            .map(|j| f.p[(nx + j) * n + nx + j].max(0.0).sqrt() * setup.scale[j])
            .collect();
        for a in 0..nb {
            for b in 0..nb {
                covariance[a * nb + b] =
                    f.p[(nx + a) * n + nx + b] * setup.scale[a] * setup.scale[b];
            }
        }
        if let Some(f) = setup.repeat_prior_factor {
            // The next pass starts from this estimate with a prior no wider than f times this
            // pass's sigma: (1/f^2 of the data's information, nothing for f = 100) but enough
            // to keep its first samples from throwing the estimate far from here.
            for j in 0..nb {
                pzz[j] = pzz[j].min((f * sigmas[j] / setup.scale[j]).powi(2));
            }
        }
        passes.push(PassEstimate { values, sigmas });
        traces.push(pass_traces);
    }
    Ok(Identification {
        passes,
        covariance,
        traces,
    })
}

/// Records the gate's rejections at sample `k` and counts consecutive ones per quantity;
/// fails with the quantity's index when one has been rejected [`MAX_GATED_RUN`] times in a row.
fn track_gate(
    rejected: &[(usize, f64)],
    k: usize,
    run_length: &mut [usize],
    out: &mut Vec<Rejection>,
) -> Result<(), usize> {
    for (a, len) in run_length.iter_mut().enumerate() {
        match rejected.iter().find(|(i, _)| *i == a) {
            Some(&(_, sigmas)) => {
                *len += 1;
                out.push(Rejection {
                    sample: k,
                    measurement: a,
                    sigmas,
                });
                if *len >= MAX_GATED_RUN {
                    return Err(a);
                }
            }
            None => *len = 0,
        }
    }
    Ok(())
}

/// The divergence of a filter that the gate has cut off from quantity `a` of `run`.
fn lost_track<M: Model>(model: &M, run: &RunData, a: usize, k: usize) -> Divergence {
    let q = model.states()[run.measured[a]].quantity;
    let first = k + 1 - MAX_GATED_RUN;
    Divergence {
        time: run.times[k],
        reason: format!(
            "the filter lost track of {q}: the innovation gate rejected it at {MAX_GATED_RUN} \
             samples in a row (lines {}-{}), so these are not isolated outliers but a model \
             that cannot follow the run there (a wrong input, fixed coefficient, unit or \
             frame) or a stretch of bad data",
            run.lines.get(first).copied().unwrap_or(0),
            run.lines.get(k).copied().unwrap_or(0)
        ),
    }
}
