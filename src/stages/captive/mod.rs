//! Captive runs (ITTC 7.5-02-06-02 practice): the vehicle held in a steady motion (static
//! drift, drift with rudder, circular motion) or moved in a harmonic one (PMM pure sway and
//! pure yaw, [`harmonic`]), and the measured forces fitted with the model's
//! own force function ([`Model::captive_forces`]), so that every model that gives forces for a
//! prescribed motion has this stage. Unlike free-running motion, measured forces fix each
//! equation's scale (docs/hekf.md, "Identifiability").

mod checks;
pub mod fit;
pub mod harmonic;
pub mod plausibility;
pub mod replica;

pub use crate::config::captive::CaptiveConfig;
pub use checks::{preflight, Preflight};

use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::io::record::{Needs, Record};
use crate::model::coefficients::{
    directions_of, Coefficient, CoefficientSet, Correlation, Direction, Source,
};
use crate::model::models::{with_model, Model, ModelVisitor, RunVehicle, Vehicle};
use crate::stages::plausible::Finding;
use fit::Condition;
use serde::Serialize;

/// The stage's name in messages.
const STAGE: &str = "captive";

/// What the stage reads: every motion quantity, force and model input a record has.
pub fn needs(_cfg: &CaptiveConfig) -> Needs<'static> {
    static OPTIONAL: std::sync::OnceLock<Vec<Quantity>> = std::sync::OnceLock::new();
    let optional = OPTIONAL.get_or_init(|| {
        // time, the motion, every force and moment, the prime-system columns and the inputs
        let forces = Quantity::ALL
            .iter()
            .filter(|q| matches!(q.si_symbol(), "N" | "N m"));
        std::iter::once(&Quantity::Time)
            .chain(&Quantity::MOTION)
            .chain(forces)
            .chain(&[
                Quantity::Speed,
                Quantity::Drift,
                Quantity::RPrime,
                Quantity::XPrime,
                Quantity::YPrime,
                Quantity::NPrime,
            ])
            .chain(crate::model::models::registry::all_inputs())
            .copied()
            .collect()
    });
    Needs {
        required: &[],
        optional,
        min_rows: 1,
    }
}

/// The coefficients the stage provides.
pub fn provides(cfg: &CaptiveConfig) -> Vec<String> {
    cfg.estimate.clone()
}

/// One captive table as fitted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// Name.
    pub name: String,
    /// Steady conditions (rows).
    pub conditions: usize,
    /// RMS of the residual of each force component (SI, in `forces` order; of a harmonic
    /// run, over a period of its Fourier-reduced force).
    pub residual_rms: Vec<f64>,
    /// A harmonic run: the periods it was reduced over.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periods: Option<harmonic::Periods>,
}

/// The stage's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaptiveResult {
    /// Model name.
    pub model: String,
    /// The measured force components, in order (`fx`, `fy`, `mz`).
    pub forces: Vec<String>,
    /// The fitted coefficients with their sigmas.
    pub coefficients: Vec<Coefficient>,
    /// Their correlations.
    pub correlation: Correlation,
    /// The noise of each force component the fit found from the rows of steady tables
    /// (SI); empty when every condition has its own standard errors.
    pub noise: Vec<f64>,
    /// Gauss-Newton iterations.
    pub iterations: usize,
    /// Each table.
    pub runs: Vec<RunSummary>,
    /// Things to know.
    pub warnings: Vec<Warning>,
    /// Covariance of the fitted coefficients, for the uncertainty budget.
    #[serde(skip)]
    pub covariance: Vec<Vec<f64>>,
}

impl CaptiveResult {
    /// Puts the fitted coefficients into `set` with their uncertainty directions: the fit's
    /// statistics and the estimates' change along earlier stages' directions (`upstream`).
    pub fn merge_into(&self, set: &mut CoefficientSet, upstream: Vec<Direction>) {
        let names: Vec<&str> = self.coefficients.iter().map(|c| c.name.as_str()).collect();
        let mut directions = directions_of("captive statistics", &names, &self.covariance);
        directions.extend(upstream);
        set.merge_stage(self.coefficients.clone(), directions);
    }
}

/// Runs the stage on its tables.
pub fn run(
    cfg: &CaptiveConfig,
    vehicle: &RunVehicle,
    known: &CoefficientSet,
    runs: &[Record],
) -> Result<CaptiveResult> {
    with_model(
        cfg.model,
        vehicle,
        Fit {
            cfg,
            known,
            runs,
            reference: reference_of(&vehicle.vehicle),
            vehicle: &vehicle.vehicle,
        },
    )
    .map_err(Error::vehicle)?
}

