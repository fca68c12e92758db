//! `hydroid.simulate`: a model of the registry integrated with hydroid's RK4
//! ([`hydroid::dynamics::sim::simulate`]) from given coefficients, vehicle and input series.

use crate::{json_text, py_err};
use hydroid::app::catalogue::model_named;
use hydroid::app::simulate::synth::coefficients_for;
use hydroid::base::error::ConfigProblem;
use hydroid::config::{FluidConfig, VehicleConfig};
use hydroid::dynamics::sim::inputs::Input;
use hydroid::dynamics::sim::{simulate as integrate, InputSeries};
use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source};
use hydroid::{with_model, Error, Model, ModelVisitor};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Simulates `model` (a registry name) with `coefficients` (SI, by name; the model's
/// relations complete them) for the vehicle of `vehicle_file` (its `[vehicle]` and `[fluid]`
/// tables) or `vehicle_json` (`{"vehicle": {...}, "fluid": {...}}`, the same keys), from the
/// state `initial` (by state name or quantity; others 0) at `t[0]`, with the inputs sampled
/// at `t` (by quantity key, SI; linear between samples), `substeps` RK4 steps per interval.
/// Returns JSON text {columns: [names], units: [SI units], rows: [[t, x...]]}.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (model, coefficients, vehicle_file, vehicle_json, t, inputs, initial, substeps))]
pub fn simulate(
    py: Python<'_>,
    model: &str,
    coefficients: BTreeMap<String, f64>,
    vehicle_file: Option<PathBuf>,
    vehicle_json: Option<String>,
    t: Vec<f64>,
    inputs: BTreeMap<String, Vec<f64>>,
    initial: BTreeMap<String, f64>,
    substeps: usize,
) -> PyResult<String> {
    let out = py
        .detach(|| {
            let name = model_named(model)?;
            let (vehicle, fluid) = match (vehicle_file, vehicle_json) {
                (Some(path), _) => vehicle_of_file(&path)?,
                (None, Some(text)) => vehicle_of_json(&text)?,
                (None, None) => {
                    return Err(Error::Usage("simulate needs a vehicle".to_string()));
                }
            };
            check_times(&t, substeps)?;
            let mut set = CoefficientSet::new();
            for (n, v) in &coefficients {
                set.insert(Coefficient::new(n, *v, None, Source::Config));
            }
            let sim = Sim {
                set: &set,
                t: &t,
                inputs: &inputs,
                initial: &initial,
                substeps,
            };
            with_model(name, &vehicle.for_model(&fluid), sim).map_err(Error::vehicle)?
        })
        .map_err(py_err)?;
    json_text(&out)
}

/// Times that an integration can step through: finite, strictly increasing, at least one.
fn check_times(t: &[f64], substeps: usize) -> Result<(), Error> {
    if t.is_empty() || t.iter().any(|v| !v.is_finite()) {
        return Err(Error::Usage(
            "inputs['t'] must hold at least one finite time, s".to_string(),
        ));
    }
    if let Some(w) = t.windows(2).find(|w| w[1] <= w[0]) {
        return Err(Error::Usage(format!(
            "inputs['t'] must increase strictly: {} follows {}",
            w[1], w[0]
        )));
    }
    if substeps == 0 {
        return Err(Error::Usage("substeps must be at least 1".to_string()));
    }
    Ok(())
}

/// A problem of the vehicle file `path` under `key`.
fn file_problem(path: &Path, key: &str, message: String) -> Error {
    Error::Config(vec![ConfigProblem {
        file: path.to_path_buf(),
        line: None,
        key: Some(key.to_string()),
        message,
    }])
}

/// The `[vehicle]` and `[fluid]` tables of a TOML file (a run or simulation configuration,
/// or a vehicle file with a `[fluid]` table).
fn vehicle_of_file(path: &Path) -> Result<(VehicleConfig, FluidConfig), Error> {
    let text = hydroid::config::read(path)?;
    let doc: toml::Table = toml::from_str(&text)
        .map_err(|e| file_problem(path, "", format!("not a TOML file: {e}")))?;
    let table = |key: &str| {
        doc.get(key)
            .cloned()
            .ok_or_else(|| file_problem(path, key, format!("the file has no [{key}] table")))
    };
    let vehicle = table("vehicle")?
        .try_into()
        .map_err(|e| file_problem(path, "vehicle", e.to_string()))?;
    let fluid = table("fluid")?
        .try_into()
        .map_err(|e| file_problem(path, "fluid", e.to_string()))?;
    Ok((vehicle, fluid))
}

/// The vehicle and fluid from `{"vehicle": {...}, "fluid": {...}}`.
fn vehicle_of_json(text: &str) -> Result<(VehicleConfig, FluidConfig), Error> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Given {
        vehicle: VehicleConfig,
        fluid: FluidConfig,
    }
    let g: Given =
        serde_json::from_str(text).map_err(|e| Error::Usage(format!("vehicle or fluid: {e}")))?;
    Ok((g.vehicle, g.fluid))
}

