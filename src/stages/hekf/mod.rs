//! Hybrid EKF stage (paper section 4, eq. 9-19 and 22): coefficients appended to the state of
//! a vehicle model and estimated from CFD motion histories, the rest held fixed.

use crate::config::hekf as config;
mod adapt;
mod balance;
pub mod bounds;
mod consistency;
pub mod history;
pub mod identifiability;
pub mod identify;
mod likelihood;
pub mod memory;
pub mod modes;
mod noise;
mod prepare;
mod result;
mod sensitivity;
pub mod states;
pub mod tuning;

pub use crate::model::models::ModelName;
pub use config::{Checks, FilterKind, HekfConfig, Mode, Outliers, Preset, Prior, DEFAULT_GATE};
pub use history::History;
mod plausibility;
pub use result::{HekfResult, PassSummary, RunSummary, RunTraces};

use crate::base::error::{Error, Result};
use crate::base::progress::Progress;
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::io::record::{Needs, Record};
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelVisitor, RunVehicle};
use identify::{identify, IdentifyError};

/// The stage's name in messages and warnings.
pub(crate) const STAGE: &str = "hekf";

/// Quantities the stage reads from a run: time, every motion quantity (the 6-DOF ones are
/// read when present, to warn when a 3-DOF model ignores out-of-plane motion) and every
/// model's inputs.
pub fn needs(_cfg: &HekfConfig) -> Needs<'static> {
    static OPTIONAL: std::sync::OnceLock<Vec<Quantity>> = std::sync::OnceLock::new();
    let optional = OPTIONAL.get_or_init(|| {
        Quantity::MOTION
            .iter()
            .chain(crate::model::models::registry::all_inputs())
            .copied()
            .collect()
    });
    Needs {
        required: &[Quantity::Time],
        optional,
        min_rows: 10,
    }
}

/// Everything the stage needs besides its configuration.
pub struct StageInputs<'a> {
    /// The run's vehicle ([`crate::config::LoadedConfig::vehicle`]).
    pub vehicle: &'a RunVehicle,
    /// Coefficients known from earlier stages, the configuration and analytic estimates.
    pub known: &'a CoefficientSet,
    /// The identification runs.
    pub runs: &'a [Record],
    /// The configuration's folder: run files are reported relative to it.
    pub base_dir: &'a std::path::Path,
}

/// Runs the stage.
pub fn run(
    cfg: &HekfConfig,
    inputs: &StageInputs,
    progress: &mut dyn Progress,
) -> Result<HekfResult> {
    with_model(
        cfg.model,
        inputs.vehicle,
        Identify {
            cfg,
            inputs,
            progress,
        },
    )
    .map_err(Error::vehicle)?
}

/// What [`preflight`] found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Preflight {
    /// Problems that stop the run before any stage runs.
    pub problems: Vec<String>,
    /// The plausibility checks' warnings, each about a run (with `hekf.checks = "warn"`,
    /// their clear mistakes too), in the order of the runs.
    pub warnings: Vec<Warning>,
}

