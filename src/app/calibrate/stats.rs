//! The replicas' estimates against the reported sigmas: per coefficient the replicas' mean
//! and standard deviation, the spread in reported sigmas, the bias, and the coverage (the
//! share of replicas whose own 1- and 2-sigma interval holds the identified value, the
//! truth of the replicas; a Gaussian estimate covers 68.3 % and 95.4 %).

use crate::base::warning::{Test, Warning};
use crate::model::coefficients::Coefficient;
use serde::Serialize;

/// How many replicas, from which seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Settings {
    /// Number of replicas.
    pub replicas: usize,
    /// Seed of replica 0.
    pub seed: u64,
}

/// One replica's identified coefficients (value, sigma by name), or why it failed.
pub type Outcome = std::result::Result<Vec<(String, f64, Option<f64>)>, String>;

/// A spread below this many reported sigmas: the sigma is too large.
pub const SPREAD_LOW: f64 = 0.67;
/// A spread above this many reported sigmas: the sigma is too small.
pub const SPREAD_HIGH: f64 = 1.5;
/// An overall coverage within 2 sigma below this share: the sigmas are too small.
pub const COVERAGE_2_LOW: f64 = 0.90;
/// A replica whose estimate lies more than this many reported sigmas from the identified
/// value is far: with Gaussian errors of the reported size one replica in ~1.7 million is.
pub const FAR_SIGMAS: f64 = 5.0;

/// The calibration check of one output folder (calibration.json).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// Layout version.
    pub schema: &'static str,
    /// Replicas asked for.
    pub replicas: usize,
    /// Seed of replica 0 (replica k: seed + k).
    pub seed: u64,
    /// Replicas identified (the statistics are over these).
    pub converged: usize,
    /// Replicas whose identification failed, with the error.
    pub failed: Vec<Failed>,
    /// Per identified coefficient.
    pub coefficients: Vec<CoefficientRow>,
    /// Over every coefficient-replica pair.
    pub overall: Coverage,
    /// The same data identified under changed settings (the "settings" row).
    pub settings: super::settings::SettingsCheck,
    /// What the check found wrong.
    pub warnings: Vec<Warning>,
}

/// A replica that could not be identified.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failed {
    /// Its number k (seed + k).
    pub replica: usize,
    /// Why.
    pub error: String,
}

/// One coefficient's calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoefficientRow {
    /// Name.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// The stage that identified it.
    pub source: String,
    /// The identified value (the replicas' truth).
    pub value: f64,
    /// The reported sigma.
    pub sigma: f64,
    /// Mean of the replicas' estimates (None without replicas).
    pub replica_mean: Option<f64>,
    /// Standard deviation of the replicas' estimates (None with fewer than 2).
    pub replica_sd: Option<f64>,
    /// replica_sd / sigma: 1 when the sigma is right.
    pub spread_ratio: Option<f64>,
    /// (replica_mean - value) / sigma.
    pub bias_sigmas: Option<f64>,
    /// The replicas' spread by the median absolute deviation (1.4826 MAD, the standard
    /// deviation for Gaussian replicas; Huber 1981, 5.1) in reported sigmas: near
    /// `spread_ratio` unless a few replicas lie far off.
    pub robust_spread_ratio: Option<f64>,
    /// Replicas whose estimate lies more than [`FAR_SIGMAS`] reported sigmas from the value.
    pub far: usize,
    /// Coverage of the identified value by the replicas' own sigmas.
    pub coverage: Coverage,
}

/// Shares of replicas whose own interval holds the identified value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coverage {
    /// Within 1 sigma (Gaussian: 0.683).
    pub within_1: Option<f64>,
    /// Within 2 sigma (Gaussian: 0.954).
    pub within_2: Option<f64>,
    /// Replicas (or coefficient-replica pairs) counted.
    pub count: usize,
}

impl Coverage {
    fn of(z: &[f64]) -> Coverage {
        let share = |k: f64| {
            (!z.is_empty())
                .then(|| z.iter().filter(|v| v.abs() < k).count() as f64 / z.len() as f64)
        };
        Coverage {
            within_1: share(1.0),
            within_2: share(2.0),
            count: z.len(),
        }
    }
}

