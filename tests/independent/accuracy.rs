//! Runs hydroid as a library on a configuration written next to generated logs and measures,
//! per estimated coefficient, estimate, sigma, truth and z = (estimate - truth) / sigma.

use super::Truth;
use std::path::Path;
use std::time::Instant;

// The rows, the determined rule and the checks, shared with the twin tests (issue 28).
pub use crate::common::accuracy::{Accuracy, Row};

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
    let out = hydroid::run(&loaded, &mut hydroid::base::progress::Silent)
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

/// One identification repeated over noise seeds (a coverage study): whether the reported
/// sigmas cover the estimates' errors, which one seed cannot tell (however right the sigmas,
/// nine coefficients all within 2 sigma is a 63 % chance for independent estimates, 0.95^9;
/// over the KVLCC2 studies' seeds it happened in 80 to 95 % of them).
#[derive(Debug, Clone)]
pub struct Study {
    /// One outcome per seed.
    pub outcomes: Vec<Outcome>,
}

/// Per coefficient over the seeds of a [`Study`].
#[derive(Debug, Clone)]
pub struct Spread {
    pub name: String,
    /// Seeds in which the run determined it (sigma below half the value).
    pub determined: usize,
    /// Seeds in which hydroid flagged it (undetermined or correlated).
    pub flagged: usize,
    /// Mean and root mean square of z = (estimate - truth) / sigma over the seeds.
    pub mean_z: f64,
    pub rms_z: f64,
    /// Mean error, per cent of the truth.
    pub mean_error_percent: f64,
    /// Standard deviation of the estimates over the seeds against their mean sigma.
    pub spread_over_sigma: f64,
}

impl Study {
    /// The coefficients' names, in the order of the first outcome.
    fn names(&self) -> Vec<String> {
        self.outcomes[0]
            .rows
            .iter()
            .map(|r| r.name.clone())
            .collect()
    }

    /// The spread of every coefficient over the seeds.
    pub fn spreads(&self) -> Vec<Spread> {
        let n = self.outcomes.len() as f64;
        self.names()
            .into_iter()
            .map(|name| {
                let rows: Vec<&Row> = self.outcomes.iter().map(|o| o.row(&name)).collect();
                let mean = |f: &dyn Fn(&Row) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
                let est = mean(&|r| r.estimate);
                let sd = (rows.iter().map(|r| (r.estimate - est).powi(2)).sum::<f64>() / (n - 1.0))
                    .sqrt();
                Spread {
                    determined: rows.iter().filter(|r| r.determined).count(),
                    flagged: rows.iter().filter(|r| r.flagged).count(),
                    mean_z: mean(&|r| r.z),
                    rms_z: mean(&|r| r.z * r.z).sqrt(),
                    mean_error_percent: 100.0 * (est - rows[0].truth) / rows[0].truth,
                    spread_over_sigma: sd / mean(&|r| r.sigma),
                    name,
                }
            })
            .collect()
    }

    /// Shares of the determined coefficient-seed pairs within 1 and within 2 sigma, and
    /// the number of pairs.
    pub fn coverage(&self) -> (f64, f64, usize) {
        let z: Vec<f64> = self
            .outcomes
            .iter()
            .flat_map(|o| o.determined().map(|r| r.z))
            .collect();
        let share = |k: f64| z.iter().filter(|v| v.abs() <= k).count() as f64 / z.len() as f64;
        (share(1.0), share(2.0), z.len())
    }

    /// The table: one line per coefficient, then the pooled coverage.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{} seeds\n{:>8} {:>6} {:>7} {:>8} {:>7} {:>9} {:>12}\n",
            self.outcomes.len(),
            "coef",
            "determ",
            "flagged",
            "mean z",
            "rms z",
            "error %",
            "spread/sigma"
        );
        for c in self.spreads() {
            s.push_str(&format!(
                "{:>8} {:>6} {:>7} {:>+8.2} {:>7.2} {:>+9.2} {:>12.2}\n",
                c.name,
                c.determined,
                c.flagged,
                c.mean_z,
                c.rms_z,
                c.mean_error_percent,
                c.spread_over_sigma
            ));
        }
        let (one, two, pairs) = self.coverage();
        s.push_str(&format!(
            "determined pairs: {pairs}, within 1 sigma {:.1} %, within 2 sigma {:.1} %\n",
            100.0 * one,
            100.0 * two
        ));
        s
    }
}
