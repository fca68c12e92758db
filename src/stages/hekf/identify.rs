//! The identification loop: several passes of the hybrid EKF over one or more runs, each pass
//! restarting from the last estimate with the prior covariance, then a smoother pass.
//!
//! Memory: a pass keeps per sample only what the report shows of the last pass (times,
//! filtered and smoothed states, NIS); the coefficient histories are thinned
//! ([`super::history`]), the innovation statistics summed as the samples come, and the
//! smoother re-runs the filter from checkpoints instead of keeping its covariances
//! ([`crate::numerics::estimation::rts`]). The last pass's state series (states, sigmas,
//! innovations, coefficients at every sample) goes to a temporary file as it is computed
//! ([`super::states`]).

use super::bounds::{BoundLog, BoundSummary, Bounds};
use super::history::{History, HistoryBuilder};
use crate::base::progress::{Progress, Silent};
use crate::dynamics::model_system::ModelSystem;
use crate::dynamics::sim::InputSeries;
use crate::model::models::{Model, Range};
use crate::numerics::estimation::hybrid_ekf::GateEvent;
use crate::numerics::estimation::rts::{self, SmoothError, Trace};
use crate::numerics::estimation::{Divergence, FilterKind, HybridEkf};

/// One run, ready for the filter.
#[derive(Debug, Clone)]
pub struct RunData {
    /// Name for messages and reports.
    pub name: String,
    /// Sample times, s.
    pub times: Vec<f64>,
    /// Indices of the measured outputs ([`Model::output_quantities`]; the states' for a model
    /// whose outputs are its states).
    pub measured: Vec<usize>,
    /// Measurements, K x m row-major (SI).
    pub y: Vec<f64>,
    /// Measurement noise variance of each measured output.
    pub r: Vec<f64>,
    /// Rounding variance of each measurement (K x m, row-major), added to `r` at its sample;
    /// empty when the run is printed finely.
    pub rounding: Vec<f64>,
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

    /// Keeps every `n`-th sample, starting with the first (`hekf.decimate`): the times and
    /// the measurements are thinned; the inputs (read at any time), the initial state and
    /// the measurement noise (per sample) stay as they are; the file lines follow the samples.
    pub fn decimate(&mut self, n: usize) {
        if n <= 1 {
            return;
        }
        let m = self.measured.len();
        let kept = self.times.len().div_ceil(n);
        for j in 0..kept {
            self.times[j] = self.times[j * n];
            self.y.copy_within(j * n * m..(j * n + 1) * m, j * m);
            if !self.rounding.is_empty() {
                self.rounding.copy_within(j * n * m..(j * n + 1) * m, j * m);
            }
            if let Some(&line) = self.lines.get(j * n) {
                self.lines[j] = line;
            }
        }
        self.lines.truncate(kept);
        self.lines.shrink_to_fit();
        self.times.truncate(kept);
        self.times.shrink_to_fit();
        self.y.truncate(kept * m);
        self.y.shrink_to_fit();
        if !self.rounding.is_empty() {
            self.rounding.truncate(kept * m);
            self.rounding.shrink_to_fit();
        }
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
    /// Admissible range of each estimated coefficient (SI), kept by projection
    /// ([`super::bounds`]); empty: none bounded.
    pub ranges: Vec<Range>,
    /// Prior correlations of the estimated coefficients (nb x nb, row-major); empty when
    /// they are uncorrelated (every prior but an earlier stage's in `hekf.mode = "joint"`).
    pub prior_correlation: Vec<f64>,
    /// Coefficients whose prior is an earlier stage's estimate (`hekf.mode = "joint"`): each
    /// pass starts them from that prior again, so that its information counts once.
    pub held_prior: Vec<bool>,
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
    /// The form of the filter (`hekf.filter`); the continuous form runs without smoother.
    pub filter: FilterKind,
    /// States (nx) whose process noise is matched to the innovations run by run
    /// (`super::adapt`); none for a preset or configured process noise.
    pub adaptable: Vec<bool>,
    /// Per run, the states' process noise densities (nx) to use instead of `q`'s (the
    /// calibrated noise, for repeated passes); empty: `q` for every run.
    pub run_q: Vec<Vec<f64>>,
    /// Factor on every noise variance, measurement and state process noise alike (1; the
    /// noise-model sensitivity repeats a pass at 1/4 and 4, the sigmas halved and doubled).
    pub noise_scale: f64,
}

impl Setup {
    /// The prior covariance of the estimated coefficients (nb x nb, row-major) with each
    /// coefficient in units of `unit` (SI: ones): the prior sigmas with the prior
    /// correlations (none: uncorrelated).
    pub fn prior_covariance(&self, unit: &[f64]) -> Vec<f64> {
        let nb = self.prior_sigma.len();
        let sd: Vec<f64> = self
            .prior_sigma
            .iter()
            .zip(unit)
            .map(|(p, s)| p / s)
            .collect();
        let mut cov = vec![0.0; nb * nb];
        for a in 0..nb {
            for b in 0..nb {
                let rho = match self.prior_correlation.get(a * nb + b) {
                    Some(r) => *r,
                    None => f64::from(u8::from(a == b)),
                };
                cov[a * nb + b] = rho * sd[a] * sd[b];
            }
        }
        cov
    }
}

/// Process noise adding less than this share of a state's measurement variance per sample
/// is none: the data cannot tell it from none.
const NEGLIGIBLE: f64 = 0.01;

/// Passes the noise calibration may add to the configured ones.
pub const MAX_CALIBRATION_PASSES: usize = 6;

/// A calibration that changes no density by more than this factor has converged.
const CONVERGED_FACTOR: f64 = 2.0;

/// Estimates after one pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PassEstimate {
    /// Coefficient values (SI), in `Setup::est` order.
    pub values: Vec<f64>,
    /// Standard deviations (SI).
    pub sigmas: Vec<f64>,
}

