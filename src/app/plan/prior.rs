//! What the planner starts from: the identified coefficients with their joint covariance (the
//! prior of the next run), and the operating point and noise levels of the run's first fitted
//! manoeuvre (the model's own noise levels, which a candidate manoeuvre is assumed to share).

use crate::app::results::RunOutput;
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::dynamics::sim::{complete_coefficients, InputSeries};
use crate::model::coefficients::{CoefficientSet, Source};
use crate::model::models::Model;
use nalgebra::DMatrix;

/// The current estimate and its covariance over the identified coefficients.
#[derive(Debug, Clone)]
pub struct Prior {
    /// The identified coefficients (the planner's parameters), in model order.
    pub names: Vec<String>,
    /// Their indices in the model's coefficient vector.
    pub est: Vec<usize>,
    /// The model's completed coefficient vector at the estimate.
    pub base: Vec<f64>,
    /// Covariance of the parameters (SI), p x p.
    pub cov: DMatrix<f64>,
}

impl Prior {
    /// The parameters' current values (SI), in `names` order.
    pub fn values(&self) -> Vec<f64> {
        self.est.iter().map(|&i| self.base[i]).collect()
    }

    /// The prior standard deviations.
    pub fn sigma(&self) -> Vec<f64> {
        (0..self.names.len())
            .map(|i| self.cov[(i, i)].max(0.0).sqrt())
            .collect()
    }
}

/// The identified model's operating point and noise, from its first fitted manoeuvre.
#[derive(Debug, Clone)]
pub struct Operating {
    /// Initial state of the first fitted run (re-simulated).
    pub x0: Vec<f64>,
    /// Its inputs at the start (SI, model input order).
    pub u0: Vec<f64>,
    /// Its initial surge speed, m/s.
    pub speed: f64,
    /// Its mean sample interval, s.
    pub dt: f64,
    /// Its duration, s.
    pub duration: f64,
    /// The measured outputs and the measurement noise sigma the filter used (SI).
    pub measured: Vec<(Quantity, f64)>,
    /// Process noise spectral density of each state (the filter's, calibrated along the run
    /// where it was).
    pub q: Vec<f64>,
    /// RK4 sub-steps per sample the filter took.
    pub substeps: usize,
}

/// The prior of the identified coefficients of `output` for `model`: every free coefficient a
/// stage identified with a positive sigma, its covariance over the final set's uncertainty
/// directions (the variance alone where the directions do not cover its sigma).
pub fn prior<M: Model>(model: &M, output: &RunOutput) -> Result<Prior> {
    let set: CoefficientSet = output
        .resim_set
        .clone()
        .ok_or_else(|| Error::Usage(NO_HEKF.into()))?;
    let base = complete_coefficients(model, &set).map_err(|missing| {
        Error::Usage(format!(
            "plan: the run's coefficients miss {}",
            missing.join(", ")
        ))
    })?;
    let mut names = Vec::new();
    let mut est = Vec::new();
    let mut sigma = Vec::new();
    for (i, name) in model.coefficient_names().iter().enumerate() {
        let Some(c) = output.result.coefficients.iter().find(|c| c.name == *name) else {
            continue;
        };
        let identified = matches!(
            c.source,
            Source::Polar | Source::Surge | Source::Captive | Source::Hekf
        );
        match c.sigma {
            Some(s) if identified && s > 0.0 && s.is_finite() && !model.is_derived(name) => {
                names.push(name.to_string());
                est.push(i);
                sigma.push(s);
            }
            _ => {}
        }
    }
    if names.is_empty() {
        return Err(Error::Usage(
            "plan: the run identified no coefficient with a sigma".into(),
        ));
    }
    let p = names.len();
    let covered: Vec<bool> = names.iter().map(|n| set.covered(n)).collect();
    let cov = DMatrix::from_fn(p, p, |i, j| match (covered[i] && covered[j], i == j) {
        (true, _) => set.covariance(&names[i], &names[j]),
        (false, true) => sigma[i] * sigma[i],
        (false, false) => 0.0,
    });
    Ok(Prior {
        names,
        est,
        base,
        cov,
    })
}

const NO_HEKF: &str = "plan needs a run with an HEKF stage: its identified model, its first \
                       fitted manoeuvre's operating point and its noise levels";

/// The operating point and noise levels of the first fitted manoeuvre of `output`.
pub fn operating<M: Model>(model: &M, output: &RunOutput) -> Result<Operating> {
    let hekf = output
        .result
        .stages
        .hekf
        .as_ref()
        .ok_or_else(|| Error::Usage(NO_HEKF.into()))?;
    let (Some((rec, trace)), Some(run)) = (output.resim_traces.first(), hekf.runs.first()) else {
        return Err(Error::Usage(NO_HEKF.into()));
    };
    let x0 = trace
        .states
        .first()
        .cloned()
        .ok_or_else(|| Error::Usage(NO_HEKF.into()))?;
    let inputs = InputSeries::from_record(model.inputs(), rec)
        .map_err(|q| Error::Usage(format!("plan: run '{}' has no input {q}", rec.name)))?;
    let mut u0 = vec![0.0; inputs.len()];
    inputs.at(trace.times.first().copied().unwrap_or(0.0), &mut u0);
    let speed = model
        .state_index(Quantity::U)
        .map_or(1.0, |i| x0[i].abs().max(1e-3));
    let nx = model.nx();
    let q = (0..nx)
        .map(|j| {
            let name = model.states()[j].name;
            run.process_noise
                .get(name)
                .or_else(|| hekf.settings.process_noise.get(j))
                .copied()
                .unwrap_or(0.0)
        })
        .collect();
    let measured = run.noise.iter().map(|n| (n.quantity, n.sigma)).collect();
    Ok(Operating {
        x0,
        u0,
        speed,
        dt: run.mean_dt,
        duration: run.duration,
        measured,
        q,
        substeps: hekf.settings.substeps.max(1),
    })
}
