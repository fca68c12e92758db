//! Captive runs (ITTC 7.5-02-06-02 practice): the vehicle held in a steady motion (static
//! drift, drift with rudder, circular motion) and the measured forces fitted with the model's
//! own force function ([`Model::steady_forces`]), so that every model that gives forces for a
//! prescribed motion has this stage. Unlike free-running motion, measured forces fix each
//! equation's scale (docs/hekf.md, "Identifiability").

pub mod fit;

pub use crate::config::captive::CaptiveConfig;

use crate::coefficients::{directions_of, Coefficient, CoefficientSet, Correlation, Source};
use crate::config::FluidConfig;
use crate::config::VehicleConfig;
use crate::error::{Error, Result};
use crate::models::{with_model, Model, ModelVisitor};
use crate::quantity::Quantity;
use crate::record::{Needs, Record};
use crate::warning::Warning;
use fit::Condition;
use serde::Serialize;

/// The stage's name in messages.
const STAGE: &str = "captive";

/// What the stage reads: every motion quantity, force and model input a record has.
pub fn needs(_cfg: &CaptiveConfig) -> Needs<'static> {
    static OPTIONAL: std::sync::OnceLock<Vec<Quantity>> = std::sync::OnceLock::new();
    let optional = OPTIONAL.get_or_init(|| {
        Quantity::MOTION
            .iter()
            .chain(&[
                Quantity::Fx,
                Quantity::Fy,
                Quantity::Fz,
                Quantity::Mx,
                Quantity::My,
                Quantity::Mz,
            ])
            .chain(crate::models::registry::all_inputs())
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
    /// RMS of the residual of each force component (SI, in `forces` order).
    pub residual_rms: Vec<f64>,
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
    /// The noise of each force component the fit found (SI).
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
    /// Puts the fitted coefficients, and their uncertainty directions, into `set`.
    pub fn merge_into(&self, set: &mut CoefficientSet) {
        let names: Vec<&str> = self.coefficients.iter().map(|c| c.name.as_str()).collect();
        let directions = directions_of("captive statistics", &names, &self.covariance);
        set.merge_stage(self.coefficients.clone(), directions);
    }
}

/// Runs the stage on its tables.
pub fn run(
    cfg: &CaptiveConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    known: &CoefficientSet,
    runs: &[Record],
) -> Result<CaptiveResult> {
    with_model(
        cfg.model,
        &vehicle.for_model(fluid),
        Fit { cfg, known, runs },
    )
    .map_err(Error::vehicle)?
}

struct Fit<'a> {
    cfg: &'a CaptiveConfig,
    known: &'a CoefficientSet,
    runs: &'a [Record],
}

