//! The identified model sailing the run's own standard manoeuvre: a turning circle or a
//! zig-zag read from the run (rudder angle, execute heading, rudder rate, execute time;
//! ITTC 7.5-04-02-01, IMO MSC.137(76)), steered by the helm from the run's first sample with
//! the run's other inputs (propeller), and measured as the run is. An open-loop replay of a
//! zig-zag's rudder history would reverse the rudder at the run's times whatever heading the
//! model has reached; steered, the model's overshoots are its own.

use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::dynamics::manoeuvre::{self, History, HistoryError, RunMeasures};
use crate::dynamics::sim::inputs::Input;
use crate::dynamics::sim::steering::{Steering, Surface};
use crate::dynamics::sim::InputSeries;
use crate::io::record::Record;
use crate::model::models::Model;
use serde::Serialize;

/// A tactical or steady turning diameter of the model further than this share from the run's
/// is a poor prediction of the turn.
pub const POOR_DIAMETER_SHARE: f64 = 0.1;

/// A zig-zag overshoot of the model further than this from the run's is a poor prediction,
/// rad (3 deg).
pub const POOR_OVERSHOOT: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// The run's manoeuvre measured, and the identified model's when steered the same way.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ManoeuvreComparison {
    /// The helm read from the run, with which the model was steered (SI: rad, rad/s, s).
    pub steering: Steering,
    /// The run's measures.
    pub measured: RunMeasures,
    /// The identified model's measures, when its manoeuvre could be simulated and measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<RunMeasures>,
    /// Why the model's measures are missing or partial (it diverged, never turned ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_note: Option<String>,
    /// The identified model's steered history (time, heading, track, the helm's rudder), for
    /// the report's manoeuvre figures; not written to results.json.
    #[serde(skip)]
    pub model_history: Option<History>,
    /// The model's wave frequency (rad/s) whose wave yaw was taken out of the run's heading
    /// before it was measured ([`Model::wave_frequency`], `signal::wave_removed`), for a
    /// model whose compass sees wave yaw.
    #[serde(skip)]
    pub waves_at: Option<f64>,
}

impl ManoeuvreComparison {
    /// The measures side by side, with the IMO criteria checked on each.
    pub fn table(&self) -> manoeuvre::ComparisonTable {
        let model = self.model.as_ref().map(RunMeasures::measures);
        let model_notes = self.model.iter().flat_map(|m| m.not_judged.iter());
        manoeuvre::ComparisonTable::new(
            &self.measured.measures(),
            model.as_deref(),
            &self.measured.checks,
            self.model.as_ref().map_or(&[][..], |m| &m.checks[..]),
        )
        .with_notes(self.measured.notes("measured"))
        .with_notes(self.waves_at.map(|w| {
            format!(
                "measured: read from the heading low-passed below half the wave frequency \
                 {} rad/s (zero phase), as the compass also sees the wave yaw the model does \
                 not sail",
                crate::base::numfmt::num(w)
            )
        }))
        .with_notes(model_notes.map(|r| format!("IMO criteria (identified model): {r}")))
    }

    /// How the model was steered, in words: "rudder 35 deg at 15.8 deg/s from t = 5 s, held",
    /// "stern planes 10 deg ... reversed at 10 deg of pitch change".
    pub fn steering_text(&self) -> String {
        let deg = |a: f64| crate::base::numfmt::num(a.to_degrees());
        let surface = self.steering.surface();
        match self.steering {
            Steering::Turn {
                rudder,
                rate,
                execute,
                ..
            } => format!(
                "{} {} deg at {} deg/s from t = {} s, held",
                surface.words(),
                deg(rudder),
                deg(rate),
                crate::base::numfmt::num(execute)
            ),
            Steering::ZigZag {
                rudder,
                heading,
                rate,
                execute,
                ..
            } => format!(
                "{} {} deg at {} deg/s from t = {} s, reversed at {} deg of {} change",
                surface.words(),
                deg(rudder),
                deg(rate),
                crate::base::numfmt::num(execute),
                deg(heading),
                surface.watched_words()
            ),
        }
    }

    /// The manoeuvre in words: "turning circle", "zig-zag", "zig-zag on the stern planes".
    pub fn kind(&self) -> String {
        match self.steering.surface() {
            Surface::Rudder => self.measured.kind().to_string(),
            s => format!("{} on the {}", self.measured.kind(), s.words()),
        }
    }
}