struct Fit<'a> {
    cfg: &'a CaptiveConfig,
    known: &'a CoefficientSet,
    runs: &'a [Record],
    /// The vehicle's scales (its length is that of a rate's steadiness).
    reference: plausibility::Reference,
    /// The vehicle.
    vehicle: &'a Vehicle,
}

/// The scales of the vehicle the plausibility checks compare with: its mass and length, and
/// the draught (`vehicle.particulars.draught`) or diameter that give its analytic added
/// masses.
fn reference_of(vehicle: &Vehicle) -> plausibility::Reference {
    #[derive(serde::Deserialize)]
    struct Draught {
        #[serde(
            default,
            deserialize_with = "crate::base::si::option::<_, crate::base::si::Length>"
        )]
        draught: Option<f64>,
    }
    let draught = toml::Value::Table(vehicle.particulars.clone())
        .try_into::<Draught>()
        .ok()
        .and_then(|d| d.draught);
    plausibility::Reference::new(
        vehicle.rho,
        vehicle.length,
        vehicle.mass,
        draught,
        vehicle.diameter,
    )
}

/// What turns a table's columns into SI: the prime system and the water density.
struct Frame {
    prime: Option<crate::config::captive::PrimeSystem>,
    rho: f64,
}

/// The non-dimensional column of each dimensional force (and whether it is a moment).
fn prime_of(force: Quantity) -> Option<(Quantity, bool)> {
    match force {
        Quantity::Fx => Some((Quantity::XPrime, false)),
        Quantity::Fy => Some((Quantity::YPrime, false)),
        Quantity::Mz => Some((Quantity::NPrime, true)),
        _ => None,
    }
}

/// What the stage has read before it fits: the model's coefficient vector with the known
/// values and the indices of the estimated ones, the conditions of every run, each run's
/// size, and what the reading noticed.
struct Prepared {
    base: Vec<f64>,
    est: Vec<usize>,
    conditions: Vec<Condition>,
    sizes: Vec<(String, usize, Option<harmonic::Periods>)>,
    warnings: Vec<Warning>,
    /// What the plausibility checks of the tables found (a clear mistake stops the run
    /// before any stage, `captive.checks`).
    findings: Vec<Finding>,
}

/// What the checks of the runs compare with: the vehicle and its scales, and the value of a
/// coefficient the configuration (or an earlier stage) gives.
struct View<'a> {
    vehicle: &'a Vehicle,
    reference: plausibility::Reference,
    expected: &'a dyn Fn(&str) -> Option<f64>,
}

/// Everything the stage checks before it fits (the model gives forces, the estimated
/// coefficients are the model's own, every held one has a value from `known`, every run reads
/// into conditions, the plausibility of each table), shared by the fit and [`preflight`].
fn prepare<M: Model>(
    model: &M,
    cfg: &CaptiveConfig,
    runs: &[&Record],
    view: &View,
    known: &dyn Fn(&str) -> Option<f64>,
) -> Result<Prepared> {
    let reference = &view.reference;
    let (rho, length) = (reference.rho, reference.length);
    let layout = plausibility::Layout::of(model);
    let forces = model.force_quantities();
    if forces.is_empty() {
        return Err(Error::numerical(
            STAGE,
            format!(
                "the {} model gives no forces for a prescribed motion, so captive runs cannot be \
                 fitted with it",
                model.name()
            ),
        ));
    }
    let (base, est) = coefficient_vector(model, cfg, known)?;
    let frame = Frame {
        prime: cfg.prime,
        rho,
    };
    let mut prepared = Prepared {
        base,
        est,
        conditions: Vec::new(),
        sizes: Vec::new(),
        warnings: Vec::new(),
        findings: Vec::new(),
    };
    let expectation = checks::expectation(model, cfg, view);
    let judge = checks::judge(model, cfg, view, &expectation);
    prepared.findings.extend(
        cfg.prime
            .and_then(|p| plausibility::table::prime_length(p.length, length)),
    );
    for (index, rec) in runs.iter().enumerate() {
        let oscillation = cfg.oscillations.get(&rec.name);
        let mut names = checks::names(rec, index, view.vehicle);
        names.oscillation = oscillation.map(|_| format!("captive.oscillations.\"{}\"", rec.name));
        let mut c = conditions_of(model, rec, &frame, oscillation)?;
        let mut periods = None;
        if let Some(after) = cfg.average_after {
            let held = Held {
                forces,
                velocities: velocity_kinds(model),
                length,
            };
            let (one, w, p) = history(rec, c, after, &held)?;
            prepared.warnings.extend(w);
            periods = p;
            c = vec![one];
        } else {
            let (kept, copies) = plausibility::table::duplicates(c, &names);
            prepared.findings.extend(copies);
            c = kept;
        }
        let (found, explained) = checks::examine(&judge, &names, rec, &c, &prepared.est);
        prepared.findings.extend(found);
        let found = plausibility::before(&rec.name, &c, &layout, reference, explained)
            .map_err(|m| Error::numerical(STAGE, format!("run '{}': {m}", rec.name)))?;
        prepared.warnings.extend(found);
        prepared.sizes.push((rec.name.clone(), c.len(), periods));
        prepared.conditions.extend(c);
    }
    // force histories averaged one condition per run: their signs and sizes across the runs
    let averaged: Vec<&Condition> = prepared
        .conditions
        .iter()
        .filter(|c| c.sigma.is_some() && c.harmonic.is_none())
        .collect();
    let found = plausibility::across_runs(&averaged, &layout, reference);
    prepared.warnings.extend(found);
    Ok(prepared)
}