impl ModelVisitor for Fit<'_> {
    type Output = Result<CaptiveResult>;

    fn visit<M: Model>(self, model: &M) -> Result<CaptiveResult> {
        let cfg = self.cfg;
        let forces = model.force_quantities();
        if forces.is_empty() {
            return Err(Error::numerical(
                STAGE,
                format!(
                    "the {} model gives no forces for a prescribed motion, so captive runs \
                     cannot be fitted with it",
                    model.name()
                ),
            ));
        }
        let (base, est) = coefficient_vector(model, cfg, self.known)?;
        let mut conditions = Vec::new();
        let mut sizes = Vec::new();
        for rec in self.runs {
            let c = conditions_of(model, rec)?;
            sizes.push((rec.name.clone(), c.len()));
            conditions.extend(c);
        }
        let start: Vec<f64> = cfg
            .estimate
            .iter()
            .map(|n| cfg.start.get(n).copied().unwrap_or(0.0))
            .collect();
        let f = fit::fit(model, &base, &est, &start, &conditions)
            .map_err(|m| Error::numerical(STAGE, m))?;
        let p = est.len();
        let sigma = |i: usize| f.covariance[i][i].max(0.0).sqrt();
        let coefficients: Vec<Coefficient> = (0..p)
            .map(|i| {
                let mut c = Coefficient::new(
                    &cfg.estimate[i],
                    f.values[i],
                    Some(sigma(i)),
                    Source::Captive,
                );
                c.note = Some(format!(
                    "{} model fitted to the forces of {} captive conditions",
                    model.name(),
                    conditions.len()
                ));
                c
            })
            .collect();
        let matrix = (0..p)
            .map(|a| {
                (0..p)
                    .map(|b| {
                        let d = sigma(a) * sigma(b);
                        if d > 0.0 {
                            (f.covariance[a][b] / d).clamp(-1.0, 1.0)
                        } else if a == b {
                            1.0
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect();
        let runs = residual_summaries(model, &base, &est, &f.values, &conditions, &sizes);
        Ok(CaptiveResult {
            model: model.name().to_string(),
            forces: forces.iter().map(|q| q.key().to_string()).collect(),
            coefficients,
            correlation: Correlation {
                names: cfg.estimate.clone(),
                matrix,
            },
            noise: f.noise.clone(),
            iterations: f.iterations,
            runs,
            warnings: Vec::new(),
            covariance: f.covariance,
        })
    }
}

/// The model's coefficient vector with the known values, and the indices of the estimated.
fn coefficient_vector<M: Model>(
    model: &M,
    cfg: &CaptiveConfig,
    known: &CoefficientSet,
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
        match known.get(n) {
            Some(c) => base[i] = c.value,
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

/// The steady conditions of one table: a row each, the model's velocities from the columns
/// (0 when a velocity is neither a column nor a constant: a static drift has no r), its
/// inputs from columns or constants, and every force component it measures.
fn conditions_of<M: Model>(model: &M, rec: &Record) -> Result<Vec<Condition>> {
    let fail = |m: String| Error::numerical(STAGE, format!("run '{}': {m}", rec.name));
    let rows = rec.rows();
    let value = |q: Quantity, k: usize| {
        rec.channel(q)
            .map(|v| v[k])
            .or_else(|| rec.constants.get(&q).copied())
    };
    for q in model.force_quantities() {
        if !rec.has(*q) {
            return Err(fail(format!(
                "no {q} column: the {} model's captive forces are {}",
                model.name(),
                model
                    .force_quantities()
                    .iter()
                    .map(|q| q.key())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    for q in model.input_quantities() {
        if !rec.has(q) {
            return Err(fail(format!(
                "no {q}: the {} model needs it (a column, or `constants = {{ {q} = ... }}`)",
                model.name()
            )));
        }
    }
    if !rec.has(Quantity::U) {
        return Err(fail("no u: the speed of the held motion is needed".into()));
    }
    let mut out = Vec::new();
    for k in 0..rows {
        let x: Vec<f64> = model
            .states()
            .iter()
            .map(|s| match s.quantity {
                q if Quantity::MOTION[..6].contains(&q) => value(q, k).unwrap_or(0.0),
                _ => 0.0,
            })
            .collect();
        let u: Vec<f64> = model
            .input_quantities()
            .iter()
            .map(|q| value(*q, k).unwrap_or(0.0))
            .collect();
        let f: Vec<f64> = model
            .force_quantities()
            .iter()
            .map(|q| value(*q, k).unwrap_or(f64::NAN))
            .collect();
        let line = rec.lines.get(k).copied().unwrap_or(k + 1);
        if x.iter().chain(&u).chain(&f).any(|v| !v.is_finite()) {
            return Err(fail(format!("line {line}: a value is not a number")));
        }
        out.push(Condition {
            x,
            u,
            f,
            place: format!("{} line {line}", rec.name),
        });
    }
    Ok(out)
}

/// The RMS residual of each force component per table.
fn residual_summaries<M: Model>(
    model: &M,
    base: &[f64],
    est: &[usize],
    values: &[f64],
    conditions: &[Condition],
    sizes: &[(String, usize)],
) -> Vec<RunSummary> {
    let mut c = base.to_vec();
    for (&i, v) in est.iter().zip(values) {
        c[i] = *v;
    }
    model.relations().apply(&mut c);
    let nf = model.force_quantities().len();
    let mut out = Vec::new();
    let mut k0 = 0;
    for (name, n) in sizes {
        let mut ss = vec![0.0; nf];
        let mut f = vec![0.0; nf];
        for cond in &conditions[k0..k0 + n] {
            model.steady_forces(&cond.x, &cond.u, &c, &mut f);
            for i in 0..nf {
                ss[i] += (cond.f[i] - f[i]).powi(2);
            }
        }
        out.push(RunSummary {
            name: name.clone(),
            conditions: *n,
            residual_rms: ss.iter().map(|s| (s / (*n).max(1) as f64).sqrt()).collect(),
        });
        k0 += n;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::spheroid3::Spheroid3;

    #[test]
    fn a_model_without_forces_for_a_prescribed_motion_is_refused() {
        let model = Spheroid3::build(&Spheroid3::example_vehicle()).unwrap();
        let cfg: CaptiveConfig =
            toml::from_str("model = \"spheroid3\"\nestimate = [\"Nvv\"]\nruns = []").unwrap();
        let known = CoefficientSet::new();
        let e = Fit {
            cfg: &cfg,
            known: &known,
            runs: &[],
        }
        .visit(&model)
        .unwrap_err()
        .to_string();
        assert!(e.contains("gives no forces for a prescribed motion"), "{e}");
    }
}
