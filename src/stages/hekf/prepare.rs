//! From configuration and records to what the filter needs: which coefficients are estimated
//! and which are held fixed (and from where), priors, noise, initial states, inputs.

use super::config::HekfConfig;
use super::config::{FilterKind, Outliers};
use super::identify::{completed, RunData, Setup};
use super::noise;
use super::result::RunSummary;
use super::tuning::{NoiseChoice, Resolved};
use super::STAGE;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::dynamics::sim::inputs::InputSeries;
use crate::io::record::Record;
use crate::model::coefficients::{Coefficient, CoefficientSet};
use crate::model::models::Model;
use crate::numerics::ad;
use crate::numerics::sampling::median_interval;
use crate::numerics::signal::{self, noise_floor};

/// Which coefficients the filter estimates, which it holds fixed, and their priors.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Estimated coefficient names.
    pub est_names: Vec<String>,
    /// Their indices in the model's coefficient vector.
    pub est: Vec<usize>,
    /// The model's coefficient vector with the fixed values.
    pub base: Vec<f64>,
    /// The fixed coefficients as used, with their sources.
    pub fixed: Vec<Coefficient>,
    /// Initial values (SI).
    pub initial: Vec<f64>,
    /// Prior standard deviations (SI).
    pub prior_sigma: Vec<f64>,
    /// Internal scales (SI).
    pub scale: Vec<f64>,
    /// Admissible ranges (SI) the model declares, kept inside the filter.
    pub ranges: Vec<crate::model::models::Range>,
    /// Which states each of the model's outputs reads, at the starting coefficients.
    pub reads: OutputReads,
    /// Prior correlations (nb x nb; empty: uncorrelated).
    pub prior_correlation: Vec<f64>,
    /// Coefficients whose prior is an earlier stage's estimate (`hekf.mode = "joint"`).
    pub held_prior: Vec<bool>,
    /// The tuning choices made, in words, for the report and the terminal.
    pub notes: Vec<String>,
}

/// Resolves estimated and fixed coefficients and the priors.
pub fn plan<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    tuning: &Resolved,
    known: &CoefficientSet,
    runs: &[Record],
) -> Result<Plan> {
    let names = model.coefficient_names();
    let est = coefficient_problems(model, cfg, |n| known.contains(n))
        .map_err(|p| Error::numerical("hekf", p.join("; ")))?;
    let (base, fixed) = held(model, &est, known);
    let mut notes = Vec::new();
    let mut initial = Vec::new();
    let mut prior_sigma = Vec::new();
    let mut scale = Vec::new();
    let mut held_prior = Vec::new();
    for (&i, n) in est.iter().zip(&cfg.estimate) {
        let typical = model.typical_magnitude(names[i]);
        let p = cfg.prior.get(n);
        // joint: an earlier stage's estimate (value and sigma) is the prior, unless the
        // configuration gives one
        if let Some((v, s, stage)) = stage_prior(cfg, known, n).filter(|_| p.is_none()) {
            let unit = crate::model::models::registry::coefficient(n).map_or("", |c| c.unit);
            notes.push(format!(
                "{n}: prior {} ± {} {unit} from the {stage} stage (hekf.mode = \"joint\")",
                sig(v),
                sig(s)
            ));
            initial.push(v);
            prior_sigma.push(s);
            scale.push(typical.max(f64::MIN_POSITIVE));
            held_prior.push(true);
            continue;
        }
        held_prior.push(false);
        // the configured start, else what the model reads from the runs, else zero
        let (init, from_data) = match p.and_then(|p| p.initial) {
            Some(v) => (v, false),
            None => match model.initial_guess(n, runs) {
                Some(v) if v.is_finite() => (v, true),
                _ => (0.0, false),
            },
        };
        let (sigma, why) = prior_sigma_of(
            p.and_then(|p| p.sigma),
            tuning,
            from_data.then_some(init),
            typical,
        );
        let unit = crate::model::models::registry::coefficient(n).map_or("", |c| c.unit);
        let range = M::COEFFICIENTS[i].range;
        let start = start_in_range(n, unit, init, typical, &range, p.and_then(|p| p.initial))?;
        let whence = match (start != init, from_data) {
            (true, _) => format!(
                " (moved from {} {unit}, outside its admissible range {})",
                sig(init),
                range.describe(unit)
            ),
            (false, true) => " (read from the runs by the model)".to_string(),
            (false, false) => String::new(),
        };
        notes.push(format!(
            "{n}: starts at {} {unit}{whence}, prior sigma {} {unit} ({why})",
            if from_data || start != init {
                sig(start)
            } else {
                start.to_string()
            },
            sig(sigma)
        ));
        let init = start;
        initial.push(init);
        prior_sigma.push(sigma);
        scale.push(typical.max(f64::MIN_POSITIVE));
    }
    let prior_correlation = stage_correlation(known, &cfg.estimate, &held_prior, &prior_sigma);
    let ranges = est.iter().map(|&i| M::COEFFICIENTS[i].range).collect();
    let reads = OutputReads::of(model, &completed(model, &base, &est, &initial));
    Ok(Plan {
        est_names: cfg.estimate.clone(),
        ranges,
        est,
        base,
        fixed,
        initial,
        prior_sigma,
        scale,
        reads,
        prior_correlation,
        held_prior,
        notes,
    })
}

