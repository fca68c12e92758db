//! Replicas of a run's inputs made from its identified model (a parametric bootstrap, Efron
//! & Tibshirani 1993, ch. 6.5): each record's measured channels replaced in memory by what
//! the identified model predicts at the record's own points plus Gaussian noise at the
//! noise the run estimated. HEKF manoeuvres: the identified model simulated from the run's
//! initial state with the run's inputs (the re-simulation), plus each channel's measurement
//! noise; static polar rows: the pooled fit at the row's angle plus each channel's residual
//! sigma; surge runs: the surge fit's u plus its residual noise (the thrust or force kept as
//! recorded); captive runs: the model's forces along the prescribed motion plus each force's
//! residual RMS. Validation manoeuvres are kept as recorded (they are not fitted).

use crate::app::pipeline::InputsByStage;
use crate::app::results::{LoadedInput, RunOutput};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::config::LoadedConfig;
use crate::io::record::Record;
use crate::model::coefficients::CoefficientSet;
use crate::stages::polar::replica::{row_values, FittedRow, Predicted};
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::collections::BTreeMap;

/// What one input's replicas are made from.
#[derive(Debug, Clone)]
pub enum Basis {
    /// Kept as recorded (a validation manoeuvre).
    Kept,
    /// Channels replaced by a prediction plus noise.
    Channels(Vec<Channel>),
    /// A manoeuvre whose states the filter lets wander: the identified model re-simulated
    /// with the run's process noise for every replica, then its channels' noise.
    Forced(Box<Forced>),
    /// Polar sweep rows: the fitted (C_D, C_L, C_M) and angle of each fitted row, and the
    /// channels' residual sigmas.
    Polar {
        /// Per row, the fitted coefficients and the angle (None: not fitted).
        rows: Vec<FittedRow>,
        /// Residual sigma of C_D, C_L, C_M.
        sigma: [f64; 3],
    },
}

/// A manoeuvre replicated by a re-simulation forced with the run's process noise.
#[derive(Debug, Clone)]
pub struct Forced {
    /// The identified model's coefficients.
    pub set: CoefficientSet,
    /// Process noise densities the filter calibrated along the run, by state name.
    pub calibrated: BTreeMap<String, f64>,
    /// The filter's process noise densities, states first (results.json's
    /// `settings.process_noise`).
    pub configured: Vec<f64>,
    /// The measured channels and their noise standard deviations (SI).
    pub channels: Vec<(Quantity, f64)>,
}

impl Forced {
    /// The process noise density the filter gave state `j` (named `name`) along the run.
    fn density(&self, j: usize, name: &str) -> f64 {
        self.calibrated
            .get(name)
            .or_else(|| self.configured.get(j))
            .copied()
            .unwrap_or(0.0)
    }
}

/// One channel's prediction at every row and its noise.
#[derive(Debug, Clone)]
pub struct Channel {
    /// The record's channel.
    pub quantity: Quantity,
    /// The model's value at each row (SI).
    pub predicted: Vec<f64>,
    /// Standard deviation of the noise added to each row (SI).
    pub sigma: f64,
}

/// The replica bases of every input of a run, from its output: the run's own fit
/// predictions and noise.
pub fn bases(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    original: &RunOutput,
) -> Result<InputsByStage<Basis>> {
    let cfg = &loaded.config;
    let records = |v: &[LoadedInput]| v.iter().map(|i| i.record.clone()).collect::<Vec<_>>();
    let stages = &original.result.stages;
    let mut out = InputsByStage::default();
    if let Some(p) = &stages.polar {
        let Predicted { rows, sigma } =
            crate::stages::polar::replica::predicted(p, &records(&inputs.polar))?;
        out.polar = rows
            .into_iter()
            .map(|rows| Basis::Polar { rows, sigma })
            .collect();
    }
    if let (Some(sc), Some(sr)) = (&cfg.surge, &stages.surge) {
        let recs = records(&inputs.surge);
        out.surge = crate::stages::surge::replica::predicted(sc, sr, &recs)?
            .into_iter()
            .zip(&recs)
            .map(|(run, rec)| surge_basis(rec, run))
            .collect();
    } else if !inputs.surge.is_empty() {
        return Err(mismatch(&inputs.surge[0].record));
    }
    if let (Some(cc), Some(_)) = (&cfg.captive, &stages.captive) {
        let set = crate::app::pipeline::identified_set(&original.result);
        let recs = records(&inputs.captive);
        let predicted =
            crate::stages::captive::replica::predicted(cc, &loaded.vehicle, &set, &recs)?;
        out.captive = recs
            .iter()
            .zip(predicted)
            .map(|(rec, forces)| captive_basis(rec, forces))
            .collect();
    }
    if let Some(h) = &stages.hekf {
        let set = original.resim_set.clone().ok_or_else(|| {
            Error::numerical("calibrate", "the run's output has no re-simulated model")
        })?;
        for (k, input) in inputs.hekf_fit.iter().enumerate() {
            let rec = &input.record;
            let trace = original.resim_traces.get(k).map(|t| &t.1);
            let (Some(trace), Some(run)) = (trace, h.runs.get(k)) else {
                return Err(mismatch(rec));
            };
            let basis = hekf_basis(rec, trace, run)?;
            let nx = trace.quantities.len();
            out.hekf_fit
                .push(forced_or(basis, h, run, nx, || set.clone()));
        }
        out.hekf_validation = inputs.hekf_validation.iter().map(|_| Basis::Kept).collect();
    }
    Ok(out)
}

