//! `hydroid plan`: which run to do next (docs/planner.md). From the current estimate and its
//! covariance ([`prior`]), each candidate run ([`candidate`]) is simulated with the identified
//! model and its information on the coefficients found in the linearisation at the current
//! estimate: a captive run's forces by automatic differentiation ([`captive`]), a manoeuvre
//! through the hybrid EKF's covariance recursion ([`manoeuvre`]); the posterior covariance
//! (P^-1 + F)^-1 gives each target's predicted sigma and the D- and A-optimal scores
//! ([`information`]), also per unit cost. [`verify`] checks the prediction by replicas
//! identified again.

pub mod candidate;
pub mod captive;
pub mod information;
pub mod limits;
pub mod manoeuvre;
pub mod prior;
pub mod verify;
pub mod write;

pub use candidate::{Candidate, Kind};

use crate::app::results::RunOutput;
use crate::base::error::{Error, Result};
use crate::config::LoadedConfig;
use crate::model::models::{with_model, Model, ModelVisitor};
use nalgebra::DMatrix;
use rayon::prelude::*;
use serde::Serialize;

/// What to plan for.
#[derive(Debug, Clone, Default)]
pub struct Settings {
    /// The coefficients whose uncertainty matters (empty: every identified one).
    pub targets: Vec<String>,
    /// The candidates (empty: the model's defaults).
    pub candidates: Vec<Candidate>,
    /// Verify the top this many candidates (0: none).
    pub verify: usize,
    /// Replicas per verified candidate.
    pub replicas: usize,
    /// Seed of the verification's noise.
    pub seed: u64,
}

/// One candidate's prediction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// Rank, 1 first.
    pub rank: usize,
    /// The candidate.
    pub candidate: Candidate,
    /// Its parameters in words.
    pub parameters: String,
    /// Predicted sigma of each target after it (SI, `targets` order).
    pub sigma_after: Vec<f64>,
    /// D_s-optimal gain on the targets, nats.
    pub d_score: f64,
    /// A-optimal share of the targets' relative variance removed.
    pub a_score: f64,
    /// D score per unit cost.
    pub d_per_cost: f64,
    /// Rank by D score per unit cost, 1 first.
    pub rank_per_cost: usize,
    /// A captive candidate's samples, whole periods and force noise as the plan assumed them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fitted: Option<captive::Fitted>,
    /// A captive candidate planned under consider mode whose information falls on
    /// coefficients the HEKF estimates from its own prior: its prediction with
    /// `hekf.mode = "joint"`, where that information is used.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint: Option<Joint>,
}

/// A captive candidate's prediction with `hekf.mode = "joint"`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Joint {
    /// The targets' predicted sigmas.
    pub sigma_after: Vec<f64>,
    /// The D-optimal gain on the targets (nats).
    pub d_score: f64,
}

/// A candidate that could not be evaluated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Skipped {
    /// Its name.
    pub name: String,
    /// Why.
    pub reason: String,
}

/// The plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// Layout version ([`SCHEMA`]).
    pub schema: &'static str,
    /// Model name.
    pub model: String,
    /// The target coefficients.
    pub targets: Vec<String>,
    /// Their units.
    pub units: Vec<String>,
    /// Their current values.
    pub values: Vec<f64>,
    /// Their current sigmas.
    pub sigma_before: Vec<f64>,
    /// Every coefficient the update acts on (the identified ones).
    pub parameters: Vec<String>,
    /// The HEKF's mode the plan is made in, the configuration's (`consider` or `joint`).
    pub mode: String,
    /// In consider mode, the parameters the HEKF estimates from its own prior: a captive
    /// run's information on them is not used (docs/planner.md, "The configuration's mode").
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub hekf_own: Vec<String>,
    /// The candidates, best first (by D score).
    pub ranked: Vec<Row>,
    /// Candidates that could not be evaluated.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub skipped: Vec<Skipped>,
    /// The method's assumptions, in words.
    pub assumptions: Vec<String>,
    /// Predicted against achieved sigma of the top candidates (`--verify`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub verification: Vec<verify::Verified>,
}

