//! Turning-circle sweeps: the sensitivity study of a ship's turning circle to the rudder
//! angle and to the approach speed (Hajizadeh, Seif & Mehdigholi 2015, ../shared/docs/
//! ship-3dof-ekf.md method step 4; ITTC 7.5-04-02-01 turning-circle test). Each case is the
//! configuration's steered turn with one rudder angle or one approach speed, simulated
//! without noise and measured (src/dynamics/manoeuvre/); at another speed the propeller (rpm or
//! thrust) is set to the self-propulsion balance of that speed. The sweep is written as a
//! folder: `sweep.csv`, `sweep.md` and the figures.

use super::config::{LoadedSim, Manoeuvre, Produces, SimConfig};
use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::si;
use crate::config::{Constant, Problems};
use crate::dynamics::manoeuvre::{self, TurningCircle};
use crate::dynamics::sim::steering::Steering;
use crate::io::output::{Protected, Replace, Staging};
use crate::model::coefficients::{Coefficient, CoefficientSet, Source};
use crate::model::models::{with_model, Model, ModelVisitor};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Which sides a sweep turns to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sides {
    /// The side of the configured rudder's sign only.
    #[default]
    Configured,
    /// Starboard and port: each case twice, the rudder's sign reversed.
    Both,
}

/// `[sweep]` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Rudder angles at the configured approach speed (`["10 deg", "35 deg"]`).
    #[serde(default, deserialize_with = "si::list::<_, si::Angle>")]
    rudder: Option<Vec<f64>>,
    /// Approach speeds (`["1.7 m/s", "2.2 m/s"]`), each with the propeller balanced.
    #[serde(default, deserialize_with = "si::list::<_, si::Speed>")]
    speed: Option<Vec<f64>>,
    /// The rudder angle of the speed cases (default: the configured steering's).
    #[serde(default, deserialize_with = "si::option::<_, si::Angle>")]
    speed_rudder: Option<f64>,
    /// `configured` (default) or `both`.
    #[serde(default)]
    sides: Sides,
    /// Output folder, relative to the configuration (`--out` overrides).
    dir: PathBuf,
}

/// A checked sweep (SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sweep {
    /// Rudder angles (magnitudes, rad) at the configured speed.
    pub rudder: Vec<f64>,
    /// Approach speeds, m/s.
    pub speed: Vec<f64>,
    /// Rudder angle (magnitude, rad) of the speed cases.
    pub speed_rudder: f64,
    /// Sides.
    pub sides: Sides,
    /// Output folder, relative to the configuration.
    pub dir: PathBuf,
}

/// Most cases one sweep may run (each a full turning circle).
pub const MAX_CASES: usize = 200;