fn mismatch(rec: &Record) -> Error {
    Error::numerical(
        "calibrate",
        format!(
            "run '{}': the run's output does not match its inputs",
            rec.name
        ),
    )
}

/// A surge run's u: the fitted u inside the fit's time window, the recorded one outside it
/// (rows the stage does not read), with the fit's noise on every row.
fn surge_basis(rec: &Record, run: crate::stages::surge::replica::PredictedRun) -> Basis {
    let recorded = rec.channel(Quantity::U).unwrap_or_default();
    let predicted = run
        .u
        .iter()
        .zip(recorded)
        .map(|(fitted, r)| fitted.unwrap_or(*r))
        .collect();
    Basis::Channels(vec![Channel {
        quantity: Quantity::U,
        predicted,
        sigma: run.sigma,
    }])
}

/// A captive run's forces: the model's, with each force's residual RMS as its noise.
fn captive_basis(rec: &Record, forces: crate::stages::captive::replica::RunForces) -> Basis {
    Basis::Channels(
        forces
            .into_iter()
            .map(|(quantity, predicted)| {
                let observed = rec.channel(quantity).unwrap_or_default();
                let n = observed.len().max(1) as f64;
                let rss: f64 = observed
                    .iter()
                    .zip(&predicted)
                    .map(|(o, p)| (o - p).powi(2))
                    .sum();
                Channel {
                    quantity,
                    predicted,
                    sigma: (rss / n).sqrt(),
                }
            })
            .collect(),
    )
}

/// A manoeuvre's measured channels: the re-simulated model's states (or sensor outputs),
/// each with the noise the data show around the filter's prediction, the run's innovation
/// RMS (else the measurement noise the filter used): a noise model set too small or too
/// large then shows as a spread off the reported sigma.
fn hekf_basis(
    rec: &Record,
    trace: &crate::app::resim::ResimTrace,
    run: &crate::stages::hekf::RunSummary,
) -> Result<Basis> {
    let (quantities, values) = trace.sensed();
    if values.len() != rec.rows() {
        return Err(Error::numerical(
            "calibrate",
            format!(
                "run '{}': the identified model's simulation stopped after {} of {} samples, so \
                 no replica of the run can be made",
                rec.name,
                values.len(),
                rec.rows()
            ),
        ));
    }
    let shown = |k: usize| run.innovation_rms.get(k).copied().filter(|s| s.is_finite());
    let channels = run
        .noise
        .iter()
        .enumerate()
        .filter(|(_, n)| rec.channel(n.quantity).is_some())
        .filter_map(|(k, n)| {
            let i = quantities.iter().position(|q| *q == n.quantity)?;
            Some(Channel {
                quantity: n.quantity,
                predicted: values.iter().map(|x| x[i]).collect(),
                sigma: shown(k).unwrap_or(n.sigma),
            })
        })
        .collect();
    Ok(Basis::Channels(channels))
}

/// A manoeuvre's basis made a forced one when the filter gave any of its states process
/// noise (the replicas then wander as the filter assumed the run did).
fn forced_or(
    basis: Basis,
    h: &crate::stages::hekf::HekfResult,
    run: &crate::stages::hekf::RunSummary,
    nx: usize,
    set: impl FnOnce() -> CoefficientSet,
) -> Basis {
    // the states' densities come first, the coefficients' random walks after them
    let noisy = run.process_noise.values().any(|q| *q > 0.0)
        || h.settings.process_noise.iter().take(nx).any(|q| *q > 0.0);
    match basis {
        Basis::Channels(channels) if noisy => Basis::Forced(Box::new(Forced {
            set: set(),
            calibrated: run.process_noise.clone(),
            configured: h.settings.process_noise.clone(),
            channels: channels.iter().map(|c| (c.quantity, c.sigma)).collect(),
        })),
        other => other,
    }
}