/// The filter's account of one run in one pass. The coefficient history is kept for every
/// pass; the per-sample fields only for the last pass (empty in the others).
#[derive(Debug, Clone, Default)]
pub struct RunTrace {
    /// Sample times.
    pub times: Vec<f64>,
    /// Filtered states (K x nx).
    pub states: Vec<f64>,
    /// Smoothed states (K x nx), when the smoother ran.
    pub smoothed: Option<Vec<f64>>,
    /// Coefficient estimates and sigmas over time (SI), thinned for drawing.
    pub history: History,
    /// Samples filtered.
    pub samples: usize,
    /// Sum over the samples of each squared innovation (per measured quantity).
    pub innovation_squares: Vec<f64>,
    /// Normalised innovation squared per sample.
    pub nis: Vec<f64>,
    /// The innovations' -2 log-likelihood over the run, less its constant: the sum over the
    /// samples of NIS + ln det S.
    pub neg_log_likelihood: f64,
    /// Measurements the innovation gate rejected as outliers.
    pub rejected: Vec<Rejection>,
    /// Stretches where a quantity stayed beyond the gate (its measurements were used).
    pub excursions: Vec<Excursion>,
    /// Every sample's row of the state series, spooled to a temporary file (the last pass;
    /// [`super::states`]).
    pub spool: Option<super::states::Spool>,
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

/// What the gate found in a run: isolated rejections and excursions.
#[derive(Debug, Clone, Default)]
struct GateLog {
    rejected: Vec<Rejection>,
    excursions: Vec<Excursion>,
}

/// Turns the gate's events into isolated rejections and excursions, sample by sample, and
/// exempts a quantity from the gate while it is in an excursion. Its state is small and is
/// saved with the smoother's checkpoints, so that the re-run gates exactly as the forward
/// pass did.
#[derive(Debug, Clone)]
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