/// The model's coefficient vector with every held coefficient at its known value (the
/// estimated, derived and absent optional ones at zero), and the held coefficients.
fn held<M: Model>(
    model: &M,
    est: &[usize],
    known: &CoefficientSet,
) -> (Vec<f64>, Vec<crate::model::coefficients::Coefficient>) {
    let names = model.coefficient_names();
    let mut base = vec![0.0; names.len()];
    let mut fixed = Vec::new();
    for (i, n) in names.iter().enumerate() {
        if est.contains(&i) || model.is_derived(n) || (model.is_optional(n) && !known.contains(n)) {
            continue;
        }
        let c = known.get(n).expect("checked by coefficient_problems");
        base[i] = c.value;
        fixed.push(c.clone());
    }
    (base, fixed)
}

/// The prior sigma of a start the model reads from the runs, as a share of its magnitude.
pub const READ_PRIOR_SHARE: f64 = 0.5;

/// A coefficient's prior sigma and why: the configured one, else the preset's, else half a
/// start the model read from the runs (`read`: w0 from the compass spectrum places the
/// coefficient within a factor of about 2), else its expected size `typical`.
fn prior_sigma_of(
    configured: Option<f64>,
    tuning: &Resolved,
    read: Option<f64>,
    typical: f64,
) -> (f64, &'static str) {
    match (configured, tuning.prior_sigma, read) {
        (Some(s), _, _) => (s, "configured"),
        (None, Some(s), _) => (s, "paper preset"),
        (None, None, Some(v)) if v != 0.0 => (
            READ_PRIOR_SHARE * v.abs(),
            "half the start read from the runs",
        ),
        _ => (typical, "the coefficient's expected size"),
    }
}

/// The refusal of a configured start `init` of `name` outside its admissible range.
fn start_outside(name: &str, unit: &str, init: f64, range: &crate::model::models::Range) -> String {
    format!(
        "hekf.prior.{name}.initial = {init}: outside the coefficient's admissible range ({}); \
         start it inside the range",
        range.describe(unit)
    )
}

/// The start of coefficient `name` inside its admissible range: a configured start
/// (`configured`) outside it is an error naming the key; a start read from the runs or the
/// default zero outside it becomes the expected size `typical` on the range's side (its
/// bound's margin inside when that is outside too).
fn start_in_range(
    name: &str,
    unit: &str,
    init: f64,
    typical: f64,
    range: &crate::model::models::Range,
    configured: Option<f64>,
) -> Result<f64> {
    if range.contains(init) {
        return Ok(init);
    }
    if configured.is_some() {
        return Err(Error::numerical(
            "hekf",
            start_outside(name, unit, init, range),
        ));
    }
    let side = if range.lo >= 0.0 { typical } else { -typical };
    if range.contains(side) {
        return Ok(side);
    }
    let m = super::bounds::OPEN_MARGIN * typical;
    Ok(init.clamp(range.lo + m, range.hi - m))
}

/// In `hekf.mode = "joint"`, an earlier stage's estimate of `name`: value, sigma and stage.
fn stage_prior(cfg: &HekfConfig, known: &CoefficientSet, name: &str) -> Option<(f64, f64, String)> {
    use crate::model::coefficients::Source;
    if cfg.mode != super::Mode::Joint {
        return None;
    }
    let c = known.get(name)?;
    let from_stage = matches!(c.source, Source::Polar | Source::Surge | Source::Captive);
    let s = c.sigma.filter(|s| *s > 0.0 && s.is_finite())?;
    from_stage.then(|| (c.value, s, c.source.to_string()))
}

/// The correlations of the held priors, from the earlier stages' uncertainty directions
/// (each a one-sigma change of the coefficients: their covariance is the sum of the outer
/// products); empty when no two held priors are correlated.
fn stage_correlation(
    known: &CoefficientSet,
    names: &[String],
    held: &[bool],
    sigma: &[f64],
) -> Vec<f64> {
    let nb = names.len();
    let mut corr = vec![0.0; nb * nb];
    let mut any = false;
    for a in 0..nb {
        corr[a * nb + a] = 1.0;
        for b in (0..nb).filter(|&b| b != a && held[a] && held[b]) {
            let cov = known.covariance(&names[a], &names[b]);
            let r = (cov / (sigma[a] * sigma[b])).clamp(-1.0, 1.0);
            if r != 0.0 {
                any = true;
            }
            corr[a * nb + b] = r;
        }
    }
    if any {
        corr
    } else {
        Vec::new()
    }
}

/// The indices of the estimated coefficients, or every problem with the names: an estimated
/// coefficient the model does not have or that a relation derives, and fixed coefficients
/// that `known` says nothing provides.
pub fn coefficient_problems<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    known: impl Fn(&str) -> bool,
) -> std::result::Result<Vec<usize>, Vec<String>> {
    let names = model.coefficient_names();
    let mut problems = Vec::new();
    let mut est = Vec::new();
    for n in &cfg.estimate {
        match model.coefficient_index(n) {
            None => problems.push(format!(
                "'{n}' is not a coefficient of the {} model (its coefficients: {})",
                model.name(),
                names.join(", ")
            )),
            Some(_) if model.is_derived(n) => problems.push(format!(
                "'{n}' follows from other coefficients by a symmetry relation (paper eq. 4); \
                 estimate the coefficient it is derived from instead"
            )),
            Some(i) => {
                est.push(i);
                // a configured start outside the admissible range: a mistake of the
                // configuration, found before anything runs (exit code 2)
                let range = M::COEFFICIENTS[i].range;
                match cfg.prior.get(n).and_then(|p| p.initial) {
                    Some(v) if !range.contains(v) => {
                        let unit =
                            crate::model::models::registry::coefficient(n).map_or("", |c| c.unit);
                        problems.push(start_outside(n, unit, v, &range));
                    }
                    _ => {}
                }
            }
        }
    }
    let missing: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(i, n)| {
            !est.contains(i) && !model.is_derived(n) && !model.is_optional(n) && !known(n)
        })
        .map(|(_, n)| *n)
        .collect();
    if !missing.is_empty() {
        let them = if missing.len() == 1 { "it" } else { "them" };
        problems.push(format!(
            "no value for {} (held fixed by the filter): give {them} in [coefficients] or \
             enable the stage that provides {them}",
            missing.join(", "),
        ));
    }
    if problems.is_empty() {
        Ok(est)
    } else {
        Err(problems)
    }
}

