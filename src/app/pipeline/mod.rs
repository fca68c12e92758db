//! The pipeline: configuration -> inputs -> polar -> surge -> hekf -> completed coefficient
//! set -> re-simulation -> comparison. Each step is a plain function of data to data; the
//! run's result ([`crate::app::results`]) is what comes out.

pub mod autopilot;
mod conflicts;
mod consider;
mod inputs;
mod preflight;

pub use crate::io::formats::input::file_sha256;
pub use inputs::{load_input, load_inputs, stage_inputs, InputsByStage, PlannedInput};
pub use preflight::{available_coefficients, preflight, Preflight};

use crate::app::resim::{resimulate, ResimMetrics, ResimTrace};
use crate::app::results::{compare, InputSummary, LoadedInput, RunOutput, RunResult, StageResults};
use crate::base::error::Result;
use crate::base::progress::Progress;
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::{Config, LoadedConfig};
use crate::io::record::Record;
use crate::model::coefficients::{Coefficient, CoefficientSet, Source, YawMoment, SYMMETRY};
use crate::stages::hekf::{self, HekfConfig, HekfResult, ModelName};
use crate::stages::polar::{PolarConfig, PolarResult};
use crate::stages::surge::{SurgeConfig, SurgeResult};

/// Analytic added mass of the vehicle when its geometry is a prolate spheroid (length and
/// diameter given): Lamb's k-factors (Fossen 1994).
pub fn analytic_added_mass(loaded: &LoadedConfig) -> Result<Vec<Coefficient>> {
    let v = &loaded.config.vehicle;
    match v.diameter {
        Some(d) => Ok(crate::model::analytic::Spheroid::from_length_diameter(
            v.length,
            d,
            loaded.config.fluid.rho,
        )?
        .coefficients()),
        None => Ok(Vec::new()),
    }
}

/// What a run computes: everything (`hydroid run`), or only the coefficients and their
/// uncertainties (the replicas of `hydroid calibrate`: no preflight, no consider-mode run
/// beside a joint estimate, no re-simulation, no autopilot).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Every step of `hydroid run`.
    Full,
    /// The stages only.
    Coefficients,
}

/// Runs every enabled stage, telling `progress` how it goes.
pub fn run(loaded: &LoadedConfig, progress: &mut dyn Progress) -> Result<RunOutput> {
    // every input first: a bad file stops the run before any stage has run
    let inputs = load_inputs(loaded, stage_inputs(&loaded.config))?;
    run_on(loaded, &inputs, progress, Scope::Full)
}

/// Runs every enabled stage on inputs already read (the configuration's files, or replicas
/// of them made in memory), telling `progress` how it goes.
pub fn run_on(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    progress: &mut dyn Progress,
    scope: Scope,
) -> Result<RunOutput> {
    let cfg = &loaded.config;
    // the autopilot's recorded sea is an input too: read before any stage runs
    let (seas, plant) = match (&cfg.autopilot, scope) {
        (Some(a), Scope::Full) => (
            autopilot::load_seas(a, &loaded.base_dir)?,
            autopilot::load_plant(a, cfg, &loaded.base_dir)?,
        ),
        _ => Default::default(),
    };
    let mut log = Log {
        progress,
        warnings: Vec::new(),
    };
    if scope == Scope::Full {
        let mut found = preflight(loaded, inputs);
        let validation_warnings = std::mem::take(&mut found.validation_warnings);
        if let Some(e) = found.into_error() {
            return Err(e);
        }
        log.say(input_warnings(inputs));
        // the fit runs' findings come with the HEKF stage's result
        log.say(validation_warnings);
    }
    let mut known = configured_coefficients(cfg);
    let analytic = analytic_added_mass(loaded)?;
    let mut stages = StageResults::default();
    if let Some(pc) = cfg.polar.as_ref().filter(|c| c.enabled) {
        stages.polar = Some(polar_step(pc, cfg, &inputs.polar, &mut known, &mut log)?);
    }
    if let Some(sc) = cfg.surge.as_ref().filter(|c| c.enabled) {
        stages.surge = Some(surge_step(sc, cfg, &inputs.surge, &mut known, &mut log)?);
    }
    if let Some(cc) = cfg.captive.as_ref().filter(|c| c.enabled) {
        stages.captive = Some(captive_step(
            cc,
            loaded,
            &inputs.captive,
            &mut known,
            &mut log,
        )?);
    }
    let mut resim = Resimulation::default();
    let mut model_name = None;
    if let Some(hc) = cfg.hekf.as_ref().filter(|c| c.enabled) {
        let (r, runs) = hekf_step(hc, loaded, inputs, &known, &analytic, &mut log, scope)?;
        known.merge_stage(r.coefficients(), r.directions.clone());
        known.correlation = Some(r.correlation.clone());
        model_name = Some(hc.model);
        stages.hekf = Some(r);
        resim = runs;
    }
    complete_reported(&mut known, model_name, cfg.vehicle.yaw_moment, &mut log);
    let autopilot = cfg.autopilot.as_ref().filter(|_| scope == Scope::Full);
    let autopilot_result = match (autopilot, &cfg.hekf, model_name) {
        (Some(a), Some(hc), Some(name)) => autopilot_step(
            name,
            loaded,
            &known,
            hc,
            (a, &seas, plant.as_ref()),
            &mut log,
        ),
        _ => None,
    };
    let comparison = compare(&known, &analytic, &cfg.reference);
    let result = RunResult::new(
        loaded,
        inputs
            .iter()
            .map(|i| InputSummary::from_loaded(i, &loaded.base_dir))
            .collect(),
        known,
        analytic,
        comparison,
        stages,
        resim.metrics,
        log.warnings,
    );
    let mut result = result;
    result.steering = resim.steering;
    result.autopilot = autopilot_result;
    Ok(RunOutput {
        result,
        resim_traces: resim.traces,
        resim_set: resim.set,
    })
}