impl ModelVisitor for Fit<'_> {
    type Output = Result<CaptiveResult>;

    fn visit<M: Model>(self, model: &M) -> Result<CaptiveResult> {
        let cfg = self.cfg;
        let forces = model.force_quantities();
        let runs: Vec<&Record> = self.runs.iter().collect();
        let known = |n: &str| self.known.get(n).map(|c| c.value);
        let view = View {
            vehicle: self.vehicle,
            reference: self.reference,
            expected: &known,
        };
        let Prepared {
            base,
            est,
            conditions,
            sizes,
            mut warnings,
            findings,
        } = prepare(model, cfg, &runs, &view, &known)?;
        // a clear mistake stopped the run before any stage unless `captive.checks = "warn"`
        warnings.extend(findings.into_iter().map(|f| f.warning));
        let start: Vec<f64> = cfg
            .estimate
            .iter()
            .map(|n| cfg.start.get(n).copied().unwrap_or(0.0))
            .collect();
        let signs: Vec<f64> = cfg
            .estimate
            .iter()
            .map(|n| match cfg.signs.get(n) {
                Some(crate::config::captive::Sign::Positive) => 1.0,
                Some(crate::config::captive::Sign::Negative) => -1.0,
                None => 0.0,
            })
            .collect();
        let mut f = fit::fit(model, &base, &est, &start, &signs, &conditions)
            .map_err(|m| Error::numerical(STAGE, m))?;
        let misfit: Vec<String> = forces
            .iter()
            .zip(&f.birge)
            .filter(|(_, b)| **b > BIRGE_WARNING)
            .map(|(q, b)| format!("{} ({} times)", q.key(), crate::base::numfmt::num(*b)))
            .collect();
        if !misfit.is_empty() {
            warnings.push(Warning::new(
                STAGE,
                format!(
                    "the model misses the measured forces by more than their standard errors \
                     explain: {}",
                    misfit.join(", ")
                ),
                "a fixed coefficient is off (one from an earlier stage or [coefficients]), or \
                 the model lacks a term the runs excite; the sigmas of what these components \
                 determine are widened by these factors. Estimating the fixed coefficient \
                 here, or in a joint HEKF, removes the bias",
            ));
        }
        let worst = add_range_term(
            model,
            (&base, &est, &signs),
            &conditions,
            self.reference.length,
            &mut f,
        );
        let shift = worst.map(|(i, d, s)| (cfg.estimate[i].as_str(), d, s));
        warnings.extend(misfit_warning(forces, &f.misfit, shift));
        let (coefficients, bound) = fitted(model.name(), cfg, &f, &signs, conditions.len());
        warnings.extend(bound);
        let runs = residual_summaries(model, &base, &est, &f.values, &conditions, &sizes);
        Ok(CaptiveResult {
            model: model.name().to_string(),
            forces: forces.iter().map(|q| q.key().to_string()).collect(),
            coefficients,
            correlation: Correlation::from_covariance(cfg.estimate.clone(), |a, b| {
                f.covariance[a][b]
            }),
            // the noise found from the residuals: only rows without their own standard error
            noise: if conditions.iter().any(|c| c.sigma.is_none()) {
                f.noise.clone()
            } else {
                Vec::new()
            },
            iterations: f.iterations,
            runs,
            warnings,
            covariance: f.covariance,
        })
    }
}