impl SweepFile {
    /// Checks the sweep against the manoeuvre: a steered turn of a model with a surge state
    /// and a propeller input to balance when speeds are swept.
    pub(super) fn check(
        self,
        manoeuvre: Option<&Manoeuvre>,
        produces: &Produces,
        p: &mut Problems,
    ) -> Option<Sweep> {
        let law = match manoeuvre {
            Some(Manoeuvre::TimeHistory {
                steering:
                    Some(
                        law @ Steering::Turn {
                            surface: crate::dynamics::sim::steering::Surface::Rudder,
                            ..
                        },
                    ),
                ..
            }) => Some(*law),
            Some(_) => {
                p.add(
                    "sweep",
                    "a sweep varies a turning circle: the manoeuvre must be a `time_history` \
                     with `[manoeuvre.steering] kind = \"turn\"` on the rudder",
                );
                None
            }
            None => None,
        };
        let rudder = self.rudder.unwrap_or_default();
        let speed = self.speed.unwrap_or_default();
        if rudder.is_empty() && speed.is_empty() {
            p.add(
                "sweep",
                "gives no case: list `rudder` angles and/or `speed`s",
            );
        }
        for (i, a) in rudder.iter().enumerate() {
            if !(a.is_finite() && *a > 0.0 && *a <= 57f64.to_radians()) {
                p.add(
                    &format!("sweep.rudder[{i}]"),
                    format!(
                        "a rudder angle from above 0 to 57 deg (the side comes from the \
                         steering's sign and `sides`), got {:.4} deg",
                        a.to_degrees()
                    ),
                );
            }
        }
        for (i, u) in speed.iter().enumerate() {
            if !(u.is_finite() && *u > 0.0) {
                p.add(
                    &format!("sweep.speed[{i}]"),
                    format!("a positive approach speed, got {u} m/s"),
                );
            } else if let Some(m) = crate::config::motion_limits::speed(*u) {
                p.add(&format!("sweep.speed[{i}]"), m);
            }
        }
        if !speed.is_empty() {
            if !produces.states.contains(&Quantity::U) {
                p.add("sweep.speed", "the model has no surge state u to set");
            }
            if !produces.inputs.iter().any(|q| PROPULSION.contains(q)) {
                p.add(
                    "sweep.speed",
                    "the model has no propeller input (rpm or thrust) to balance at each speed",
                );
            }
        }
        let sides = if self.sides == Sides::Both { 2 } else { 1 };
        let cases = (rudder.len() + speed.len()) * sides;
        if cases > MAX_CASES {
            p.add(
                "sweep",
                format!("asks for {cases} turning circles; at most {MAX_CASES}"),
            );
        }
        let configured = law.map(|l| match l {
            Steering::Turn { rudder, .. } | Steering::ZigZag { rudder, .. } => rudder.abs(),
        });
        let speed_rudder = self.speed_rudder.or(configured);
        if let Some(a) = self.speed_rudder {
            if !(a.is_finite() && a > 0.0 && a <= 57f64.to_radians()) {
                p.add(
                    "sweep.speed_rudder",
                    "a rudder angle from above 0 to 57 deg",
                );
            }
        }
        law?;
        Some(Sweep {
            rudder,
            speed,
            speed_rudder: speed_rudder?,
            sides: self.sides,
            dir: self.dir,
        })
    }
}

/// The inputs a speed case balances, in order of preference.
const PROPULSION: [Quantity; 2] = [Quantity::Rpm, Quantity::Thrust];

/// Which parameter a case varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Varies {
    /// The rudder angle, at the configured speed.
    Rudder,
    /// The approach speed, at `speed_rudder`.
    Speed,
}

/// One turning circle of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Case {
    /// What the case varies.
    pub varies: Varies,
    /// Rudder angle as the model reads it (its sign chooses the side), rad.
    pub rudder: f64,
    /// Approach speed, m/s.
    pub speed: f64,
    /// The propeller input held (SI internal unit: rev/s or N), and whether it was balanced.
    pub propeller: Option<(Quantity, f64)>,
    /// The measures.
    pub turn: TurningCircle,
    /// The track, x and y, m (for the figures).
    #[serde(skip)]
    pub track: (Vec<f64>, Vec<f64>),
}

/// The sweep's result.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepResult {
    /// Ship length, m.
    pub length: f64,
    /// Every case, rudder cases first.
    pub cases: Vec<Case>,
    /// What the user should know (a case that never turned through 180 deg ...).
    pub warnings: Vec<String>,
}

/// Runs every case of the sweep of `loaded` (which must have one).
pub fn simulate_sweep(loaded: &LoadedSim) -> Result<SweepResult> {
    let cfg = &loaded.config;
    let sweep = cfg
        .sweep
        .as_ref()
        .ok_or_else(|| Error::Usage("the configuration has no [sweep]".into()))?;
    let Manoeuvre::TimeHistory {
        inputs,
        initial,
        steering: Some(law),
        ..
    } = &cfg.manoeuvre
    else {
        return Err(Error::Usage("a sweep needs a steered time history".into()));
    };
    let Steering::Turn {
        rudder: configured, ..
    } = *law
    else {
        return Err(Error::Usage("a sweep needs a turning circle".into()));
    };
    let base_speed = initial.get(&Quantity::U).map_or(0.0, |c| c.si);
    let plan = cases(sweep, configured, base_speed);
    let mut result = SweepResult {
        length: cfg.vehicle.length,
        cases: Vec::new(),
        warnings: Vec::new(),
    };
    for (varies, rudder, speed) in plan {
        let case = run_case(cfg, inputs, varies, rudder, speed, &mut result.warnings)?;
        result.cases.push(case);
    }
    Ok(result)
}