impl Plan {
    /// The estimated coefficients, for messages.
    pub fn describe_estimates(&self) -> String {
        self.est_names.join(", ")
    }
}

fn sig(v: f64) -> String {
    crate::base::numfmt::fixed_trimmed(v, 4)
}

/// The filter's view of one run: measurements, noise, inputs, initial state.
///
/// `reads` tells which states each output reads ([`Plan::reads`]).
pub fn run_data<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    tuning: &Resolved,
    rec: &Record,
    base_dir: &std::path::Path,
    reads: &OutputReads,
) -> Result<(RunData, RunSummary)> {
    filterable(model, cfg, rec)?;
    let times = rec.time().unwrap_or_default().to_vec();
    let measured_q = measured_quantities(model, cfg, rec)?;
    let measured: Vec<usize> = measured_q
        .iter()
        .map(|q| model.output_index(*q).expect("checked"))
        .collect();
    let mut y = measurements(rec, &measured_q, times.len());
    let mut warnings = Vec::new();
    let (noise, r, rounding) =
        measurement_noise(cfg, tuning, rec, &measured_q, &mut y, &mut warnings);
    let inputs = InputSeries::from_record(model.inputs(), rec).map_err(|q| {
        run_error(
            rec,
            format!(
                "the {} model needs {q}: map a {q} column or give `constants = {{ {q} = ... }}`",
                model.name()
            ),
        )
    })?;
    let (x0, p0) = initial_state(model, &measured_q, &y, &r, tuning, reads);
    warnings.extend(coverage_warnings(model, rec, &times, &measured_q));
    let summary = RunSummary {
        name: rec.name.clone(),
        file: crate::io::record::report_path(&rec.source, base_dir),
        samples: times.len(),
        duration: times.last().copied().unwrap_or(0.0) - times.first().copied().unwrap_or(0.0),
        mean_dt: mean_interval(&times),
        measured: measured_q.iter().map(|q| q.key().to_string()).collect(),
        noise,
        process_noise: Default::default(),
        nis: None,
        innovation_rms: Vec::new(),
        between: inputs.between(model.inputs()),
        states: None,
        warnings,
    };
    Ok((
        RunData {
            name: rec.name.clone(),
            times,
            measured,
            y,
            r,
            rounding,
            inputs,
            x0,
            p0,
            lines: rec.lines.clone(),
        },
        summary,
    ))
}

/// What [`run_data`] refuses in a run before it reads a sample (no time column, nothing the
/// filter can measure), as the stage says it; run before any stage by `preflight`, so that
/// `hydroid check` refuses it too.
pub(super) fn filterable<M: Model>(model: &M, cfg: &HekfConfig, rec: &Record) -> Result<()> {
    if rec.time().is_none() {
        return Err(run_error(rec, "the run has no time column".into()));
    }
    measured_quantities(model, cfg, rec).map(drop)
}

/// A numerical error of the stage about one run, naming it and its file.
fn run_error(rec: &Record, msg: String) -> Error {
    Error::numerical(
        STAGE,
        format!("run '{}' ({}): {msg}", rec.name, rec.source.display()),
    )
}

/// The quantities the filter measures in this run: `hekf.measure` (each a state of the model
/// and a column of the run), or else every state of the model the run has a column for.
fn measured_quantities<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    rec: &Record,
) -> Result<Vec<Quantity>> {
    // what the run measures: the model's outputs (its states unless it declares outputs)
    let outputs = model.output_quantities();
    let what = if model.outputs().is_empty() {
        ("a state", "states")
    } else {
        ("an output", "outputs")
    };
    let measured_q: Vec<Quantity> = match &cfg.measure {
        Some(list) => {
            for q in list {
                if model.output_index(*q).is_none() {
                    return Err(run_error(
                        rec,
                        format!(
                            "hekf.measure lists {q}, which is not {} of the {} model",
                            what.0,
                            model.name()
                        ),
                    ));
                }
                if rec.channel(*q).is_none() {
                    return Err(run_error(
                        rec,
                        format!("hekf.measure lists {q}, but the run has no {q} column"),
                    ));
                }
            }
            list.clone()
        }
        // the columns, then the states the run holds at a constant (v = r = 0 of a straight
        // surge run): measured at that value at every sample
        None => outputs
            .iter()
            .copied()
            .filter(|q| rec.channel(*q).is_some())
            .chain(
                outputs
                    .iter()
                    .copied()
                    .filter(|q| rec.channel(*q).is_none() && held_state(model, rec, *q)),
            )
            .collect(),
    };
    if measured_q.is_empty() {
        return Err(run_error(
            rec,
            format!(
                "none of the {} model's {} ({}) is in the run: its column map (columns) maps \
                 none of them; map at least one to a column of the file (e.g. `{} = \"<column \
                 name>\"`)",
                model.name(),
                what.1,
                outputs
                    .iter()
                    .map(|q| q.key())
                    .collect::<Vec<_>>()
                    .join(", "),
                outputs.first().map_or("u", |q| q.key())
            ),
        ));
    }
    Ok(measured_q)
}