/// Problems the stage would meet, found before any stage runs: estimated coefficients the
/// model does not have or that a relation derives, fixed coefficients that nothing will
/// provide (`available`: names the configuration, analytic formulas and enabled stages give),
/// model inputs a run lacks, a run too large for the memory there is, and the plausibility
/// checks of every run (a clear mistake is a problem with `hekf.checks = "error"`; the model
/// is judged at the `configured` coefficients over its example). `runs` are the fit runs
/// followed by the validation runs, as [`HekfConfig::inputs`] lists them.
pub fn preflight(
    cfg: &HekfConfig,
    vehicle: &RunVehicle,
    available: &[String],
    configured: &std::collections::BTreeMap<String, f64>,
    runs: &[&Record],
) -> Preflight {
    struct Pre<'a> {
        cfg: &'a HekfConfig,
        available: &'a [String],
        configured: &'a std::collections::BTreeMap<String, f64>,
        vehicle: crate::model::models::Vehicle,
        runs: &'a [&'a Record],
    }
    impl ModelVisitor for Pre<'_> {
        type Output = Preflight;
        fn visit<M: Model>(self, model: &M) -> Preflight {
            let mut p = prepare::coefficient_problems(model, self.cfg, |n| {
                self.available.iter().any(|a| a == n)
            })
            .err()
            .unwrap_or_default();
            let configured = |n: &str| self.configured.get(n).copied();
            let expect = expectation(model, self.cfg, &configured, &self.vehicle);
            let mut warnings = Vec::new();
            for r in self.runs {
                for q in model.input_quantities() {
                    if !r.has(q) {
                        p.push(format!(
                            "run '{}' gives no {q}, which the {} model needs: map a {q} column \
                             or give `constants = {{ {q} = ... }}`",
                            r.name,
                            model.name()
                        ));
                    }
                }
                for f in plausibility::before_filter(model, r, &expect) {
                    match f.sorted(self.cfg.checks, "hekf.checks") {
                        Ok(w) => warnings.push(w),
                        Err(problem) => p.push(problem),
                    }
                }
            }
            p.extend(
                self.cfg
                    .process_noise
                    .keys()
                    .filter_map(|n| prepare::process_noise_problem(model, self.cfg, n)),
            );
            p.extend(memory_problem(self.cfg, model.nx(), self.runs));
            Preflight {
                problems: p,
                warnings,
            }
        }
    }
    with_model(
        cfg.model,
        vehicle,
        Pre {
            cfg,
            available,
            configured,
            vehicle: vehicle.vehicle.clone(),
            runs,
        },
    )
    // a model that cannot be built for the vehicle is reported by the configuration's
    // validation, against the vehicle's keys
    .unwrap_or_default()
}

/// Why one of the HEKF's fit runs cannot be filtered, found before any stage runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunProblem {
    /// The key to fix, after the run's own (`hekf.runs[0]`): `columns` (no time column, no
    /// output of the model mapped), or None when it is `hekf.measure` (a quantity the model
    /// or the run lacks).
    pub run_key: Option<&'static str>,
    /// What the stage would say.
    pub message: String,
}

/// What keeps one of the HEKF's fit runs from being filtered, found before any stage runs
/// (the stage's own check of the run): no time column, no output of the model measured (a
/// column map that maps none of them, `columns = {}`), a `hekf.measure` the model or the run
/// lacks. None when the run can be filtered, or when the model cannot be built for the
/// vehicle (the configuration's validation says why).
pub fn fit_run_problem(cfg: &HekfConfig, vehicle: &RunVehicle, run: &Record) -> Option<RunProblem> {
    struct Check<'a> {
        cfg: &'a HekfConfig,
        run: &'a Record,
    }
    impl ModelVisitor for Check<'_> {
        type Output = Option<String>;
        fn visit<M: Model>(self, model: &M) -> Option<String> {
            match prepare::filterable(model, self.cfg, self.run) {
                Ok(()) => None,
                Err(Error::Numerical { message, .. }) => Some(message),
                Err(e) => Some(e.to_string()),
            }
        }
    }
    let message = with_model(cfg.model, vehicle, Check { cfg, run })
        .ok()
        .flatten()?;
    // with a time column, what the filter measures is hekf.measure's when it is given
    let measure = run.time().is_some() && cfg.measure.is_some();
    Some(RunProblem {
        run_key: (!measure).then_some("columns"),
        message,
    })
}