/// Each replica's (value, sigma) of every coefficient of `identified`, in that order, or why
/// it cannot be counted (failed, a coefficient missing, not finite or without sigma).
fn checked(identified: &[&Coefficient], outcome: &Outcome) -> Result<Vec<(f64, f64)>, String> {
    let found = outcome.as_ref().map_err(Clone::clone)?;
    identified
        .iter()
        .map(|c| {
            let hit = found.iter().find(|f| f.0 == c.name);
            match hit {
                Some((_, v, Some(s))) if v.is_finite() && s.is_finite() && *s > 0.0 => Ok((*v, *s)),
                _ => Err(format!("{} was not identified with a finite sigma", c.name)),
            }
        })
        .collect()
}

/// The calibration from the replicas' outcomes (in replica order).
pub fn summarise(
    identified: &[&Coefficient],
    outcomes: &[Outcome],
    settings: Settings,
) -> Calibration {
    let mut failed = Vec::new();
    let mut good = Vec::new();
    for (k, o) in outcomes.iter().enumerate() {
        match checked(identified, o) {
            Ok(v) => good.push(v),
            Err(error) => failed.push(Failed { replica: k, error }),
        }
    }
    let mut all_z = Vec::new();
    let coefficients: Vec<CoefficientRow> = identified
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let pairs: Vec<(f64, f64)> = good.iter().map(|g| g[i]).collect();
            let z: Vec<f64> = pairs.iter().map(|(v, s)| (v - c.value) / s).collect();
            all_z.extend_from_slice(&z);
            row(c, &pairs, &z)
        })
        .collect();
    let overall = Coverage::of(&all_z);
    let mut cal = Calibration {
        schema: "hydroid-calibration/1",
        replicas: settings.replicas,
        seed: settings.seed,
        converged: good.len(),
        failed,
        coefficients,
        overall,
        settings: Default::default(),
        warnings: Vec::new(),
    };
    cal.warnings = warnings(&cal);
    cal
}

