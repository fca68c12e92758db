//! The `hydroid simulate` configuration: a model, its coefficients, a manoeuvre, seeded noise
//! and the export layout. Documented in docs/simulate.md.
//!
//! The file is read like a run configuration (every problem listed with its line, units
//! checked against each key's dimension), then checked against limits that keep a
//! simulation finite in time and memory: see [`limits`].

use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::si;
use crate::base::units::{check_dim, Unit};
use crate::config::{
    quantity_key, read_collecting, Constant, FluidConfig, Problems, VehicleConfig,
};
use crate::io::formats::Format;
use crate::model::coefficients::YawMoment;
use crate::model::models::{with_model, Model, ModelVisitor};
use crate::stages::hekf::ModelName;
use serde::de::{Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// Bounds on what one simulation may ask for.
pub mod limits {
    /// Most rows an export may have. Ten million samples is ten times a long CFD run (1e4 s
    /// at 10 ms): 850 MB of text and 2.2 GB of memory while it is written (measured in
    /// docs/simulate.md).
    pub const MAX_ROWS: u64 = 10_000_000;
    /// Most RK4 sub-steps per exported sample.
    pub const MAX_SUBSTEPS: u64 = 10_000;
    /// Most RK4 steps in all (rows times sub-steps): about a minute of integration on two
    /// busy cores (docs/simulate.md).
    pub const MAX_RK4_STEPS: u64 = 50_000_000;
    /// Most significant digits written: 17 round-trip any f64 exactly.
    pub const MAX_DIGITS: u64 = 17;
}

/// A whole simulation configuration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimConfig {
    /// Title written into the export's header where the layout has one.
    pub title: Option<String>,
    /// The model that plays the CFD solver.
    pub model: ModelName,
    /// The vehicle.
    pub vehicle: VehicleConfig,
    /// The fluid.
    pub fluid: FluidConfig,
    /// The "true" coefficients (SI); symmetry relations complete them.
    pub coefficients: BTreeMap<String, f64>,
    /// What to simulate.
    pub manoeuvre: Manoeuvre,
    /// Measurement noise added to the export.
    pub noise: NoiseConfig,
    /// How to write it (a configuration writes an export or a sweep).
    pub export: Option<ExportConfig>,
    /// A turning-circle sweep over rudder angles and approach speeds, written as a folder.
    pub sweep: Option<super::sweep::Sweep>,
}

/// The manoeuvre.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Manoeuvre {
    /// A time history from an initial state with constant or stepped inputs.
    TimeHistory {
        /// Duration, s.
        duration: f64,
        /// Sampling interval of the export, s.
        dt: f64,
        /// RK4 steps per sample (default 10).
        substeps: usize,
        /// Initial state by quantity (SI); missing states start at 0.
        initial: BTreeMap<Quantity, Constant>,
        /// Inputs at the start, by quantity.
        inputs: BTreeMap<Quantity, Constant>,
        /// Input changes: at `time`, the listed inputs take new values.
        steps: Vec<Step>,
        /// Largest rate of change per input (SI per second): an input with a rate moves
        /// towards each new value at most at that rate (an actuator) instead of jumping.
        rates: BTreeMap<Quantity, f64>,
        /// A helmsman steering the rudder (turning circle, zig-zag), if any.
        steering: Option<crate::dynamics::sim::steering::Steering>,
        /// White-noise forcing per state, variance per second (SI^2/s): waves on a wave-yaw
        /// state, gusts on a rate.
        process_noise: BTreeMap<Quantity, f64>,
    },
    /// Steady polars implied by the coefficients (paper eq. 5 inverted) over a sweep of
    /// angles of attack and speeds, one row per (speed, angle).
    PolarSweep {
        /// Angles of attack, degrees.
        alpha_deg: Vec<f64>,
        /// Flow speeds, m/s.
        speeds: Vec<f64>,
        /// Moment reference length used to define C_M, m.
        moment_reference_length: f64,
        /// Cubic terms added to C_L and C_M (per rad^3), to mimic nonlinear polars.
        cubic: BTreeMap<Quantity, f64>,
        /// Which part of the yaw moment the written C_M is: `lift-only` (the default, the
        /// paper's reading: Nuvl) or `total` (Munk moment included: Nuv of the completed
        /// truth, as a CFD static drift run measures it).
        #[serde(skip_serializing_if = "is_lift_only")]
        moment: YawMoment,
    },
    /// Steady captive conditions (static drift, drift with rudder, circular motion): the
    /// model held at every combination of speed, drift angle, non-dimensional yaw rate
    /// r' = r L / U and rudder angle, one row each with the forces of
    /// [`crate::model::models::Model::captive_forces`] (no acceleration).
    Captive {
        /// Speeds U, m/s.
        speeds: Vec<f64>,
        /// Drift angles beta = atan(-v / u), degrees.
        drift_deg: Vec<f64>,
        /// Non-dimensional yaw rates r' = r L / U.
        yaw_rate_prime: Vec<f64>,
        /// Rudder angles, degrees (when the model has a rudder).
        rudder_deg: Vec<f64>,
        /// The other inputs, constant (`rpm`).
        inputs: BTreeMap<Quantity, Constant>,
    },
    /// A harmonic captive run (PMM pure sway, pure yaw): the force history of the model
    /// moved with oscillating velocities.
    Pmm(super::pmm::Pmm),
}

fn is_lift_only(m: &YawMoment) -> bool {
    *m == YawMoment::LiftOnly
}

/// An input change (the same as a run configuration's `steps`).
pub use crate::config::Step;