/// plan.json's layout version.
pub const SCHEMA: &str = "hydroid-plan/1";

/// The assumptions every plan rests on.
pub const ASSUMPTIONS: &[&str] = &[
    "the model is correct and the current estimate is close enough for the linearisation at \
     it to hold",
    "noise is white and Gaussian: a captive run's force noise per sample as given (default 0.3 % \
     of 0.5 rho U^2 A_ref, times the length for a moment), a manoeuvre's measurement and process \
     noise those the filter used on the first fitted run",
    "the information of earlier runs is the current covariance (the identified coefficients; \
     coefficients given in the configuration are exact)",
    "the plan is made in the configuration's hekf.mode: in consider mode a captive run's \
     information on a coefficient the HEKF also estimates is not used (the HEKF estimates it \
     from its own prior); such a candidate's sigmas with hekf.mode = \"joint\" are given beside",
    "the default costs (captive 40, PMM 80, manoeuvre 150 CPU hours) are placeholders; a \
     candidates file gives real ones",
];

/// Called as the verification goes: (candidate 1-based, candidates verified, replicas
/// identified of that candidate so far, its replicas), from any thread.
pub type VerifyProgress<'a> = &'a (dyn Fn(usize, usize, usize, usize) + Sync);

/// Plans the next run for the identified model of `output`.
pub fn plan(loaded: &LoadedConfig, output: &RunOutput, settings: &Settings) -> Result<Plan> {
    plan_with(loaded, output, settings, &|_, _, _, _| {})
}

/// [`plan`], telling `progress` how the verification goes.
pub fn plan_with(
    loaded: &LoadedConfig,
    output: &RunOutput,
    settings: &Settings,
    progress: VerifyProgress,
) -> Result<Plan> {
    limits::check_settings(&settings.targets, settings.verify, settings.replicas)?;
    let hekf =
        loaded.config.hekf.as_ref().ok_or_else(|| {
            Error::Usage("plan needs a configuration with an [hekf] stage".into())
        })?;
    let scale = captive::ForceScale {
        rho: loaded.vehicle.vehicle.rho,
        area: loaded.vehicle.vehicle.reference_area,
        length: loaded.vehicle.vehicle.length,
    };
    with_model(
        hekf.model,
        &loaded.vehicle,
        Planner {
            output,
            settings,
            scale,
            progress,
            hekf,
        },
    )
    .map_err(|p| {
        let what: Vec<String> = p
            .iter()
            .map(|p| format!("{}: {}", p.key, p.message))
            .collect();
        Error::Usage(format!("plan: {}", what.join("; ")))
    })?
}

/// The planner generic over the model.
struct Planner<'a> {
    output: &'a RunOutput,
    settings: &'a Settings,
    scale: captive::ForceScale,
    progress: VerifyProgress<'a>,
    hekf: &'a crate::config::hekf::HekfConfig,
}

impl ModelVisitor for Planner<'_> {
    type Output = Result<Plan>;
    fn visit<M: Model>(self, model: &M) -> Result<Plan> {
        let ctx = Context::new(model, self.output, self.settings, (self.scale, self.hekf))?;
        let candidates = if self.settings.candidates.is_empty() {
            candidate::defaults(ctx.abilities())
        } else {
            self.settings.candidates.clone()
        };
        ctx.check(&candidates)?;
        let mut plan = ctx.rank(&candidates);
        verify::verify(&ctx, &mut plan, self.settings, self.progress);
        Ok(plan)
    }
}