/// The warning of the lack-of-fit test of the steady rows ([`fit::Fit::misfit`]), with the
/// largest shift of a coefficient when the outer conditions are left out (`shift`: name,
/// shift, its sigma before the range term).
fn misfit_warning(
    forces: &[Quantity],
    ratios: &[f64],
    shift: Option<(&str, f64, f64)>,
) -> Option<Warning> {
    let missed: Vec<String> = forces
        .iter()
        .zip(ratios)
        .filter(|(_, f)| **f > fit::MISFIT_RATIO)
        .map(|(q, f)| format!("{} ({} times)", q.key(), crate::base::numfmt::num(*f)))
        .collect();
    let moved = shift.map_or(String::new(), |(name, d, s)| {
        format!(
            "; without the outer quarter of the conditions' range {name} moves by {} ({} of its \
             sigma from the residuals)",
            crate::base::numfmt::num(d),
            crate::base::numfmt::num(d.abs() / s.max(f64::MIN_POSITIVE))
        )
    });
    (!missed.is_empty()).then(|| {
        Warning::new(
            STAGE,
            format!(
                "lack of fit: the residuals of the steady rows vary with the condition; their \
                 variance over the pure noise of near-neighbour conditions is {}, 1 when the \
                 model fits{moved}",
                missed.join(", ")
            ),
            "the model lacks a term the runs excite (a higher power of the drift or yaw \
             rate), or a fixed coefficient is off: the fitted coefficients depend on the \
             range of the conditions. The sigmas are widened by the square roots of these \
             ratios and by the shift of the coefficients when the outer quarter of the \
             conditions' range is left out (docs/stages.md, \"Captive plausibility\")",
        )
        .failed(crate::base::warning::Test::Misfit)
    })
}

/// When the steady rows show a lack of fit: the fit again without the outer quarter of
/// their range ([`plausibility::inner`]), and its shift d of each coefficient, beyond what
/// the noise explains, added to its variance: max(0, d^2 - (V_inner - V)) (the variance of
/// the difference of two nested fits without misfit, Hausman 1978 eq. 2.4). A model-error
/// term: how far the answer depends on the range the model is made to cover. Returns the
/// coefficient that moved most against its sigma before the term.
fn add_range_term<M: Model>(
    model: &M,
    (base, est, signs): (&[f64], &[usize], &[f64]),
    conditions: &[Condition],
    length: f64,
    f: &mut fit::Fit,
) -> Option<(usize, f64, f64)> {
    if !f.misfit.iter().any(|r| *r > fit::MISFIT_RATIO) {
        return None;
    }
    let keep = plausibility::inner(conditions, &plausibility::Layout::of(model), length);
    let kept: Vec<Condition> = conditions
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(c, _)| c.clone())
        .collect();
    if kept.len() == conditions.len() {
        return None;
    }
    let inner = fit::fit(model, base, est, &f.values, signs, &kept).ok()?;
    let sigma = |i: usize| f.covariance[i][i].max(0.0).sqrt();
    let p = f.values.len();
    let worst = (0..p)
        .map(|i| (i, inner.values[i] - f.values[i], sigma(i)))
        .max_by(|a, b| (a.1.abs() / a.2).total_cmp(&(b.1.abs() / b.2)))?;
    for i in 0..p {
        let d = inner.values[i] - f.values[i];
        let noise = (inner.covariance[i][i] - f.covariance[i][i]).max(0.0);
        f.covariance[i][i] += (d * d - noise).max(0.0);
    }
    Some(worst)
}

/// The fitted coefficients with their sigmas (one that ends on its sign bound held at 0
/// without a sigma), and the warning naming those held.
fn fitted(
    model: &str,
    cfg: &CaptiveConfig,
    f: &fit::Fit,
    signs: &[f64],
    n_conditions: usize,
) -> (Vec<Coefficient>, Option<Warning>) {
    let p = cfg.estimate.len();
    let sigma = |i: usize| f.covariance[i][i].max(0.0).sqrt();
    let at_bound = |i: usize| signs[i] != 0.0 && f.values[i] == 0.0;
    let coefficients: Vec<Coefficient> = (0..p)
        .map(|i| {
            let mut c = Coefficient::new(
                &cfg.estimate[i],
                f.values[i],
                Some(sigma(i)),
                Source::Captive,
            );
            c.note = Some(format!(
                "{model} model fitted to the forces of {n_conditions} captive conditions"
            ));
            if at_bound(i) {
                c.held(&format!(
                    "its sign bound 0 (captive.signs.{}): the data want the other sign",
                    cfg.estimate[i]
                ))
            } else {
                c
            }
        })
        .collect();
    let bounded: Vec<&str> = (0..p)
        .filter(|&i| at_bound(i))
        .map(|i| cfg.estimate[i].as_str())
        .collect();
    let warning = (!bounded.is_empty()).then(|| {
        Warning::new(
            STAGE,
            format!(
                "held at their sign bound 0 (captive.signs): {}",
                bounded.join(", ")
            ),
            "the forces pull these coefficients across the sign you gave; they are held at \
             0 without variance and the others are fitted with them there. A coefficient \
             whose sign the runs cannot tell is better left free or given a known value",
        )
    });
    (coefficients, warning)
}

