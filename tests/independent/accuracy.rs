//! Runs hydroid as a library on a configuration written next to generated logs and measures,
//! per estimated coefficient, estimate, sigma, truth and z = (estimate - truth) / sigma.

use super::Truth;
use std::path::Path;
use std::time::Instant;

// The rows, the determined rule and the checks, shared with the twin tests (issue 28). A
// test that declares both `mod common` and `mod independent` compiles the file twice, as
// two private modules of the same content: harmless, so clippy's duplicate_mod is allowed.
#[allow(clippy::duplicate_mod)]
#[path = "../common/accuracy.rs"]
mod shared;
pub use shared::Accuracy;

/// What one identification gave: its estimates against the truth (the methods of
/// [`Accuracy`] through `Deref`), its warnings and how long it took.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The estimates; the table's title says the run's title and its seconds.
    pub accuracy: Accuracy,
    /// Every warning hydroid gave, as text.
    pub warnings: Vec<String>,
    /// Seconds the run took.
    pub seconds: f64,
}

impl std::ops::Deref for Outcome {
    type Target = Accuracy;
    fn deref(&self) -> &Accuracy {
        &self.accuracy
    }
}

/// Loads `config` (hydroid::load), runs it (hydroid::run) and compares the HEKF stage's
/// estimates with `truth`.
pub fn identify(config: &Path, truth: &Truth) -> Outcome {
    let started = Instant::now();
    let loaded = hydroid::load(config, &[]).unwrap_or_else(|e| panic!("{config:?}: {e}"));
    let out = hydroid::run(&loaded, &mut hydroid::progress::Silent)
        .unwrap_or_else(|e| panic!("{config:?}: {e}"));
    let seconds = started.elapsed().as_secs_f64();
    let h = out.result.stages.hekf.as_ref().expect("an HEKF stage");
    let warnings = out
        .result
        .warnings
        .iter()
        .map(|w| format!("[{}] {}", w.stage, w.message))
        .collect();
    let title = out.result.title.clone().unwrap_or_default();
    let title = format!("{title} ({seconds:.1} s)");
    Outcome {
        accuracy: Accuracy::of_hekf_result(&title, h, |name| super::truth_of(truth, name)),
        warnings,
        seconds,
    }
}