/// The sweep's cases in order (varied rudder, then varied speed; each on the configured
/// side, then the other when both are swept): what varies, the rudder angle and the speed.
fn cases(sweep: &Sweep, configured: f64, base_speed: f64) -> Vec<(Varies, f64, f64)> {
    let sign = if configured < 0.0 { -1.0 } else { 1.0 };
    let signs: &[f64] = if sweep.sides == Sides::Both {
        &[1.0, -1.0]
    } else {
        &[1.0]
    };
    let mut plan: Vec<(Varies, f64, f64)> = Vec::new();
    for &s in signs {
        for a in &sweep.rudder {
            plan.push((Varies::Rudder, sign * s * a, base_speed));
        }
    }
    for &s in signs {
        for u in &sweep.speed {
            plan.push((Varies::Speed, sign * s * sweep.speed_rudder, *u));
        }
    }
    plan
}

/// Simulates one case without noise (at the self-propulsion point when the speed varies)
/// and measures its turning circle; a tactical diameter the run does not reach is a warning.
fn run_case(
    cfg: &SimConfig,
    inputs: &std::collections::BTreeMap<Quantity, Constant>,
    varies: Varies,
    rudder: f64,
    speed: f64,
    warnings: &mut Vec<String>,
) -> Result<Case> {
    let mut case_cfg = cfg.clone();
    case_cfg.noise.sigma.clear();
    let propeller = match varies {
        Varies::Speed => Some(balance(cfg, speed, inputs)?),
        Varies::Rudder => None,
    };
    if let Manoeuvre::TimeHistory {
        initial,
        inputs,
        steering: Some(Steering::Turn { rudder: r, .. }),
        ..
    } = &mut case_cfg.manoeuvre
    {
        *r = rudder;
        initial.insert(Quantity::U, Constant::si(speed));
        if let Some((q, v)) = propeller {
            inputs.insert(q, Constant::si(v * q.internal_unit().factor));
        }
    }
    let cols = super::synth::synthesize(&case_cfg)?;
    let col = |q: Quantity| cols.get(&q).cloned();
    let label = format!(
        "rudder {:.1} deg at {} m/s",
        rudder.to_degrees(),
        crate::base::numfmt::num(speed)
    );
    let history = manoeuvre::history_of(col)
        .map_err(|e| Error::numerical("sweep", format!("{label}: {e}")))?
        .ok_or_else(|| Error::Usage(format!("{label}: the model has no heading")))?;
    let nominal = manoeuvre::Nominal {
        rudder: Some(rudder.abs()),
        check: None,
    };
    let measured = manoeuvre::measure_history(&history, cfg.vehicle.length, None, nominal)
        .map_err(|e| Error::numerical("sweep", format!("{label}: {e}")))?;
    let Some(turn) = measured.turning_circle else {
        return Err(Error::numerical("sweep", format!("{label}: not a turn")));
    };
    if turn.tactical_diameter.value().is_none() {
        warnings.push(format!(
            "{label}: the heading changed by {:.0} deg only, so the tactical diameter is \
             missing; lengthen `manoeuvre.duration`",
            turn.max_heading_change.to_degrees()
        ));
    }
    let track = (
        cols.get(&Quantity::X).cloned().unwrap_or_default(),
        cols.get(&Quantity::Y).cloned().unwrap_or_default(),
    );
    Ok(Case {
        varies,
        rudder,
        speed,
        propeller,
        turn,
        track,
    })
}