/// Seeded Gaussian noise per exported quantity.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct NoiseConfig {
    /// Random seed (fixed, so exports are reproducible).
    pub seed: u64,
    /// Standard deviation per quantity (SI or with units).
    #[serde(flatten)]
    pub sigma: BTreeMap<Quantity, Constant>,
}

/// How the export is written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportConfig {
    /// Output file, relative to the simulation configuration (`--out` overrides).
    pub file: PathBuf,
    /// Layout: delimited, cfx, starccm, fluent or openfoam-sixdof.
    pub layout: String,
    /// Columns in order.
    pub columns: Vec<ExportColumn>,
    /// Write Euler angles wrapped to (-180, 180] deg as CFD codes do (default true).
    #[serde(default = "crate::config::yes")]
    pub wrap_angles: bool,
    /// Significant digits (default 10).
    #[serde(default = "default_digits")]
    pub digits: usize,
    /// Separator for the delimited layout (default ",").
    #[serde(default)]
    pub separator: Option<String>,
}

fn default_digits() -> usize {
    10
}

/// One exported column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportColumn {
    /// The quantity.
    pub quantity: Quantity,
    /// Column name in the file.
    pub name: String,
    /// Unit to write in (default SI).
    #[serde(default)]
    pub unit: Option<String>,
}

/// Loaded simulation configuration.
#[derive(Debug, Clone)]
pub struct LoadedSim {
    /// The configuration.
    pub config: SimConfig,
    /// Its folder.
    pub base_dir: PathBuf,
    /// The export layout.
    pub layout: Format,
}

/// The layouts `simulate` writes.
const LAYOUTS: [Format; 6] = [
    Format::Delimited,
    Format::Cfx,
    Format::StarCcm,
    Format::Fluent,
    Format::OpenFoamSixDof,
    Format::OpenFoamForcesLegacy,
];

/// Reads and checks a simulation configuration; every problem is listed.
pub fn load(path: &Path) -> Result<LoadedSim> {
    load_str(path, &crate::config::read(path)?)
}

/// Like [`load`], from text already read (`path` places messages and resolves paths).
pub fn load_str(path: &Path, text: &str) -> Result<LoadedSim> {
    let mut p = Problems::new(path, text);
    let file = read_collecting::<SimFile>(&mut p, text, &[]);
    let checked = file.and_then(|f| f.check(&mut p));
    match checked {
        Some((config, layout)) if p.is_empty() => Ok(LoadedSim {
            config,
            base_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            layout,
        }),
        _ => Err(Error::Config(p.in_file_order())),
    }
}

/// The file as written: every manoeuvre key optional, so that each kind can say which keys
/// it needs and which it does not use.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SimFile {
    #[serde(default)]
    title: Option<String>,
    #[serde(default)]
    model: ModelName,
    vehicle: VehicleConfig,
    fluid: FluidConfig,
    coefficients: BTreeMap<String, f64>,
    manoeuvre: ManoeuvreFile,
    #[serde(default)]
    noise: NoiseConfig,
    #[serde(default)]
    export: Option<ExportConfig>,
    #[serde(default)]
    sweep: Option<super::sweep::SweepFile>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum Kind {
    TimeHistory,
    PolarSweep,
    Captive,
    Pmm,
}