/// Everything a candidate is evaluated against.
pub(crate) struct Context<'a, M: Model> {
    model: &'a M,
    output: &'a RunOutput,
    prior: prior::Prior,
    op: prior::Operating,
    /// Target indices into the parameters.
    targets: Vec<usize>,
    scale: captive::ForceScale,
    /// The configuration's HEKF mode.
    mode: crate::config::hekf::Mode,
    /// Per parameter: a captive run's information on it is not used (consider mode, the
    /// HEKF estimates it from its own prior; [`captive::drop_unused`]).
    unused: Vec<bool>,
}

impl<'a, M: Model> Context<'a, M> {
    fn new(
        model: &'a M,
        output: &'a RunOutput,
        settings: &Settings,
        (scale, hekf): (captive::ForceScale, &crate::config::hekf::HekfConfig),
    ) -> Result<Self> {
        let prior = prior::prior(model, output)?;
        let op = prior::operating(model, output)?;
        let targets = if settings.targets.is_empty() {
            (0..prior.names.len()).collect()
        } else {
            settings
                .targets
                .iter()
                .map(|t| {
                    prior.names.iter().position(|n| n == t).ok_or_else(|| {
                        Error::Usage(format!(
                            "--target {t}: not an identified coefficient of this run (those \
                             are {}){}",
                            prior.names.join(", "),
                            crate::base::suggest::did_you_mean(
                                t,
                                prior.names.iter().map(String::as_str)
                            )
                        ))
                    })
                })
                .collect::<Result<_>>()?
        };
        let consider = hekf.mode == crate::config::hekf::Mode::Consider;
        let unused = prior
            .names
            .iter()
            .map(|n| consider && hekf.estimate.contains(n))
            .collect();
        Ok(Context {
            model,
            output,
            prior,
            op,
            targets,
            scale,
            mode: hekf.mode,
            unused,
        })
    }

    fn abilities(&self) -> candidate::Abilities {
        candidate::Abilities {
            captive: !self.model.force_quantities().is_empty(),
            rudder: self
                .model
                .input_quantities()
                .contains(&crate::base::quantity::Quantity::Rudder),
            planes: self
                .model
                .input_quantities()
                .contains(&crate::base::quantity::Quantity::SternPlanes),
            speed: self.op.speed,
            length: self.scale.length,
        }
    }

    /// Refuses candidates whose defaults, resolved on the identified run, make them
    /// implausible ([`limits::against`]), naming each with the speed and length used.
    fn check(&self, candidates: &[Candidate]) -> Result<()> {
        let resolved = limits::Resolved {
            speed: self.op.speed,
            dt: self.op.dt,
            duration: self.op.duration,
            length: self.scale.length,
            forces: self.model.force_quantities(),
            measured: self.op.measured.iter().map(|(q, _)| *q).collect(),
            model: self.model.name(),
        };
        let problems: Vec<String> = candidates
            .iter()
            .flat_map(|c| {
                limits::against(c, &resolved)
                    .into_iter()
                    .map(move |m| format!("candidate '{}': {m}", c.name))
            })
            .collect();
        if problems.is_empty() {
            return Ok(());
        }
        Err(Error::Usage(format!(
            "{} problem{} with the candidates on the identified run (U = {} m/s, L = {} m, a \
             manoeuvre's default {} s sampled every {} s):\n  - {}",
            problems.len(),
            if problems.len() == 1 { "" } else { "s" },
            crate::base::numfmt::short(resolved.speed),
            crate::base::numfmt::short(resolved.length),
            crate::base::numfmt::short(resolved.duration),
            crate::base::numfmt::short(resolved.dt),
            problems.join("\n  - ")
        )))
    }

    /// The posterior covariance after candidate `c` in the configuration's mode, and for a
    /// captive candidate whose information that mode leaves partly unused, the one with
    /// `hekf.mode = "joint"`.
    fn posterior(&self, c: &Candidate) -> Result<(DMatrix<f64>, Option<DMatrix<f64>>)> {
        if !c.kind.is_captive() {
            return manoeuvre::posterior(self.model, &self.prior, &self.op, c).map(|p| (p, None));
        }
        let cond = captive::condition(self.model, &self.prior, &self.op, c, self.scale)?;
        let post = captive::posterior(self.model, &self.prior, &cond, &self.unused)?;
        let joint = if self.unused.iter().any(|u| *u) {
            Some(captive::posterior(self.model, &self.prior, &cond, &[])?)
        } else {
            None
        };
        Ok((post, joint))
    }