/// Replica `seed` of the inputs: each input's record with its basis applied, in the order
/// of [`InputsByStage::iter`], from one random stream seeded with `seed`.
pub fn replica(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    bases: &InputsByStage<Basis>,
    seed: u64,
) -> Result<InputsByStage<LoadedInput>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut basis = bases.iter();
    inputs.clone().try_map(|mut input| {
        match basis.next() {
            Some(Basis::Channels(channels)) => {
                for c in channels {
                    let noisy = with_noise(&c.predicted, c.sigma, &mut rng)?;
                    set_channel(&mut input.record, c.quantity, noisy);
                }
            }
            Some(Basis::Forced(f)) => forced_replica(loaded, &mut input.record, f, &mut rng)?,
            Some(Basis::Polar { rows, sigma }) => {
                polar_rows(loaded, &mut input.record, rows, *sigma, &mut rng)?
            }
            Some(Basis::Kept) | None => {}
        }
        Ok(input)
    })
}

/// A manoeuvre's replica: the identified model forced by the run's process noise, then each
/// measured channel with its noise.
fn forced_replica(
    loaded: &LoadedConfig,
    rec: &mut Record,
    f: &Forced,
    rng: &mut StdRng,
) -> Result<()> {
    let Some(hc) = &loaded.config.hekf else {
        return Ok(());
    };
    let density = |j: usize, name: &str| f.density(j, name);
    let trace =
        crate::app::resim::forced::forced(hc.model, &loaded.vehicle, &f.set, rec, &density, rng)?;
    let (quantities, values) = trace.sensed();
    for &(q, sigma) in &f.channels {
        let Some(i) = quantities.iter().position(|x| *x == q) else {
            continue;
        };
        let predicted: Vec<f64> = values.iter().map(|x| x[i]).collect();
        let noisy = with_noise(&predicted, sigma, rng)?;
        set_channel(rec, q, noisy);
    }
    Ok(())
}

/// `values` plus independent Gaussian noise of standard deviation `sigma`.
fn with_noise(values: &[f64], sigma: f64, rng: &mut StdRng) -> Result<Vec<f64>> {
    let mut noisy = values.to_vec();
    crate::numerics::noise::add_gaussian(&mut noisy, sigma, rng)
        .map_err(|e| Error::numerical("calibrate", e))?;
    Ok(noisy)
}

/// Puts `values` into the record's channel `q`, rounded to the record's printed resolution
/// where it has one (the replica is printed as the run was).
fn set_channel(rec: &mut Record, q: Quantity, mut values: Vec<f64>) {
    if let Some(steps) = rec.resolution.get(&q) {
        for (v, step) in values.iter_mut().zip(steps) {
            if *step > 0.0 {
                *v = (*v / step).round() * step;
            }
        }
    }
    rec.channels.insert(q, values);
}

/// A polar sweep's fitted rows with noise on each coefficient, written back as the
/// record's values.
fn polar_rows(
    loaded: &LoadedConfig,
    rec: &mut Record,
    rows: &[FittedRow],
    sigma: [f64; 3],
    rng: &mut StdRng,
) -> Result<()> {
    let cfg = &loaded.config;
    let Some(pc) = &cfg.polar else {
        return Ok(());
    };
    let fitted: Vec<(usize, [f64; 3], f64)> = rows
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.map(|(c, a)| (i, c, a)))
        .collect();
    let mut noisy = fitted.clone();
    for (k, s) in sigma.iter().enumerate() {
        let column: Vec<f64> = fitted.iter().map(|f| f.1[k]).collect();
        for (n, v) in noisy.iter_mut().zip(with_noise(&column, *s, rng)?) {
            n.1[k] = v;
        }
    }
    let mut updates = Vec::new();
    for (i, c, alpha) in noisy {
        updates.extend(row_values(pc, &cfg.vehicle, &cfg.fluid, rec, i, alpha, c)?.map(|v| (i, v)));
    }
    for (i, (q, v)) in updates {
        if let Some(col) = rec.channels.get_mut(&q) {
            col[i] = v;
        }
    }
    Ok(())
}