/// Where a run goes with its surface put over, in words: "turns to starboard" (heading
/// increasing), "pitches bow up" (pitch increasing).
fn goes(side: manoeuvre::Side, surface: Surface) -> String {
    match (surface, side) {
        (Surface::Rudder, side) => format!("turns to {side}"),
        (Surface::SternPlanes, manoeuvre::Side::Starboard) => "pitches bow up".to_string(),
        (Surface::SternPlanes, manoeuvre::Side::Port) => "pitches bow down".to_string(),
    }
}

/// The ship of the run, its length (m) and scale ratio (None when unknown), and the nominal
/// angles of its manoeuvre given in the configuration (the others are inferred from the run).
#[derive(Debug, Clone, Copy)]
pub struct RunSettings {
    /// Ship length L of the run, m.
    pub length: f64,
    /// Scale ratio lambda (1 at full scale).
    pub lambda: Option<f64>,
    /// The nominal rudder and check angles given for the run.
    pub nominal: manoeuvre::Nominal,
}

/// The run's measures and the model's on the same manoeuvre, or None when the run is not a
/// standard manoeuvre of a steered model: a turning circle or zig-zag on the rudder (a
/// rudder input and a heading state, the run's rudder and heading), else a zig-zag on the
/// stern planes watching the pitch (a stern-plane input and a pitch state; an AUV's vertical
/// zig-zag), or no turn that the measures recognise.
pub fn compare<M: Model>(
    model: &M,
    c: &[f64],
    rec: &Record,
    inputs: &InputSeries,
    substeps: usize,
    run: RunSettings,
) -> Option<ManoeuvreComparison> {
    [Surface::Rudder, Surface::SternPlanes]
        .into_iter()
        .find_map(|surface| compare_on(model, c, rec, inputs, substeps, run, surface))
}

/// The run's history as the measures of a manoeuvre on `surface` read it: on the rudder,
/// the time, heading, track, velocities and rudder; on the stern planes, the pitch in place
/// of the heading and the stern planes in place of the rudder, without the track (a dive has
/// no turning circle). None without the time or the watched angle.
pub fn history_on(rec: &Record, surface: Surface) -> Option<History> {
    manoeuvre::history_of(|q| {
        let column = match (surface, q) {
            (_, Quantity::Time) => Quantity::Time,
            (_, Quantity::Yaw) => surface.watched(),
            (_, Quantity::Rudder) => surface.input(),
            (Surface::Rudder, q) => q,
            (Surface::SternPlanes, _) => return None,
        };
        rec.channel(column).map(<[f64]>::to_vec)
    })
    .ok()?
}

/// [`compare`] on one control surface.
fn compare_on<M: Model>(
    model: &M,
    c: &[f64],
    rec: &Record,
    inputs: &InputSeries,
    substeps: usize,
    run: RunSettings,
    surface: Surface,
) -> Option<ManoeuvreComparison> {
    let input = model
        .input_quantities()
        .iter()
        .position(|q| *q == surface.input())?;
    model.state_index(surface.watched())?;
    let deflection = rec.channel(surface.input())?;
    // a compass that sees the wave yaw (Fossen 2011, 8.2): the manoeuvre is the slow heading
    // the model sails, read below the wave band
    let waves_at = model.wave_frequency(c).filter(|_| surface.is_rudder());
    let h = history_on(rec, surface)?;
    let h = match waves_at {
        Some(w0) => h
            .map_heading(|t, psi| crate::numerics::signal::wave_removed(t, psi, w0))
            .ok()?,
        None => h,
    };
    let mut measured = manoeuvre::measure_history(&h, run.length, run.lambda, run.nominal).ok()?;
    if !surface.is_rudder() {
        measured.zigzag.as_ref()?;
        not_judged_in_pitch(&mut measured);
    }
    let steering = law_of(&measured, &h, surface)?;
    let mut steered_inputs = inputs.clone();
    // the helm's surface is read between samples as the run's own is (`between`): linear for
    // a moving rudder, as `hydroid simulate` steers, held where the run's rudder is held
    let helm_start = vec![deflection[0]; h.time().len()];
    steered_inputs.inputs[input] = match inputs.inputs[input] {
        Input::Held(_) => Input::Held(helm_start),
        _ => Input::Series(helm_start),
    };
    // the start from the run's first sample, of its slow part when the compass sees waves
    let start = |v: &[f64]| match (waves_at, rec.time()) {
        (Some(w0), Some(t)) => crate::numerics::signal::wave_removed(t, v, w0)[0],
        _ => v[0],
    };
    let x0: Vec<f64> = model
        .states()
        .iter()
        .map(|s| rec.channel(s.quantity).map_or(0.0, start))
        .collect();
    let (xs, note) = match crate::app::simulate::synth::steered(
        model,
        c,
        &x0,
        &mut steered_inputs,
        steering,
        substeps,
    ) {
        Ok(xs) => (xs, None),
        Err(e) => {
            return Some(ManoeuvreComparison {
                steering,
                measured,
                model: None,
                model_note: Some(format!("the steered model stopped: {e}")),
                model_history: None,
                waves_at,
            })
        }
    };
    let helm = match &steered_inputs.inputs[input] {
        Input::Held(s) | Input::Series(s) => s.clone(),
        Input::Constant(v) => vec![*v; xs.len()],
    };
    let history = model_history(model, h.time(), &xs, surface, helm);
    let (model_measures, failure) =
        match history.as_ref().map_err(Clone::clone).and_then(|mh| {
            manoeuvre::measure_history(mh, run.length, run.lambda, nominal_of(steering))
        }) {
            Ok(mut m) => {
                if !surface.is_rudder() {
                    not_judged_in_pitch(&mut m);
                }
                (Some(m), note)
            }
            Err(e) => (
                None,
                Some(format!("the model's manoeuvre cannot be measured: {e}")),
            ),
        };
    Some(ManoeuvreComparison {
        steering,
        measured,
        model: model_measures,
        model_note: failure,
        model_history: history.ok(),
        waves_at,
    })
}