/// The model's coefficient vector with the known values, and the indices of the estimated.
fn coefficient_vector<M: Model>(
    model: &M,
    cfg: &CaptiveConfig,
    known: &dyn Fn(&str) -> Option<f64>,
) -> Result<(Vec<f64>, Vec<usize>)> {
    let names = model.coefficient_names();
    let mut est = Vec::new();
    for n in &cfg.estimate {
        match model.coefficient_index(n) {
            Some(i) if !model.is_derived(n) => est.push(i),
            Some(_) => {
                return Err(Error::numerical(
                    STAGE,
                    format!(
                        "{n} is derived by a relation of the {} model and cannot be fitted",
                        model.name()
                    ),
                ))
            }
            None => {
                return Err(Error::numerical(
                    STAGE,
                    format!("the {} model has no coefficient {n}", model.name()),
                ))
            }
        }
    }
    let mut base = vec![0.0; names.len()];
    let mut missing = Vec::new();
    for (i, n) in names.iter().enumerate() {
        if est.contains(&i) || model.is_derived(n) {
            continue;
        }
        match known(n) {
            Some(v) => base[i] = v,
            None if model.is_optional(n) => {}
            None => missing.push(*n),
        }
    }
    if !missing.is_empty() {
        return Err(Error::numerical(
            STAGE,
            format!(
                "no value for {} (held fixed by the fit): give them in [coefficients] or add \
                 them to captive.estimate",
                missing.join(", ")
            ),
        ));
    }
    Ok((base, est))
}

/// The steady conditions of one table: a row each. The motion is the columns `u`, `v`, `r`
/// (0 when a velocity is neither a column nor a constant: a static drift has no r), or, in
/// a table of non-dimensional results, `speed` U with `drift` beta (u = U cos beta,
/// v = -U sin beta; Y&Y 2015 eq. 5) and `r_prime` (r = r' U / L); the inputs come from
/// columns or constants; each force is its column in SI, or its prime column times
/// 0.5 rho A U^2 (and L for a moment).
///
/// A run with a prescribed `oscillation` (a force file of a PMM run) takes each oscillating
/// velocity as its constant (or 0) plus A sin(2 pi f t + phase) at the row's time.
fn conditions_of<M: Model>(
    model: &M,
    rec: &Record,
    frame: &Frame,
    oscillation: Option<&crate::config::captive::Oscillation>,
) -> Result<Vec<Condition>> {
    check_columns(model, rec, frame)?;
    let table = Table {
        rec,
        frame,
        oscillation,
        by_drift: motion_columns(rec, oscillation)?,
    };
    (0..rec.rows()).map(|k| table.condition(model, k)).collect()
}

/// An error of the run `rec`.
fn run_error(rec: &Record, m: String) -> Error {
    Error::numerical(STAGE, format!("run '{}': {m}", rec.name))
}