    fn step(&mut self, k: usize, events: &[GateEvent], ungated: &mut [bool], log: &mut GateLog) {
        for a in 0..self.streak.len() {
            let ev = events.iter().find(|e| e.measurement == a);
            if let Some(x) = self.open[a].as_mut() {
                match ev {
                    Some(e) => {
                        x.last = k;
                        x.peak = x.peak.max(e.sigmas);
                    }
                    None => {
                        log.excursions.push(*x);
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
            log.rejected.push(Rejection {
                sample: k,
                measurement: a,
                sigmas: e.sigmas,
            });
            if self.streak[a] >= MAX_OUTLIER_RUN {
                // not outliers: an excursion from the first of them on
                let first = k + 1 - self.streak[a];
                let mut peak: f64 = 0.0;
                log.rejected.retain(|r| {
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
    fn finish(self, log: &mut GateLog) {
        log.excursions.extend(self.open.into_iter().flatten());
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
    /// Per run, the states' process noise densities of the last pass (calibrated when the
    /// setup adapts them).
    pub process_noise: Vec<Vec<f64>>,
    /// What the noise calibration did, for the report (empty when it did nothing).
    pub calibration: Vec<String>,
    /// Per estimated coefficient, what its admissible range did (empty: none bounded).
    pub bounds: Vec<BoundSummary>,
    /// The innovations' -2 log-likelihood over every run of the last pass, less its
    /// constant ([`RunTrace::neg_log_likelihood`]).
    pub neg_log_likelihood: f64,
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
    /// The estimated coefficients (`Setup::est` order) the filter had held at their bounds
    /// in this run before it failed, with the number of samples: an estimate that kept
    /// hitting its admissible range.
    pub at_bounds: Vec<(usize, usize)>,
}

/// The model's coefficient vector: `base` with the estimated coefficients (indices `est`)
/// at `values`, the model's relations applied.
pub fn completed<M: Model>(model: &M, base: &[f64], est: &[usize], values: &[f64]) -> Vec<f64> {
    let mut c = base.to_vec();
    for (&i, &v) in est.iter().zip(values) {
        c[i] = v;
    }
    model.relations().apply(&mut c);
    c
}

/// Runs the passes, keeping the traces the report draws.
pub fn identify<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    progress: &mut dyn Progress,
) -> Result<Identification, IdentifyError> {
    passes(model, setup, runs, progress, true)
}

/// Runs the passes and keeps the estimates only (no traces, no smoother): the repeated
/// identifications of the consider analysis.
pub fn estimates<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
) -> Result<Vec<PassEstimate>, IdentifyError> {
    silent_passes(model, setup, runs).map(|id| id.passes)
}

/// The last pass of [`estimates`] with its coefficients' covariance (nb x nb, row-major, SI).
pub fn last_estimate<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
) -> Result<(PassEstimate, Vec<f64>), IdentifyError> {
    let mut id = silent_passes(model, setup, runs)?;
    let last = id.passes.pop().expect("at least one pass");
    Ok((last, id.covariance))
}

/// The last pass's estimates (SI), the runs' process noise and the innovations' -2
/// log-likelihood over the last pass ([`Identification::neg_log_likelihood`]): one point
/// of a profile likelihood (`stages::hekf::likelihood`).
pub fn profile_point<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
) -> Result<(PassEstimate, Vec<Vec<f64>>, f64), IdentifyError> {
    let mut id = silent_passes(model, setup, runs)?;
    let last = id.passes.pop().expect("at least one pass");
    Ok((last, id.process_noise, id.neg_log_likelihood))
}

/// The passes without traces, smoother or progress.
fn silent_passes<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
) -> Result<Identification, IdentifyError> {
    let setup = Setup {
        smoother: false,
        ..setup.clone()
    };
    passes(model, &setup, runs, &mut Silent, false)
}

fn passes<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    progress: &mut dyn Progress,
    keep_traces: bool,
) -> Result<Identification, IdentifyError> {
    let nx = model.nx();
    let nb = setup.est.len();
    let mut prior = ScaledPrior::new(setup, nx);
    let mut cal = Calibration::new(setup, runs, nx);
    cal.update(model, setup, runs, &setup.initial, 0);
    let bounds = Bounds::new(&setup.ranges, &setup.scale, nx);
    let unbounded = Bounds::new(&[], &setup.scale, nx);
    let mut bound_summary = vec![BoundSummary::default(); nb];
    let mut passes = Vec::new();
    let mut traces = Vec::new();
    let mut covariance = vec![0.0; nb * nb];
    let mut counter = PassProgress {
        progress,
        passes: setup.passes,
        pass: 0,
        done: 0,
        total: runs.iter().map(RunData::len).sum(),
    };
    let mut pass = 0;
    let mut neg_log_likelihood;
    loop {
        let last_pass = cal.is_last(pass, setup.passes);
        let keep = Keep {
            samples: keep_traces && last_pass,
            history: keep_traces,
            // the continuous (Kalman-Bucy) filter has no transition matrix to smooth with
            smooth: setup.smoother && last_pass && setup.filter != FilterKind::Continuous,
        };
        counter.pass = pass + 1;
        counter.passes = counter.passes.max(pass + 1);
        counter.done = 0;
        let gate_on = pass >= cal.cold_pass + setup.gate_from_pass;
        // a cold pass that others follow finds its way from the prior unbounded, as it runs
        // ungated: only its end is brought into range, where the next pass starts
        let cold = pass == cal.cold_pass && !last_pass;
        let outcome = one_pass(
            model,
            setup,
            runs,
            (&prior, if cold { &unbounded } else { &bounds }),
            &cal.q,
            (keep, gate_on),
            &mut counter,
        );
        let (f, pass_traces, logs) = match outcome {
            Ok(done) => done,
            // a noise model too tight for the data: widen it and start again (not a failure
            // at a run's first sample, before any noise has acted: the model or the priors),
            // in the last pass too (a single configured pass, whose divergence was an error)
            Err(e) if after_first_sample(&e, runs) && cal.widen(runs) => {
                prior = ScaledPrior::new(setup, nx);
                cal.note_divergence(&e, pass);
                pass += 1;
                continue;
            }
            Err(e) => return Err(e),
        };
        neg_log_likelihood = pass_traces.iter().map(|t| t.neg_log_likelihood).sum();
        let summary = pass_summary(&f, setup, &mut prior, &mut covariance);
        bounds.clamp(&mut prior.z, None);
        summarise_bounds(&mut bound_summary, &logs);
        if !last_pass {
            // the noise is calibrated with the estimate the next pass starts from
            let mut start = summary.values.clone();
            bounds.clamp(&mut start, Some(&setup.scale));
            cal.update(model, setup, runs, &start, pass + 1);
        }
        passes.push(summary);
        if keep_traces {
            traces.push(pass_traces);
        }
        if last_pass {
            break;
        }
        pass += 1;
    }
    if bounds.any() {
        cal.notes.extend(bound_notes(model, setup, &bound_summary));
    }
    Ok(Identification {
        passes,
        covariance,
        traces,
        process_noise: cal.q,
        calibration: cal.notes,
        bounds: if bounds.any() {
            bound_summary
        } else {
            Vec::new()
        },
        neg_log_likelihood,
    })
}

/// The tuning notes of the coefficients held at their bounds on the way
/// ([`super::bounds::notes`]).
fn bound_notes<M: Model>(model: &M, setup: &Setup, summary: &[BoundSummary]) -> Vec<String> {
    let all = model.coefficient_names();
    let names: Vec<&str> = setup.est.iter().map(|&i| all[i]).collect();
    let defs: Vec<&crate::model::models::CoefDef> = setup
        .est
        .iter()
        .map(|&i| &model.coefficients()[i])
        .collect();
    super::bounds::notes(&names, &defs, summary)
}

/// Adds one pass's bound logs (one per run) to the summary: the counts are the pass's (the
/// last pass's remain), the passes ending at a bound accumulate.
fn summarise_bounds(summary: &mut [BoundSummary], logs: &[BoundLog]) {
    for (j, s) in summary.iter_mut().enumerate() {
        s.hits = logs.iter().map(|l| l.hits[j]).sum();
        s.samples = logs.iter().map(|l| l.samples).sum();
        s.at_end = logs.last().is_some_and(|l| l.at_end(j));
        s.passes_at_end += usize::from(s.at_end);
        s.total_hits += s.hits;
    }
}

/// One pass over every run with the runs' process noise `q`: the filter after the last run
/// and each run's trace.
fn one_pass<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    (prior, bounds): (&ScaledPrior, &Bounds),
    q: &[Vec<f64>],
    (keep, gate_on): (Keep, bool),
    counter: &mut PassProgress<'_>,
) -> Result<(HybridEkf, Vec<RunTrace>, Vec<BoundLog>), IdentifyError> {
    let mut filter: Option<HybridEkf> = None;
    let mut pass_traces = Vec::new();
    let mut logs = Vec::new();
    let pass = counter.pass;
    for (run, q_run) in runs.iter().zip(q) {
        let mut log = BoundLog::new(setup.est.len(), run.len());
        let fail = |divergence, log: &BoundLog| IdentifyError {
            run: run.name.clone(),
            pass,
            divergence,
            at_bounds: (0..log.hits.len())
                .filter(|&j| log.hits[j] > 0)
                .map(|j| (j, log.hits[j]))
                .collect(),
        };
        let mut sys = ModelSystem::new(
            model,
            setup.base.clone(),
            &setup.est,
            &setup.scale,
            &run.inputs,
            &run.measured,
        );
        let f = start_filter(&mut filter, run, prior, setup.max_step);
        for (fq, q) in f.q.iter_mut().zip(q_run) {
            *fq = q * setup.noise_scale;
        }
        f.kind = setup.filter;
        f.gate = if gate_on { setup.gate } else { 0.0 };
        f.ungated = vec![false; run.measured.len()];
        let (mut tr, mut checkpoints) =
            filter_run(f, &mut sys, run, setup, keep, counter, bounds, &mut log)
                .map_err(|d| fail(d, &log))?;
        if keep.smooth {
            let smoothed = smooth_run(&mut sys, run, &mut checkpoints, bounds);
            tr.smoothed = Some(smoothed.map_err(|d| fail(d, &log))?);
        }
        tr.spool = checkpoints.spool.map(super::states::SpoolWriter::finish);
        pass_traces.push(tr);
        logs.push(log);
    }
    Ok((filter.expect("at least one run"), pass_traces, logs))
}

/// The noise calibration across passes: each run's process noise from the model's misfit
/// along its measured states ([`super::adapt`]), before the first pass (with the initial
/// coefficients) and after every pass but the last, until it settles; the pass after it has
/// settled is the last.
struct Calibration {
    /// Per run, the states' process noise densities.
    q: Vec<Vec<f64>>,
    /// Per run, per measured quantity: the state whose noise it calibrates.
    adaptable: Vec<Vec<Option<usize>>>,
    /// Whether the noise has settled (always, when nothing is adapted).
    settled: bool,
    /// The pass the estimate last started from the prior.
    cold_pass: usize,
    /// Divergences met and widened past.
    widened: usize,

    /// What was done, for the report.
    notes: Vec<String>,
}

impl Calibration {
    fn new(setup: &Setup, runs: &[RunData], nx: usize) -> Self {
        let q: Vec<Vec<f64>> = (0..runs.len())
            .map(|i| {
                setup
                    .run_q
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| setup.q[..nx].to_vec())
            })
            .collect();
        let adaptable: Vec<Vec<Option<usize>>> = runs
            .iter()
            .map(|r| {
                r.measured
                    .iter()
                    .map(|&j| {
                        setup
                            .adaptable
                            .get(j)
                            .copied()
                            .unwrap_or(false)
                            .then_some(j)
                    })
                    .collect()
            })
            .collect();
        let any = adaptable.iter().flatten().any(Option::is_some);
        Calibration {
            q,
            adaptable,
            settled: !any,
            cold_pass: 0,
            widened: 0,
            notes: Vec::new(),
        }
    }

    /// Whether pass `pass` (0-based) is the last: the configured passes are done, the noise
    /// has settled and the estimate has had a pass to converge since it last started cold;
    /// or the calibration has used all its passes.
    fn is_last(&self, pass: usize, configured: usize) -> bool {
        let done = pass + 1 >= configured && self.settled && pass > self.cold_pass;
        done || pass + 1 >= configured + MAX_CALIBRATION_PASSES || configured == 1
    }

    /// The process noise of every run from the model's misfit along its measured states
    /// with the coefficients `values` (the estimated ones, SI) after `passes` passes
    /// ([`super::adapt::from_misfit`]); the noise has settled when no density moved by more
    /// than [`CONVERGED_FACTOR`] (and a tenth of the largest).
    fn update<M: Model>(
        &mut self,
        model: &M,
        setup: &Setup,
        runs: &[RunData],
        values: &[f64],
        passes: usize,
    ) {
        if self.adaptable.iter().flatten().all(Option::is_none) {
            return;
        }
        let c = completed(model, &setup.base, &setup.est, values);
        let mut largest: f64 = 1.0;
        for (i, run) in runs.iter().enumerate() {
            let Some(q) = super::adapt::from_misfit(model, &c, run, &setup.adaptable) else {
                continue;
            };
            let dt = mean_interval(&run.times);
            for (j, new) in q.into_iter().enumerate() {
                let Some(a) = run.measured.iter().position(|&s| s == j) else {
                    continue;
                };
                if !setup.adaptable[j] {
                    continue;
                }
                // a density that adds less than NEGLIGIBLE of the measurement variance per
                // sample changes nothing the data can tell: none
                let floor = NEGLIGIBLE * run.r[a] / dt;
                let new = if new > floor { new } else { 0.0 };
                let old = self.q[i][j];
                let (a_, b_) = (old.max(floor), new.max(floor));
                largest = largest.max((a_ / b_).max(b_ / a_));
                self.q[i][j] = new.max(setup.q[j]);
            }
        }
        self.settled = largest <= CONVERGED_FACTOR;
        if passes > 0 && !self.settled {
            self.notes.push(format!(
                "after pass {passes}: process noise from the model's misfit along the measured \
                 states (changed up to {})",
                if largest.is_finite() {
                    format!("{largest:.3} times")
                } else {
                    "from none".to_string()
                }
            ));
        }
    }

    /// After a divergence in a pass (the last too): raises the adaptable states' process
    /// noise to what the measured velocities' sample-to-sample changes allow (the filter
    /// then follows the measurements as an equation-error fit would) and starts again; at
    /// most twice. False when there is nothing to widen.
    fn widen(&mut self, runs: &[RunData]) -> bool {
        if self.widened >= 2 || self.adaptable.iter().flatten().all(Option::is_none) {
            return false;
        }
        self.widened += 1;
        for (i, run) in runs.iter().enumerate() {
            let m = run.measured.len();
            let dt = mean_interval(&run.times);
            for (a, state) in self.adaptable[i].iter().enumerate() {
                let Some(j) = *state else { continue };
                let steps = run
                    .y
                    .chunks_exact(m)
                    .map(|row| row[a])
                    .collect::<Vec<f64>>();
                let var = steps
                    .windows(2)
                    .map(|w| w[1] - w[0])
                    .filter(|d| d.is_finite())
                    .map(|d| d * d)
                    .sum::<f64>()
                    / steps.len().max(2) as f64;
                self.q[i][j] = (self.q[i][j] * 100.0).max(var / dt);
            }
        }
        self.settled = false;
        true
    }

    /// Records a divergence widened past.
    fn note_divergence(&mut self, e: &IdentifyError, pass: usize) {
        self.cold_pass = pass + 1;
        self.notes.push(format!(
            "pass {} diverged in run '{}' at t = {} s ({}): process noise widened to follow \
             the measured velocities, the estimate starts again from the prior",
            pass + 1,
            e.run,
            crate::base::numfmt::num(e.divergence.time),
            e.divergence.reason
        ));
    }
}

/// Whether the divergence `e` came after the first sample of its run.
fn after_first_sample(e: &IdentifyError, runs: &[RunData]) -> bool {
    runs.iter()
        .find(|r| r.name == e.run)
        .and_then(|r| r.times.first())
        .is_some_and(|t0| e.divergence.time > *t0)
}

/// Mean sampling interval of a run (1 s for fewer than two samples).
fn mean_interval(times: &[f64]) -> f64 {
    let n = times.len();
    if n < 2 || times[n - 1] <= times[0] {
        return 1.0;
    }
    (times[n - 1] - times[0]) / (n - 1) as f64
}

/// The estimated coefficients as the filter sees them, divided by their scale
/// (`Setup::scale`): the estimate a pass starts from, the prior variances, and the process
/// noise of the augmented state (states, then coefficients).
struct ScaledPrior {
    nx: usize,
    z: Vec<f64>,
    /// Prior covariance of the scaled coefficients, nb x nb.
    pzz: Vec<f64>,
    q: Vec<f64>,
    /// The first pass's start and covariance, for the coefficients whose prior is held.
    z0: Vec<f64>,
    pzz0: Vec<f64>,
}

impl ScaledPrior {
    fn new(setup: &Setup, nx: usize) -> Self {
        let z: Vec<f64> = setup
            .initial
            .iter()
            .zip(&setup.scale)
            .map(|(v, s)| v / s)
            .collect();
        let pzz = setup.prior_covariance(&setup.scale);
        let mut q = setup.q.clone();
        for (j, s) in setup.scale.iter().enumerate() {
            q[nx + j] /= s * s;
        }
        ScaledPrior {
            nx,
            z0: z.clone(),
            pzz0: pzz.clone(),
            z,
            pzz,
            q,
        }
    }
}

/// What a pass keeps of a run besides the estimates.
#[derive(Debug, Clone, Copy)]
struct Keep {
    /// The per-sample traces the report draws (the last pass of `identify`).
    samples: bool,
    /// The thinned coefficient history (every pass of `identify`).
    history: bool,
    /// Smoothed states (the last pass, when the smoother is on).
    smooth: bool,
}

/// The filter's progress through the samples of all runs in one pass.
struct PassProgress<'a> {
    progress: &'a mut dyn Progress,
    /// 1-based.
    pass: usize,
    passes: usize,
    done: usize,
    total: usize,
}