/// What the model expects of the runs: its coefficients at the priors' initial values that
/// say something (at least one prior sigma from zero: `initial = 1e-4, sigma = 0.3` is a
/// placeholder, not a sign), else the `configured` values, else its example's. A configured
/// value of an estimated coefficient counts only when it says something too (a tenth of the
/// coefficient's typical magnitude: `Ndr = 0.0` as the starting point of an estimate is a
/// placeholder, and judging the rudder's sign by it would refuse a sound run).
fn expectation<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    configured: &dyn Fn(&str) -> Option<f64>,
    vehicle: &crate::model::models::Vehicle,
) -> plausibility::Expectation {
    // a configured value of an estimated coefficient below a tenth of its typical magnitude
    // (`Ndr = 0.0` as the start of an estimate) is a placeholder, not a sign
    let given = |n: &str| {
        let typical = model.typical_magnitude(n);
        let informative = cfg.prior.get(n).and_then(|p| {
            let v = p.initial?;
            let sigma = p.sigma.unwrap_or(typical);
            (v.abs() >= sigma).then_some(v)
        });
        let estimated = cfg.estimate.iter().any(|e| e == n);
        informative.or_else(|| {
            configured(n).filter(|v| !estimated || v.abs() >= 0.1 * typical || v.is_nan())
        })
    };
    plausibility::Expectation::new(model, &given, vehicle)
}

struct Identify<'a> {
    cfg: &'a HekfConfig,
    inputs: &'a StageInputs<'a>,
    progress: &'a mut dyn Progress,
}

impl ModelVisitor for Identify<'_> {
    type Output = Result<HekfResult>;

    fn visit<M: Model>(self, model: &M) -> Result<HekfResult> {
        let (cfg, inputs) = (self.cfg, self.inputs);
        let (balanced, balance_warnings) = surge_balance(model, cfg, inputs);
        let cfg = &balanced;
        let tuning = tuning::Resolved::from_config(cfg);
        let plan = prepare::plan(model, cfg, &tuning, inputs.known, inputs.runs)?;
        // the model's expectation as preflight judged it: configured coefficients only
        let configured = |n: &str| {
            inputs
                .known
                .get(n)
                .filter(|c| c.source == crate::model::coefficients::Source::Config)
                .map(|c| c.value)
        };
        let expect = expectation(model, cfg, &configured, &inputs.vehicle.vehicle);
        let (runs, summaries) = prepared_runs(model, cfg, &tuning, &plan, inputs, &expect)?;
        let setup = prepare::setup(model, cfg, &plan, &tuning, &runs)?;
        let (setup, profile, kept) = match likelihood::search(model, &setup, &runs) {
            likelihood::Outcome::Nothing => (setup, None, None),
            likelihood::Outcome::Profiled(held, p) => (*held, Some(p), None),
            likelihood::Outcome::Kept(why) => (setup, None, Some(why)),
        };
        let mut id = identify(model, &setup, &runs, self.progress)
            .map_err(|e| divergence_error(model, &plan, &runs, &summaries, e))?;
        // the repeated identifications below hold the profiled coefficients: their sigmas
        // are the filter's, before the likelihood's are added
        let conditional = id
            .passes
            .last()
            .map(|p| p.sigmas.clone())
            .unwrap_or_default();
        if let Some(p) = &profile {
            likelihood::widen(&mut id, p, &plan.est_names);
        }
        let defs: Vec<&crate::model::models::CoefDef> =
            plan.est.iter().map(|&i| &model.coefficients()[i]).collect();
        let bound_warnings = bounds::warnings(&defs, &id.bounds);
        let gated = gated(&id);
        let last = id.passes.last().cloned().expect("at least one pass");
        // the repeated passes keep the noise as calibrated
        let calibrated = identify::Setup {
            run_q: id.process_noise.clone(),
            ..setup.clone()
        };
        let converged = sensitivity::Converged {
            setup: &calibrated,
            runs: &runs,
            estimate: &last.values,
            sigma: &conditional,
            est_names: &plan.est_names,
        };
        let (mut upstream, failed) = sensitivity::upstream(model, converged, inputs.known);
        let spread = sensitivity::noise_model(model, converged);
        // a move within chance is in the statistical sigma already (sensitivity::chance_variances)
        if let Some(s) = spread.as_ref().filter(|s| s.within_chance.is_none()) {
            upstream.push(s.direction.clone());
        }
        let mut result = result::build(
            model,
            cfg,
            &plan,
            &setup,
            &runs,
            summaries,
            id,
            result::Upstream {
                directions: upstream,
                failed,
            },
        );
        if let Some(worst) = spread.as_ref().and_then(|s| s.within_chance) {
            result.tuning.push(format!(
                "noise model: halving and doubling the noise moves the estimates within what a \
                 right noise model moves them by chance (at most {} of that standard \
                 deviation): in the statistical sigma, not added to the uncertainty budget",
                crate::base::numfmt::num(worst)
            ));
        }
        result
            .warnings
            .extend(noise_model_warning(&plan.est_names, spread.as_ref()));
        if let Some(why) = &kept {
            let at = likelihood::profiled(model, &setup);
            let names: Vec<&str> = at.iter().map(|&j| plan.est_names[j].as_str()).collect();
            result.warnings.push(likelihood::kept_warning(why, &names));
        }
        result.warnings.extend(balance_warnings);
        result.warnings.extend(bound_warnings);
        result.identifiability = advise(model, &plan, &runs, &result);
        result
            .warnings
            .extend(identifiability_warning(&result.identifiability));
        run_warnings(model, &mut result, &runs, &gated, setup.gate);
        Ok(result)
    }
}