/// The closed loop of the `[autopilot]` section around the identified model. The
/// identification stands on its own: an autopilot that cannot be tuned or closed (K not
/// identified, an unstable model) is a warning, not the end of the run.
fn autopilot_step(
    name: ModelName,
    loaded: &LoadedConfig,
    known: &CoefficientSet,
    hc: &HekfConfig,
    (a, seas, plant): (
        &crate::config::autopilot::AutopilotConfig,
        &crate::dynamics::autopilot::seas::Seas,
        Option<&autopilot::PlantSpec>,
    ),
    log: &mut Log,
) -> Option<crate::dynamics::autopilot::AutopilotResult> {
    match autopilot::run(name, &loaded.vehicle, known, hc, a, (seas, plant)) {
        Ok(r) => {
            let rates: Vec<String> = r
                .feeds
                .iter()
                .map(|c| {
                    format!(
                        "{:.3} deg/s {}",
                        c.rudder_rate_rms.to_degrees(),
                        c.feed.name()
                    )
                })
                .collect();
            log.stage(&format!("autopilot: rudder rate RMS {}", rates.join(", ")));
            log.say(autopilot::loop_warnings(&r, a, plant));
            log.say(r.warnings());
            Some(r)
        }
        Err(e) => {
            log.say([Warning::new(
                "autopilot",
                format!("the autopilot was not run: {e}"),
                "the [autopilot] section asks for a closed loop around the identified model; \
                 with these coefficients none can be tuned",
            )]);
            None
        }
    }
}

/// Where the pipeline tells how it goes: each warning is said as soon as it arises, and kept
/// for results.json and the report.
struct Log<'p> {
    progress: &'p mut dyn Progress,
    warnings: Vec<Warning>,
}

impl Log<'_> {
    /// Says each warning to the progress as it arises and keeps it.
    fn say(&mut self, warnings: impl IntoIterator<Item = Warning>) {
        for w in warnings {
            self.progress.warning(&w);
            self.warnings.push(w);
        }
    }

    /// Tells the progress that a stage is done, with what it gave.
    fn stage(&mut self, summary: &str) {
        self.progress.stage(summary);
    }
}

/// What the inputs' readers noticed, as warnings of the run they belong to.
fn input_warnings(inputs: &InputsByStage<LoadedInput>) -> impl Iterator<Item = Warning> + '_ {
    inputs.iter().flat_map(|i| {
        i.record.warnings.iter().map(|w| {
            Warning::new(
                "input",
                w.clone(),
                "hydroid read the file as described here; check that this is what the export \
                 meant",
            )
            .for_run(&i.record.name)
        })
    })
}

/// The records of some inputs, for a stage.
fn records(inputs: &[LoadedInput]) -> Vec<Record> {
    inputs.iter().map(|i| i.record.clone()).collect()
}

/// "run" or "runs".
fn runs_word(n: usize) -> &'static str {
    if n == 1 {
        "run"
    } else {
        "runs"
    }
}

/// The coefficients the configuration gives.
fn configured_coefficients(cfg: &Config) -> CoefficientSet {
    let mut known = CoefficientSet::new();
    for (name, v) in &cfg.coefficients {
        known.insert(Coefficient::new(name, *v, None, Source::Config));
    }
    known
}