    /// Every candidate evaluated (in parallel) and ranked by D score, ties by name.
    fn rank(&self, candidates: &[Candidate]) -> Plan {
        type Posteriors = Result<(DMatrix<f64>, Option<DMatrix<f64>>)>;
        let results: Vec<Posteriors> = candidates.par_iter().map(|c| self.posterior(c)).collect();
        let mut ranked = Vec::new();
        let mut skipped = Vec::new();
        for (c, r) in candidates.iter().zip(results) {
            match r {
                Ok((post, joint)) => ranked.push(self.row(c, &post, joint.as_ref())),
                Err(e) => skipped.push(Skipped {
                    name: c.name.clone(),
                    reason: e.to_string(),
                }),
            }
        }
        ranked.sort_by(|a, b| {
            b.d_score
                .total_cmp(&a.d_score)
                .then_with(|| a.candidate.name.cmp(&b.candidate.name))
        });
        for (k, r) in ranked.iter_mut().enumerate() {
            r.rank = k + 1;
        }
        let mut by_cost: Vec<usize> = (0..ranked.len()).collect();
        by_cost.sort_by(|&a, &b| {
            ranked[b]
                .d_per_cost
                .total_cmp(&ranked[a].d_per_cost)
                .then(a.cmp(&b))
        });
        for (k, &i) in by_cost.iter().enumerate() {
            ranked[i].rank_per_cost = k + 1;
        }
        let sigma = self.prior.sigma();
        let coef = |n: &str| self.output.result.coefficients.iter().find(|c| c.name == n);
        let names: Vec<String> = self
            .targets
            .iter()
            .map(|&i| self.prior.names[i].clone())
            .collect();
        Plan {
            schema: SCHEMA,
            model: self.model.name().to_string(),
            units: names
                .iter()
                .map(|n| coef(n).map(|c| c.unit.clone()).unwrap_or_default())
                .collect(),
            values: names
                .iter()
                .map(|n| coef(n).map_or(f64::NAN, |c| c.value))
                .collect(),
            sigma_before: self.targets.iter().map(|&i| sigma[i]).collect(),
            targets: names,
            parameters: self.prior.names.clone(),
            mode: self.mode.name().into(),
            hekf_own: self
                .prior
                .names
                .iter()
                .zip(&self.unused)
                .filter(|(_, u)| **u)
                .map(|(n, _)| n.clone())
                .collect(),
            ranked,
            skipped,
            assumptions: ASSUMPTIONS.iter().map(|s| s.to_string()).collect(),
            verification: Vec::new(),
        }
    }

    fn row(&self, c: &Candidate, post: &DMatrix<f64>, joint: Option<&DMatrix<f64>>) -> Row {
        let s = information::scores(&self.prior.cov, post, &self.targets);
        let sigmas = |p: &DMatrix<f64>| -> Vec<f64> {
            self.targets
                .iter()
                .map(|&i| p[(i, i)].max(0.0).sqrt())
                .collect()
        };
        Row {
            rank: 0,
            candidate: c.clone(),
            parameters: c.parameters(),
            sigma_after: sigmas(post),
            d_score: s.d,
            a_score: s.a,
            d_per_cost: s.d / c.cost,
            rank_per_cost: 0,
            fitted: c.kind.is_captive().then(|| {
                captive::fitted(self.model, c, c.speed.unwrap_or(self.op.speed), self.scale)
            }),
            joint: joint.map(|p| Joint {
                sigma_after: sigmas(p),
                d_score: information::scores(&self.prior.cov, p, &self.targets).d,
            }),
        }
    }
}