/// Each run's samples the last pass's gate rejected and its excursions.
type Gated = Vec<(Vec<identify::Rejection>, Vec<identify::Excursion>)>;

/// The last pass's [`Gated`] of every run.
fn gated(id: &identify::Identification) -> Gated {
    id.traces
        .last()
        .map(|p| {
            p.iter()
                .map(|t| (t.rejected.clone(), t.excursions.clone()))
                .collect()
        })
        .unwrap_or_default()
}

/// Each run's consistency warnings (rejected samples, excursions beyond the `gate`, NIS),
/// named by the run.
fn run_warnings<M: Model>(
    model: &M,
    result: &mut HekfResult,
    runs: &[identify::RunData],
    gated: &Gated,
    gate: f64,
) {
    for ((run, data), (rej, exc)) in result.runs.iter_mut().zip(runs).zip(gated) {
        run.warnings
            .extend(consistency::gate_warning(model, data, rej));
        run.warnings
            .extend(consistency::excursion_warning(model, data, exc, gate));
        run.warnings.extend(consistency::nis_warning(run));
        for w in run.warnings.iter_mut().filter(|w| w.run.is_none()) {
            w.run = Some(run.name.clone());
        }
    }
}

/// Each run's samples for the filter, with its plausibility findings (blocking ones stopped
/// the run in preflight unless `checks = "warn"`), decimated as configured.
fn prepared_runs<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    tuning: &tuning::Resolved,
    plan: &prepare::Plan,
    inputs: &StageInputs<'_>,
    expect: &plausibility::Expectation,
) -> Result<(Vec<identify::RunData>, Vec<RunSummary>)> {
    let mut runs = Vec::new();
    let mut summaries = Vec::new();
    let held = held_estimates(model, plan);
    for rec in inputs.runs {
        let (mut data, mut summary) =
            prepare::run_data(model, cfg, tuning, rec, inputs.base_dir, &plan.reads)?;
        summary.warnings.extend(
            plausibility::before_filter(model, rec, expect)
                .into_iter()
                .filter(|f| !f.blocking || cfg.checks == Checks::Warn)
                .map(|f| f.warning),
        );
        let start = plausibility::Start {
            base: &plan.base,
            est: &plan.est,
            scale: &plan.scale,
            initial: &plan.initial,
            held: &held,
        };
        summary.warnings.extend(
            plausibility::constant_inputs(model, rec, &data, &start)
                .into_iter()
                .map(|f| f.warning),
        );
        decimate(&mut data, &mut summary, cfg.decimate.unwrap_or(1));
        runs.push(data);
        summaries.push(summary);
    }
    Ok((runs, summaries))
}