/// The propeller input (its quantity and value in the internal unit) at which the model's
/// surge acceleration vanishes in straight motion at `speed` with the rudder amidships (the
/// self-propulsion point): bracketed from zero upwards, then bisected.
fn balance(
    cfg: &SimConfig,
    speed: f64,
    inputs: &std::collections::BTreeMap<Quantity, Constant>,
) -> Result<(Quantity, f64)> {
    struct Balance<'a> {
        cfg: &'a SimConfig,
        speed: f64,
        inputs: &'a std::collections::BTreeMap<Quantity, Constant>,
    }
    impl ModelVisitor for Balance<'_> {
        type Output = Result<(Quantity, f64)>;
        fn visit<M: Model>(self, model: &M) -> Self::Output {
            let mut set = CoefficientSet::new();
            for (n, v) in &self.cfg.coefficients {
                set.insert(Coefficient::new(n, *v, None, Source::Config));
            }
            let c = crate::dynamics::sim::complete_coefficients(model, &set)
                .map_err(|missing| Error::Usage(format!("no value for {}", missing.join(", "))))?;
            let quantities = model.input_quantities();
            let (k, q) = quantities
                .iter()
                .enumerate()
                .find(|(_, q)| PROPULSION.contains(q))
                .map(|(k, q)| (k, *q))
                .ok_or_else(|| Error::Usage("the model has no propeller input".into()))?;
            let iu = model
                .state_index(Quantity::U)
                .ok_or_else(|| Error::Usage("the model has no surge state".into()))?;
            let mut x = vec![0.0; model.nx()];
            x[iu] = self.speed;
            let mut u = crate::dynamics::sim::inputs::constant_inputs(&quantities, self.inputs);
            if let Some(r) = quantities.iter().position(|q| *q == Quantity::Rudder) {
                u[r] = 0.0;
            }
            let mut dx = vec![0.0; model.nx()];
            let start = u[k].abs().max(1.0);
            let mut accel = |p: f64| {
                u[k] = p;
                model.derivatives(&x, &u, &c, &mut dx);
                dx[iu]
            };
            let fail = || {
                Error::numerical(
                    "sweep",
                    format!(
                        "no {q} holds {} m/s straight ahead (the surge acceleration does not \
                         change sign between 0 and a very large {q}): the speed is beyond the \
                         propeller's reach or the model's resistance has the wrong sign",
                        self.speed
                    ),
                )
            };
            let (mut lo, mut hi) = (0.0, start);
            if accel(lo) >= 0.0 {
                return Err(fail());
            }
            let mut doublings = 0;
            while accel(hi) <= 0.0 {
                hi *= 2.0;
                doublings += 1;
                if doublings > 60 {
                    return Err(fail());
                }
            }
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if accel(mid) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo <= 1e-13 * hi {
                    break;
                }
            }
            Ok((q, 0.5 * (lo + hi)))
        }
    }
    with_model(
        cfg.model,
        &cfg.vehicle.for_model(&cfg.fluid),
        Balance { cfg, speed, inputs },
    )
    .map_err(Error::vehicle)?
}

/// Writes the sweep's folder (atomically, under the output rules of [`crate::io::output`]):
/// `sweep.csv`, `sweep.md` and the figures. Returns the folder.
pub fn write_sweep(
    loaded: &LoadedSim,
    config_path: &Path,
    result: &SweepResult,
    out: Option<&Path>,
    replace: Replace,
) -> Result<PathBuf> {
    let sweep = loaded
        .config
        .sweep
        .as_ref()
        .ok_or_else(|| Error::Usage("the configuration has no [sweep]".into()))?;
    let target = match out {
        Some(p) => p.to_path_buf(),
        None => loaded.base_dir.join(&sweep.dir),
    };
    let mut protected = Protected::new();
    protected.config(config_path);
    let staging = Staging::guarded(&target, &protected, replace)?;
    staging.write("sweep.csv", table_csv(result).as_bytes())?;
    staging.write("sweep.md", table_markdown(loaded, result).as_bytes())?;
    for plot in crate::app::report::plots::sweep::figures(result) {
        let fig = crate::app::report::plots::render(&plot, Some(staging.dir()))
            .map_err(|e| staging.as_target(e))?;
        staging.write(&format!("{}.svg", fig.meta.name), fig.svg.as_bytes())?;
    }
    staging.commit()
}

