//! `hydroid calibrate`: does a run's reported sigma describe the spread of its estimates? A
//! parametric bootstrap (Efron & Tibshirani 1993, ch. 6.5): N replicas of every input made
//! from the identified model with the run's own noise ([`replica`]), each identified again
//! with the run's settings (in parallel, replica k from seed S + k), and per coefficient the
//! replicas' spread against the reported sigma and the share of replicas whose own sigma
//! covers the identified value ([`stats`]); and the estimates of the same data under changed
//! settings, the "settings" row ([`settings`]).

pub mod replica;
pub mod settings;
pub mod stats;
pub mod write;

pub use stats::{Calibration, CoefficientRow, Coverage, Failed, Outcome, Settings};

use crate::app::pipeline::{self, InputsByStage, Scope};
use crate::app::results::{LoadedInput, RunOutput};
use crate::base::error::Result;
use crate::base::progress::Silent;
use crate::config::LoadedConfig;
use crate::model::coefficients::{Coefficient, Source};
use rayon::prelude::*;

/// Replicas made when none are asked for.
pub const DEFAULT_REPLICAS: usize = 50;

/// The seed of replica 0 when none is given (replica k uses this + k).
pub const DEFAULT_SEED: u64 = 2026;

/// Identifies `settings.replicas` replicas of the run whose inputs are `inputs` and whose
/// output is `original`, and compares their spread with the reported sigmas. `done` is told
/// the number of replicas finished so far (from any thread).
pub fn calibrate(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    original: &RunOutput,
    settings: Settings,
    done: &(dyn Fn(usize) + Sync),
) -> Result<Calibration> {
    let bases = replica::bases(loaded, inputs, original)?;
    let counter = std::sync::atomic::AtomicUsize::new(0);
    let outcomes: Vec<Outcome> = (0..settings.replicas)
        .into_par_iter()
        .map(|k| {
            let seed = settings.seed.wrapping_add(k as u64);
            let outcome = identify(loaded, inputs, &bases, seed);
            done(counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            outcome
        })
        .collect();
    let identified: Vec<&Coefficient> = original
        .result
        .coefficients
        .iter()
        .filter(|c| is_identified(c))
        .collect();
    let mut cal = stats::summarise(&identified, &outcomes, settings);
    let (check, warnings) = settings::check(loaded, inputs, original, &identified);
    cal.settings = check;
    cal.warnings.extend(warnings);
    Ok(cal)
}

/// A coefficient a stage identified with a sigma (not given, analytic or by symmetry).
fn is_identified(c: &Coefficient) -> bool {
    matches!(
        c.source,
        Source::Polar | Source::Surge | Source::Captive | Source::Hekf
    ) && c.sigma.is_some_and(|s| s > 0.0 && s.is_finite())
}

/// One replica made and identified.
fn identify(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    bases: &InputsByStage<replica::Basis>,
    seed: u64,
) -> Outcome {
    let data = replica::replica(loaded, inputs, bases, seed).map_err(|e| e.to_string())?;
    identified_on(loaded, &data)
}

/// The coefficients (name, value, sigma) identified on `data` with the configuration's
/// settings, or why the identification failed.
fn identified_on(loaded: &LoadedConfig, data: &InputsByStage<LoadedInput>) -> Outcome {
    let out = pipeline::run_on(loaded, data, &mut Silent, Scope::Coefficients)
        .map_err(|e| e.to_string())?;
    Ok(out
        .result
        .coefficients
        .iter()
        .map(|c| (c.name.clone(), c.value, c.sigma))
        .collect())
}