/// The measurements, `samples` x measured quantities, row-major (SI).
fn measurements(rec: &Record, measured_q: &[Quantity], samples: usize) -> Vec<f64> {
    let mut y = Vec::with_capacity(samples * measured_q.len());
    for k in 0..samples {
        for q in measured_q {
            y.push(match rec.channel(*q) {
                Some(c) => c[k],
                None => rec.constants[q],
            });
        }
    }
    y
}

/// Whether the run gives state `q` of the model as a constant (`constants = { v = 0 }`): a
/// state held by the experiment, which the filter measures at that value.
fn held_state<M: Model>(model: &M, rec: &Record, q: Quantity) -> bool {
    model.outputs().is_empty() && model.state_index(q).is_some() && rec.constants.contains_key(&q)
}

/// Noise standard deviation of a held state's constant measurement, SI (0.1 mm/s, 1e-4
/// rad/s, 0.1 mm): the experiment holds it far better than the dynamics move it.
const HELD_SIGMA: f64 = 1e-4;

/// The noise source of a held state: its measurement carries no information on the noise
/// model, so the innovation test does not count it.
pub(super) const HELD_SOURCE: &str = "held constant by the run (constants)";

/// The measurement noise of each measured quantity (its choice and its variance), from the
/// data without their gross outliers, and the rounding variance of each sample (K x m,
/// row-major; empty when no channel is printed coarsely). The outliers are left out of the
/// filter: they become NaN in `y`, a missing measurement the update skips, and a warning
/// naming their lines.
fn measurement_noise(
    cfg: &HekfConfig,
    tuning: &Resolved,
    rec: &Record,
    measured_q: &[Quantity],
    y: &mut [f64],
    warnings: &mut Vec<Warning>,
) -> (Vec<NoiseChoice>, Vec<f64>, Vec<f64>) {
    let m = measured_q.len();
    let mut noise = Vec::new();
    let mut r = Vec::new();
    let mut rounding = Vec::new();
    let rate_bias = noise::rate_bias(rec);
    if let Some((b, drift)) = rate_bias.filter(|_| measured_q.contains(&Quantity::R)) {
        warnings.push(rate_bias_warning(rec, b, drift));
    }
    for (a, q) in measured_q.iter().enumerate() {
        let Some(raw) = rec.channel(*q) else {
            // a held state (a run's constant): configured noise, else HELD_SIGMA
            let sigma = cfg.noise.get(q).map_or(HELD_SIGMA, |c| c.si);
            r.push(sigma * sigma);
            noise.push(NoiseChoice {
                quantity: *q,
                sigma,
                source: HELD_SOURCE.to_string(),
                rounding: None,
                estimate_variance: 0.0,
            });
            continue;
        };
        let steps = rec.resolution.get(q).map(Vec::as_slice);
        let spikes = match cfg.outliers {
            Outliers::Exclude => signal::outliers_beyond(raw, steps),
            Outliers::Keep => Vec::new(),
        };
        let mut values = signal::cleaned(raw, &spikes);
        let bias = match (*q, tuning.fixed_r, cfg.noise.get(q)) {
            (Quantity::R, None, None) => rate_bias.map_or(0.0, |(b, _)| b),
            _ => 0.0,
        };
        if bias != 0.0 {
            values.iter_mut().for_each(|v| *v -= bias);
            for k in 0..y.len() / m {
                y[k * m + a] -= bias;
            }
        }
        let (sigma, source, rounds, estimate_variance) = match (tuning.fixed_r, cfg.noise.get(q)) {
            (Some(rv), _) => (rv.sqrt(), "paper preset".to_string(), None, 0.0),
            (None, Some(c)) => (c.si, "configured".to_string(), None, 0.0),
            (None, None) => match noise::estimate(rec, *q, &values, bias) {
                Some(n) => (
                    n.sigma,
                    n.source,
                    steps.map(|s| (n.rounding, s)),
                    n.estimate_variance,
                ),
                None => (
                    noise_floor(&values),
                    "floor (the data look noise-free)".to_string(),
                    None,
                    0.0,
                ),
            },
        };
        // the rounding of each sample adds its own variance (estimated noise only: a
        // configured or preset noise is what the user says the whole error is)
        if let Some((_, s)) = rounds {
            if rounding.is_empty() {
                rounding = vec![0.0; y.len()];
            }
            for (k, step) in s.iter().enumerate() {
                let var = step * step / 12.0;
                rounding[k * m + a] = if var.is_finite() { var } else { 0.0 };
            }
        }
        r.push(sigma * sigma);
        noise.push(NoiseChoice {
            quantity: *q,
            sigma,
            source,
            rounding: rounds.and_then(|(rms, _)| rms),
            estimate_variance,
        });
        if !spikes.is_empty() {
            for o in &spikes {
                y[o.index * m + a] = f64::NAN;
                // a sample left out adds no rounding either (an outlier's print step is huge)
                if let Some(v) = rounding.get_mut(o.index * m + a) {
                    *v = 0.0;
                }
            }
            warnings.push(outlier_warning(*q, &spikes, rec).for_run(&rec.name));
        }
    }
    (noise, r, rounding)
}

