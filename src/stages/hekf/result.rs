//! What the HEKF stage reports: coefficients with sigma and correlations, the estimate after
//! every pass, noise and tuning choices, innovation statistics, and the traces for plots.

use super::config::HekfConfig;
use super::history::History;
use super::identify::{Identification, RunData, Setup};
use super::prepare::Plan;
use super::tuning::NoiseChoice;
use crate::base::warning::Warning;
use crate::model::coefficients::{directions_of, Coefficient, Correlation, Direction, Source};
use crate::model::models::Model;
use crate::numerics::estimation::nis::{summarize, NisSummary};
use serde::Serialize;
use std::collections::BTreeMap;

/// The estimate after one pass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassSummary {
    /// 1-based pass number.
    pub pass: usize,
    /// Values, in the order of `HekfResult::estimated`.
    pub values: Vec<f64>,
    /// Standard deviations.
    pub sigmas: Vec<f64>,
}

/// One identification run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// Name.
    pub name: String,
    /// File.
    pub file: String,
    /// Number of samples.
    pub samples: usize,
    /// Duration, s.
    pub duration: f64,
    /// Mean sampling interval, s.
    pub mean_dt: f64,
    /// Measured quantities.
    pub measured: Vec<String>,
    /// Measurement noise used per quantity, and where it came from.
    pub noise: Vec<NoiseChoice>,
    /// Process noise density (SI^2/s) of each state calibrated from the model's misfit along
    /// this run (`hekf.adapt_noise`, docs/hekf.md "The noise model"), by state name; empty
    /// when the noise was not calibrated.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub process_noise: BTreeMap<String, f64>,
    /// Innovation consistency in the last pass.
    pub nis: Option<NisSummary>,
    /// RMS of the innovations in the last pass, per measured quantity (SI).
    pub innovation_rms: Vec<f64>,
    /// How each sampled input is read between its samples (`held` or `linear`, by quantity:
    /// the run's `between`, docs/config.md); constant inputs are not listed.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub between: BTreeMap<String, String>,
    /// The run's state series in the output folder (`states/NAME.csv`, docs/results.md,
    /// "State series"): filtered and smoothed states, innovations and coefficients at every
    /// sample of the last pass.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub states: Option<String>,
    /// Things to know about this run.
    pub warnings: Vec<Warning>,
}

/// Per-sample traces of one run in the last pass, and the coefficient history of every
/// pass, for plots (not written to results.json).
#[derive(Debug, Clone, PartialEq)]
pub struct RunTraces {
    /// Sample times, s.
    pub times: Vec<f64>,
    /// Measured states' names.
    pub measured: Vec<String>,
    /// Filtered states (K x nx).
    pub filtered: Vec<f64>,
    /// Smoothed states (K x nx).
    pub smoothed: Option<Vec<f64>>,
    /// Coefficient estimates and sigmas over time, per pass, thinned for drawing (every
    /// sample of a pass up to [`super::history::KEEP_ALL`]).
    pub history: Vec<History>,
    /// Normalised innovation squared per sample (last pass).
    pub nis: Vec<f64>,
    /// The state series table (`RunSummary::states` says where it goes).
    pub states: Option<super::states::Table>,
}

/// The stage's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HekfResult {
    /// Model name.
    pub model: String,
    /// Tuning preset.
    pub preset: String,
    /// Estimated coefficients, in order.
    pub estimated: Vec<String>,
    /// The estimates with sigma (source `hekf`).
    pub coefficients: Vec<Coefficient>,
    /// Correlation matrix of the estimates.
    pub correlation: Correlation,
    /// The estimate after each pass.
    pub passes: Vec<PassSummary>,
    /// Coefficients held fixed, with their sources.
    pub fixed: Vec<Coefficient>,
    /// Tuning choices in words.
    pub tuning: Vec<String>,
    /// Number of passes, sub-steps, smoother.
    pub settings: Settings,
    /// The runs.
    pub runs: Vec<RunSummary>,
    /// Standard deviations from the data alone (the filter's, with the fixed coefficients
    /// taken as exact), in `estimated` order; the coefficients' sigmas add the uncertainty of
    /// the fixed coefficients.
    pub sigma_filter: Vec<f64>,
    /// Things to know.
    pub warnings: Vec<Warning>,
    /// The estimates the runs leave uncertain or correlated, with the quantities their terms
    /// act through and a manoeuvre that would determine them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub identifiability: Vec<super::identifiability::Advice>,
    /// In joint mode: each coefficient beside its consider-mode estimate and the earlier
    /// stage's, and what pins it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modes: Option<super::modes::ModeComparison>,
    /// Traces for plots.
    #[serde(skip)]
    pub traces: Vec<RunTraces>,
    /// Uncertainty directions: the estimates' change along every upstream direction, and the
    /// filter's own.
    #[serde(skip)]
    pub directions: Vec<Direction>,
}