/// The held coefficients that come from an earlier stage with a sigma (polar, surge run,
/// captive runs): the constant-input check names them when they explain a misfit.
fn held_estimates<M: Model>(model: &M, plan: &prepare::Plan) -> Vec<plausibility::Held> {
    use crate::model::coefficients::Source;
    let names = model.coefficient_names();
    plan.fixed
        .iter()
        .filter(|c| matches!(c.source, Source::Polar | Source::Surge | Source::Captive))
        .filter_map(|c| {
            let sigma = c.sigma.filter(|s| s.is_finite() && *s > 0.0)?;
            Some(plausibility::Held {
                index: names.iter().position(|n| *n == c.name)?,
                sigma,
                stage: c.source.to_string(),
            })
        })
        .collect()
}

/// The configuration the stage runs: `cfg`, with the model's surge-balance coefficient added
/// to the estimated ones when a run's approach contradicts its held value
/// ([`balance::approach`]; `hekf.balance = "estimate"`), and the warnings that say so.
fn surge_balance<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    inputs: &StageInputs,
) -> (HekfConfig, Vec<Warning>) {
    let mut out = cfg.clone();
    let Some(name) = model.surge_balance() else {
        return (out, Vec::new());
    };
    let Some(held) = inputs.known.value(name) else {
        return (out, Vec::new());
    };
    if cfg.estimate.iter().any(|e| e == name) {
        return (out, Vec::new());
    }
    let pairs: Vec<(&str, f64)> = model
        .coefficient_names()
        .iter()
        .filter_map(|n| inputs.known.value(n).map(|v| (*n, v)))
        .collect();
    let c = model.coefficient_vector(&pairs);
    let found: Vec<balance::Imbalance> = inputs
        .runs
        .iter()
        .filter_map(|rec| balance::approach(model, &c, rec))
        .collect();
    let Some(worst) = found.iter().max_by(|a, b| {
        (a.measured - a.model)
            .abs()
            .total_cmp(&(b.measured - b.model).abs())
    }) else {
        return (out, Vec::new());
    };
    let num = crate::base::numfmt::num;
    let runs: Vec<&str> = found.iter().map(|i| i.run.as_str()).collect();
    let seen = format!(
        "the approach is not an equilibrium of the model's surge equation in {} run{} ({}): in \
         run '{}' the ship holds {} m/s (surge acceleration {} m/s^2 over the first {} s) where \
         the model with the logged propeller and {name} = {} accelerates at {} m/s^2, a surge \
         force of {} N it lacks",
        found.len(),
        if found.len() == 1 { "" } else { "s" },
        runs.join(", "),
        worst.run,
        num(worst.speed),
        num(worst.measured),
        num(worst.until),
        num(held),
        num(worst.model),
        num(worst.force(inputs.vehicle.vehicle.mass))
    );
    let warning = match cfg.balance {
        config::Balance::Estimate => {
            out.estimate.push(name.to_string());
            Warning::new(
                STAGE,
                format!("{seen}; {name} is estimated with the other coefficients"),
                format!(
                    "basins run the propeller at the model's self-propulsion point, not where \
                     a published resistance balances it; held, {name} would leave every \
                     estimate absorbing the missing force (hekf.balance = \"hold\" keeps it)"
                ),
            )
        }
        config::Balance::Hold => Warning::new(
            STAGE,
            format!("{seen}; {name} is held as configured (hekf.balance = \"hold\")"),
            format!(
                "the estimates absorb the missing surge force: estimate {name} (the default, \
                 hekf.balance = \"estimate\") or give the propeller speed that balances it"
            ),
        ),
    };
    (out, vec![warning])
}