impl Kind {
    /// The configuration's word.
    fn name(self) -> &'static str {
        match self {
            Kind::TimeHistory => "time_history",
            Kind::PolarSweep => "polar_sweep",
            Kind::Captive => "captive",
            Kind::Pmm => "pmm",
        }
    }

    /// The optional `[manoeuvre]` keys a manoeuvre of this kind reads; any other given is
    /// an error.
    fn keys(self) -> &'static [&'static str] {
        match self {
            Kind::TimeHistory => &[
                "duration",
                "dt",
                "substeps",
                "initial",
                "inputs",
                "steps",
                "rates",
                "steering",
                "process_noise",
            ],
            Kind::PolarSweep => &[
                "alpha_deg",
                "speeds",
                "moment_reference_length",
                "cubic",
                "moment",
            ],
            Kind::Captive => &[
                "speeds",
                "drift_deg",
                "yaw_rate_prime",
                "rudder_deg",
                "inputs",
            ],
            Kind::Pmm => &[
                "speed",
                "amplitude",
                "frequency",
                "duration",
                "dt",
                "inputs",
            ],
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ManoeuvreFile {
    kind: Kind,
    #[serde(default, deserialize_with = "si::option::<_, si::Time>")]
    duration: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Time>")]
    dt: Option<f64>,
    #[serde(default)]
    substeps: Option<u64>,
    #[serde(default)]
    initial: Option<BTreeMap<Quantity, Constant>>,
    #[serde(default)]
    inputs: Option<BTreeMap<Quantity, Constant>>,
    #[serde(default)]
    steps: Option<Vec<Step>>,
    #[serde(default)]
    rates: Option<BTreeMap<Quantity, Constant>>,
    #[serde(default)]
    alpha_deg: Option<Vec<f64>>,
    #[serde(default, deserialize_with = "si::list::<_, si::Speed>")]
    speeds: Option<Vec<f64>>,
    #[serde(default, deserialize_with = "si::option::<_, si::Length>")]
    moment_reference_length: Option<f64>,
    #[serde(default)]
    cubic: Option<BTreeMap<Quantity, f64>>,
    #[serde(default)]
    moment: Option<YawMoment>,
    #[serde(default)]
    drift_deg: Option<Vec<f64>>,
    #[serde(default)]
    yaw_rate_prime: Option<Vec<f64>>,
    #[serde(default)]
    rudder_deg: Option<Vec<f64>>,
    #[serde(default)]
    steering: Option<crate::dynamics::sim::steering::SteeringFile>,
    #[serde(default)]
    process_noise: Option<BTreeMap<Quantity, f64>>,
    #[serde(default, deserialize_with = "si::option::<_, si::Speed>")]
    speed: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Frequency>")]
    frequency: Option<f64>,
    #[serde(default)]
    amplitude: Option<BTreeMap<Quantity, Constant>>,
}

/// The quantities a manoeuvre produces, and which of them the model integrates or takes as
/// inputs.
pub(super) struct Produces {
    pub(super) states: Vec<Quantity>,
    pub(super) inputs: Vec<Quantity>,
    /// The force components of a captive or PMM run (empty for the other kinds, and for a
    /// model that gives no forces for a prescribed motion).
    pub(super) forces: Vec<Quantity>,
    pub(super) all: Vec<Quantity>,
}

impl Produces {
    /// What a manoeuvre of `kind` produces from a model with these states, inputs and
    /// forces.
    fn of(kind: Kind, states: Vec<Quantity>, inputs: Vec<Quantity>, forces: Vec<Quantity>) -> Self {
        match kind {
            Kind::TimeHistory => Produces {
                all: std::iter::once(Quantity::Time)
                    .chain(states.iter().copied())
                    .chain(inputs.iter().copied())
                    .collect(),
                states,
                inputs,
                forces: Vec::new(),
            },
            Kind::PolarSweep => Produces {
                states: Vec::new(),
                inputs: Vec::new(),
                forces: Vec::new(),
                all: vec![
                    Quantity::Speed,
                    Quantity::Alpha,
                    Quantity::Cd,
                    Quantity::Cl,
                    Quantity::Cm,
                ],
            },
            Kind::Captive | Kind::Pmm => Produces {
                // a PMM run is a history in time, a captive programme a table of conditions
                all: (kind == Kind::Pmm)
                    .then_some(Quantity::Time)
                    .into_iter()
                    .chain(
                        states
                            .iter()
                            .copied()
                            .filter(|q| Quantity::MOTION[..6].contains(q)),
                    )
                    .chain(inputs.iter().copied())
                    .chain(forces.iter().copied())
                    .collect(),
                states,
                inputs,
                forces,
            },
        }
    }
}

/// What the configuration writes: the export's format, or a sweep (checked against the
/// manoeuvre); exactly one of `[export]` and `[sweep]`.
fn output(
    export: Option<&ExportConfig>,
    sweep: Option<super::sweep::SweepFile>,
    noise: &NoiseConfig,
    manoeuvre: Option<&Manoeuvre>,
    produces: &Produces,
    p: &mut Problems,
) -> (Option<Format>, Option<super::sweep::Sweep>) {
    match (export, sweep) {
        (Some(e), None) => (check_export(e, produces, p), None),
        (None, Some(s)) => {
            if !noise.sigma.is_empty() {
                p.add(
                    "noise",
                    "is not used by a sweep: its turning circles are measured without noise",
                );
            }
            (Some(Format::Delimited), s.check(manoeuvre, produces, p))
        }
        (Some(_), Some(_)) => {
            p.add(
                "sweep",
                "a configuration writes either an export (`[export]`) or a sweep \
                 (`[sweep]`), not both",
            );
            (None, None)
        }
        (None, None) => {
            p.add(
                "export",
                "the required section `[export]` is missing (or give `[sweep]` for a \
                 turning-circle sweep)",
            );
            (None, None)
        }
    }
}

struct Signature;

impl ModelVisitor for Signature {
    /// States, inputs and the force components of a prescribed motion.
    type Output = (Vec<Quantity>, Vec<Quantity>, Vec<Quantity>);
    fn visit<M: Model>(self, model: &M) -> Self::Output {
        (
            model.states().iter().map(|s| s.quantity).collect(),
            model.input_quantities(),
            model.force_quantities().to_vec(),
        )
    }
}

impl SimFile {
    /// Checks everything and builds the configuration; None when a part is unusable.
    fn check(self, p: &mut Problems) -> Option<(SimConfig, Format)> {
        self.vehicle.validate(p);
        self.fluid.validate(p);
        for (name, v) in &self.coefficients {
            let key = format!("coefficients.{name}");
            p.known_coefficient(&key, name);
            p.coefficient_sized(&key, *v);
        }
        let (states, inputs, forces) =
            match with_model(self.model, &self.vehicle.for_model(&self.fluid), Signature) {
                Ok(signature) => signature,
                Err(problems) => {
                    for vp in problems {
                        p.add(&vp.key, vp.message);
                    }
                    return None;
                }
            };
        let produces = Produces::of(self.manoeuvre.kind, states, inputs, forces);
        let manoeuvre = self
            .manoeuvre
            .check(self.model, self.vehicle.length, &produces, p);
        check_noise(&self.noise, &produces, p);
        let (layout, sweep) = output(
            self.export.as_ref(),
            self.sweep,
            &self.noise,
            manoeuvre.as_ref(),
            &produces,
            p,
        );
        // the truth's yaw-moment reading, as a run's known coefficients give it
        let mut vehicle = self.vehicle;
        match YawMoment::of_names(self.coefficients.keys().map(String::as_str)) {
            Some(reading) => vehicle.yaw_moment = reading,
            None => p.add(
                "coefficients.Nuvl",
                YawMoment::both_given("coefficients.Nuv", "coefficients.Nuvl"),
            ),
        }
        Some((
            SimConfig {
                title: self.title,
                model: self.model,
                vehicle,
                fluid: self.fluid,
                coefficients: self.coefficients,
                manoeuvre: manoeuvre?,
                noise: self.noise,
                export: self.export,
                sweep,
            },
            layout?,
        ))
    }
}

impl ManoeuvreFile {
    /// Every optional key and whether the file gives it.
    fn given(&self) -> [(&'static str, bool); 20] {
        [
            ("duration", self.duration.is_some()),
            ("dt", self.dt.is_some()),
            ("substeps", self.substeps.is_some()),
            ("initial", self.initial.is_some()),
            ("inputs", self.inputs.is_some()),
            ("steps", self.steps.is_some()),
            ("rates", self.rates.is_some()),
            ("steering", self.steering.is_some()),
            ("process_noise", self.process_noise.is_some()),
            ("alpha_deg", self.alpha_deg.is_some()),
            ("speeds", self.speeds.is_some()),
            (
                "moment_reference_length",
                self.moment_reference_length.is_some(),
            ),
            ("cubic", self.cubic.is_some()),
            ("moment", self.moment.is_some()),
            ("drift_deg", self.drift_deg.is_some()),
            ("yaw_rate_prime", self.yaw_rate_prime.is_some()),
            ("rudder_deg", self.rudder_deg.is_some()),
            ("speed", self.speed.is_some()),
            ("frequency", self.frequency.is_some()),
            ("amplitude", self.amplitude.is_some()),
        ]
    }

    /// Checks the manoeuvre of a vehicle `length` m long: keys its kind does not use, then
    /// the keys of its kind.
    fn check(
        self,
        model: ModelName,
        length: f64,
        produces: &Produces,
        p: &mut Problems,
    ) -> Option<Manoeuvre> {
        let kind = self.kind.name();
        for (key, given) in self.given() {
            if given && !self.kind.keys().contains(&key) {
                p.add(
                    &format!("manoeuvre.{key}"),
                    format!("is not used by a {kind} manoeuvre"),
                );
            }
        }
        match self.kind {
            Kind::TimeHistory => self.time_history(model, produces, p),
            Kind::PolarSweep => self.polar_sweep(p),
            Kind::Captive => self.captive(produces, p),
            Kind::Pmm => super::pmm::check(
                super::pmm::PmmKeys {
                    speed: self.speed,
                    amplitude: self.amplitude,
                    frequency: self.frequency,
                    duration: self.duration,
                    dt: self.dt,
                    inputs: self.inputs,
                    length,
                },
                &produces.states,
                &produces.inputs,
                !produces.forces.is_empty(),
                p,
            ),
        }
    }

    /// The keys of a time history: timing, helm, rates, initial state, inputs, steps and
    /// process noise.
    fn time_history(
        self,
        model: ModelName,
        produces: &Produces,
        p: &mut Problems,
    ) -> Option<Manoeuvre> {
        let kind = self.kind;
        let (Some(duration), Some(dt)) = (self.duration, self.dt) else {
            if self.duration.is_none() {
                required(p, kind, "duration", "s");
            }
            if self.dt.is_none() {
                required(p, kind, "dt", "s");
            }
            return None;
        };
        let substeps = self.substeps.unwrap_or(10);
        let initial = self.initial.unwrap_or_default();
        let inputs = self.inputs.unwrap_or_default();
        let steps = self.steps.unwrap_or_default();
        let mut ok = check_timing(duration, dt, substeps, p);
        let model_name = model.to_string();
        let steering = match &self.steering {
            None => None,
            Some(s) => match s.check("manoeuvre.steering") {
                Ok(law) => {
                    ok &= super::plausible::helm_within(&law, duration, p);
                    Some(law)
                }
                Err(problems) => {
                    for (k, m) in problems {
                        p.add(&k, m);
                    }
                    ok = false;
                    None
                }
            },
        };
        let rates = check_rates(self.rates.unwrap_or_default(), produces, &model_name, p);
        ok &= rates.is_some();
        let rates = rates.unwrap_or_default();
        if let Some(file) = &self.steering {
            let moves = Moves {
                inputs: &inputs,
                steps: &steps,
                rates: &rates,
            };
            ok &= check_helm(file.surface, produces, &model_name, &moves, p);
        }
        check_initial_and_inputs(&initial, &inputs, produces, &model_name, p);
        check_steps(&steps, duration, produces, &model_name, p);
        let process_noise = self.process_noise.unwrap_or_default();
        ok &= check_process_noise(&process_noise, produces, &model_name, p);
        ok.then_some(Manoeuvre::TimeHistory {
            duration,
            dt,
            substeps: substeps as usize,
            initial,
            inputs,
            steps,
            rates,
            steering,
            process_noise,
        })
    }

    /// The keys of a polar sweep: angles, speeds, moment reference length and cubic terms.
    fn polar_sweep(self, p: &mut Problems) -> Option<Manoeuvre> {
        let kind = self.kind;
        if self.alpha_deg.is_none() {
            required(p, kind, "alpha_deg", "a list of angles in degrees");
        }
        if self.speeds.is_none() {
            required(p, kind, "speeds", "a list of speeds in m/s");
        }
        let (Some(alpha_deg), Some(speeds), Some(l_ref)) =
            (self.alpha_deg, self.speeds, self.moment_reference_length)
        else {
            if self.moment_reference_length.is_none() {
                required(p, kind, "moment_reference_length", "m");
            }
            return None;
        };
        let mut ok = true;
        for (key, list) in [("alpha_deg", &alpha_deg), ("speeds", &speeds)] {
            if list.is_empty() {
                p.add(&format!("manoeuvre.{key}"), "is empty");
                ok = false;
            }
            let text: Vec<String> = list.iter().map(|v| v.to_string()).collect();
            p.no_duplicates(&format!("manoeuvre.{key}"), text.iter().map(String::as_str));
        }
        for (i, a) in alpha_deg.iter().enumerate() {
            if !(a.is_finite() && a.abs() <= 180.0) {
                p.add(
                    &format!("manoeuvre.alpha_deg[{i}]"),
                    format!("must be an angle from -180 to 180 degrees, got {a}"),
                );
                ok = false;
            }
        }
        ok &= super::plausible::speeds(&speeds, p);
        p.positive("manoeuvre.moment_reference_length", l_ref, "m");
        let cubic = self.cubic.unwrap_or_default();
        for (q, v) in &cubic {
            let key = format!("manoeuvre.cubic.{q}");
            if !matches!(q, Quantity::Cl | Quantity::Cm) {
                p.add(
                    &key,
                    format!("cubic terms exist for cl and cm only, not {q}"),
                );
            }
            p.finite(&key, *v);
        }
        let rows = alpha_deg.len() as u64 * speeds.len() as u64;
        ok &= rows_within_limit(p, "manoeuvre.alpha_deg", rows, "angles times speeds");
        ok.then_some(Manoeuvre::PolarSweep {
            alpha_deg,
            speeds,
            moment_reference_length: l_ref,
            cubic,
            moment: self.moment.unwrap_or(YawMoment::LiftOnly),
        })
    }

    /// The keys of a captive programme: speeds, drift angles, yaw rates r' and rudder
    /// angles (every combination is a condition), and the constant inputs.
    fn captive(self, produces: &Produces, p: &mut Problems) -> Option<Manoeuvre> {
        if produces.forces.is_empty() {
            p.add(
                "model",
                "this model gives no forces for a prescribed motion, so it has no captive runs",
            );
            return None;
        }
        let Some(speeds) = self.speeds else {
            p.add(
                "manoeuvre.speeds",
                "a captive manoeuvre needs `speeds` (m/s)",
            );
            return None;
        };
        let drift_deg = self.drift_deg.unwrap_or_else(|| vec![0.0]);
        let yaw_rate_prime = self.yaw_rate_prime.unwrap_or_else(|| vec![0.0]);
        let rudder_deg = self.rudder_deg.unwrap_or_else(|| vec![0.0]);
        let mut ok = super::plausible::speeds(&speeds, p);
        for (key, list, limit) in [
            ("drift_deg", &drift_deg, 90.0),
            ("rudder_deg", &rudder_deg, 90.0),
            ("yaw_rate_prime", &yaw_rate_prime, 2.0),
        ] {
            if list.is_empty() {
                p.add(&format!("manoeuvre.{key}"), "is empty");
                ok = false;
            }
            for (i, v) in list.iter().enumerate() {
                if !(v.is_finite() && v.abs() <= limit) {
                    p.add(
                        &format!("manoeuvre.{key}[{i}]"),
                        format!("must be within +-{limit}, got {v}"),
                    );
                    ok = false;
                }
            }
        }
        if !rudder_deg.iter().all(|d| *d == 0.0) && !produces.inputs.contains(&Quantity::Rudder) {
            p.add("manoeuvre.rudder_deg", "the model has no rudder");
            ok = false;
        }
        let inputs = self.inputs.unwrap_or_default();
        for q in &produces.inputs {
            if *q != Quantity::Rudder && !inputs.contains_key(q) {
                p.add(
                    "manoeuvre.inputs",
                    format!("the model needs {q}: give it, e.g. `inputs = {{ {q} = ... }}`"),
                );
                ok = false;
            }
        }
        let rows =
            (speeds.len() * drift_deg.len() * yaw_rate_prime.len() * rudder_deg.len()) as u64;
        ok &= rows_within_limit(p, "manoeuvre.drift_deg", rows, "conditions");
        ok.then_some(Manoeuvre::Captive {
            speeds,
            drift_deg,
            yaw_rate_prime,
            rudder_deg,
            inputs,
        })
    }
}

/// True when `rows` (of `what`) fit in an export; else a problem at `key`.
fn rows_within_limit(p: &mut Problems, key: &str, rows: u64, what: &str) -> bool {
    if rows > limits::MAX_ROWS {
        p.add(
            key,
            format!(
                "{rows} {what} is more than the {} rows an export may have",
                limits::MAX_ROWS
            ),
        );
        return false;
    }
    true
}

/// Checks duration, dt and sub-steps against [`limits`]; true when a simulation of them is
/// bounded.
fn check_timing(duration: f64, dt: f64, substeps: u64, p: &mut Problems) -> bool {
    let mut ok = true;
    if !(duration.is_finite() && duration > 0.0) {
        p.positive("manoeuvre.duration", duration, "s");
        ok = false;
    }
    if !(dt.is_finite() && dt > 0.0) {
        p.positive("manoeuvre.dt", dt, "s");
        ok = false;
    } else if ok && dt > duration {
        p.add(
            "manoeuvre.dt",
            format!("the sampling interval {dt} s is longer than the duration {duration} s"),
        );
        ok = false;
    }
    let before = p.list.len();
    p.count_within(
        "manoeuvre.substeps",
        substeps,
        1,
        limits::MAX_SUBSTEPS,
        "RK4 steps per sample",
    );
    ok &= p.list.len() == before;
    if ok {
        let rows = (duration / dt).round() + 1.0;
        if rows > limits::MAX_ROWS as f64 {
            p.add(
                "manoeuvre.dt",
                format!(
                    "duration / dt = {duration} s / {dt} s gives {rows:.3e} samples, more than \
                     the {} an export may have; use a longer dt or a shorter duration",
                    limits::MAX_ROWS
                ),
            );
            return false;
        }
        let steps = rows * substeps as f64;
        if steps > limits::MAX_RK4_STEPS as f64 {
            p.add(
                "manoeuvre.substeps",
                format!(
                    "{rows} samples times {substeps} sub-steps is {steps:.3e} RK4 steps, more \
                     than the {:e} allowed (about a minute of integration); use fewer sub-steps",
                    limits::MAX_RK4_STEPS as f64
                ),
            );
            return false;
        }
    }
    ok
}

/// Reports a key a manoeuvre of this kind needs and lacks.
fn required(p: &mut Problems, kind: Kind, key: &str, unit: &str) {
    let kind = kind.name();
    p.add(
        &format!("manoeuvre.{key}"),
        format!("a {kind} manoeuvre needs `{key}` ({unit})"),
    );
}

/// What else moves the inputs of a time history: constant inputs, steps and rate limits.
struct Moves<'a> {
    inputs: &'a BTreeMap<Quantity, Constant>,
    steps: &'a [Step],
    rates: &'a BTreeMap<Quantity, f64>,
}

/// Checks the helm of a time history; false if it cannot steer or shares its surface.
fn check_helm(
    surface: crate::dynamics::sim::steering::Surface,
    produces: &Produces,
    model_name: &str,
    moves: &Moves,
    p: &mut Problems,
) -> bool {
    let mut ok = true;
    // the helm needs a surface to move and an angle to watch (the rudder and
    // the heading, or the stern planes and the pitch), and is the only one to
    // move that surface
    let (input, watched) = (surface.input(), surface.watched());
    if !produces.inputs.contains(&input) || !produces.states.contains(&watched) {
        let key = if surface == crate::dynamics::sim::steering::Surface::Rudder {
            "manoeuvre.steering"
        } else {
            "manoeuvre.steering.surface"
        };
        p.add(
            key,
            format!(
                "the {model_name} model has no {} input or no {} state to steer",
                surface.words(),
                surface.watched_words()
            ),
        );
        ok = false;
    }
    let moved = moves.inputs.contains_key(&input)
        || moves.steps.iter().any(|s| s.values.contains_key(&input));
    if moved {
        p.add(
            "manoeuvre.steering",
            format!(
                "the helm moves the {0}: remove {input} from `inputs` and \
                 `steps`",
                surface.words()
            ),
        );
        ok = false;
    }
    if moves.rates.contains_key(&input) {
        p.add(
            &format!("manoeuvre.rates.{input}"),
            format!(
                "the helm moves the {} at `manoeuvre.steering.rate`: remove \
                 {input} from `rates`",
                surface.words()
            ),
        );
        ok = false;
    }
    ok
}

/// Checks the initial state and the constant inputs of a time history: each a state or an
/// input of the model, in its quantity's unit.
fn check_initial_and_inputs(
    initial: &BTreeMap<Quantity, Constant>,
    inputs: &BTreeMap<Quantity, Constant>,
    produces: &Produces,
    model_name: &str,
    p: &mut Problems,
) {
    for (q, c) in initial {
        let key = format!("manoeuvre.initial.{q}");
        member(p, &key, *q, &produces.states, "a state", model_name);
        if let Err(m) = c.expect_quantity(*q) {
            p.add(&key, m);
        } else if *q == Quantity::U {
            super::plausible::initial_speed(&key, c.si, p);
        }
    }
    for (q, c) in inputs {
        let key = format!("manoeuvre.inputs.{q}");
        member(p, &key, *q, &produces.inputs, "an input", model_name);
        if let Err(m) = c.expect_quantity(*q) {
            p.add(&key, m);
        }
    }
}

/// Checks the input steps of a time history: within the manoeuvre, each changing some
/// input of the model, no two setting the same input at the same time.
fn check_steps(
    steps: &[Step],
    duration: f64,
    produces: &Produces,
    model_name: &str,
    p: &mut Problems,
) {
    for (i, s) in steps.iter().enumerate() {
        let key = format!("manoeuvre.steps[{i}]");
        if !(s.time >= 0.0 && s.time <= duration) {
            p.add(
                &format!("{key}.time"),
                format!(
                    "must be within the manoeuvre, 0 to {duration} s, got {}",
                    s.time
                ),
            );
        }
        if s.values.is_empty() {
            p.add(&key, "changes no input: give e.g. thrust = \"30 N\"");
        }
        for (q, c) in &s.values {
            let k = format!("{key}.{q}");
            member(p, &k, *q, &produces.inputs, "an input", model_name);
            if let Err(m) = c.expect_quantity(*q) {
                p.add(&k, m);
            }
            if let Some(j) = steps[..i]
                .iter()
                .position(|o| o.time == s.time && o.values.contains_key(q))
            {
                p.add(
                    &k,
                    format!("steps {} and {} both set {q} at {} s", j + 1, i + 1, s.time),
                );
            }
        }
    }
}

/// Checks the process-noise intensities of a time history; false if one is negative or not
/// finite.
fn check_process_noise(
    process_noise: &BTreeMap<Quantity, f64>,
    produces: &Produces,
    model_name: &str,
    p: &mut Problems,
) -> bool {
    let mut ok = true;
    for (q, v) in process_noise {
        let key = format!("manoeuvre.process_noise.{q}");
        member(p, &key, *q, &produces.states, "a state", model_name);
        if !(v.is_finite() && *v >= 0.0) {
            p.add(
                &key,
                format!(
                    "a white-noise intensity (variance per second, SI), 0 or more, \
                     got {v}"
                ),
            );
            ok = false;
        }
    }
    ok
}

/// The inputs' rates (`manoeuvre.rates`) in SI per second, or None when one is unusable: each
/// an input of the model, of its quantity's dimension per second, positive and finite.
fn check_rates(
    rates: BTreeMap<Quantity, Constant>,
    produces: &Produces,
    model: &str,
    p: &mut Problems,
) -> Option<BTreeMap<Quantity, f64>> {
    let mut ok = true;
    let mut out = BTreeMap::new();
    for (q, c) in rates {
        let key = format!("manoeuvre.rates.{q}");
        let before = p.list.len();
        member(p, &key, q, &produces.inputs, "an input", model);
        // a rate is the input's dimension per second: [kg, m, s, rad] exponents, s - 1
        let mut dim = q.dim();
        dim[2] -= 1;
        if let Err(m) = c.expect_dim(dim) {
            p.add(&key, format!("a rate of {q} per second: {m}"));
        } else if !(c.si.is_finite() && c.si > 0.0) {
            p.add(
                &key,
                format!(
                    "must be a positive rate, got {}; leave {q} out for steps that jump",
                    c.text
                ),
            );
        }
        ok &= p.list.len() == before;
        out.insert(q, c.si);
    }
    ok.then_some(out)
}

fn member(p: &mut Problems, key: &str, q: Quantity, allowed: &[Quantity], what: &str, model: &str) {
    if !allowed.contains(&q) {
        let names: Vec<&str> = allowed.iter().map(|q| q.key()).collect();
        p.add(
            key,
            format!(
                "{q} is not {what} of the {model} model ({})",
                if names.is_empty() {
                    "it has none".to_string()
                } else {
                    names.join(", ")
                }
            ),
        );
    }
}

fn check_noise(noise: &NoiseConfig, produces: &Produces, p: &mut Problems) {
    for (q, c) in &noise.sigma {
        let key = format!("noise.{q}");
        if *q == Quantity::Time || !produces.all.contains(q) {
            let names: Vec<&str> = produces
                .all
                .iter()
                .filter(|q| **q != Quantity::Time)
                .map(|q| q.key())
                .collect();
            p.add(
                &key,
                format!(
                    "this manoeuvre does not produce {q} with noise (it gives {})",
                    names.join(", ")
                ),
            );
        }
        match c.expect_quantity(*q) {
            Ok(()) if c.si > 0.0 => {}
            Ok(()) => p.add(
                &key,
                format!(
                    "a noise standard deviation must be positive, got {}; leave {q} out for no \
                     noise",
                    c.text
                ),
            ),
            Err(m) => p.add(&key, m),
        }
    }
}

/// Characters a delimited separator may not be: they occur in numbers, quotes or line ends.
const NOT_SEPARATORS: &str = "0123456789.-+eE\"'\n\r";

fn check_export(e: &ExportConfig, produces: &Produces, p: &mut Problems) -> Option<Format> {
    let layout = Format::from_name(&e.layout).filter(|f| LAYOUTS.contains(f));
    if layout.is_none() {
        let names: Vec<&str> = LAYOUTS.iter().map(|f| f.name()).collect();
        p.add(
            "export.layout",
            format!(
                "cannot write layout '{}'{}; choose one of {}",
                e.layout,
                crate::base::suggest::did_you_mean(&e.layout, names.iter().copied()),
                names.join(", ")
            ),
        );
    }
    p.count_within(
        "export.digits",
        e.digits as u64,
        1,
        limits::MAX_DIGITS,
        "significant digits; 17 keep every bit of a number",
    );
    let separator = export_separator(e, layout, p);
    if e.columns.is_empty() {
        p.add("export.columns", "lists no column to write");
    }
    p.no_duplicates("export.columns", e.columns.iter().map(|c| c.name.as_str()));
    let name_breaks = match layout {
        Some(Format::Delimited) => Some(separator),
        Some(Format::Cfx) => Some(','),
        _ => None,
    };
    for (i, c) in e.columns.iter().enumerate() {
        check_export_column(
            &format!("export.columns[{i}]"),
            c,
            layout,
            name_breaks,
            produces,
            p,
        );
    }
    layout
}

/// The delimited layout's separator (`,` by default): one character that cannot occur in a
/// number or a name, and given for the delimited layout only.
fn export_separator(e: &ExportConfig, layout: Option<Format>, p: &mut Problems) -> char {
    let mut separator = ',';
    if let Some(s) = &e.separator {
        let mut chars = s.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) if !NOT_SEPARATORS.contains(c) => separator = c,
            _ => p.add(
                "export.separator",
                format!(
                    "must be one character that cannot occur in a number or a name, such as \
                     \",\", \";\" or a tab; got {s:?} (not a digit, '.', '-', '+', 'e', a quote \
                     or a line end)"
                ),
            ),
        }
        if layout.is_some_and(|f| f != Format::Delimited) {
            p.add(
                "export.separator",
                format!("is used by the delimited layout only, not by {}", e.layout),
            );
        }
    }
    separator
}