impl PassProgress<'_> {
    /// One more sample filtered: told every 250 samples and at the last.
    fn sample(&mut self) {
        self.done += 1;
        if self.done.is_multiple_of(250) || self.done == self.total {
            self.progress
                .filter(self.pass, self.passes, self.done, self.total);
        }
    }
}

/// The filter for the next run of a pass: the first run starts it from the prior (its
/// initial state and covariance, the coefficients' estimate and prior variances,
/// uncorrelated); a later run restarts only the dynamic states, keeping what the earlier
/// runs taught about the coefficients.
fn start_filter<'a>(
    filter: &'a mut Option<HybridEkf>,
    run: &RunData,
    prior: &ScaledPrior,
    max_step: f64,
) -> &'a mut HybridEkf {
    if let Some(f) = filter.as_mut() {
        f.restart_dynamic(&run.x0, &run.p0);
    } else {
        let (nx, nb) = (prior.nx, prior.z.len());
        let n = nx + nb;
        let mut x = run.x0.clone();
        x.extend_from_slice(&prior.z);
        let mut p = vec![0.0; n * n];
        for i in 0..nx {
            for j in 0..nx {
                p[i * n + j] = run.p0[i * nx + j];
            }
        }
        for a in 0..nb {
            for b in 0..nb {
                p[(nx + a) * n + nx + b] = prior.pzz[a * nb + b];
            }
        }
        *filter = Some(HybridEkf::new(n, nx, x, p, prior.q.clone(), max_step));
    }
    filter.as_mut().expect("created above")
}