/// The measures of a case as numbers (m, s, m/s), or empty cells.
fn cells(c: &Case, l: f64) -> Vec<String> {
    let t = &c.turn;
    let v = |m: &crate::dynamics::manoeuvre::Measure| {
        m.value().map_or(String::new(), |x| format!("{x:.6}"))
    };
    let in_l = |m: &crate::dynamics::manoeuvre::Measure| {
        m.value().map_or(String::new(), |x| format!("{:.6}", x / l))
    };
    vec![
        match c.varies {
            Varies::Rudder => "rudder".into(),
            Varies::Speed => "speed".into(),
        },
        format!("{:.3}", c.rudder.to_degrees()),
        format!("{:.6}", c.speed),
        t.side.to_string(),
        c.propeller
            .map_or(String::new(), |(q, v)| format!("{v:.6} {}", q.si_symbol())),
        v(&t.advance),
        in_l(&t.advance),
        v(&t.transfer),
        v(&t.tactical_diameter),
        in_l(&t.tactical_diameter),
        v(&t.steady_diameter),
        in_l(&t.steady_diameter),
        t.speed_ratio
            .value()
            .map_or(String::new(), |r| format!("{:.6}", 1.0 - r)),
        v(&t.time_to_90),
        v(&t.time_to_180),
    ]
}

const HEADER: [&str; 15] = [
    "varies",
    "rudder (deg)",
    "approach speed (m/s)",
    "side",
    "propeller",
    "advance (m)",
    "advance (L)",
    "transfer (m)",
    "tactical diameter (m)",
    "tactical diameter (L)",
    "steady diameter (m)",
    "steady diameter (L)",
    "speed loss (-)",
    "time to 90 deg (s)",
    "time to 180 deg (s)",
];

fn table_csv(r: &SweepResult) -> String {
    let mut s = HEADER.join(",");
    s.push('\n');
    for c in &r.cases {
        s.push_str(&cells(c, r.length).join(","));
        s.push('\n');
    }
    s
}

fn table_markdown(loaded: &LoadedSim, r: &SweepResult) -> String {
    let title = loaded
        .config
        .title
        .clone()
        .unwrap_or_else(|| "turning-circle sweep".into());
    let header: Vec<String> = HEADER.iter().map(|h| h.to_string()).collect();
    let rows: Vec<Vec<String>> = r.cases.iter().map(|c| cells(c, r.length)).collect();
    let mut right = vec![false; HEADER.len()];
    for (i, r) in right.iter_mut().enumerate() {
        *r = !(i == 0 || i == 3 || i == 4);
    }
    let mut s = format!(
        "# {}\n\nTurning circles of the {} model (L = {} m), each simulated without noise and \
         measured as docs/manoeuvres.md defines (ITTC 7.5-04-02-01); a speed case holds the \
         propeller at the self-propulsion balance of its approach speed.\n\n",
        crate::base::markdown_text::escape_markdown(&title),
        loaded.config.model,
        crate::base::numfmt::num(r.length)
    );
    s.push_str(&crate::base::markdown_text::markdown_table(
        &header, &rows, &right,
    ));
    if !r.warnings.is_empty() {
        s.push_str("\n## Warnings\n\n");
        for w in &r.warnings {
            s.push_str(&format!(
                "- {}\n",
                crate::base::markdown_text::escape_markdown(w)
            ));
        }
    }
    s.push_str(
        "\nFigures: tracks_rudder.svg, tracks_speed.svg, diameter_vs_rudder.svg, \
         diameter_vs_speed.svg (PNG beside each).\n",
    );
    s
}

/// The sweep as a plain-text table for the console: rudder, speed, side, advance, tactical
/// and steady diameters in ship lengths.
pub fn summary(r: &SweepResult) -> String {
    let l = r.length;
    let in_l = |m: &crate::dynamics::manoeuvre::Measure| {
        m.value()
            .map_or("-".to_string(), |x| format!("{:.2}", x / l))
    };
    let mut s = format!(
        "{:>8}  {:>9}  {:<9}  {:>11}  {:>14}  {:>12}\n",
        "rudder", "speed", "side", "advance/L", "tactical D/L", "steady D/L"
    );
    for c in &r.cases {
        s.push_str(&format!(
            "{:>8}  {:>9}  {:<9}  {:>11}  {:>14}  {:>12}\n",
            format!("{:.1} deg", c.rudder.to_degrees()),
            format!("{:.3} m/s", c.speed),
            c.turn.side.to_string(),
            in_l(&c.turn.advance),
            in_l(&c.turn.tactical_diameter),
            in_l(&c.turn.steady_diameter),
        ));
    }
    s.trim_end().to_string()
}