/// Checks one column of the export: a quantity the manoeuvre produces (and the layout
/// holds), a name the layout can write, a unit of the quantity's dimension.
fn check_export_column(
    key: &str,
    c: &ExportColumn,
    layout: Option<Format>,
    name_breaks: Option<char>,
    produces: &Produces,
    p: &mut Problems,
) {
    let written = matches!(
        c.quantity,
        Quantity::Time
            | Quantity::Fx
            | Quantity::Fy
            | Quantity::Fz
            | Quantity::Mx
            | Quantity::My
            | Quantity::Mz
    );
    if layout == Some(Format::OpenFoamForcesLegacy) && !written {
        p.add(
            &format!("{key}.quantity"),
            format!(
                "the openfoam-forces layout holds the time, the force and the moment \
                 only, not {}: give the prescribed motion in the fitting configuration \
                 (captive.oscillations) or write another layout",
                c.quantity
            ),
        );
    }
    // the attitude quaternion is written from the Euler angles of a run that has a heading
    let from_attitude =
        Quantity::QUATERNION.contains(&c.quantity) && produces.all.contains(&Quantity::Yaw);
    if !produces.all.contains(&c.quantity) && !from_attitude {
        let names: Vec<&str> = produces.all.iter().map(|q| q.key()).collect();
        p.add(
            &format!("{key}.quantity"),
            format!(
                "this manoeuvre does not produce {} (it gives {})",
                c.quantity,
                names.join(", ")
            ),
        );
    }
    if c.name.trim().is_empty()
        || c.name.contains(['"', '\n', '\r'])
        || name_breaks.is_some_and(|s| c.name.contains(s))
    {
        p.add(
            &format!("{key}.name"),
            format!(
                "{:?} cannot be written as a column name: it must not be empty nor hold a \
                 quote, a line end or the separator",
                c.name
            ),
        );
    }
    if let Some(u) = &c.unit {
        match Unit::parse(u) {
            Ok(unit) => {
                if let Err(m) = check_dim(&unit, c.quantity.dim()) {
                    p.add(&format!("{key}.unit"), format!("{} {m}", c.quantity));
                }
            }
            Err(err) => p.add(&format!("{key}.unit"), err.to_string()),
        }
    }
}