/// Whether the table gives what the model's conditions need: the prime system of its
/// non-dimensional columns, each captive force (or its prime column) and each input.
fn check_columns<M: Model>(model: &M, rec: &Record, frame: &Frame) -> Result<()> {
    let uses_prime = [
        Quantity::RPrime,
        Quantity::XPrime,
        Quantity::YPrime,
        Quantity::NPrime,
    ]
    .iter()
    .any(|q| rec.has(*q));
    if uses_prime && frame.prime.is_none() {
        return Err(run_error(
            rec,
            "the table has non-dimensional columns (r_prime, x_prime, y_prime or n_prime): \
             give their normalisation, captive.prime = { length = ..., area = ... }"
                .into(),
        ));
    }
    for q in model.force_quantities() {
        let prime = prime_of(*q).map(|(p, _)| p);
        if !rec.has(*q) && !prime.is_some_and(|p| rec.has(p)) {
            return Err(run_error(
                rec,
                format!(
                    "no {q}{} column: the {} model's captive forces are {}",
                    prime.map(|p| format!(" (or {p})")).unwrap_or_default(),
                    model.name(),
                    model
                        .force_quantities()
                        .iter()
                        .map(|q| q.key())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    }
    for q in model.input_quantities() {
        if !rec.has(q) {
            return Err(run_error(
                rec,
                format!(
                    "no {q}: the {} model needs it (a column, or `constants = {{ {q} = ... }}`)",
                    model.name()
                ),
            ));
        }
    }
    Ok(())
}

/// Whether the table gives its motion (its prescribed oscillation, if any, with the time
/// and no column of the same velocity): true when by speed and drift, false when by u.
fn motion_columns(
    rec: &Record,
    oscillation: Option<&crate::config::captive::Oscillation>,
) -> Result<bool> {
    let fail = |m: &str| Err(run_error(rec, m.to_string()));
    if let Some(o) = oscillation {
        for q in o.amplitude.keys() {
            if rec.channel(*q).is_some() {
                return Err(run_error(
                    rec,
                    format!(
                        "{q} is both a column and a prescribed oscillation \
                         (captive.oscillations): give one"
                    ),
                ));
            }
        }
        if rec.time().is_none() {
            return fail("a prescribed oscillation needs the time column of the force history");
        }
    }
    let by_drift = rec.has(Quantity::Drift);
    if by_drift && !rec.has(Quantity::Speed) {
        return fail("a drift column needs the speed U (`speed`) too");
    }
    let u_given =
        rec.has(Quantity::U) || oscillation.is_some_and(|o| o.amplitude.contains_key(&Quantity::U));
    if !by_drift && !u_given {
        return fail("no motion: give u (and v, r) or speed and drift (and r_prime)");
    }
    Ok(by_drift)
}

/// A table checked by [`check_columns`] and [`motion_columns`], read row by row.
struct Table<'a> {
    rec: &'a Record,
    frame: &'a Frame,
    oscillation: Option<&'a crate::config::captive::Oscillation>,
    /// The motion is given by speed and drift (else by u).
    by_drift: bool,
}

impl Table<'_> {
    /// The value of `q` at row `k`: its column's, else its constant.
    fn value(&self, q: Quantity, k: usize) -> Option<f64> {
        self.rec
            .channel(q)
            .map(|v| v[k])
            .or_else(|| self.rec.constants.get(&q).copied())
    }

    /// The prescribed oscillating velocity `q` at row `k` (its constant, or 0, plus
    /// A sin(2 pi f t + phase)); None when `q` does not oscillate.
    fn oscillating(&self, q: Quantity, k: usize) -> Option<f64> {
        let o = self.oscillation?;
        let a = o.amplitude.get(&q)?.si;
        let t = self.rec.time()?[k];
        let mean = self.rec.constants.get(&q).copied().unwrap_or(0.0);
        Some(mean + a * (2.0 * std::f64::consts::PI * o.frequency * t + o.phase).sin())
    }

    /// The velocity `q` at row `k` with the speed U `speed`.
    fn motion(&self, q: Quantity, k: usize, speed: Option<f64>) -> Option<f64> {
        if let Some(v) = self.oscillating(q, k) {
            return Some(v);
        }
        let rec = self.rec;
        match (q, self.by_drift) {
            (Quantity::U, true) => Some(speed? * self.value(Quantity::Drift, k)?.cos()),
            (Quantity::V, true) => Some(-speed? * self.value(Quantity::Drift, k)?.sin()),
            (Quantity::R, _) if !rec.has(Quantity::R) && rec.has(Quantity::RPrime) => {
                Some(self.value(Quantity::RPrime, k)? * speed? / self.frame.prime?.length)
            }
            _ => self.value(q, k),
        }
    }

    /// The force `q` at row `k` in SI: its column, or its prime column times
    /// 0.5 rho A U^2 (and L for a moment); NaN when neither gives it.
    fn force(&self, q: Quantity, k: usize, speed: Option<f64>) -> f64 {
        match (self.value(q, k), prime_of(q)) {
            (Some(v), _) => v,
            (None, Some((p, moment))) => match (self.value(p, k), speed, self.frame.prime) {
                (Some(v), Some(speed), Some(ps)) => {
                    let q = 0.5 * self.frame.rho * ps.area * speed * speed;
                    v * if moment { q * ps.length } else { q }
                }
                _ => f64::NAN,
            },
            (None, None) => f64::NAN,
        }
    }

    /// The steady condition of row `k`.
    fn condition<M: Model>(&self, model: &M, k: usize) -> Result<Condition> {
        let rec = self.rec;
        let line = rec.lines.get(k).copied().unwrap_or(k + 1);
        let speed = self.value(Quantity::Speed, k);
        if rec.has(Quantity::RPrime) && speed.is_none() {
            return Err(run_error(
                rec,
                format!("line {line}: r_prime needs the speed U (`speed`)"),
            ));
        }
        let x: Vec<f64> = model
            .states()
            .iter()
            .map(|s| match s.quantity {
                q if Quantity::MOTION[..6].contains(&q) => self.motion(q, k, speed).unwrap_or(0.0),
                _ => 0.0,
            })
            .collect();
        let u: Vec<f64> = model
            .input_quantities()
            .iter()
            .map(|q| self.value(*q, k).unwrap_or(0.0))
            .collect();
        let f: Vec<f64> = model
            .force_quantities()
            .iter()
            .map(|q| self.force(*q, k, speed))
            .collect();
        if x.iter().chain(&u).chain(&f).any(|v| !v.is_finite()) {
            return Err(run_error(
                rec,
                format!(
                    "line {line}: a value is missing or not a number (a prime force needs the \
                     speed U in `speed`)"
                ),
            ));
        }
        Ok(Condition {
            x,
            u,
            f,
            sigma: None,
            place: format!("{} line {line}", rec.name),
            harmonic: None,
        })
    }
}

/// Birge ratio of a force component above which the misfit is reported.
const BIRGE_WARNING: f64 = 2.0;

/// Fewest samples a force history is averaged over.
const MIN_AVERAGED: usize = 10;

/// What [`history`] knows of the model: its force components, which states are linear
/// velocities (`Some(false)`) or rates (`Some(true)`), and the vehicle's length.
struct Held<'a> {
    forces: &'a [Quantity],
    velocities: Vec<(&'static str, Option<bool>)>,
    length: f64,
}

/// For each state of the model, its name and Some(false) for a linear velocity, Some(true)
/// for an angular rate, None for a position or angle.
fn velocity_kinds<M: Model>(model: &M) -> Vec<(&'static str, Option<bool>)> {
    model
        .states()
        .iter()
        .map(|s| {
            let kind = match s.quantity {
                Quantity::U | Quantity::V | Quantity::W => Some(false),
                Quantity::P | Quantity::Q | Quantity::R => Some(true),
                _ => None,
            };
            (s.name, kind)
        })
        .collect()
}

/// Largest share of the speed (of U / L for a rate) by which a held motion may vary over the
/// averaged part of a force history.
const STEADY_MOTION: f64 = 0.02;

/// A force history from `after` (s) on: averaged into one condition when its held motion is
/// steady, reduced to Fourier parts over whole periods when a velocity oscillates (a PMM
/// run, [`harmonic::reduce`]).
fn history(
    rec: &Record,
    rows: Vec<Condition>,
    after: f64,
    held: &Held,
) -> Result<(Condition, Option<Warning>, Option<harmonic::Periods>)> {
    let fail = |m: String| Error::numerical(STAGE, format!("run '{}': {m}", rec.name));
    let times = rec
        .time()
        .ok_or_else(|| fail("a force history needs a time column to be averaged".into()))?;
    let kept: Vec<(f64, &Condition)> = rows
        .iter()
        .zip(times)
        .filter(|(_, t)| **t >= after)
        .map(|(c, t)| (*t, c))
        .collect();
    if kept.len() < MIN_AVERAGED {
        return Err(fail(format!(
            "{} samples from t = {} s on (captive.average_after): at least {MIN_AVERAGED} are \
             needed to average; the run ends at t = {} s",
            kept.len(),
            crate::base::numfmt::num(after),
            crate::base::numfmt::num(times.last().copied().unwrap_or(0.0))
        )));
    }
    let oscillating = moving_states(&kept, held);
    if oscillating.is_empty() {
        let kept: Vec<&Condition> = kept.iter().map(|(_, c)| *c).collect();
        let (c, w) = averaged(rec, &kept, after, held.forces);
        return Ok((c, w, None));
    }
    let samples: Vec<harmonic::Sample> = kept
        .iter()
        .map(|(t, row)| harmonic::Sample { t: *t, row })
        .collect();
    let names: Vec<&str> = held.velocities.iter().map(|(n, _)| *n).collect();
    let forces: Vec<&str> = held.forces.iter().map(|q| q.key()).collect();
    let (c, periods, w) = harmonic::reduce(&rec.name, &samples, &oscillating, &names, &forces)
        .map_err(|m| {
            fail(format!(
                "from t = {} s: {m}",
                crate::base::numfmt::num(after)
            ))
        })?;
    Ok((c, w, Some(periods)))
}

/// The velocity states that vary by more than [`STEADY_MOTION`] of their scale over the
/// samples (none: a steady run).
fn moving_states(kept: &[(f64, &Condition)], held: &Held) -> Vec<usize> {
    let n = kept.len() as f64;
    let mean: Vec<f64> = (0..kept[0].1.x.len())
        .map(|i| kept.iter().map(|(_, c)| c.x[i]).sum::<f64>() / n)
        .collect();
    let speed = mean
        .iter()
        .zip(&held.velocities)
        .filter(|(_, (_, k))| *k == Some(false))
        .map(|(v, _)| v * v)
        .sum::<f64>()
        .sqrt();
    held.velocities
        .iter()
        .enumerate()
        .filter(|(i, (_, kind))| {
            let Some(rate) = kind else { return false };
            let scale = if *rate { speed / held.length } else { speed };
            let (lo, hi) = crate::numerics::signal::range(kept.iter().map(|(_, c)| c.x[*i]));
            hi - lo > 2.0 * STEADY_MOTION * scale
        })
        .map(|(i, _)| i)
        .collect()
}

/// The rows of a steady force history averaged into one condition, each force's
/// uncertainty the standard error of its mean ([`crate::numerics::signal::mean_and_standard_error`]);
/// a warning when a force still drifts (the means of the two halves differ by more than
/// three combined standard errors).
fn averaged(
    rec: &Record,
    kept: &[&Condition],
    after: f64,
    forces: &[Quantity],
) -> (Condition, Option<Warning>) {
    let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len() as f64;
    let x: Vec<f64> = (0..kept[0].x.len())
        .map(|i| mean(kept.iter().map(|c| c.x[i]).collect()))
        .collect();
    let u = (0..kept[0].u.len())
        .map(|i| mean(kept.iter().map(|c| c.u[i]).collect()))
        .collect();
    let mut f = Vec::new();
    let mut sigma = Vec::new();
    let mut drifting = Vec::new();
    for i in 0..kept[0].f.len() {
        let series: Vec<f64> = kept.iter().map(|c| c.f[i]).collect();
        let (m, se) =
            crate::numerics::signal::mean_and_standard_error(&series).unwrap_or((series[0], 0.0));
        let half = series.len() / 2;
        if let (Some((m1, s1)), Some((m2, s2))) = (
            crate::numerics::signal::mean_and_standard_error(&series[..half]),
            crate::numerics::signal::mean_and_standard_error(&series[half..]),
        ) {
            if (m1 - m2).abs() > 3.0 * s1.hypot(s2) {
                drifting.push(format!(
                    "{} ({} then {})",
                    forces.get(i).map_or("a force", |q| q.key()),
                    crate::base::numfmt::num(m1),
                    crate::base::numfmt::num(m2)
                ));
            }
        }
        f.push(m);
        sigma.push(se);
    }
    let warning = (!drifting.is_empty()).then(|| {
        Warning::new(
            STAGE,
            format!(
                "the forces still drift in the averaged part from t = {} s: {} (mean of the \
                 first half, then of the second)",
                crate::base::numfmt::num(after),
                drifting.join(", ")
            ),
            "the run may not have reached its steady state: its average and standard error \
             are biased; average from a later time (captive.average_after) or run longer",
        )
        .for_run(&rec.name)
    });
    (
        Condition {
            x,
            u,
            f,
            sigma: Some(sigma),
            place: format!(
                "{} from t = {} s",
                rec.name,
                crate::base::numfmt::num(after)
            ),
            harmonic: None,
        },
        warning,
    )
}

/// The RMS residual of each force component per table (of a harmonic run: over one period
/// of the Fourier-reduced force, sqrt(a0^2 + sum (a_k^2 + b_k^2) / 2) of the residual parts).
fn residual_summaries<M: Model>(
    model: &M,
    base: &[f64],
    est: &[usize],
    values: &[f64],
    conditions: &[Condition],
    sizes: &[(String, usize, Option<harmonic::Periods>)],
) -> Vec<RunSummary> {
    let mut c = base.to_vec();
    for (&i, v) in est.iter().zip(values) {
        c[i] = *v;
    }
    model.relations().apply(&mut c);
    let nf = model.force_quantities().len();
    let mut out = Vec::new();
    let mut k0 = 0;
    for (name, n, periods) in sizes {
        let mut ss = vec![0.0; nf];
        for cond in &conditions[k0..k0 + n] {
            let mut f = vec![0.0; cond.f.len()];
            cond.predict(model, &c, &mut f);
            for (k, (m, p)) in cond.f.iter().zip(&f).enumerate() {
                let weight = match (&cond.harmonic, k % harmonic::PER_FORCE) {
                    (Some(_), 0) | (None, _) => 1.0,
                    (Some(_), _) => 0.5,
                };
                ss[cond.component(k)] += weight * (m - p).powi(2);
            }
        }
        out.push(RunSummary {
            name: name.clone(),
            conditions: *n,
            residual_rms: ss.iter().map(|s| (s / (*n).max(1) as f64).sqrt()).collect(),
            periods: periods.clone(),
        });
        k0 += n;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::surge1::Surge1;

    #[test]
    fn a_model_without_forces_for_a_prescribed_motion_is_refused() {
        let model = Surge1::build(&Surge1::example_vehicle()).unwrap();
        let cfg: CaptiveConfig =
            toml::from_str("model = \"surge1\"\nestimate = [\"Xud\"]\nruns = []").unwrap();
        let known = CoefficientSet::new();
        let e = Fit {
            cfg: &cfg,
            known: &known,
            runs: &[],
            reference: plausibility::Reference::new(1000.0, 1.2, 10.0, None, None),
            vehicle: &Surge1::example_vehicle(),
        }
        .visit(&model)
        .unwrap_err()
        .to_string();
        assert!(e.contains("gives no forces for a prescribed motion"), "{e}");
    }
}