/// One coefficient's row from its replicas' (value, sigma) and z = (value - identified) /
/// own sigma.
fn row(c: &Coefficient, pairs: &[(f64, f64)], z: &[f64]) -> CoefficientRow {
    let sigma = c.sigma.unwrap_or(f64::NAN);
    let n = pairs.len() as f64;
    let mean = (!pairs.is_empty()).then(|| pairs.iter().map(|p| p.0).sum::<f64>() / n);
    // sample standard deviation (n - 1)
    let sd = mean
        .filter(|_| pairs.len() > 1)
        .map(|m| (pairs.iter().map(|p| (p.0 - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt());
    CoefficientRow {
        name: c.name.clone(),
        unit: c.unit.clone(),
        source: c.source.to_string(),
        value: c.value,
        sigma,
        replica_mean: mean,
        replica_sd: sd,
        spread_ratio: sd.map(|s| s / sigma),
        bias_sigmas: mean.map(|m| (m - c.value) / sigma),
        robust_spread_ratio: mad_sd(pairs.iter().map(|p| p.0).collect()).map(|s| s / sigma),
        far: pairs
            .iter()
            .filter(|p| (p.0 - c.value).abs() > FAR_SIGMAS * sigma)
            .count(),
        coverage: Coverage::of(z),
    }
}

/// 1.4826 times the median absolute deviation from the median (Huber 1981, 5.1): the
/// standard deviation of a Gaussian sample, unmoved by a few outliers; None below 2 values.
fn mad_sd(mut v: Vec<f64>) -> Option<f64> {
    fn median(v: &mut [f64]) -> f64 {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    }
    if v.len() < 2 {
        return None;
    }
    let m = median(&mut v);
    let mut dev: Vec<f64> = v.iter().map(|x| (x - m).abs()).collect();
    Some(1.4826 * median(&mut dev))
}

/// The spreads (in reported sigmas) that are off with `n` identified replicas: below `low`
/// or above `high`, where the ratio's 2-standard-error interval lies wholly outside
/// [`SPREAD_LOW`, `SPREAD_HIGH`]; and the spread's relative standard error
/// 1/sqrt(2 (n - 1)) (a Gaussian sample's standard deviation).
fn spread_band(n: usize) -> (f64, f64, f64) {
    let se = 1.0 / (2.0 * (n.max(2) - 1) as f64).sqrt();
    let high = if 2.0 * se < 1.0 {
        SPREAD_HIGH / (1.0 - 2.0 * se)
    } else {
        f64::INFINITY
    };
    (SPREAD_LOW / (1.0 + 2.0 * se), high, se)
}

/// What the check finds wrong: a spread outside [`SPREAD_LOW`, `SPREAD_HIGH`] reported
/// sigmas by more than two of its own standard errors, an overall 2-sigma coverage below
/// [`COVERAGE_2_LOW`], failed replicas.
fn warnings(cal: &Calibration) -> Vec<Warning> {
    let mut out = Vec::new();
    // the spread is itself an estimate (relative standard error 1/sqrt(2 (N - 1)) for N
    // Gaussian replicas): a ratio is off only when its 2-standard-error interval lies
    // wholly outside the band, so that few replicas do not warn by chance
    let n = cal.converged;
    let (low, high, se) = spread_band(n);
    let off: Vec<String> = cal
        .coefficients
        .iter()
        .filter_map(|r| {
            let ratio = r.spread_ratio?;
            let num = crate::base::numfmt::num;
            let robust = match r.robust_spread_ratio {
                Some(m) if r.far > 0 => format!(" (robust {})", num(m)),
                _ => String::new(),
            };
            (!(low..=high).contains(&ratio)).then(|| format!("{} {}{robust}", r.name, num(ratio)))
        })
        .collect();
    if !off.is_empty() {
        out.push(
            Warning::new(
                "calibration",
                format!(
                    "the replicas' spread is outside {SPREAD_LOW}-{SPREAD_HIGH} reported sigmas \
                     by more than its own uncertainty with {n} replicas (+-{:.0} %): {}",
                    200.0 * se,
                    off.join(", ")
                ),
                "above: the sigma is too small for how much the estimate moves with new noise; \
                 below: too large. Check the runs' noise (hekf.noise) and the stages' residuals",
            )
            .failed(Test::Calibration),
        );
    }
    out.extend(far_warning(cal));
    if let Some(c2) = cal.overall.within_2.filter(|c| *c < COVERAGE_2_LOW) {
        out.push(
            Warning::new(
                "calibration",
                format!(
                    "the replicas' own 2-sigma intervals hold the identified value for {:.1} % \
                     of the coefficient-replica pairs, below {:.0} %",
                    100.0 * c2,
                    100.0 * COVERAGE_2_LOW
                ),
                "the reported sigmas are too small (a Gaussian estimate is covered 95.4 %)",
            )
            .failed(Test::Calibration),
        );
    }
    if !cal.failed.is_empty() {
        out.push(Warning::new(
            "calibration",
            format!(
                "{} of {} replicas could not be identified (first: replica {}: {})",
                cal.failed.len(),
                cal.replicas,
                cal.failed[0].replica,
                cal.failed[0].error
            ),
            "the statistics count the identified replicas only; replicas that fail are \
             themselves a sign of a fragile identification",
        ));
    }
    out
}

/// Replicas far from the identified value: the data let the identification end elsewhere
/// (another minimum, or a run away), which a sigma from the local curvature cannot show.
fn far_warning(cal: &Calibration) -> Option<Warning> {
    let far: Vec<String> = cal
        .coefficients
        .iter()
        .filter(|r| r.far > 0)
        .map(|r| format!("{} {}", r.name, r.far))
        .collect();
    (!far.is_empty()).then(|| {
        Warning::new(
            "calibration",
            format!(
                "of {} replicas, some identified a coefficient more than {FAR_SIGMAS} reported \
                 sigmas from its value (how many replicas): {}",
                cal.converged,
                far.join(", ")
            ),
            "with the same model and new noise the identification can end far from this \
             estimate: the reported sigma describes only its neighbourhood. More informative \
             runs (or captive runs for these coefficients) pin it down; the robust spread \
             (robust_spread_ratio) shows the rest of the replicas",
        )
        .failed(Test::Calibration)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::coefficients::Source;

    #[test]
    fn the_spread_band_widens_with_fewer_replicas() {
        // docs/calibrate.md: "at 50 replicas: below 0.56 or above 1.88 sigma; at 24: below
        // 0.52 or above 2.13"
        let show = |n| {
            let (l, h, _) = spread_band(n);
            format!("{l:.2}-{h:.2}")
        };
        assert_eq!(show(50), "0.56-1.88");
        assert_eq!(show(24), "0.52-2.13");
        // two replicas say nothing about a spread that is too large
        assert!(spread_band(2).1.is_infinite());
    }

    fn settings(replicas: usize) -> Settings {
        Settings { replicas, seed: 1 }
    }

    #[test]
    fn failed_replicas_are_counted_not_averaged() {
        let c = Coefficient::new("Yvd", -10.0, Some(1.0), Source::Hekf);
        let outcomes: Vec<Outcome> = vec![
            Ok(vec![("Yvd".into(), -10.5, Some(1.0))]),
            Err("diverged".into()),
            Ok(vec![("Yvd".into(), -8.5, Some(1.0))]),
            Ok(vec![("Yvd".into(), f64::NAN, Some(1.0))]),
            Ok(vec![("Xud".into(), 1.0, Some(1.0))]),
        ];
        let cal = summarise(&[&c], &outcomes, settings(5));
        assert_eq!(cal.converged, 2);
        assert_eq!(
            cal.failed.iter().map(|f| f.replica).collect::<Vec<_>>(),
            [1, 3, 4]
        );
        let row = &cal.coefficients[0];
        assert_eq!(row.replica_mean, Some(-9.5));
        // sample standard deviation of -10.5 and -8.5: sqrt(2) = 1.414
        assert!((row.replica_sd.unwrap() - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(row.coverage.within_1, Some(0.5));
        assert_eq!(row.coverage.within_2, Some(1.0));
        assert!(cal.warnings.iter().any(|w| w.message.starts_with("3 of 5")));
    }

    /// One replica far off moves the standard deviation, not the robust spread, and is
    /// counted and named.
    #[test]
    fn a_far_replica_is_counted_and_the_robust_spread_ignores_it() {
        let c = Coefficient::new("Nrd", 0.0, Some(1.0), Source::Hekf);
        let values = [-1.0, -0.5, 0.0, 0.5, 1.0, 40.0];
        let outcomes: Vec<Outcome> = values
            .iter()
            .map(|v| Ok(vec![("Nrd".into(), *v, Some(1.0))]))
            .collect();
        let cal = summarise(&[&c], &outcomes, settings(6));
        let row = &cal.coefficients[0];
        assert_eq!(row.far, 1);
        // median 0.25; absolute deviations 1.25 0.75 0.25 0.25 0.75 39.75: MAD 0.75
        assert!((row.robust_spread_ratio.unwrap() - 1.4826 * 0.75).abs() < 1e-12);
        assert!(row.spread_ratio.unwrap() > 10.0);
        let far = cal
            .warnings
            .iter()
            .find(|w| w.message.contains("more than 5 reported"))
            .expect("a far warning");
        assert!(far.message.ends_with("Nrd 1"), "{}", far.message);
        assert_eq!(mad_sd(vec![1.0]), None);
    }

    #[test]
    fn without_replicas_the_statistics_are_null_not_nan() {
        let c = Coefficient::new("Yvd", -10.0, Some(1.0), Source::Hekf);
        let cal = summarise(&[&c], &[Err("no".into())], settings(1));
        let json = serde_json::to_string(&cal).unwrap();
        assert!(!json.contains("NaN"), "{json}");
        assert_eq!(cal.coefficients[0].replica_sd, None);
        assert_eq!(cal.overall.within_2, None);
    }

    #[test]
    fn a_spread_far_from_the_sigma_is_a_failed_calibration() {
        let c = Coefficient::new("Yvd", 0.0, Some(0.1), Source::Hekf);
        let outcomes: Vec<Outcome> = (0..10)
            .map(|k| {
                Ok(vec![(
                    "Yvd".into(),
                    if k % 2 == 0 { 1.0 } else { -1.0 },
                    Some(0.1),
                )])
            })
            .collect();
        let cal = summarise(&[&c], &outcomes, settings(10));
        assert!(cal
            .warnings
            .iter()
            .all(|w| w.failed_test == Some(Test::Calibration)));
        // the spread, the far replicas (all ten are 10 sigma off) and the coverage
        assert_eq!(cal.warnings.len(), 3, "{:?}", cal.warnings);
    }
}