/// The IMO criteria judge a ship's heading: none is judged on a zig-zag of the pitch.
fn not_judged_in_pitch(m: &mut RunMeasures) {
    m.checks.clear();
    m.not_judged = vec![
        "MSC.137(76) 5.3 judges a ship's heading; a zig-zag of the pitch on the stern planes \
         is not judged"
            .to_string(),
    ];
}

/// The helm that sailed the run, at the run's nominal angles: a zig-zag's rudder angle and
/// check angle, or a turn's rudder angle, put over in the direction the run's rudder was
/// (in the model's sign convention, as the run was read: a rudder column whose sign was
/// reversed with `scale = -1` already is); the steepest rudder rate of the run; the execute
/// time the measures found.
fn law_of(m: &RunMeasures, h: &History, surface: Surface) -> Option<Steering> {
    let rate = manoeuvre::rudder_rate(h.time(), h.rudder()?)?;
    match (&m.zigzag, &m.turning_circle) {
        (Some(z), _) => Some(Steering::ZigZag {
            rudder: z.rudder_angle.value()? * manoeuvre::rudder_put_over(h, z.execute_time)?,
            heading: z.heading_angle,
            rate,
            execute: z.execute_time,
            surface,
        }),
        (None, Some(t)) => Some(Steering::Turn {
            rudder: t.nominal_rudder_angle.value()?
                * manoeuvre::rudder_put_over(h, t.execute_time)?,
            rate,
            execute: t.execute_time,
            surface,
        }),
        (None, None) => None,
    }
}

/// The nominal angles a steering law sails at, as given angles for measuring the model.
fn nominal_of(law: Steering) -> manoeuvre::Nominal {
    match law {
        Steering::Turn { rudder, .. } => manoeuvre::Nominal {
            rudder: Some(rudder.abs()),
            check: None,
        },
        Steering::ZigZag {
            rudder, heading, ..
        } => manoeuvre::Nominal {
            rudder: Some(rudder.abs()),
            check: Some(heading),
        },
    }
}

/// The model's simulated history in the measures' terms, as [`history_on`] reads the run's:
/// the watched angle (heading or pitch) from its states, the deflection the helm moved, and
/// on the rudder the track and velocities from its states.
fn model_history<M: Model>(
    model: &M,
    time: &[f64],
    xs: &[Vec<f64>],
    surface: Surface,
    helm: Vec<f64>,
) -> Result<History, HistoryError> {
    let n = xs.len();
    let state = |q: Quantity| {
        model
            .state_index(q)
            .map(|i| xs.iter().map(|x| x[i]).collect::<Vec<f64>>())
    };
    manoeuvre::history_of(|q| match q {
        Quantity::Time => Some(time[..n].to_vec()),
        Quantity::Yaw => state(surface.watched()),
        Quantity::Rudder => Some(helm[..n].to_vec()),
        q if surface.is_rudder() => state(q),
        _ => None,
    })
    .and_then(|h| {
        h.ok_or(HistoryError::Lacks {
            what: "the steered model's manoeuvre",
            series: "watched angle",
        })
    })
}