/// The static polar stage; its coefficients join `known`.
fn polar_step(
    pc: &PolarConfig,
    cfg: &Config,
    inputs: &[LoadedInput],
    known: &mut CoefficientSet,
    log: &mut Log,
) -> Result<PolarResult> {
    let r = crate::stages::polar::run(pc, &cfg.vehicle, &cfg.fluid, &records(inputs))?;
    known.merge_stage(r.coefficients(), r.directions.clone());
    log.stage(&format!(
        "polar: {} coefficients from {} steady points; C_M read as the {} yaw moment ({})",
        r.coefficients.len(),
        r.pooled.n_points,
        r.reference.moment,
        pc.moment_part().polar_coefficient()
    ));
    log.say(r.warnings.iter().cloned());
    Ok(r)
}

/// The surge stage (with `known` completed by symmetry first); its coefficients join `known`.
fn surge_step(
    sc: &SurgeConfig,
    cfg: &Config,
    inputs: &[LoadedInput],
    known: &mut CoefficientSet,
    log: &mut Log,
) -> Result<SurgeResult> {
    let recs = records(inputs);
    known.complete(SYMMETRY, cfg.vehicle.yaw_moment);
    let r = crate::stages::surge::run(sc, &cfg.vehicle, known, &recs)?;
    log.say(conflicts::warnings(known, &r.coefficients(), "surge", cfg));
    r.merge_into(known);
    log.stage(&format!(
        "surge: Xud from {} {}",
        recs.len(),
        runs_word(recs.len())
    ));
    log.say(r.warnings.iter().cloned());
    Ok(r)
}

fn captive_step(
    cc: &crate::stages::captive::CaptiveConfig,
    loaded: &LoadedConfig,
    inputs: &[LoadedInput],
    known: &mut CoefficientSet,
    log: &mut Log,
) -> Result<crate::stages::captive::CaptiveResult> {
    let recs = records(inputs);
    let fit = |set: &CoefficientSet| crate::stages::captive::run(cc, &loaded.vehicle, set, &recs);
    let mut r = fit(known)?;
    // the earlier stages' uncertainty of the coefficients the fit holds (consider analysis)
    let upstream = consider::upstream(known, &r.coefficients, |set| {
        fit(set).ok().map(|x| x.coefficients)
    });
    upstream.widen(&mut r.coefficients);
    if !upstream.failed.is_empty() {
        r.warnings.push(Warning::new(
            "captive",
            format!(
                "the sensitivity to {} could not be computed (the fit failed with the fixed \
                 coefficients moved by one sigma)",
                upstream.failed.join(", ")
            ),
            "the sigmas leave that uncertainty out and are too small",
        ));
    }
    log.say(conflicts::warnings(
        known,
        &r.coefficients,
        "captive",
        &loaded.config,
    ));
    r.merge_into(known, upstream.directions);
    let harmonic = r.runs.iter().filter(|x| x.periods.is_some()).count();
    let conditions: usize = r
        .runs
        .iter()
        .filter(|x| x.periods.is_none())
        .map(|x| x.conditions)
        .sum();
    let mut parts = Vec::new();
    if conditions > 0 {
        parts.push(format!("{conditions} steady conditions"));
    }
    if harmonic > 0 {
        parts.push(format!(
            "{harmonic} harmonic {}",
            if harmonic == 1 { "run" } else { "runs" }
        ));
    }
    log.stage(&format!(
        "captive: {} coefficients from {} in {} {}",
        r.coefficients.len(),
        parts.join(" and "),
        recs.len(),
        if recs.len() == 1 { "file" } else { "files" }
    ));
    log.say(r.warnings.iter().cloned());
    Ok(r)
}

/// The identified model re-simulated against each run.
#[derive(Default)]
struct Resimulation {
    set: Option<CoefficientSet>,
    metrics: Vec<ResimMetrics>,
    traces: Vec<(Record, ResimTrace)>,
    steering: Option<crate::dynamics::course_stability::SteeringIndices>,
}