/// The smoother's checkpoints of one run: the whole filter and its gate at the start of
/// every segment of `segment` samples (none when the smoother is off).
struct Checkpoints {
    segment: usize,
    /// The factor on the measurement noise the forward pass used (`Setup::noise_scale`).
    r_scale: f64,
    saved: Vec<(HybridEkf, GateTracker)>,
    /// The state series being spooled (when the pass keeps its samples).
    spool: Option<super::states::SpoolWriter>,
}

/// The forward pass over one run: every sample through [`filter_sample`], with the innovation
/// gate's rejections and excursions, what `keep` asks for, and the smoother's checkpoints;
/// the covariance is checked at the end. The coefficients are kept in their admissible
/// ranges (`bounds`), each projection recorded in `log`.
#[allow(clippy::too_many_arguments)]
fn filter_run<M: Model>(
    f: &mut HybridEkf,
    sys: &mut ModelSystem<M>,
    run: &RunData,
    setup: &Setup,
    keep: Keep,
    counter: &mut PassProgress<'_>,
    bounds: &Bounds,
    log: &mut BoundLog,
) -> Result<(RunTrace, Checkpoints), Divergence> {
    let n = f.n();
    let nb = setup.est.len();
    let nx = n - nb;
    let k_len = run.len();
    let m = run.measured.len();
    let mut gate = GateTracker::new(m);
    let mut gate_log = GateLog::default();
    let mut tr = RunTrace {
        samples: k_len,
        innovation_squares: vec![0.0; m],
        ..Default::default()
    };
    if keep.samples {
        tr.times = run.times.clone();
        tr.states.reserve_exact(k_len * nx);
        tr.nis.reserve_exact(k_len);
    }
    let mut history = keep.history.then(|| HistoryBuilder::new(nb, k_len));
    let mut row_values = vec![0.0; nb];
    let mut row_sigmas = vec![0.0; nb];
    let segment = rts::segment_length(k_len);
    let layout = super::states::Layout {
        nx,
        m,
        nb,
        smoothed: keep.smooth,
    };
    let mut checkpoints = Checkpoints {
        segment,
        r_scale: setup.noise_scale,
        saved: Vec::new(),
        spool: keep
            .samples
            .then(|| super::states::SpoolWriter::new(layout, segment)),
    };
    let mut phi = vec![0.0; n * n];
    for k in 0..k_len {
        if keep.smooth && k % checkpoints.segment == 0 {
            checkpoints.saved.push((f.clone(), gate.clone()));
        }
        let mut gating = (&mut gate, &mut gate_log);
        let nis = filter_sample(
            f,
            sys,
            run,
            k,
            &mut gating,
            (bounds, &mut *log),
            None,
            &mut phi,
            setup.noise_scale,
        )?;
        tr.neg_log_likelihood += nis + f.log_det_s;
        if let Some(h) = history.as_mut() {
            for j in 0..nb {
                row_values[j] = f.x[nx + j] * setup.scale[j];
                row_sigmas[j] = f.p[(nx + j) * n + nx + j].max(0.0).sqrt() * setup.scale[j];
            }
            h.push(k, run.times[k], &row_values, &row_sigmas);
        }
        if let Some(spool) = checkpoints.spool.as_mut() {
            spool.push(&super::states::Sample {
                t: run.times[k],
                x: &f.x,
                p: &f.p,
                y: &run.y[k * m..(k + 1) * m],
                innovation: f.innovation(),
                innovation_variance: f.innovation_variance(),
                nis,
                scale: &setup.scale,
            });
        }
        if keep.samples {
            tr.states.extend_from_slice(&f.x[..nx]);
            tr.nis.push(nis);
            for (s, v) in tr.innovation_squares.iter_mut().zip(f.innovation()) {
                *s += v * v;
            }
        }
        counter.sample();
    }
    gate.finish(&mut gate_log);
    tr.rejected = gate_log.rejected;
    tr.excursions = gate_log.excursions;
    if let Some(&t_end) = run.times.last() {
        f.check_covariance(t_end)?;
    }
    tr.history = history.map(HistoryBuilder::finish).unwrap_or_default();
    Ok((tr, checkpoints))
}