/// The note for a yaw rate taken off its bias against the heading.
fn rate_bias_warning(rec: &Record, bias: f64, drift: f64) -> Warning {
    Warning::new(
        STAGE,
        format!(
            "the yaw rate reads {} deg/s {} the heading's rate over the whole run (integrated, \
             it drifts {} deg from the heading): taken off as a constant bias of the rate \
             sensor",
            sig(bias.abs().to_degrees()),
            if bias > 0.0 { "above" } else { "below" },
            sig(drift.to_degrees())
        ),
        "left in, a rate sensor's bias reads as a steady turn that the model's yaw \
         derivatives would have to explain; the heading (from the track or a compass) is \
         taken as the reference, and the rate is judged against it",
    )
    .for_run(&rec.name)
}

/// The initial state and its covariance: the first measurement (that is not an outlier)
/// with the measurement's variance where measured, zero with variance 1 elsewhere.
///
/// A state read through an output that other states enter as well (`reads`; the compass
/// reads the ship's heading plus the wave yaw, Fossen 2011, 11.3) starts at its first sample
/// but with the unmeasured states' variance: the sample contains the others' part (a wave
/// yaw of degrees), and pinned at the measurement's variance the state would carry that part
/// into the estimates. The first update then ties the sum to the sample.
fn initial_state<M: Model>(
    model: &M,
    measured_q: &[Quantity],
    y: &[f64],
    r: &[f64],
    tuning: &Resolved,
    reads: &OutputReads,
) -> (Vec<f64>, Vec<f64>) {
    let nx = model.nx();
    let m = measured_q.len();
    let k_len = y.len().checked_div(m).unwrap_or(0);
    let unmeasured = tuning.p0_states.unwrap_or(1.0);
    let mut x0 = vec![0.0; nx];
    let mut p0 = vec![0.0; nx * nx];
    for i in 0..nx {
        p0[i * nx + i] = unmeasured;
    }
    for (a, q) in measured_q.iter().enumerate() {
        // a state measured directly starts at its first sample that is not an outlier
        let Some(i) = model.state_index(*q) else {
            continue;
        };
        x0[i] = (0..k_len)
            .map(|k| y[k * m + a])
            .find(|v| v.is_finite())
            .unwrap_or(0.0);
        let through_shared = model.output_index(*q).is_some_and(|o| reads.shared(o));
        p0[i * nx + i] = if through_shared {
            unmeasured
        } else {
            tuning.p0_states.or(tuning.p0_measured).unwrap_or(r[a])
        };
    }
    (x0, p0)
}

/// Which states enter each output of the model: the sparsity of the Jacobian of
/// [`Model::measure`] (forward-mode AD at the zero state and inputs, with the starting
/// coefficients). Empty for a model whose outputs are its states.
#[derive(Debug, Clone)]
pub struct OutputReads {
    /// Per output, per state: whether the state enters it (outputs x states, row-major).
    enters: Vec<bool>,
    nx: usize,
}

impl OutputReads {
    fn of<M: Model>(model: &M, c: &[f64]) -> Self {
        let (m, nx) = (model.outputs().len(), model.nx());
        if m == 0 {
            return OutputReads {
                enters: Vec::new(),
                nx,
            };
        }
        let u = vec![0.0; model.inputs().len()];
        let mut value = vec![0.0; m];
        let mut jac = vec![0.0; m * nx];
        ad::jacobian(
            &vec![0.0; nx],
            m,
            |xd, yd| {
                let cd: Vec<ad::Dual> = c.iter().map(|v| ad::constant(*v)).collect();
                model.measure(xd, &u, &cd, yd);
            },
            &mut value,
            &mut jac,
        );
        OutputReads {
            enters: jac.iter().map(|d| *d != 0.0).collect(),
            nx,
        }
    }

    /// Whether state `i` enters output `o`.
    fn enters(&self, o: usize, i: usize) -> bool {
        self.enters.get(o * self.nx + i).copied().unwrap_or(false)
    }

    /// Whether more than one state enters output `o`.
    fn shared(&self, o: usize) -> bool {
        (0..self.nx).filter(|&i| self.enters(o, i)).count() > 1
    }
}

/// Control inputs (rudder, planes) that never move in a run: the response to them, which
/// identifies the steering coefficients, is not in its data.
fn still_inputs<M: Model>(model: &M, rec: &Record) -> Vec<Warning> {
    let controls = [Quantity::Rudder, Quantity::SternPlanes, Quantity::BowPlanes];
    model
        .input_quantities()
        .into_iter()
        .filter(|q| controls.contains(q))
        .filter_map(|q| {
            let held = match rec.channel(q) {
                Some(v) => {
                    let (lo, hi) = crate::numerics::signal::range(v.iter().copied());
                    // less than 0.1 deg of motion
                    (hi - lo < 0.1f64.to_radians()).then_some(0.5 * (lo + hi))
                }
                None => rec.constants.get(&q).copied(),
            }?;
            Some(
                Warning::new(
                    STAGE,
                    format!(
                        "the {q} does not move in this run (held at {:.2} deg)",
                        held.to_degrees()
                    ),
                    "nothing in this run shows the response to it: the coefficients of the \
                     steering response (a gain such as Nomoto's K, a rudder bias) cannot be \
                     identified from it, and their sigmas say so; the states are still \
                     filtered",
                )
                .for_run(&rec.name),
            )
        })
        .collect()
}