/// The HEKF stage on its fit runs, then the identified model re-simulated against the fit
/// and the validation runs.
fn hekf_step(
    hc: &HekfConfig,
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    known: &CoefficientSet,
    analytic: &[Coefficient],
    log: &mut Log,
    scope: Scope,
) -> Result<(HekfResult, Resimulation)> {
    let cfg = &loaded.config;
    let fit = records(&inputs.hekf_fit);
    let validation = records(&inputs.hekf_validation);
    let for_filter = fixed_for_filter(known, analytic, cfg.vehicle.yaw_moment);
    let stage_inputs = hekf::StageInputs {
        vehicle: &loaded.vehicle,
        known: &for_filter,
        runs: &fit,
        base_dir: &loaded.base_dir,
    };
    let mut r = hekf::run(hc, &stage_inputs, log.progress)?;
    log.stage(&format!(
        "hekf: {} coefficients from {} {} ({} passes)",
        r.estimated.len(),
        fit.len(),
        runs_word(fit.len()),
        r.settings.passes
    ));
    if hc.mode == hekf::Mode::Joint && scope == Scope::Full {
        // the same runs in consider mode, for the report's side-by-side
        let consider_cfg = HekfConfig {
            mode: hekf::Mode::Consider,
            ..hc.clone()
        };
        match hekf::run(&consider_cfg, &stage_inputs, log.progress) {
            Ok(consider) => {
                r.modes = Some(hekf::modes::compare(&r, &consider, known));
                log.stage("hekf: consider mode run beside it for the comparison of both modes");
            }
            Err(e) => log.say([Warning::new(
                "hekf",
                format!("consider mode, run for the comparison of both modes, failed: {e}"),
                "the joint estimate stands; the report has no side-by-side of both modes",
            )]),
        }
    }
    log.say(
        r.runs
            .iter()
            .flat_map(|run| run.warnings.iter().cloned())
            .chain(r.warnings.iter().cloned()),
    );
    let mut final_set = for_filter.clone();
    final_set.merge_stage(r.coefficients(), r.directions.clone());
    final_set.correlation = Some(r.correlation.clone());
    hc.model.complete(&mut final_set, cfg.vehicle.yaw_moment);
    let vehicle = &loaded.vehicle;
    let mut resim = Resimulation {
        set: Some(final_set.clone()),
        ..Resimulation::default()
    };
    if scope == Scope::Coefficients {
        return Ok((r, resim));
    }
    // the nominal angles each run's configuration gives (runs are read in the order listed)
    let nominal = |spec: &crate::config::InputSpec| {
        spec.manoeuvre
            .as_ref()
            .map(crate::dynamics::manoeuvre::Nominal::given)
            .unwrap_or_default()
    };
    for ((rec, used), given) in fit
        .iter()
        .map(|r| (r, true))
        .chain(validation.iter().map(|r| (r, false)))
        .zip(hc.runs.iter().chain(&hc.validation).map(nominal))
    {
        let scale = cfg.vehicle.scale;
        let (m, t) = resimulate(hc.model, vehicle, &final_set, rec, used, scale, given)?;
        log.say(crate::app::resim::warnings(&m, rec));
        resim.metrics.push(m);
        resim.traces.push((rec.clone(), t));
    }
    // Nomoto's indices of the identified model at the approach of the first run with a
    // rudder (ships: to compare with K and T from a zig-zag)
    if let Some(rec) = fit.iter().find(|r| r.channel(Quantity::Rudder).is_some()) {
        match crate::dynamics::course_stability::at_approach(hc.model, vehicle, &final_set, rec) {
            Some(Ok(s)) => resim.steering = Some(s),
            Some(Err(e)) => log.say([Warning::new(
                "hekf",
                format!("no Nomoto indices for the identified model: {e}"),
                "the model's steering cannot be summarised by K and T at this speed",
            )]),
            None => {}
        }
    }
    Ok((r, resim))
}

/// The identified model of a run's result: its reported coefficients, with the analytic
/// values where nothing else gives one, completed by symmetry ([`fixed_for_filter`]).
pub fn identified_set(result: &RunResult) -> CoefficientSet {
    let mut known = CoefficientSet::new();
    for c in &result.coefficients {
        known.insert(c.clone());
    }
    fixed_for_filter(
        &known,
        &result.analytic,
        result.configuration.vehicle.yaw_moment,
    )
}

/// The coefficients the filter holds fixed: stages and configuration first, analytic values
/// where nothing else gives one, completed by symmetry in the run's yaw-moment reading.
fn fixed_for_filter(
    known: &CoefficientSet,
    analytic: &[Coefficient],
    reading: YawMoment,
) -> CoefficientSet {
    let mut for_filter = known.clone();
    for c in analytic {
        if !for_filter.contains(&c.name) {
            for_filter.insert(c.clone());
        }
    }
    for_filter.complete(SYMMETRY, reading);
    for_filter
}

/// The reported set: what the stages and the configuration gave, completed by symmetry (by
/// the model's relations when the HEKF ran; otherwise with a warning for each coefficient
/// the relations cannot complete).
fn complete_reported(
    known: &mut CoefficientSet,
    model: Option<ModelName>,
    reading: YawMoment,
    log: &mut Log,
) {
    match model {
        Some(m) => m.complete(known, reading),
        None => {
            let incomplete = known.complete(SYMMETRY, reading).into_iter().map(|w| {
                Warning::new(
                    "coefficients",
                    w,
                    "the coefficient set is incomplete: a re-simulation with it is not possible",
                )
            });
            log.say(incomplete);
        }
    }
}
