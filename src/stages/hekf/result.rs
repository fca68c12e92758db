//! What the HEKF stage reports: coefficients with sigma and correlations, the estimate after
//! every pass, noise and tuning choices, innovation statistics, and the traces for plots.

use super::config::HekfConfig;
use super::identify::{Identification, RunData, Setup};
use super::prepare::Plan;
use super::tuning::NoiseChoice;
use crate::coefficients::{Coefficient, Correlation, Source};
use crate::estimation::nis::{summarize, NisSummary};
use crate::models::Model;
use serde::Serialize;

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
    /// Innovation consistency in the last pass.
    pub nis: Option<NisSummary>,
    /// RMS of the innovations in the last pass, per measured quantity (SI).
    pub innovation_rms: Vec<f64>,
    /// Things to know about this run.
    pub warnings: Vec<String>,
}

/// Per-sample traces of one run in the last pass, for plots (not written to results.json).
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
    /// Coefficient estimates over time, per pass (pass -> K x nb).
    pub coefficients: Vec<Vec<f64>>,
    /// Their sigmas over time, per pass.
    pub sigmas: Vec<Vec<f64>>,
    /// Normalised innovation squared per sample (last pass).
    pub nis: Vec<f64>,
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
    /// Traces for plots.
    #[serde(skip)]
    pub traces: Vec<RunTraces>,
}

/// Numerical settings used.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Settings {
    /// Filter passes.
    pub passes: usize,
    /// RK4 sub-steps per sample.
    pub substeps: usize,
    /// Smoother on the last pass.
    pub smoother: bool,
    /// Process noise of states and coefficients (spectral density).
    pub process_noise: Vec<f64>,
}

impl HekfResult {
    /// The estimated coefficients (source `hekf`).
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }
}

/// Assembles the result from the identification.
pub fn build<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    plan: &Plan,
    setup: &Setup,
    runs: &[RunData],
    mut summaries: Vec<RunSummary>,
    id: Identification,
) -> HekfResult {
    let nb = plan.est.len();
    let last = id
        .passes
        .last()
        .cloned()
        .unwrap_or_else(|| super::identify::PassEstimate {
            values: plan.initial.clone(),
            sigmas: plan.prior_sigma.clone(),
        });
    let coefficients: Vec<Coefficient> = plan
        .est_names
        .iter()
        .enumerate()
        .map(|(j, n)| {
            Coefficient::new(n, last.values[j], Some(last.sigmas[j]), Source::Hekf).with_note(
                format!(
                    "{} model, {} pass{}",
                    model.name(),
                    setup.passes,
                    if setup.passes == 1 { "" } else { "es" }
                ),
            )
        })
        .collect();
    let mut matrix = vec![vec![0.0; nb]; nb];
    for a in 0..nb {
        for b in 0..nb {
            let d = (id.covariance[a * nb + a] * id.covariance[b * nb + b]).sqrt();
            matrix[a][b] = if d > 0.0 {
                (id.covariance[a * nb + b] / d).clamp(-1.0, 1.0)
            } else if a == b {
                1.0
            } else {
                0.0
            };
        }
    }
    let last_traces = id.traces.last().cloned().unwrap_or_default();
    let mut traces = Vec::new();
    for (r, (run, summary)) in runs.iter().zip(summaries.iter_mut()).enumerate() {
        let tr = &last_traces[r];
        let m = run.measured.len();
        summary.nis = summarize(&tr.nis, m);
        summary.innovation_rms = (0..m)
            .map(|k| {
                let s: f64 = tr
                    .innovations
                    .iter()
                    .skip(k)
                    .step_by(m)
                    .map(|v| v * v)
                    .sum();
                (s / tr.nis.len().max(1) as f64).sqrt()
            })
            .collect();
        traces.push(RunTraces {
            times: tr.times.clone(),
            measured: summary.measured.clone(),
            filtered: tr.states.clone(),
            smoothed: tr.smoothed.clone(),
            coefficients: id
                .traces
                .iter()
                .map(|p| p[r].coefficients.clone())
                .collect(),
            sigmas: id.traces.iter().map(|p| p[r].sigmas.clone()).collect(),
            nis: tr.nis.clone(),
        });
    }
    HekfResult {
        model: model.name().to_string(),
        preset: cfg.preset.to_string(),
        estimated: plan.est_names.clone(),
        coefficients,
        correlation: Correlation {
            names: plan.est_names.clone(),
            matrix,
        },
        passes: id
            .passes
            .iter()
            .enumerate()
            .map(|(i, p)| PassSummary {
                pass: i + 1,
                values: p.values.clone(),
                sigmas: p.sigmas.clone(),
            })
            .collect(),
        fixed: plan.fixed.clone(),
        tuning: plan.notes.clone(),
        settings: Settings {
            passes: setup.passes,
            substeps: setup.substeps,
            smoother: setup.smoother,
            process_noise: setup.q.clone(),
        },
        runs: summaries,
        traces,
    }
}