/// Warnings on the model's manoeuvre against the run's: it turns the other way, could not be
/// steered or measured, or misses the turning diameters by more than
/// [`POOR_DIAMETER_SHARE`] or an overshoot by more than [`POOR_OVERSHOOT`].
pub fn warnings(cmp: &ManoeuvreComparison, run: &str) -> Vec<Warning> {
    let kind = cmp.kind();
    let warn = |message: String, meaning: &str| {
        Warning::new("resimulation", message, meaning.to_string()).for_run(run)
    };
    let mut out = Vec::new();
    if let Some(note) = &cmp.model_note {
        out.push(warn(
            format!("the identified model's {kind}: {note}"),
            "the model cannot be judged on this manoeuvre, and should not be used to predict \
             it until the reason is understood",
        ));
    }
    let Some(model) = &cmp.model else {
        return out;
    };
    if let (Some(a), Some(b)) = (cmp.measured.side(), model.side()) {
        if a != b {
            let surface = cmp.steering.surface();
            out.push(warn(
                format!(
                    "the identified model {} where the run {} with the same {}",
                    goes(b, surface),
                    goes(a, surface),
                    surface.words()
                ),
                &format!(
                    "a {} or {} coefficient has the wrong sign, or the {} column's sign \
                     convention differs from the model's (columns.{}.scale = -1 reverses it): \
                     none of its coefficients can be trusted",
                    surface.words(),
                    surface.watched_words(),
                    surface.words(),
                    surface.input().key()
                ),
            ));
            return out;
        }
    }
    let measured = cmp.measured.measures();
    let pairs = model.measures().into_iter().filter_map(|n| {
        let judged = matches!(
            n.key,
            "tactical_diameter" | "steady_diameter" | "first_overshoot" | "second_overshoot"
        );
        let run = measured.iter().find(|m| m.key == n.key)?;
        judged.then(|| (n.label, run.value.value(), n.value.value()))
    });
    let mut poor = Vec::new();
    for (label, measured, predicted) in pairs {
        let (Some(a), Some(b)) = (measured, predicted) else {
            continue;
        };
        if label.contains("diameter") {
            if (b - a).abs() > POOR_DIAMETER_SHARE * a.abs() {
                poor.push(format!(
                    "{label} {b:.3} m against {a:.3} m ({:+.0} %)",
                    100.0 * (b - a) / a
                ));
            }
        } else if (b - a).abs() > POOR_OVERSHOOT {
            poor.push(format!(
                "{label} {:.1} deg against {:.1} deg",
                b.to_degrees(),
                a.to_degrees()
            ));
        }
    }
    if !poor.is_empty() {
        out.push(warn(
            format!(
                "the identified model predicts the {kind} poorly: {}",
                poor.join("; ")
            ),
            "the manoeuvre measures a naval architect quotes from this model would be wrong \
             by this much: the model structure, a fixed coefficient or an input differs from \
             the run's, or the run lies outside what the fit runs covered",
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::manoeuvre::{Nominal, Side};
    use std::collections::BTreeMap;

    /// A free-running log of the KVLCC2 model (mmg3, Yasukawa & Yoshimura 2015; a positive
    /// rudder turns it to starboard) steered by a helm written here: the rudder trimmed `trim`
    /// (rad) on the approach, put over to `rudder` (rad) at 5 s at 2.32 deg/s (a slow gear:
    /// the rudder leaves its trim over several samples), and, for a
    /// zig-zag (`check` given, rad), reversed each time the heading change from the execute
    /// reaches `check` beyond the side the rudder turns it to.
    fn kvlcc2_log(rudder: f64, check: Option<f64>, trim: f64, duration: f64) -> Record {
        use crate::base::quantity::Quantity as Q;
        use crate::dynamics::sim::{simulate, InputSeries};
        use crate::model::models::mmg3::{self, Mmg3};
        use crate::model::models::Model;
        let m = Mmg3::build(&mmg3::kvlcc2_model_vehicle()).unwrap();
        let c = m.coefficient_vector(mmg3::KVLCC2);
        let (dt, execute, rate) = (0.1, 5.0, 2.32f64.to_radians());
        let mut x = vec![mmg3::KVLCC2_SPEED, 0.0, 0.0, 0.0, 0.0, 0.0];
        let (mut delta, mut target, mut psi0) = (trim, trim, 0.0);
        let mut cols: BTreeMap<Q, Vec<f64>> = BTreeMap::new();
        let quantities = [
            Q::Time,
            Q::U,
            Q::V,
            Q::R,
            Q::X,
            Q::Y,
            Q::Yaw,
            Q::Rudder,
            Q::Rpm,
        ];
        for k in 0..=(duration / dt) as usize {
            let t = k as f64 * dt;
            let row = [
                t,
                x[0],
                x[1],
                x[2],
                x[3],
                x[4],
                x[5],
                delta,
                mmg3::KVLCC2_RPS,
            ];
            for (q, v) in quantities.iter().zip(row) {
                cols.entry(*q).or_default().push(v);
            }
            if (t - execute).abs() < 1e-9 {
                (target, psi0) = (rudder, x[5]);
            }
            if let (Some(check), true) = (check, t > execute) {
                // the rudder turns the ship to the side of its sign (mmg3)
                let change = (x[5] - psi0) * target.signum();
                if change >= check {
                    target = -target;
                }
            }
            delta += (target - delta).clamp(-rate * dt, rate * dt);
            let inputs = InputSeries::constant(&[delta, mmg3::KVLCC2_RPS]);
            x = simulate(&m, &c, &x, &inputs, &[t, t + dt], 4).unwrap()[1].clone();
        }
        Record::from_channels("log", "log.csv", cols)
    }

    /// The model steered through `rec`'s manoeuvre at the run's nominal angles.
    fn steered(rec: &Record) -> ManoeuvreComparison {
        use crate::model::models::mmg3::{self, Mmg3};
        use crate::model::models::Model;
        let m = Mmg3::build(&mmg3::kvlcc2_model_vehicle()).unwrap();
        let c = m.coefficient_vector(mmg3::KVLCC2);
        let inputs = crate::dynamics::sim::InputSeries::from_record(m.inputs(), rec).unwrap();
        let run = RunSettings {
            length: 7.0,
            lambda: Some(45.7),
            nominal: Nominal::default(),
        };
        compare(&m, &c, rec, &inputs, 4, run).expect("a manoeuvre the model can sail")
    }

    /// A frigate's 20/20 zig-zag written here from Nomoto's first-order model (Fossen 2011,
    /// 7.2: T r_dot + r = K delta, K 0.18 1/s, T 27 s, solved exactly over 0.01 s steps of a
    /// rudder moving at 2.3 deg/s), the helm reversing on the ship's heading, logged every
    /// 0.1 s by a compass and a gyro that also see a wave yaw of 3 deg at 0.8 rad/s.
    fn frigate_zigzag_in_waves(wave: f64) -> Record {
        use crate::base::quantity::Quantity as Q;
        let (k, t_n, w0) = (0.18, 27.0, 0.8);
        let (rate, rudder, check) = (2.3f64.to_radians(), 20f64.to_radians(), 20f64.to_radians());
        let (mut r, mut psi, mut delta, mut target) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let mut cols: BTreeMap<Q, Vec<f64>> = BTreeMap::new();
        for step in 0..=4000usize {
            let t = step as f64 * 0.1;
            let wave_yaw = wave * (w0 * t + 0.7).sin();
            for (q, v) in [
                (Q::Time, t),
                (Q::Yaw, psi + wave_yaw),
                (Q::R, r + wave * w0 * (w0 * t + 0.7).cos()),
                (Q::Rudder, delta),
            ] {
                cols.entry(q).or_default().push(v);
            }
            if step == 100 {
                target = rudder;
            }
            if step > 100 && psi * target.signum() >= check {
                target = -target;
            }
            for _ in 0..10 {
                let h = 0.01;
                delta += (target - delta).clamp(-rate * h, rate * h);
                let (steady, decay) = (k * delta, (-h / t_n).exp());
                psi += steady * h + (r - steady) * t_n * (1.0 - decay);
                r = steady + (r - steady) * decay;
            }
        }
        Record::from_channels("zigzag", "zigzag.csv", cols)
    }

    /// The Nomoto wave model (the generator's K, T and waves) steered through the log's
    /// zig-zag: its overshoots against the run's (first, second), and the raw compass's.
    fn nomoto_overshoots(rec: &Record) -> ([f64; 2], [f64; 2], [f64; 2]) {
        use crate::model::models::nomoto_wave::NomotoWave;
        let m = NomotoWave::build(&NomotoWave::example_vehicle()).unwrap();
        let c = vec![0.18, 1.0 / 27.0, 0.0, 0.8, 0.1];
        let inputs = crate::dynamics::sim::InputSeries::from_record(m.inputs(), rec).unwrap();
        let run = RunSettings {
            length: 120.0,
            lambda: None,
            nominal: Nominal::default(),
        };
        let cmp = compare(&m, &c, rec, &inputs, 4, run).expect("a zig-zag");
        assert_eq!(cmp.waves_at, Some(0.8));
        let both = |z: &crate::dynamics::manoeuvre::ZigZag| {
            [&z.first_overshoot, &z.second_overshoot].map(|o| o.value().unwrap().to_degrees())
        };
        let raw = manoeuvre::measure_history(
            &history_on(rec, Surface::Rudder).unwrap(),
            120.0,
            None,
            Nominal::default(),
        )
        .unwrap();
        (
            both(cmp.measured.zigzag.as_ref().unwrap()),
            both(cmp.model.as_ref().unwrap().zigzag.as_ref().unwrap()),
            both(raw.zigzag.as_ref().unwrap()),
        )
    }

    #[test]
    fn a_compass_that_sees_waves_is_measured_as_the_heading_the_model_sails() {
        // issue 24 item 9: the compass's overshoots include the wave yaw, the model's not
        let (run, model, raw) = nomoto_overshoots(&frigate_zigzag_in_waves(3f64.to_radians()));
        let (calm, calm_model, _) = nomoto_overshoots(&frigate_zigzag_in_waves(0.0));
        for i in 0..2 {
            assert!((run[i] - model[i]).abs() < 0.3, "{run:?} {model:?} {raw:?}");
            assert!((run[i] - calm[i]).abs() < 0.3, "{run:?} {calm:?}");
            assert!(
                (calm[i] - calm_model[i]).abs() < 0.3,
                "{calm:?} {calm_model:?}"
            );
        }
        // read from the raw compass, an overshoot is off by a degree or more
        assert!(
            (0..2).any(|i| (raw[i] - model[i]).abs() > 1.0),
            "{raw:?} {model:?}"
        );
    }

    /// A port-first 20/20 zig-zag and a 35 deg turning circle to port, each after an approach
    /// with the rudder trimmed 1 deg to starboard (the first samples after the execute are
    /// still on the starboard side): the model (the truth here) is steered to port as the run
    /// went, and sails the run's manoeuvre.
    #[test]
    fn the_model_is_steered_to_the_side_the_run_went() {
        let trim = 1f64.to_radians();
        let zz = kvlcc2_log(-20f64.to_radians(), Some(20f64.to_radians()), trim, 150.0);
        let turn = kvlcc2_log(-35f64.to_radians(), None, trim, 120.0);
        for (rec, rudder) in [(&zz, -20.0), (&turn, -35.0)] {
            let cmp = steered(rec);
            let model = cmp
                .model
                .as_ref()
                .expect("the model's manoeuvre is measured");
            assert_eq!(cmp.measured.side(), Some(Side::Port));
            assert_eq!(model.side(), Some(Side::Port), "{}", cmp.steering_text());
            let law = match cmp.steering {
                Steering::Turn { rudder, .. } | Steering::ZigZag { rudder, .. } => rudder,
            };
            assert!((law.to_degrees() - rudder).abs() < 1e-9, "{law}");
            assert!(
                warnings(&cmp, "log").is_empty(),
                "{:?}",
                warnings(&cmp, "log")
            );
        }
        // the truth sails the zig-zag as the run did, to the helm's timing: hydroid's helm
        // reverses the rudder within a step, this log's at its samples (0.1 s), which moves
        // the 42 deg overshoot of this slow gear by half a degree
        let cmp = steered(&zz);
        let (run, model) = (
            cmp.measured.zigzag.unwrap(),
            cmp.model.unwrap().zigzag.unwrap(),
        );
        let first = |z: &crate::dynamics::manoeuvre::ZigZag| {
            z.first_overshoot.value().unwrap().to_degrees()
        };
        assert!(
            (first(&run) - first(&model)).abs() < 1.0,
            "{} {}",
            first(&run),
            first(&model)
        );
    }
}