/// What the run does not cover well: gaps in time, out-of-plane motion a 3-DOF model
/// ignores, states it does not measure.
fn coverage_warnings<M: Model>(
    model: &M,
    rec: &Record,
    times: &[f64],
    measured_q: &[Quantity],
) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if let Some(w) = gap_warning(times, &rec.lines) {
        warnings.push(w.for_run(&rec.name));
    }
    warnings.extend(out_of_plane_warnings(model, rec));
    warnings.extend(still_inputs(model, rec));
    let unmeasured: Vec<&str> = model
        .states()
        .iter()
        .filter(|s| !measured_q.contains(&s.quantity))
        .map(|s| s.name)
        .collect();
    if !unmeasured.is_empty() {
        warnings.push(Warning::new(
            STAGE,
            format!(
                "not measured: {} (start at 0 with sigma 1 SI unit)",
                unmeasured.join(", ")
            ),
            "these states are inferred from the dynamics only; coefficients that act mainly \
             through them are less well determined",
        ));
    }
    warnings
}

/// The mean sample interval, s (0 for a single sample).
fn mean_interval(times: &[f64]) -> f64 {
    let k_len = times.len();
    if k_len > 1 {
        (times[k_len - 1] - times[0]) / (k_len - 1) as f64
    } else {
        0.0
    }
}

/// The warning for the gross outliers of one measured quantity, naming their lines.
fn outlier_warning(q: Quantity, spikes: &[signal::Outlier], rec: &Record) -> Warning {
    const SHOWN: usize = 5;
    let mut at: Vec<String> = spikes
        .iter()
        .take(SHOWN)
        .map(|o| {
            format!(
                "line {} (t = {} s: {:e} where its neighbours give about {})",
                rec.lines.get(o.index).copied().unwrap_or(0),
                sig(rec.time().map_or(f64::NAN, |t| t[o.index])),
                o.value,
                sig(o.median)
            )
        })
        .collect();
    if spikes.len() > SHOWN {
        at.push(format!("and {} more", spikes.len() - SHOWN));
    }
    Warning::new(
        STAGE,
        format!(
            "{} outlier{} in {q} left out: {}",
            spikes.len(),
            if spikes.len() == 1 { "" } else { "s" },
            at.join(", ")
        ),
        "these samples of this quantity are not used by the filter nor by the noise estimate; \
         check the export there (hekf.outliers = \"keep\" uses them)",
    )
}

/// The warning for the gaps in a run's time axis, naming where they are.
fn gap_warning(times: &[f64], lines: &[usize]) -> Option<Warning> {
    const SHOWN: usize = 5;
    let gaps = crate::numerics::sampling::gaps(times);
    if gaps.is_empty() {
        return None;
    }
    let dt = median_interval(times).unwrap_or(0.0);
    let mut at: Vec<String> = gaps
        .iter()
        .take(SHOWN)
        .map(|g| {
            format!(
                "{} s after t = {} s (lines {}-{})",
                sig(g.length),
                sig(g.start),
                lines.get(g.after).copied().unwrap_or(0),
                lines.get(g.after + 1).copied().unwrap_or(0)
            )
        })
        .collect();
    if gaps.len() > SHOWN {
        at.push(format!("and {} more", gaps.len() - SHOWN));
    }
    Some(Warning::new(
        STAGE,
        format!(
            "{} gap{} in the time axis (regular sampling {} s): {}",
            gaps.len(),
            if gaps.len() == 1 { "" } else { "s" },
            sig(dt),
            at.join(", ")
        ),
        "no data constrain the estimate across a gap; the filter integrates through it in \
         steps no longer than the regular ones, so the estimates stay unbiased but are less \
         certain, and a gap longer than the motion's time scale can let the state drift far \
         enough to diverge",
    ))
}

/// Warns when a model without out-of-plane states (a 3-DOF model) is fed a run with
/// out-of-plane motion that is not small.
fn out_of_plane_warnings<M: Model>(model: &M, rec: &Record) -> Vec<Warning> {
    let peak = |q: Quantity| {
        rec.channel(q)
            .map(|v| v.iter().fold(0.0f64, |a, x| a.max(x.abs())))
    };
    let speed = peak(Quantity::U)
        .unwrap_or(0.0)
        .max(peak(Quantity::V).unwrap_or(0.0));
    let mut w = Vec::new();
    for (q, limit, what) in [
        (Quantity::Roll, 3f64.to_radians(), "3 deg"),
        (Quantity::Pitch, 3f64.to_radians(), "3 deg"),
        (Quantity::P, 2f64.to_radians(), "2 deg/s"),
        (Quantity::Q, 2f64.to_radians(), "2 deg/s"),
        (Quantity::W, 0.05 * speed, "5 % of the speed"),
    ] {
        if model.state_index(q).is_some() {
            continue;
        }
        if let Some(p) = peak(q) {
            if p > limit {
                w.push(Warning::new(
                    STAGE,
                    format!(
                        "{q} reaches {:.3} (more than {what}): the {} model ignores it",
                        if q.dim() == [0, 0, 0, 1] || q.dim() == [0, 0, -1, 1] {
                            p.to_degrees()
                        } else {
                            p
                        },
                        model.name()
                    ),
                    "the model's coefficients absorb the out-of-plane coupling; consider a \
                     model with these states (`hydroid coefficients` lists the models)",
                ));
            }
        }
    }
    w
}