/// Numerical settings used.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Settings {
    /// The form of the filter that ran (`hekf.filter`: hybrid, discrete or continuous).
    pub filter: crate::numerics::estimation::FilterKind,
    /// Filter passes.
    pub passes: usize,
    /// RK4 sub-steps per sample.
    pub substeps: usize,
    /// Smoother on the last pass.
    pub smoother: bool,
    /// The filter used every `decimate`-th sample of each run (`hekf.decimate`; left out
    /// of results.json when 1).
    #[serde(skip_serializing_if = "is_one")]
    pub decimate: usize,
    /// Process noise of states and coefficients (spectral density).
    pub process_noise: Vec<f64>,
    /// The initial variance of every state when configured (`hekf.state_variance`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state_variance: Option<f64>,
    /// `joint` when earlier stages' estimates were the prior of the coefficients the HEKF
    /// estimates too (`hekf.mode`); absent for `consider`.
    #[serde(skip_serializing_if = "is_consider")]
    pub mode: super::Mode,
}

fn is_consider(m: &super::Mode) -> bool {
    *m == super::Mode::Consider
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

impl HekfResult {
    /// The estimated coefficients (source `hekf`).
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }
}

/// The estimates' sensitivity to the uncertainty of the fixed coefficients.
pub struct Upstream {
    /// Change of the estimates along each upstream direction (upstream labels).
    pub directions: Vec<Direction>,
    /// Directions whose repeated identification failed.
    pub failed: Vec<String>,
}

/// The tuning choices in words, and what the filter's form changes.
fn tuning_notes(plan: &Plan, setup: &Setup, cfg: &HekfConfig) -> Vec<String> {
    use crate::numerics::estimation::FilterKind;
    let mut notes = plan.notes.clone();
    if let Some(v) = cfg.state_variance {
        notes.push(format!(
            "every state starts with variance {} SI^2 (hekf.state_variance), measured or not",
            crate::base::numfmt::num(v)
        ));
    }
    match setup.filter {
        FilterKind::Hybrid => {}
        FilterKind::Discrete => notes.push(
            "filter: discrete-time EKF, one explicit Euler step x + h f(x) per sub-step, \
             Phi = I + h F, Q_d = Q h (Simon 2006, section 13.1; the Nomoto wave-filter \
             paper, eq. 20-25)"
                .into(),
        ),
        FilterKind::Continuous => notes.push(
            "filter: continuous-time (Kalman-Bucy) EKF, each sample held over the next \
             interval with R_c = R dt (Simon 2006, section 13.3); no smoother (the RTS \
             smoother needs a transition matrix per interval, which this filter has not): \
             the states shown are the filtered ones"
                .into(),
        ),
    }
    notes
}

/// Assembles the result from the identification.
#[allow(clippy::too_many_arguments)]
pub fn build<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    plan: &Plan,
    setup: &Setup,
    runs: &[RunData],
    mut summaries: Vec<RunSummary>,
    id: Identification,
    upstream: Upstream,
) -> HekfResult {
    let nb = plan.est.len();
    let id_passes = pass_summaries(&id.passes);
    let last = id
        .passes
        .last()
        .cloned()
        .unwrap_or_else(|| super::identify::PassEstimate {
            values: plan.initial.clone(),
            sigmas: plan.prior_sigma.clone(),
        });
    let total = total_covariance(plan, &id.covariance, &upstream);
    let coefficients = coefficient_list(model, plan, &id, &last, &total);
    let cov_rows: Vec<Vec<f64>> = (0..nb)
        .map(|a| (0..nb).map(|b| id.covariance[a * nb + b]).collect())
        .collect();
    let est: Vec<&str> = plan.est_names.iter().map(String::as_str).collect();
    let mut directions = upstream.directions.clone();
    directions.extend(directions_of("hekf", &est, &cov_rows));
    let warnings = upstream_warnings(&upstream);
    let correlation =
        Correlation::from_covariance(plan.est_names.clone(), |a, b| id.covariance[a * nb + b]);
    let pass_count = id.passes.len();
    let calibration = id.calibration.clone();
    let traces = run_traces(
        model,
        setup,
        runs,
        &mut summaries,
        id.traces,
        &id.process_noise,
    );
    HekfResult {
        model: model.name().to_string(),
        preset: cfg.preset.to_string(),
        estimated: plan.est_names.clone(),
        coefficients,
        correlation,
        passes: id_passes,
        fixed: plan.fixed.clone(),
        tuning: {
            let mut notes = tuning_notes(plan, setup, cfg);
            notes.extend(calibration);
            notes
        },
        settings: Settings {
            filter: setup.filter,
            passes: pass_count,
            substeps: setup.substeps,
            smoother: setup.smoother,
            decimate: cfg.decimate.unwrap_or(1).max(1),
            state_variance: cfg.state_variance,
            mode: cfg.mode,
            process_noise: setup.q.clone(),
        },
        runs: summaries,
        sigma_filter: last.sigmas.clone(),
        warnings,
        identifiability: Vec::new(),
        modes: None,
        traces,
        directions,
    }
}

/// Each pass's estimates, numbered from 1.
fn pass_summaries(passes: &[super::identify::PassEstimate]) -> Vec<PassSummary> {
    passes
        .iter()
        .enumerate()
        .map(|(i, p)| PassSummary {
            pass: i + 1,
            values: p.values.clone(),
            sigmas: p.sigmas.clone(),
        })
        .collect()
}