/// A key of `[noise]`: `seed`, or a quantity.
enum NoiseKey {
    Seed,
    Sigma(Quantity),
}

impl<'de> Deserialize<'de> for NoiseKey {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        Ok(quantity_key(d, "seed")?.map_or(NoiseKey::Seed, NoiseKey::Sigma))
    }
}

impl<'de> Deserialize<'de> for NoiseConfig {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = NoiseConfig;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table of a seed and standard deviations by quantity")
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<NoiseConfig, A::Error> {
                let mut n = NoiseConfig::default();
                while let Some(k) = map.next_key::<NoiseKey>()? {
                    match k {
                        NoiseKey::Seed => n.seed = map.next_value()?,
                        NoiseKey::Sigma(q) => {
                            n.sigma.insert(q, map.next_value::<Constant>()?);
                        }
                    }
                }
                Ok(n)
            }
        }
        d.deserialize_map(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> String {
        std::fs::read_to_string("configs/simulate/turn_validation.toml").unwrap()
    }

    fn problems(text: &str) -> String {
        match load_str(Path::new("configs/simulate/x.toml"), text) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn the_bundled_configurations_load() {
        for f in [
            "polar_sweep",
            "surge_run",
            "turn_paper",
            "turn_validation",
            "npsauv_helix",
            "npsauv_zigzag_vertical",
            "npsauv_zigzag_horizontal",
        ] {
            let path = format!("configs/simulate/{f}.toml");
            load(Path::new(&path)).unwrap_or_else(|e| panic!("{f}: {e}"));
        }
    }

    #[test]
    fn limits_and_units_are_checked() {
        let t = example();
        let e = problems(&t.replace("dt = 0.05", "dt = 1e-9"));
        assert!(e.contains("manoeuvre.dt") && e.contains("10000000"), "{e}");
        let e = problems(&t.replace("duration = 25.0", "duration = 1e12"));
        assert!(e.contains("samples, more than"), "{e}");
        let e = problems(&t.replace("dt = 0.05", "dt = 0.05\nsubsteps = 100000000"));
        assert!(
            e.contains("manoeuvre.substeps") && e.contains("10000"),
            "{e}"
        );
        let e = problems(&t.replace("dt = 0.05", "dt = 0.05\nsubsteps = 0"));
        assert!(
            e.contains("manoeuvre.substeps: must be a whole number from 1"),
            "{e}"
        );
        let e = problems(&t.replace("u = 2.0", "u = \"3 deg\""));
        assert!(
            e.contains("manoeuvre.initial.u") && e.contains("an angle"),
            "{e}"
        );
        let e = problems(&t.replace("yaw = \"0.05 deg\"", "yaw = \"0.05 m/s\""));
        assert!(
            e.contains("noise.yaw") && e.contains("a speed (m/s)"),
            "{e}"
        );
        for sep in ["\".\"", "\"ab\"", "\"\"", "\"1\"", "\"\\n\""] {
            let e = problems(&t.replace(
                "layout = \"starccm\"",
                &format!("layout = \"delimited\"\nseparator = {sep}"),
            ));
            assert!(
                e.contains("export.separator: must be one character"),
                "{sep}: {e}"
            );
        }
        let e = problems(&t.replace("layout = \"starccm\"", "layout = \"starccm\"\ndigits = 0"));
        assert!(
            e.contains("export.digits") && e.contains("from 1 to 17"),
            "{e}"
        );
    }
}