/// The states whose process noise the filter matches to the innovations
/// ([`super::adapt`]): every state of a model measured through its states (a measured state
/// the model does not follow gets the noise its misfit needs: velocities for forces the model
/// lacks, positions and angles for velocities or rates that their measured derivatives do
/// not match), unless the preset fixes the noise (`adapt_noise`) or the configuration gives
/// it for that state.
fn adaptable_states<M: Model>(model: &M, cfg: &HekfConfig, tuning: &Resolved) -> Vec<bool> {
    model
        .states()
        .iter()
        .map(|s| {
            tuning.adapt_noise
                && model.outputs().is_empty()
                && !cfg.process_noise.contains_key(s.name)
        })
        .collect()
}

/// The variance the state jitter of state `i` is a fraction of, in one run.
///
/// For a model whose outputs are its states: the measurement variance of the state where
/// measured, 1 SI unit squared where not. For a model measured through outputs
/// ([`OutputReads`]): the variance of an output that reads the state alone; 1 SI unit squared
/// for a state that the run's only measured output reads together with others (the heading
/// under a compass's wave yaw: a random walk of 1e-6 rad^2 per sample interval lets the filter
/// follow slow heading changes the model lacks while the wave frequency converges, where
/// nothing else in the run tells them from the ship's turning; measured in
/// tests/independent_nomoto.rs); the run's smallest measurement variance otherwise (the yaw
/// rate under a compass; every state when a gyro is logged with the compass, whose
/// combination pins the heading's drift), which a unit variance would let wander away from
/// the dynamics that identify the coefficients (K's sigma half of K with the gyro).
fn jitter_variance<M: Model>(model: &M, reads: &OutputReads, run: &RunData, i: usize) -> f64 {
    if model.outputs().is_empty() {
        // the outputs are the states: output index = state index
        return run
            .measured
            .iter()
            .position(|&s| s == i)
            .map_or(1.0, |k| run.r[k]);
    }
    let quantities = model.output_quantities();
    let alone = run
        .measured
        .iter()
        .position(|&o| model.state_index(quantities[o]) == Some(i) && !reads.shared(o));
    if let Some(k) = alone {
        return run.r[k];
    }
    if let [o] = run.measured[..] {
        if reads.shared(o) && reads.enters(o, i) {
            return 1.0;
        }
    }
    let smallest = run.r.iter().copied().fold(f64::INFINITY, f64::min);
    if smallest.is_finite() {
        smallest
    } else {
        1.0
    }
}

