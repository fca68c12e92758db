//! The identification loop: several passes of the hybrid EKF over one or more runs, each pass
//! restarting from the last estimate with the prior covariance, then a smoother pass.

use super::system::ModelSystem;
use crate::estimation::hybrid_ekf::GateEvent;
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
    /// Measurements the innovation gate rejected as outliers.
    pub rejected: Vec<Rejection>,
    /// Stretches where a quantity stayed beyond the gate (its measurements were used).
    pub excursions: Vec<Excursion>,
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

/// Consecutive samples one quantity may lie beyond the gate and still be taken for outliers.
/// A longer stretch is the model departing from the data (after a gap, at a step input, a
/// wrong input or coefficient): rejecting it would cut the filter off from the run, so the
/// filter uses those measurements again and the stretch is reported as an excursion.
pub const MAX_OUTLIER_RUN: usize = 3;

/// A stretch of samples where one quantity's innovations lay beyond the gate (and were used).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Excursion {
    /// Index of the measured quantity (into `RunData::measured`).
    pub measurement: usize,
    /// First and last sample of the stretch.
    pub first: usize,
    /// Last sample.
    pub last: usize,
    /// Largest innovation in standard deviations.
    pub peak: f64,
}

/// Turns the gate's events into isolated rejections and excursions, sample by sample, and
/// exempts a quantity from the gate while it is in an excursion.
struct GateTracker {
    streak: Vec<usize>,
    open: Vec<Option<Excursion>>,
}

impl GateTracker {
    fn new(m: usize) -> Self {
        GateTracker {
            streak: vec![0; m],
            open: vec![None; m],
        }
    }

    fn step(&mut self, k: usize, events: &[GateEvent], ungated: &mut [bool], tr: &mut RunTrace) {
        for a in 0..self.streak.len() {
            let ev = events.iter().find(|e| e.measurement == a);
            if let Some(x) = self.open[a].as_mut() {
                match ev {
                    Some(e) => {
                        x.last = k;
                        x.peak = x.peak.max(e.sigmas);
                    }
                    None => {
                        tr.excursions.push(*x);
                        self.open[a] = None;
                        ungated[a] = false;
                    }
                }
                continue;
            }
            let Some(e) = ev else {
                self.streak[a] = 0;
                continue;
            };
            self.streak[a] += 1;
            tr.rejected.push(Rejection {
                sample: k,
                measurement: a,
                sigmas: e.sigmas,
            });
            if self.streak[a] >= MAX_OUTLIER_RUN {
                // not outliers: an excursion from the first of them on
                let first = k + 1 - self.streak[a];
                let mut peak: f64 = 0.0;
                tr.rejected.retain(|r| {
                    let mine = r.measurement == a && r.sample >= first;
                    if mine {
                        peak = peak.max(r.sigmas);
                    }
                    !mine
                });
                self.open[a] = Some(Excursion {
                    measurement: a,
                    first,
                    last: k,
                    peak,
                });
                self.streak[a] = 0;
                ungated[a] = true;
            }
        }
    }

    /// Closes the excursions still open at the end of a run.
    fn finish(self, tr: &mut RunTrace) {
        tr.excursions.extend(self.open.into_iter().flatten());
    }
}

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
            f.ungated = vec![false; run.measured.len()];
            let mut gate = GateTracker::new(run.measured.len());
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
                let events = f.beyond_gate().to_vec();
                gate.step(k, &events, &mut f.ungated, &mut tr);
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
            gate.finish(&mut tr);
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