/// A move (in sigmas from the data) of an estimate by halving or doubling the noise model
/// above which it is warned: up to it the spread, already in the reported sigma, at most
/// doubles it (docs/hekf.md, "The noise model").
const NOISE_MOVE_WARNED: f64 = 2.0;

/// The warning when halving or doubling the noise model moves an estimate by more than
/// [`NOISE_MOVE_WARNED`] of its sigmas (or when the repeated passes failed).
fn noise_model_warning(
    names: &[String],
    spread: Option<&sensitivity::NoiseSpread>,
) -> Option<Warning> {
    let Some(spread) = spread else {
        return Some(Warning::new(
            STAGE,
            "the estimates' dependence on the noise model could not be computed (a pass with \
             the noise halved or doubled failed)",
            "the sigmas leave the choice of noise model out",
        ));
    };
    let mut moved: Vec<(f64, &String)> = spread
        .moves
        .iter()
        .zip(names)
        .filter(|(m, _)| **m > NOISE_MOVE_WARNED)
        .map(|(m, n)| (*m, n))
        .collect();
    if moved.is_empty() {
        return None;
    }
    moved.sort_by(|a, b| b.0.total_cmp(&a.0));
    let list: Vec<String> = moved
        .iter()
        .map(|(m, n)| format!("{n} {} sigma", crate::base::numfmt::num(*m)))
        .collect();
    Some(
        Warning::new(
            STAGE,
            format!(
                "halving or doubling the noise model (every measurement and process noise sigma) \
             moves {}: {}",
                if moved.len() == 1 {
                    "one estimate by more than twice its sigma"
                } else {
                    "estimates by more than twice their sigma"
                },
                list.join(", ")
            ),
            "the estimates depend on how noisy the data are taken to be, as much as on the data: \
         that spread is in the reported sigmas (uncertainty budget, row \"noise model\"), \
         but look for the misfit behind it (the runs' innovation tests, a coefficient held \
         at a value the data contradict)",
        )
        .failed(crate::base::warning::Test::NoiseModel),
    )
}

/// The identifiability advice for the estimates of `result` ([`identifiability::advise`]).
fn advise<M: Model>(
    model: &M,
    plan: &prepare::Plan,
    runs: &[identify::RunData],
    result: &HekfResult,
) -> Vec<identifiability::Advice> {
    let mut c = plan.base.clone();
    let mut sigmas = Vec::new();
    for (name, &i) in plan.est_names.iter().zip(&plan.est) {
        let est = result.coefficients.iter().find(|k| &k.name == name);
        c[i] = est.map_or(0.0, |k| k.value);
        sigmas.push(est.and_then(|k| k.sigma).unwrap_or(f64::INFINITY));
    }
    model.relations().apply(&mut c);
    identifiability::advise(
        model,
        runs,
        &result.traces,
        &identifiability::Estimates {
            c: &c,
            est: &plan.est,
            names: &plan.est_names,
            sigmas: &sigmas,
            correlation: &result.correlation.matrix,
        },
    )
}

/// One warning listing the coefficients the runs leave undetermined, with what would
/// determine each.
fn identifiability_warning(advice: &[identifiability::Advice]) -> Option<Warning> {
    if advice.is_empty() {
        return None;
    }
    let names: Vec<String> = advice
        .iter()
        .map(|a| format!("{} ({})", a.coefficient, a.finding))
        .collect();
    // the coefficients grouped by the manoeuvre that would determine them, in first-seen order
    let mut ways: Vec<(&str, Vec<&str>)> = Vec::new();
    for a in advice {
        match ways.iter_mut().find(|(w, _)| *w == a.separate_by) {
            Some((_, names)) => names.push(&a.coefficient),
            None => ways.push((&a.separate_by, vec![&a.coefficient])),
        }
    }
    let ways: Vec<String> = ways
        .iter()
        .map(|(w, names)| format!("{w} for {}", names.join(", ")))
        .collect();
    Some(Warning::new(
        STAGE,
        format!("not determined by these runs: {}", names.join(", ")),
        format!(
            "their values rest on little information. What would determine them: {}. Runs \
             given together in [[hekf.runs]] are identified jointly (they share the \
             coefficients). The report's Identifiability table says why for each",
            ways.join("; ")
        ),
    ))
}

