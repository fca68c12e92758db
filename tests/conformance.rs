//! The conformance suite every registered model passes, run for each entry of the model
//! registry (`ModelName::ALL`): a model added to the registry is checked here without any
//! change to this file.
//!
//! 1. The AD Jacobians of the dynamics and of the measurement function, over the augmented
//!    state (states and every free coefficient, relations included), agree with central
//!    finite differences.
//! 2. The model's relations hit their targets: every derived coefficient equals its
//!    definition.
//! 3. The model's physical check passes at its example values.
//! 4. Round trip: simulate the example run, export it as a CSV file, read it back as hydroid
//!    reads any export, and identify the example's coefficients from the noise-free data with
//!    the hybrid EKF: each within 1 % of the truth.

use hydroid::config::{FluidConfig, InputSpec, VehicleConfig};
use hydroid::dynamics::model_system::ModelSystem;
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::io::record;
use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source, YawMoment};
use hydroid::model::models::{with_model, Model, ModelName, ModelVisitor, Vehicle};
use hydroid::numerics::ad;
use hydroid::stages::hekf::{self, HekfConfig};

/// Runs `check` on every registered model, built for its example vehicle; failures name the
/// model.
fn for_every_model<V: ModelVisitor<Output = Result<(), String>> + Clone>(check: V) {
    let mut failures = Vec::new();
    for name in ModelName::ALL {
        let vehicle = name.example_vehicle();
        match with_model(*name, &vehicle, check.clone()) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => failures.push(format!("{name}: {e}")),
            Err(problems) => failures.push(format!("{name}: example vehicle: {problems:?}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The example's coefficient vector, the free coefficients' indices and their scales.
fn example_coefficients<M: Model>(m: &M) -> (Vec<f64>, Vec<usize>, Vec<f64>) {
    let c = m.coefficient_vector(m.example().coefficients);
    let free: Vec<usize> = (0..c.len())
        .filter(|&i| !m.is_derived(m.coefficients()[i].name))
        .collect();
    let scale = free
        .iter()
        .map(|&i| m.typical_magnitude(m.coefficients()[i].name))
        .collect();
    (c, free, scale)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[derive(Clone)]
struct Jacobians;

impl ModelVisitor for Jacobians {
    type Output = Result<(), String>;
    fn visit<M: Model>(self, m: &M) -> Result<(), String> {
        let ex = m.example();
        // at the example as it is (coefficients that are zero included: an estimate starts
        // there, and a zero value must still carry its derivative), and moved off every
        // plane of symmetry so that every term counts
        let moved: Vec<f64> = ex
            .state
            .iter()
            .enumerate()
            .map(|(k, v)| v + 0.03 * (k + 1) as f64)
            .collect();
        jacobians_at(m, &ex.state, 0.0).map_err(|e| format!("at the example: {e}"))?;
        jacobians_at(m, &moved, 0.1).map_err(|e| format!("off the example: {e}"))
    }
}

/// Compares the AD Jacobians of the augmented dynamics and measurements at state `x0` and
/// the example's coefficients moved by `dz` (in scaled units) with finite differences.
fn jacobians_at<M: Model>(m: &M, x0: &[f64], dz: f64) -> Result<(), String> {
    let ex = m.example();
    let (c, free, scale) = example_coefficients(m);
    let inputs = InputSeries::constant(&ex.inputs);
    let outputs: Vec<usize> = (0..m.output_quantities().len()).collect();
    let mut sys = ModelSystem::new(m, c.clone(), &free, &scale, &inputs, &outputs);
    let nx = m.nx();
    let n = nx + free.len();
    let mut x = x0.to_vec();
    x.extend(free.iter().zip(&scale).map(|(&i, s)| c[i] / s + dz));
    // the dynamics
    let mut dx = vec![0.0; nx];
    let mut fa = vec![0.0; nx * n];
    hydroid::numerics::estimation::System::jacobian(
        &mut sys,
        hydroid::numerics::ode::StageTime::at(0.0),
        &x,
        &mut dx,
        &mut fa,
    );
    let mut ff = vec![0.0; nx * n];
    ad::jacobian_fd(
        &x,
        nx,
        |xs, out| {
            hydroid::numerics::estimation::System::derivative(
                &mut sys,
                hydroid::numerics::ode::StageTime::at(0.0),
                xs,
                out,
            )
        },
        &mut ff,
    );
    for (k, (a, b)) in fa.iter().zip(&ff).enumerate() {
        if !close(*a, *b, 1e-5) {
            return Err(format!(
                "df/dx[{}][{}] = {a} by AD, {b} by finite differences",
                k / n,
                k % n
            ));
        }
    }
    // the measurement function
    let ny = outputs.len();
    let (mut y, mut ha) = (vec![0.0; ny], vec![0.0; ny * n]);
    hydroid::numerics::estimation::System::observe(
        &mut sys,
        hydroid::numerics::ode::StageTime::at(0.0),
        &x,
        &mut y,
        &mut ha,
    );
    let mut hf = vec![0.0; ny * n];
    let mut h = vec![0.0; ny * n];
    ad::jacobian_fd(
        &x,
        ny,
        |xs, out| {
            hydroid::numerics::estimation::System::observe(
                &mut sys,
                hydroid::numerics::ode::StageTime::at(0.0),
                xs,
                out,
                &mut h,
            )
        },
        &mut hf,
    );
    for (k, (a, b)) in ha.iter().zip(&hf).enumerate() {
        if !close(*a, *b, 1e-5) {
            return Err(format!(
                "dh/dx[{}][{}] = {a} by AD, {b} by finite differences",
                k / n,
                k % n
            ));
        }
    }
    Ok(())
}

#[test]
fn jacobians_of_dynamics_and_measurements_match_finite_differences() {
    for_every_model(Jacobians);
}

#[derive(Clone)]
struct Relations;

impl ModelVisitor for Relations {
    type Output = Result<(), String>;
    fn visit<M: Model>(self, m: &M) -> Result<(), String> {
        // arbitrary free values, so that no relation holds by accident
        let mut c: Vec<f64> = (0..m.coefficients().len())
            .map(|i| 0.37 + 0.11 * i as f64)
            .collect();
        m.relations().apply(&mut c);
        let value = |name: &str| m.coefficient_index(name).map(|i| c[i]);
        for target in m.relations().targets() {
            let name = m.coefficients()[target].name;
            let definition = M::COMPLETING_RELATIONS
                .iter()
                .flat_map(|r| r.iter())
                .find(|r| r.target == name && r.terms.iter().all(|(_, t)| value(t).is_some()))
                .ok_or_else(|| {
                    format!("{name} is derived but no relation of the model says how")
                })?;
            let want: f64 = definition
                .terms
                .iter()
                .map(|(f, t)| f * value(t).expect("checked"))
                .sum();
            if !close(c[target], want, 1e-12) {
                return Err(format!(
                    "{name} = {} after the relations, {want} by {}",
                    c[target], definition.cite
                ));
            }
        }
        Ok(())
    }
}

#[test]
fn relations_hit_their_targets() {
    for_every_model(Relations);
}

#[derive(Clone)]
struct Check;

impl ModelVisitor for Check {
    type Output = Result<(), String>;
    fn visit<M: Model>(self, m: &M) -> Result<(), String> {
        let ex = m.example();
        let c = m.coefficient_vector(ex.coefficients);
        if ex.state.len() != m.nx() || ex.inputs.len() != m.inputs().len() {
            return Err("the example's state or inputs have the wrong length".into());
        }
        for n in ex.estimated {
            if m.coefficient_index(n).is_none() || m.is_derived(n) {
                return Err(format!(
                    "the example estimates {n}, which is not a free coefficient of the model"
                ));
            }
        }
        m.check(&ex.state, &c).map_err(|e| e.to_string())
    }
}

#[test]
fn the_physical_check_passes_at_the_example() {
    for_every_model(Check);
}

/// The example vehicle as a configuration gives it.
fn vehicle_config(v: &Vehicle) -> (VehicleConfig, FluidConfig) {
    (
        VehicleConfig {
            name: "example".into(),
            mass: v.mass,
            length: v.length,
            diameter: v.diameter,
            ixx: v.ixx,
            iyy: v.iyy,
            izz: v.izz,
            reference_area: v.reference_area,
            reference_length: 1.0,
            buoyancy: v.buoyancy,
            bg: v.bg,
            scale: None,
            particulars: v.particulars.clone(),
            yaw_moment: Default::default(),
        },
        FluidConfig {
            rho: v.rho,
            mu: 1e-3,
        },
    )
}

#[derive(Clone)]
struct RoundTrip {
    vehicle: Vehicle,
}

impl ModelVisitor for RoundTrip {
    type Output = Result<(), String>;
    fn visit<M: Model>(self, m: &M) -> Result<(), String> {
        let ex = m.example();
        let truth = m.coefficient_vector(ex.coefficients);
        // simulate the example run at 100 Hz
        let times: Vec<f64> = (0..=(ex.duration * 100.0).round() as usize)
            .map(|k| k as f64 * 0.01)
            .collect();
        let inputs = InputSeries::constant(&ex.inputs);
        let xs = simulate(m, &truth, &ex.state, &inputs, &times, 4).map_err(|e| e.to_string())?;
        // export: every output and input, SI units in the header
        let outputs = m.output_quantities();
        let mut csv = String::from("time [s]");
        for q in outputs.iter().chain(&m.input_quantities()) {
            csv.push_str(&format!(",{} [{}]", q.key(), q.si_symbol()));
        }
        csv.push('\n');
        for (k, x) in xs.iter().enumerate() {
            csv.push_str(&format!("{:.17e}", times[k]));
            for v in m
                .output_values(x, &ex.inputs, &truth)
                .iter()
                .chain(&ex.inputs)
            {
                csv.push_str(&format!(",{v:.17e}"));
            }
            csv.push('\n');
        }
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        std::fs::write(dir.path().join("run.csv"), csv).map_err(|e| e.to_string())?;
        // identify the example's coefficients, the others known
        let cfg: HekfConfig = toml::from_str(&format!(
            "model = \"{}\"\nestimate = {:?}\nsmoother = false\nruns = []\n",
            m.name(),
            ex.estimated
        ))
        .map_err(|e| e.to_string())?;
        // read it back as any export
        let spec: InputSpec = toml::from_str("file = \"run.csv\"").map_err(|e| e.to_string())?;
        let rec = record::load(&spec, dir.path(), &hekf::needs(&cfg)).map_err(|e| e.to_string())?;
        let mut known = CoefficientSet::new();
        for (n, v) in ex.coefficients {
            if !ex.estimated.contains(n) {
                known.insert(Coefficient::new(n, *v, None, Source::Config));
            }
        }
        for rel in M::COMPLETING_RELATIONS {
            known.complete(rel, YawMoment::LiftOnly);
        }
        let (vehicle, fluid) = vehicle_config(&self.vehicle);
        let result = hekf::run(
            &cfg,
            &hekf::StageInputs {
                vehicle: &vehicle.for_model(&fluid),
                known: &known,
                runs: std::slice::from_ref(&rec),
                base_dir: dir.path(),
            },
            &mut hydroid::base::progress::Silent,
        )
        .map_err(|e| e.to_string())?;
        for c in result.coefficients() {
            let want = truth[m.coefficient_index(&c.name).expect("the model's")];
            // within 1 % (of 1e-3 for a zero truth), or within 2 sigma with a sigma inside
            // that band: noise-free data still leave the filter its numerical noise floors
            let band = 0.01 * want.abs().max(1e-3);
            let error = (c.value - want).abs();
            let sigma = c.sigma.unwrap_or(f64::INFINITY);
            if error > band && (error > 2.0 * sigma || sigma > band) {
                return Err(format!(
                    "{} identified as {} +- {:?}, truth {want}",
                    c.name, c.value, c.sigma
                ));
            }
        }
        Ok(())
    }
}

#[test]
fn simulate_export_read_identify_recovers_the_coefficients() {
    let mut failures = Vec::new();
    for name in ModelName::ALL {
        let vehicle = name.example_vehicle();
        let check = RoundTrip {
            vehicle: vehicle.clone(),
        };
        match with_model(*name, &vehicle, check) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => failures.push(format!("{name}: {e}")),
            Err(problems) => failures.push(format!("{name}: example vehicle: {problems:?}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