/// The problem with the `hekf.process_noise` entry `name` when it is neither a state of the
/// model nor an estimated coefficient (checked before any stage runs, and by [`setup`]).
pub(super) fn process_noise_problem<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    name: &str,
) -> Option<String> {
    let state = model.states().iter().any(|s| s.name == name);
    let estimated = cfg.estimate.iter().any(|e| e == name);
    (!state && !estimated).then(|| {
        format!(
            "hekf.process_noise.{name}: not a state of the {} model ({}) nor an estimated \
             coefficient",
            model.name(),
            model
                .states()
                .iter()
                .map(|s| s.name)
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

/// The filter set-up from the plan, the tuning and the runs; `hekf.process_noise` entries
/// (by state or coefficient name) override the preset.
pub fn setup<M: Model>(
    model: &M,
    cfg: &HekfConfig,
    plan: &Plan,
    tuning: &Resolved,
    runs: &[RunData],
) -> Result<Setup> {
    let nx = model.nx();
    let nb = plan.est.len();
    // the regular sampling interval: the median interval, which a gap does not move
    let dt = runs
        .iter()
        .filter_map(|r| median_interval(&r.times))
        .fold(0.0f64, f64::max);
    let substeps = tuning.substeps_for(dt);
    let mut q = vec![tuning.q_states; nx];
    if let Some(j) = tuning.state_jitter {
        for (i, qi) in q.iter_mut().enumerate() {
            // the smallest measurement variance per sample interval over the runs
            let per_second = runs
                .iter()
                .filter(|r| r.len() > 1)
                .map(|r| {
                    let dt = (r.times[r.len() - 1] - r.times[0]) / (r.len() - 1) as f64;
                    jitter_variance(model, &plan.reads, r, i) / dt
                })
                .fold(f64::INFINITY, f64::min);
            if per_second.is_finite() {
                *qi += j * per_second;
            }
        }
    }
    q.extend(std::iter::repeat_n(tuning.q_coefficients, nb));
    for (name, v) in &cfg.process_noise {
        if let Some(i) = model.states().iter().position(|s| s.name == name.as_str()) {
            q[i] = *v;
        } else if let Some(j) = plan.est_names.iter().position(|e| e == name) {
            q[nx + j] = *v;
        } else {
            let m = process_noise_problem(model, cfg, name).unwrap_or_default();
            return Err(Error::numerical("hekf", m));
        }
    }
    Ok(Setup {
        base: plan.base.clone(),
        est: plan.est.clone(),
        scale: plan.scale.clone(),
        ranges: plan.ranges.clone(),
        initial: plan.initial.clone(),
        prior_sigma: plan.prior_sigma.clone(),
        prior_correlation: plan.prior_correlation.clone(),
        held_prior: plan.held_prior.clone(),
        q,
        passes: tuning.passes,
        substeps,
        max_step: dt / substeps as f64,
        // the RTS smoother needs a transition per interval, which the continuous
        // (Kalman-Bucy) filter does not have (src/numerics/estimation/kalman_bucy.rs)
        smoother: tuning.smoother && cfg.filter != FilterKind::Continuous,
        gate: tuning.gate,
        gate_from_pass: 1,
        repeat_prior_factor: tuning.repeat_prior_factor,
        filter: cfg.filter,
        adaptable: adaptable_states(model, cfg, tuning),
        run_q: Vec::new(),
        noise_scale: 1.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::nomoto_wave::{NomotoWave, FRIGATE_9MS};
    use crate::model::models::spheroid3::Spheroid3;

    fn tuning() -> Resolved {
        Resolved::preset(crate::config::hekf::Preset::Hydroid)
    }

    fn frigate() -> (NomotoWave, Vec<f64>) {
        let m = NomotoWave::build(&NomotoWave::example_vehicle()).unwrap();
        let c = m.coefficient_vector(FRIGATE_9MS);
        (m, c)
    }

    /// A compass run of the frigate: output 0 (the compass) at `r`, 10 Hz.
    fn compass_run(r: f64) -> RunData {
        RunData {
            name: "compass".into(),
            times: vec![0.0, 0.1, 0.2],
            measured: vec![0],
            y: vec![0.05, 0.04, 0.03],
            r: vec![r],
            rounding: Vec::new(),
            inputs: InputSeries::constant(&[0.0]),
            x0: vec![0.0; 4],
            p0: vec![0.0; 16],
            lines: vec![2, 3, 4],
        }
    }

    /// Fossen 2011, 11.3: the compass reads psi_L + psi_H, the gyro r_L plus the wave yaw's
    /// rate (xi and psi_H through w0 and zeta_w); states r_L, psi_L, xi, psi_H.
    #[test]
    fn the_compass_reads_the_heading_with_the_wave_yaw() {
        let (m, c) = frigate();
        let reads = OutputReads::of(&m, &c);
        let compass: Vec<bool> = (0..4).map(|i| reads.enters(0, i)).collect();
        assert_eq!(compass, [false, true, false, true]);
        let gyro: Vec<bool> = (0..4).map(|i| reads.enters(1, i)).collect();
        assert_eq!(gyro, [true, false, true, true]);
        assert!(reads.shared(0) && reads.shared(1));
        let s = Spheroid3::paper_vehicle();
        let none = OutputReads::of(&s, &vec![0.0; s.coefficients().len()]);
        assert!(!none.shared(0) && !none.enters(0, 0));
    }

    /// The heading under the compass starts at the first sample with the unmeasured states'
    /// variance (the sample holds the wave yaw too); a spheroid's measured velocity with R.
    #[test]
    fn a_state_read_with_others_starts_as_uncertain_as_the_unmeasured() {
        let (m, c) = frigate();
        let reads = OutputReads::of(&m, &c);
        let (x0, p0) = initial_state(&m, &[Quantity::Yaw], &[0.05], &[1e-6], &tuning(), &reads);
        assert_eq!(x0, [0.0, 0.05, 0.0, 0.0]);
        assert_eq!([p0[0], p0[5], p0[10], p0[15]], [1.0, 1.0, 1.0, 1.0]);
        let s = Spheroid3::paper_vehicle();
        let none = OutputReads::of(&s, &[]);
        let (x0, p0) = initial_state(&s, &[Quantity::U], &[1.5], &[1e-4], &tuning(), &none);
        assert_eq!(x0[0], 1.5);
        assert_eq!(p0[0], 1e-4);
    }

    /// The jitter's variance per state of the frigate under a compass of variance 1e-6: the
    /// heading and the wave yaw (read together) 1 rad^2; the yaw rate and xi (not read) the
    /// compass's 1e-6; with a gyro too, the smallest variance everywhere. A spheroid's
    /// measured state gets its R, an unmeasured one 1.
    #[test]
    fn the_jitter_follows_what_each_output_reads() {
        let (m, c) = frigate();
        let reads = OutputReads::of(&m, &c);
        let run = compass_run(1e-6);
        let v: Vec<f64> = (0..4)
            .map(|i| jitter_variance(&m, &reads, &run, i))
            .collect();
        assert_eq!(v, [1e-6, 1.0, 1e-6, 1.0]);
        // a gyro logged as well: the combination pins the heading's drift
        let mut both = compass_run(1e-6);
        both.measured = vec![0, 1];
        both.r = vec![1e-6, 4e-8];
        both.y = vec![0.05, 0.0, 0.04, 0.0, 0.03, 0.0];
        let v: Vec<f64> = (0..4)
            .map(|i| jitter_variance(&m, &reads, &both, i))
            .collect();
        assert_eq!(v, [4e-8; 4]);
        let s = Spheroid3::paper_vehicle();
        let none = OutputReads::of(&s, &[]);
        let mut run = compass_run(2e-4);
        run.measured = vec![2];
        assert_eq!(jitter_variance(&s, &none, &run, 2), 2e-4);
        assert_eq!(jitter_variance(&s, &none, &run, 0), 1.0);
    }
}