/// The smoothed states of one run (K x nx): the RTS smoother goes through the run's segments
/// last first, re-running the filter over each from its checkpoint (through
/// [`filter_sample`], gating as the forward pass did) to get the priors, transitions and
/// posteriors it needs.
fn smooth_run<M: Model>(
    sys: &mut ModelSystem<M>,
    run: &RunData,
    checkpoints: &mut Checkpoints,
    bounds: &Bounds,
) -> Result<Vec<f64>, Divergence> {
    let Some((first, _)) = checkpoints.saved.first() else {
        return Ok(Vec::new());
    };
    let n = first.n();
    let nx = run.x0.len();
    let k_len = run.len();
    let Checkpoints {
        segment,
        r_scale,
        saved,
        spool,
    } = checkpoints;
    let (segment, r_scale) = (*segment, *r_scale);
    let mut states = vec![0.0; k_len * nx];
    let mut phi = vec![0.0; n * n];
    rts::smooth_segments(
        n,
        k_len,
        segment,
        |start, end, trace| {
            // segments come last first: the last checkpoint is this segment's
            debug_assert_eq!(saved.len(), start / segment + 1);
            let (mut g, mut gt) = saved.pop().expect("one checkpoint per segment");
            // the re-run gates as the forward pass did; what it finds was kept then
            let mut scratch = GateLog::default();
            let mut gating = (&mut gt, &mut scratch);
            let mut held = BoundLog::new(bounds.coefficients(), k_len);
            for k in start..end {
                filter_sample(
                    &mut g,
                    sys,
                    run,
                    k,
                    &mut gating,
                    (bounds, &mut held),
                    Some(trace),
                    &mut phi,
                    r_scale,
                )?;
            }
            Ok(())
        },
        |k, x, p| {
            states[k * nx..(k + 1) * nx].copy_from_slice(&x[..nx]);
            if let Some(w) = spool.as_mut() {
                w.push_smoothed(k, x, p);
            }
        },
    )
    .map_err(|e| match e {
        SmoothError::Filter(d) => d,
        SmoothError::NotPositiveDefinite(k) => Divergence {
            time: run.times[k],
            reason: "the smoother met a predicted covariance that is not positive definite".into(),
        },
    })?;
    Ok(states)
}

/// The pass's estimates and sigmas (SI) from the filter after its last run, the
/// coefficients' covariance into `covariance` (nb x nb, SI), and the next pass's start: this
/// estimate, with the prior narrowed by `Setup::repeat_prior_factor`.
fn pass_summary(
    f: &HybridEkf,
    setup: &Setup,
    prior: &mut ScaledPrior,
    covariance: &mut [f64],
) -> PassEstimate {
    let (nx, nb) = (prior.nx, prior.z.len());
    let n = nx + nb;
    prior.z.copy_from_slice(&f.x[nx..]);
    let values: Vec<f64> = prior
        .z
        .iter()
        .zip(&setup.scale)
        .map(|(v, s)| v * s)
        .collect();
    let sigmas: Vec<f64> = (0..nb)
        .map(|j| f.p[(nx + j) * n + nx + j].max(0.0).sqrt() * setup.scale[j])
        .collect();
    for a in 0..nb {
        for b in 0..nb {
            covariance[a * nb + b] = f.p[(nx + a) * n + nx + b] * setup.scale[a] * setup.scale[b];
        }
    }
    let held = |j: usize| setup.held_prior.get(j).copied().unwrap_or(false);
    if let Some(f) = setup.repeat_prior_factor {
        // The next pass starts from this estimate with a prior no wider than f times this
        // pass's sigma: (1/f^2 of the data's information, nothing for f = 100) but enough
        // to keep its first samples from throwing the estimate far from here.
        for j in (0..nb).filter(|&j| !held(j)) {
            let d = prior.pzz[j * nb + j].min((f * sigmas[j] / setup.scale[j]).powi(2));
            for k in 0..nb {
                prior.pzz[j * nb + k] = 0.0;
                prior.pzz[k * nb + j] = 0.0;
            }
            prior.pzz[j * nb + j] = d;
        }
    }
    // an earlier stage's prior counts once: every pass starts from it again
    for j in (0..nb).filter(|&j| held(j)) {
        prior.z[j] = prior.z0[j];
        for k in (0..nb).filter(|&k| held(k)) {
            prior.pzz[j * nb + k] = prior.pzz0[j * nb + k];
        }
    }
    PassEstimate { values, sigmas }
}