/// The total covariance of the estimates: the filter's plus each fixed coefficient's share
/// (consider analysis: the change along each upstream direction, outer product).
fn total_covariance(plan: &Plan, covariance: &[f64], upstream: &Upstream) -> Vec<f64> {
    let nb = plan.est.len();
    let mut total = covariance.to_vec();
    for d in &upstream.directions {
        for (a, na) in plan.est_names.iter().enumerate() {
            for (b, nb_) in plan.est_names.iter().enumerate() {
                if let (Some(da), Some(db)) = (d.deltas.get(na), d.deltas.get(nb_)) {
                    total[a * nb + b] += da * db;
                }
            }
        }
    }
    total
}

/// The estimated coefficients with their total sigmas and a note on where the sigma comes
/// from.
fn coefficient_list<M: Model>(
    model: &M,
    plan: &Plan,
    id: &Identification,
    last: &super::identify::PassEstimate,
    total: &[f64],
) -> Vec<Coefficient> {
    let nb = plan.est.len();
    plan
        .est_names
        .iter()
        .enumerate()
        .map(|(j, n)| {
            let sigma = total[j * nb + j].max(0.0).sqrt();
            let num = crate::base::numfmt::num;
            // joint: the filter's sigma holds the earlier stage's prior as well as the data
            let from = if plan.held_prior.get(j).copied().unwrap_or(false) {
                format!(
                    "joint with the earlier stage's {} ± {} as prior: sigma {} from it and the data",
                    num(plan.initial[j]),
                    num(plan.prior_sigma[j]),
                    num(last.sigmas[j])
                )
            } else {
                format!("sigma {} from the data alone", num(last.sigmas[j]))
            };
            Coefficient::new(n, last.values[j], Some(sigma), Source::Hekf).with_note(format!(
                "{} model, {} pass{}; {from}",
                model.name(),
                id.passes.len(),
                if id.passes.len() == 1 { "" } else { "es" },
            ))
        })
        .collect()
}

/// The warning for upstream directions whose repeated identification failed.
fn upstream_warnings(upstream: &Upstream) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if !upstream.failed.is_empty() {
        warnings.push(Warning::new(
            super::STAGE,
            format!(
                "the sensitivity to {} could not be computed (the filter failed with the fixed \
                 coefficients moved by one sigma)",
                upstream.failed.join(", ")
            ),
            "the sigmas leave that uncertainty out and are too small",
        ));
    }
    warnings
}

/// Per run, the last pass's traces with every pass's coefficient history, and the run's
/// summary completed (process noise, NIS, innovation RMS).
fn run_traces<M: Model>(
    model: &M,
    setup: &Setup,
    runs: &[RunData],
    summaries: &mut [RunSummary],
    mut passes: Vec<Vec<super::identify::RunTrace>>,
    process_noise: &[Vec<f64>],
) -> Vec<RunTraces> {
    let last_traces = passes.pop().unwrap_or_default();
    let names: Vec<String> = summaries.iter().map(|s| s.name.clone()).collect();
    let paths = super::states::file_names(&names);
    let mut traces = Vec::new();
    for (r, (tr, summary)) in last_traces
        .into_iter()
        .zip(summaries.iter_mut())
        .enumerate()
    {
        // a held state's measurement (the run's constant) is predicted exactly: its
        // innovation adds nothing to the test
        let counted: Vec<&NoiseChoice> = summary
            .noise
            .iter()
            .filter(|n| n.source != super::prepare::HELD_SOURCE)
            .collect();
        let m = runs[r].measured.len() - (summary.noise.len() - counted.len());
        // an estimated noise's own error widens the test (numerics::estimation::nis)
        let extra = counted.iter().map(|n| n.estimate_variance).sum();
        let states = model.states();
        summary.process_noise = setup
            .adaptable
            .iter()
            .enumerate()
            .filter(|(j, a)| **a && process_noise[r][*j] > 0.0)
            .map(|(j, _)| (states[j].name.to_string(), process_noise[r][j]))
            .collect();
        summary.nis = summarize(&tr.nis, m, extra);
        summary.innovation_rms = tr
            .innovation_squares
            .iter()
            .map(|s| (s / tr.samples.max(1) as f64).sqrt())
            .collect();
        let mut history: Vec<History> = passes
            .iter_mut()
            .map(|p| std::mem::take(&mut p[r].history))
            .collect();
        history.push(tr.history);
        let states = tr.spool.map(|spool| super::states::Table {
            path: paths[r].clone(),
            columns: super::states::header(
                model,
                &runs[r].measured,
                &setup.est,
                spool.layout().smoothed,
            ),
            spool,
        });
        summary.states = states.as_ref().map(|t| t.path.clone());
        traces.push(RunTraces {
            times: tr.times,
            measured: summary.measured.clone(),
            filtered: tr.states,
            smoothed: tr.smoothed,
            history,
            nis: tr.nis,
            states,
        });
    }
    traces
}