/// Keeps every `n`-th sample of a run for the filter (`hekf.decimate`); its summary then
/// gives the samples and the interval the filter used, with a note.
fn decimate(data: &mut identify::RunData, summary: &mut RunSummary, n: usize) {
    if n <= 1 {
        return;
    }
    let rows = data.len();
    data.decimate(n);
    let k = data.len();
    summary.samples = k;
    if k > 1 {
        summary.mean_dt = (data.times[k - 1] - data.times[0]) / (k - 1) as f64;
    }
    summary.warnings.push(
        Warning::new(
            "hekf",
            format!("the filter used one sample in {n} of the {rows} (hekf.decimate = {n})"),
            "the coefficients and their sigmas rest on the kept samples only",
        )
        .for_run(&summary.name),
    );
}

/// The memory check of [`preflight`]: the estimate for these runs (fit runs first, then
/// validation runs) against the memory there is.
fn memory_problem(cfg: &HekfConfig, states: usize, runs: &[&Record]) -> Option<String> {
    let limit = cfg
        .memory_limit
        .as_deref()
        .and_then(|m| memory::parse_size(m).ok());
    let demand = memory::Demand {
        rows: runs.iter().map(|r| r.rows()).sum(),
        fit_rows: runs.iter().take(cfg.runs.len()).map(|r| r.rows()).collect(),
        states,
    };
    let supply = memory::supply(limit)?;
    let smoother = tuning::Resolved::from_config(cfg).smoother;
    memory::check(&demand, cfg.decimate.unwrap_or(1), smoother, &supply).err()
}

fn divergence_error<M: Model>(
    model: &M,
    plan: &prepare::Plan,
    runs: &[identify::RunData],
    summaries: &[RunSummary],
    e: IdentifyError,
) -> Error {
    let defs: Vec<&crate::model::models::CoefDef> =
        plan.est.iter().map(|&i| &model.coefficients()[i]).collect();
    // what was noticed about the run before filtering, and a gap just before the failure
    let mut likely: Vec<String> = summaries
        .iter()
        .filter(|s| s.name == e.run)
        .flat_map(|s| s.warnings.iter())
        .map(|w| format!("{}; {}", w.message, w.meaning))
        .collect();
    if let Some(run) = runs.iter().find(|r| r.name == e.run) {
        if let Some(g) = crate::numerics::sampling::gaps(&run.times)
            .into_iter()
            .rfind(|g| {
                let after = e.divergence.time - (g.start + g.length);
                g.start <= e.divergence.time && after <= 5.0 * g.length
            })
        {
            likely.push(format!(
                "the failure came {} s after a gap of {} s in the time axis at t = {} s",
                crate::base::numfmt::num(e.divergence.time - g.start - g.length),
                crate::base::numfmt::num(g.length),
                crate::base::numfmt::num(g.start)
            ));
        }
    }
    let likely = if likely.is_empty() {
        String::new()
    } else {
        format!(
            "\nNoticed in this run before filtering:\n  - {}",
            likely.join("\n  - ")
        )
    };
    Error::numerical(
        "hekf",
        format!(
            "run '{}', pass {}: {} (estimating {} with the {} model).{} Check the priors of \
             the estimated coefficients (hekf.prior), the measurement noise (hekf.noise) and \
             the fixed coefficients.{likely}",
            e.run,
            e.pass,
            e.divergence,
            plan.describe_estimates(),
            model.name(),
            bounds::divergence_note(&defs, &e.at_bounds)
        ),
    )
}