/// One sample of a run: the prediction from the sample before (none at the first), the
/// update and the projection of the coefficients onto their admissible ranges (recorded in
/// the log). With `trace`, the prior, the transition matrix (into `phi`) and the posterior are
/// recorded for the smoother. The innovation gate's events go to the tracker, which may
/// exempt a quantity from the gate for the samples after. The forward pass and the
/// smoother's re-run both go through here, so that the re-run repeats the forward pass's
/// numbers exactly.
#[allow(clippy::too_many_arguments)]
fn filter_sample<M: Model>(
    f: &mut HybridEkf,
    sys: &mut ModelSystem<M>,
    run: &RunData,
    k: usize,
    gating: &mut (&mut GateTracker, &mut GateLog),
    (bounds, log): (&Bounds, &mut BoundLog),
    mut trace: Option<&mut Trace>,
    phi: &mut [f64],
    r_scale: f64,
) -> Result<f64, Divergence> {
    let m = run.measured.len();
    let t = run.times[k];
    if k > 0 {
        let want_phi = trace.is_some();
        f.predict(sys, run.times[k - 1], t, want_phi.then_some(&mut *phi))?;
    }
    if let Some(tr) = trace.as_deref_mut() {
        tr.push_prior(&f.x, &f.p, (k > 0).then_some(&*phi));
    }
    let y = &run.y[k * m..(k + 1) * m];
    let nis = if run.rounding.is_empty() && r_scale == 1.0 {
        f.update(sys, t, y, &run.r)?
    } else {
        let r: Vec<f64> = (0..m)
            .map(|a| r_scale * (run.r[a] + run.rounding.get(k * m + a).copied().unwrap_or(0.0)))
            .collect();
        f.update(sys, t, y, &r)?
    };
    log.project(bounds, k, &mut f.x, &f.p);
    if !f.beyond_gate().is_empty() || gating.0.open.iter().any(Option::is_some) {
        let events = f.beyond_gate().to_vec();
        gating.0.step(k, &events, &mut f.ungated, gating.1);
    } else {
        gating.0.streak.iter_mut().for_each(|s| *s = 0);
    }
    if let Some(tr) = trace {
        tr.push_post(&f.x, &f.p);
    }
    Ok(nis)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::sim::simulate;
    use crate::model::models::spheroid3::{Spheroid3, BOUNDED_TRUTH};
    use crate::numerics::estimation::rts::tests::dense_smooth;

    const ESTIMATED: [&str; 6] = ["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"];

    /// The paper's manoeuvre from (u0, v0), `k` samples at 10 ms, with seeded noise.
    fn run(m: &Spheroid3, u0: f64, v0: f64, k: usize, seed: u64) -> RunData {
        use rand::{rngs::StdRng, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let truth = m.coefficient_vector(BOUNDED_TRUTH);
        let times: Vec<f64> = (0..k).map(|i| i as f64 * 0.01).collect();
        let inputs = InputSeries::constant(&[22.0]);
        let xs = simulate(m, &truth, &[u0, v0, 0.0, 0.0, 0.0, 0.0], &inputs, &times, 4).unwrap();
        let sig = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3];
        let mut rng = StdRng::seed_from_u64(seed);
        let mut y = Vec::new();
        for x in &xs {
            for i in 0..6 {
                y.push(x[i] + Normal::new(0.0, sig[i]).unwrap().sample(&mut rng));
            }
        }
        let r: Vec<f64> = sig.iter().map(|s| s * s).collect();
        let mut p0 = vec![0.0; 36];
        for i in 0..6 {
            p0[i * 6 + i] = r[i];
        }
        RunData {
            name: format!("u0 = {u0}"),
            times,
            measured: (0..6).collect(),
            x0: y[..6].to_vec(),
            y,
            r,
            rounding: Vec::new(),
            inputs,
            p0,
            lines: (2..k + 2).collect(),
        }
    }

    fn setup(m: &Spheroid3, passes: usize, smoother: bool) -> Setup {
        let est: Vec<usize> = ESTIMATED
            .iter()
            .map(|n| m.coefficient_index(n).unwrap())
            .collect();
        let scale: Vec<f64> = ESTIMATED.iter().map(|n| m.typical_magnitude(n)).collect();
        let mut base = m.coefficient_vector(BOUNDED_TRUTH);
        for &i in &est {
            base[i] = 0.0;
        }
        let mut q = vec![1e-10; 6];
        q.extend([0.0; 6]);
        Setup {
            base,
            est,
            initial: vec![0.0; 6],
            prior_sigma: scale.clone(),
            ranges: Vec::new(),
            prior_correlation: Vec::new(),
            held_prior: Vec::new(),
            scale,
            q,
            passes,
            substeps: 1,
            max_step: 0.01,
            smoother,
            gate: 0.0,
            gate_from_pass: 1,
            repeat_prior_factor: Some(100.0),
            filter: Default::default(),
            adaptable: Vec::new(),
            run_q: Vec::new(),
            noise_scale: 1.0,
        }
    }

    /// One pass the way the smoother was fed before checkpoints: every sample's prior,
    /// transition and posterior kept in one trace per run, smoothed by one dense sweep.
    fn dense_reference(m: &Spheroid3, s: &Setup, runs: &[RunData]) -> Vec<Vec<f64>> {
        let (nx, nb) = (6, s.est.len());
        let n = nx + nb;
        let prior = ScaledPrior::new(s, nx);
        let mut filter: Option<HybridEkf> = None;
        let mut out = Vec::new();
        for run in runs {
            let mut sys = ModelSystem::new(
                m,
                s.base.clone(),
                &s.est,
                &s.scale,
                &run.inputs,
                &run.measured,
            );
            let f = start_filter(&mut filter, run, &prior, s.max_step);
            // a single pass: the gate applies when it applies from the first pass
            f.gate = if s.gate_from_pass == 0 { s.gate } else { 0.0 };
            f.ungated = vec![false; 6];
            let mut gate = GateTracker::new(6);
            let mut log = GateLog::default();
            let mut tr = Trace::new(n);
            let mut phi = vec![0.0; n * n];
            for k in 0..run.len() {
                if k > 0 {
                    f.predict(&mut sys, run.times[k - 1], run.times[k], Some(&mut phi))
                        .unwrap();
                }
                tr.push_prior(&f.x, &f.p, (k > 0).then_some(phi.as_slice()));
                f.update(&mut sys, run.times[k], &run.y[k * 6..(k + 1) * 6], &run.r)
                    .unwrap();
                let events = f.beyond_gate().to_vec();
                gate.step(k, &events, &mut f.ungated, &mut log);
                tr.push_post(&f.x, &f.p);
            }
            f.check_covariance(run.times[run.len() - 1]).unwrap();
            let (xs, _) = dense_smooth(&tr).unwrap();
            out.push(xs.chunks_exact(n).flat_map(|x| x[..nx].to_vec()).collect());
        }
        out
    }

    #[test]
    fn checkpointed_smoothing_gives_the_dense_smoothers_states_bit_for_bit() {
        let m = Spheroid3::paper_vehicle();
        let runs = [run(&m, 3.0, 1.0, 3000, 1), run(&m, 2.0, -0.5, 1234, 2)];
        let s = setup(&m, 1, true);
        let id = identify(&m, &s, &runs, &mut Silent).unwrap();
        let reference = dense_reference(&m, &s, &runs);
        for (tr, want) in id.traces[0].iter().zip(&reference) {
            let got = tr.smoothed.as_ref().expect("smoothed");
            assert_eq!(got.len(), want.len());
            let same = got
                .iter()
                .zip(want)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "smoothed states differ from the dense smoother's");
        }
    }

    #[test]
    fn checkpointed_smoothing_replays_the_innovation_gate() {
        let m = Spheroid3::paper_vehicle();
        let mut r = run(&m, 3.0, 1.0, 3000, 5);
        // isolated spikes (rejected) and a stretch of eight (an excursion) across a segment boundary (1210)
        for (k, j) in [(100, 0), (517, 2), (1800, 1), (2401, 5)] {
            r.y[k * 6 + j] += 0.05;
        }
        for k in 1207..1215 {
            r.y[k * 6 + 1] += 0.05;
        }
        let mut s = setup(&m, 1, true);
        s.initial = ESTIMATED
            .iter()
            .map(|n| m.coefficient_vector(BOUNDED_TRUTH)[m.coefficient_index(n).unwrap()])
            .collect();
        s.gate = 5.0;
        s.gate_from_pass = 0;
        let runs = [r];
        let id = identify(&m, &s, &runs, &mut Silent).unwrap();
        let tr = &id.traces[0][0];
        assert!(tr.rejected.len() >= 4, "{:?}", tr.rejected);
        assert!(!tr.excursions.is_empty());
        let want = &dense_reference(&m, &s, &runs)[0];
        let got = tr.smoothed.as_ref().expect("smoothed");
        let same = got
            .iter()
            .zip(want)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "the re-run gated differently from the forward pass");
    }

    #[test]
    fn passes_keep_bounded_traces_and_the_estimates_do_not_depend_on_them() {
        let m = Spheroid3::paper_vehicle();
        let runs = [run(&m, 3.0, 1.0, 5000, 3)];
        let s = setup(&m, 2, false);
        let id = identify(&m, &s, &runs, &mut Silent).unwrap();
        assert_eq!(estimates(&m, &s, &runs).unwrap(), id.passes);
        // the first pass keeps its thinned coefficient history only
        let first = &id.traces[0][0];
        assert!(first.times.is_empty() && first.states.is_empty() && first.nis.is_empty());
        assert!(first.history.len() <= super::super::history::BUCKETS * (2 + 4 * 6));
        assert!(first.history.len() > 500);
        // the last keeps every sample of what the report shows
        let last = &id.traces[1][0];
        assert_eq!((last.times.len(), last.nis.len()), (5000, 5000));
        assert_eq!(last.states.len(), 5000 * 6);
        assert_eq!(last.samples, 5000);
        assert!(last.innovation_squares.iter().all(|s| *s > 0.0));
    }

    #[test]
    fn decimation_keeps_every_nth_sample_from_the_first() {
        let m = Spheroid3::paper_vehicle();
        let mut r = run(&m, 3.0, 1.0, 11, 4);
        let full = r.clone();
        r.decimate(4);
        assert_eq!(r.times, vec![0.0, full.times[4], full.times[8]]);
        assert_eq!(&r.y[6..12], &full.y[24..30]);
        assert_eq!(r.y.len(), 18);
        assert_eq!(r.x0, full.x0);
        r.decimate(1);
        assert_eq!(r.len(), 3);
    }
}