/// The simulated series of one model.
#[derive(serde::Serialize)]
struct Series {
    /// `t`, then the states' names.
    columns: Vec<String>,
    /// Their SI units.
    units: Vec<String>,
    /// One row per time.
    rows: Vec<Vec<f64>>,
}

/// The simulation, for whichever model is named.
struct Sim<'a> {
    set: &'a CoefficientSet,
    t: &'a [f64],
    inputs: &'a BTreeMap<String, Vec<f64>>,
    initial: &'a BTreeMap<String, f64>,
    substeps: usize,
}

impl ModelVisitor for Sim<'_> {
    type Output = Result<Series, Error>;

    fn visit<M: Model>(self, m: &M) -> Result<Series, Error> {
        let c = coefficients_for(m, self.set, "coefficients")?;
        let states = m.states();
        let mut x0 = vec![0.0; m.nx()];
        for (name, v) in self.initial {
            let i = states
                .iter()
                .position(|s| s.name == name || s.quantity.key() == name)
                .ok_or_else(|| {
                    let names: Vec<&str> = states.iter().map(|s| s.name).collect();
                    Error::Usage(format!(
                        "initial '{name}' is not a state of the {} model (states: {})",
                        m.name(),
                        names.join(", ")
                    ))
                })?;
            x0[i] = *v;
        }
        let series = InputSeries {
            t: self.t.to_vec(),
            inputs: input_columns(m, self.inputs, self.t.len())?,
        };
        let rows = integrate(m, &c, &x0, &series, self.t, self.substeps)
            .map_err(|e| Error::numerical("simulate", e.to_string()))?;
        Ok(Series {
            columns: std::iter::once("t")
                .chain(states.iter().map(|s| s.name))
                .map(String::from)
                .collect(),
            units: std::iter::once("s")
                .chain(states.iter().map(|s| s.quantity.si_symbol()))
                .map(String::from)
                .collect(),
            rows: self
                .t
                .iter()
                .zip(rows)
                .map(|(t, x)| std::iter::once(*t).chain(x).collect())
                .collect(),
        })
    }
}

/// The model's inputs in its order from the given series (each `n` samples); an input the
/// model does not have, or one it has that is not given, is refused.
fn input_columns<M: Model>(
    m: &M,
    given: &BTreeMap<String, Vec<f64>>,
    n: usize,
) -> Result<Vec<Input>, Error> {
    let keys: Vec<&str> = m.inputs().iter().map(|d| d.quantity.key()).collect();
    if let Some(k) = given.keys().find(|k| !keys.contains(&k.as_str())) {
        return Err(Error::Usage(format!(
            "'{k}' is not an input of the {} model (inputs: {})",
            m.name(),
            keys.join(", ")
        )));
    }
    keys.iter()
        .map(|k| match given.get(*k) {
            Some(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => {
                Ok(Input::Series(v.clone()))
            }
            Some(v) => Err(Error::Usage(format!(
                "input '{k}' must hold {n} finite values, one per time (it holds {})",
                v.len()
            ))),
            None => Err(Error::Usage(format!(
                "the {} model needs the input '{k}' (inputs: {})",
                m.name(),
                keys.join(", ")
            ))),
        })
        .collect()
}
