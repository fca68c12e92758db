//! Model inputs (thrust, rudder, rpm ...) over time: constants or sampled series, linearly
//! interpolated between samples and held beyond the ends; inputs given as steps, sampled.

use crate::base::quantity::Quantity;
use crate::base::si::Constant;
use crate::io::input_spec::Between;
use crate::model::models::{InputDef, InputRule};
use crate::numerics::ode::StageTime;

/// Like `stepped` (`io::steps`), through an actuator of largest rate `rate` (per second, > 0): from
/// `start`, the value moves towards the latest commanded value at most at `rate` and stops on
/// it, so that each step becomes a ramp of slope `rate` lasting |change| / rate (a first-order
/// rate limiter, the steering-gear model of IMO MSC.137(76) and ITTC 7.5-04-02-01 applied to
/// any input). The command is piecewise constant, so the ramp is exact at every sample time,
/// whatever the step times; a change within 1e-12 s after a sample applies from that sample,
/// as in `stepped` (`io::steps`).
pub fn rate_limited(start: f64, changes: &[(f64, f64)], times: &[f64], rate: f64) -> Vec<f64> {
    let (mut value, mut command) = (start, start);
    let mut clock = times.first().copied().unwrap_or(0.0);
    let mut next = changes.iter().peekable();
    // the actuator from `clock` to `to` towards `command`
    let toward = |value: f64, command: f64, span: f64| {
        let most = rate * span.max(0.0);
        value + (command - value).clamp(-most, most)
    };
    times
        .iter()
        .map(|t| {
            while let Some((at, v)) = next.next_if(|(at, _)| *t >= at - 1e-12) {
                let at = at.min(*t).max(clock);
                value = toward(value, command, at - clock);
                clock = at;
                command = *v;
            }
            value = toward(value, command, t - clock);
            clock = *t;
            value
        })
        .collect()
}

/// The model inputs `quantities` held at the constants `given` (`inputs = { rpm = ... }`),
/// in hydroid's internal unit as a record holds them (rev/s for rpm); one not given is 0.
pub fn constant_inputs(
    quantities: &[Quantity],
    given: &std::collections::BTreeMap<Quantity, Constant>,
) -> Vec<f64> {
    quantities
        .iter()
        .map(|q| {
            given
                .get(q)
                .map_or(0.0, |c| c.si / q.internal_unit().factor)
        })
        .collect()
}

/// Whether a sampled input is held between its samples: as the configuration's `between`
/// says, else (`auto`) by the model's rule unless the samples move continuously
/// ([`moves_continuously`]), which a held step log does not.
fn held(between: Option<Between>, rule: InputRule, v: &[f64]) -> bool {
    match between.unwrap_or_default() {
        Between::Hold => true,
        Between::Linear => false,
        Between::Auto => rule == InputRule::Hold && !moves_continuously(v),
    }
}

/// Whether a sampled signal moves through intermediate values between its levels, as a
/// sampled continuous signal does (a rudder moving at its rate, a measured deflection with its
/// noise), rather than jumping from one level to the next within one interval and holding
/// it (a step log). Each interval where the signal changes is part of a ramp when a
/// neighbouring interval changes it in the same direction by at least a quarter as much (so
/// that a step's neighbouring noise does not make it a ramp), else a jump; the signal moves
/// continuously when it travels farther in ramps than in jumps (the sums of the changes'
/// sizes), so that a level that flickers by one printed digit (a 35 deg rudder printed with
/// three significant digits reading 35.0, 34.9, 35.0 ...: many jumps of 0.1 deg) does not
/// outweigh the ramp that reached it. A constant signal does not move.
pub fn moves_continuously(v: &[f64]) -> bool {
    let (lo, hi) = v
        .iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
            (l.min(x), h.max(x))
        });
    let tol = 1e-9 * (hi - lo);
    // NaN or no spread: nothing moves
    if tol.is_nan() || tol <= 0.0 {
        return false;
    }
    let d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    // interval i moves in the direction of a change `x` by at least a quarter of it
    let moves = |i: usize, x: f64| {
        d.get(i)
            .is_some_and(|y| y.abs() > tol && y.signum() == x.signum() && 4.0 * y.abs() >= x.abs())
    };
    let (mut ramps, mut jumps) = (0.0, 0.0);
    for (i, x) in d.iter().enumerate() {
        if x.is_nan() || x.abs() <= tol {
            continue;
        }
        if (i > 0 && moves(i - 1, *x)) || moves(i + 1, *x) {
            ramps += x.abs();
        } else {
            jumps += x.abs();
        }
    }
    ramps > jumps
}

/// The inputs of a model over time.
#[derive(Debug, Clone, PartialEq)]
pub struct InputSeries {
    /// Sample times, s (empty when every input is constant).
    pub t: Vec<f64>,
    /// One entry per model input: a constant or a series sampled at `t`.
    pub inputs: Vec<Input>,
}

/// One input.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// The same value at all times (SI).
    Constant(f64),
    /// Samples at the series' times (SI), interpolated linearly between them.
    Series(Vec<f64>),
    /// Samples at the series' times (SI), each held until the next.
    Held(Vec<f64>),
}

impl InputSeries {
    /// The inputs `wanted` from a record: a column if the record has one, else its constant.
    /// Returns the first input it has neither for.
    pub fn from_record(
        wanted: &[InputDef],
        rec: &crate::io::record::Record,
    ) -> Result<Self, crate::base::quantity::Quantity> {
        let t = rec.time().map(<[f64]>::to_vec).unwrap_or_default();
        let mut inputs = Vec::new();
        for InputDef { quantity: q, rule } in wanted {
            let input = match (rec.channel(*q), rec.constants.get(q)) {
                (Some(v), _) if held(rec.between.get(q).copied(), *rule, v) => {
                    Input::Held(v.to_vec())
                }
                (Some(v), _) => Input::Series(v.to_vec()),
                (None, Some(c)) => Input::Constant(*c),
                (None, None) => return Err(*q),
            };
            inputs.push(input);
        }
        Ok(InputSeries { t, inputs })
    }

    /// How each sampled input of `wanted` (the defs this series was made from) is read
    /// between its samples, `held` or `linear`, by quantity key; constants are left out.
    pub fn between(&self, wanted: &[InputDef]) -> std::collections::BTreeMap<String, String> {
        wanted
            .iter()
            .zip(&self.inputs)
            .filter_map(|(d, i)| {
                let rule = match i {
                    Input::Held(_) => "held",
                    Input::Series(_) => "linear",
                    Input::Constant(_) => return None,
                };
                Some((d.quantity.key().to_string(), rule.to_string()))
            })
            .collect()
    }

    /// Every input constant.
    pub fn constant(values: &[f64]) -> Self {
        InputSeries {
            t: Vec::new(),
            inputs: values.iter().map(|v| Input::Constant(*v)).collect(),
        }
    }

    /// Number of inputs.
    pub fn len(&self) -> usize {
        self.inputs.len()
    }

    /// True when the model has no inputs.
    pub fn is_empty(&self) -> bool {
        self.inputs.is_empty()
    }

    /// The inputs at time `t` into `out` (a held input's sample at t_k from t_k on).
    pub fn at(&self, t: f64, out: &mut [f64]) {
        self.in_step(StageTime::at(t), out);
    }

    /// The inputs at one evaluation of an integration step into `out`: an interpolated input
    /// at the stage's time, a held input (zero-order hold: u(t) = u_k for t_k <= t < t_k+1,
    /// Astrom & Wittenmark 1997, section 2.3) at the step's start, so that every stage of a
    /// step inside [t_k, t_k+1] reads u_k, also the last at t_k+1 (its left limit; the
    /// module docs of [`crate::numerics::ode`]).
    pub fn in_step(&self, at: StageTime, out: &mut [f64]) {
        let (i, w) = self.locate(at.t);
        let (ih, wh) = if at.step_start == at.t {
            (i, w)
        } else {
            self.locate(at.step_start)
        };
        for (o, input) in out.iter_mut().zip(&self.inputs) {
            *o = match input {
                Input::Constant(v) => *v,
                Input::Series(s) => {
                    if s.len() == 1 {
                        s[0]
                    } else {
                        s[i] + w * (s[i + 1] - s[i])
                    }
                }
                Input::Held(s) => {
                    if s.len() == 1 || wh < 1.0 {
                        s[ih]
                    } else {
                        s[ih + 1]
                    }
                }
            };
        }
    }

    /// Interval index and weight of `t` in the time axis (held at the ends).
    fn locate(&self, t: f64) -> (usize, f64) {
        let ts = &self.t;
        if ts.len() < 2 || t <= ts[0] {
            return (0, 0.0);
        }
        let last = ts.len() - 1;
        if t >= ts[last] {
            return (last - 1, 1.0);
        }
        let i = ts
            .partition_point(|&x| x <= t)
            .saturating_sub(1)
            .min(last - 1);
        let span = ts[i + 1] - ts[i];
        let w = if span > 0.0 { (t - ts[i]) / span } else { 0.0 };
        (i, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::input_spec::InputSpec;
    use crate::io::record::{self, Needs};
    use crate::io::steps::stepped;

    /// What `between` reports: held and linear inputs by key, constants left out.
    #[test]
    fn between_names_each_sampled_inputs_rule() {
        let series = InputSeries {
            t: vec![0.0, 1.0],
            inputs: vec![
                Input::Held(vec![0.0, 0.1]),
                Input::Series(vec![10.0, 10.0]),
                Input::Constant(0.0),
            ],
        };
        let defs = [
            InputDef {
                quantity: Quantity::Rudder,
                rule: InputRule::Hold,
            },
            InputDef {
                quantity: Quantity::Rpm,
                rule: InputRule::Interpolate,
            },
            InputDef {
                quantity: Quantity::Thrust,
                rule: InputRule::Interpolate,
            },
        ];
        let b = series.between(&defs);
        assert_eq!(b.len(), 2, "{b:?}");
        assert_eq!(b[Quantity::Rudder.key()], "held");
        assert_eq!(b[Quantity::Rpm.key()], "linear");
    }

    /// The bundled validation turn (15 N, then 30 N from 10 s) read with `extra` added to its
    /// input table and its thrust column mapped or not.
    fn validation_turn(thrust_column: bool, extra: &str) -> Result<record::Record, String> {
        let mut text = String::from(
            "file = \"cfd_exports/turn_validation.csv\"\n\
             [columns]\n\
             time = \"Physical Time: Physical Time\"\n\
             u = \"u Monitor: Expression\"\n",
        );
        if thrust_column {
            text.push_str("thrust = \"Thrust Monitor: Force\"\n");
        }
        let text = format!("{extra}\n{text}");
        let spec: InputSpec = toml::from_str(&text).map_err(|e| e.message().to_string())?;
        let needs = Needs {
            required: &[Quantity::Time, Quantity::U, Quantity::Thrust],
            optional: &[],
            min_rows: 10,
        };
        record::load(
            &spec,
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")),
            &needs,
        )
        .map_err(|e| e.to_string())
    }

    #[test]
    fn steps_sample_like_the_column_they_replace() {
        let column = validation_turn(true, "").unwrap();
        let steps = validation_turn(
            false,
            "constants = { thrust = \"15 N\" }\nsteps = [{ time = 10.0, thrust = \"0.03 kN\" }]",
        )
        .unwrap();
        assert_eq!(
            steps.channel(Quantity::Thrust),
            column.channel(Quantity::Thrust)
        );
        assert!(!steps.constants.contains_key(&Quantity::Thrust));
        // the first step at the start gives the value before it
        let from_zero = validation_turn(
            false,
            "steps = [{ time = 0, thrust = \"15 N\" }, { time = 10, thrust = \"30 N\" }]",
        )
        .unwrap();
        assert_eq!(
            from_zero.channel(Quantity::Thrust),
            column.channel(Quantity::Thrust)
        );
    }

    #[test]
    fn bad_steps_are_named() {
        let e = validation_turn(false, "steps = [{ time = 10.0, thrust = \"30 N\" }]").unwrap_err();
        assert!(
            e.contains("thrust changes first at 10 s but the run starts at 0 s"),
            "{e}"
        );
        let e = validation_turn(
            true,
            "steps = [{ time = 0, thrust = 15 }, { time = 10.0, thrust = 30 }]",
        )
        .unwrap_err();
        assert!(e.contains("both as a column and as steps"), "{e}");
        let e = validation_turn(
            false,
            "steps = [{ time = 10, thrust = \"30 N\" }, { time = 5, thrust = \"1 N\" }]",
        )
        .unwrap_err();
        assert!(e.contains("increasing time: 10 s then 5 s"), "{e}");
        let e = validation_turn(false, "steps = [{ time = 10, thrust = \"30 deg\" }]").unwrap_err();
        assert!(
            e.contains("thrust = \"30 deg\": unit 'deg' is an angle (rad); expected a force"),
            "{e}"
        );
        let e = validation_turn(false, "steps = [{ time = 10 }]").unwrap_err();
        assert!(e.contains("changes nothing"), "{e}");
    }

    #[test]
    fn interpolates_and_holds() {
        let s = InputSeries {
            t: vec![0.0, 1.0, 2.0],
            inputs: vec![Input::Series(vec![0.0, 10.0, 20.0]), Input::Constant(5.0)],
        };
        let mut o = [0.0; 2];
        s.at(0.25, &mut o);
        assert_eq!(o, [2.5, 5.0]);
        s.at(1.5, &mut o);
        assert_eq!(o, [15.0, 5.0]);
        s.at(-1.0, &mut o);
        assert_eq!(o[0], 0.0);
        s.at(9.0, &mut o);
        assert_eq!(o[0], 20.0);
    }

    /// Inside an integration step a held input has its value at the step's start, also at the
    /// step's end on the next sample (the left limit); an interpolated one is read at the
    /// stage's time; at a sample (`at`) a held input already has the sample's value.
    #[test]
    fn a_step_reads_a_held_input_at_its_start() {
        let s = InputSeries {
            t: vec![0.0, 1.0, 2.0],
            inputs: vec![
                Input::Held(vec![1.0, 7.0, 3.0]),
                Input::Series(vec![1.0, 7.0, 3.0]),
            ],
        };
        let mut o = [0.0; 2];
        let stage = |t: f64, step_start: f64| StageTime { t, step_start };
        s.in_step(stage(1.0, 0.5), &mut o);
        assert_eq!(o, [1.0, 7.0], "the end of a step in [0, 1]");
        s.in_step(stage(0.75, 0.5), &mut o);
        assert_eq!(o, [1.0, 5.5]);
        s.in_step(stage(2.0, 1.0), &mut o);
        assert_eq!(o, [7.0, 3.0], "the end of the last interval");
        s.in_step(stage(2.5, 2.0), &mut o);
        assert_eq!(o, [3.0, 3.0], "beyond the samples: the last held");
        s.at(1.0, &mut o);
        assert_eq!(o, [7.0, 7.0], "at a sample, the sample");
        s.in_step(StageTime::at(1.0), &mut o);
        assert_eq!(o, [7.0, 7.0], "the start of a step on a sample");
    }

    /// A rudder moving at 2.32 deg/s sampled at 10 Hz ramps, also with noise, and also when
    /// printed with three significant digits, so that its held levels flicker by one digit;
    /// the same zig-zag logged as commanded steps jumps, also with noise (its jumps outweigh
    /// the noise's ramps); a constant does not move.
    #[test]
    fn continuous_signals_are_told_from_step_logs() {
        let t: Vec<f64> = (0..600).map(|k| k as f64 * 0.1).collect();
        let ramp = rate_limited(0.0, &[(5.0, 0.35), (25.0, -0.35)], &t, 0.0405);
        assert!(moves_continuously(&ramp));
        let steps = stepped(0.0, &[(5.0, 0.35), (25.0, -0.35), (45.0, 0.0)], &t);
        assert!(!moves_continuously(&steps));
        // white noise: an interval is a jump only between two opposite local extrema
        // (10 of the 24 orders of four samples), so ramps are ~58 % of the changes
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let mut rng = StdRng::seed_from_u64(7);
        let mut noise = |v: &Vec<f64>| -> Vec<f64> {
            v.iter()
                .map(|v| v + 1e-3 * rng.random_range(-1.0..1.0))
                .collect()
        };
        assert!(moves_continuously(&noise(&ramp)));
        assert!(!moves_continuously(&noise(&steps)));
        // three significant digits in degrees, and a level flickering by one digit at most
        // samples (more jumps than the ramp has intervals)
        let printed: Vec<f64> = ramp
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let deg = v.to_degrees();
                let step = if deg.abs() >= 10.0 { 0.1 } else { 0.01 };
                let flicker = if deg.abs() > 19.9 && k % 2 == 0 {
                    step
                } else {
                    0.0
                };
                ((deg / step).round() * step - flicker * deg.signum()).to_radians()
            })
            .collect();
        let d: Vec<f64> = printed.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
        let flickers = d
            .iter()
            .filter(|&&x| x > 0.0 && x < 0.11f64.to_radians())
            .count();
        let moved = d.iter().filter(|&&x| x > 0.0).count();
        assert!(2 * flickers > moved, "{flickers} of {moved}");
        assert!(moves_continuously(&printed));
        assert!(!moves_continuously(&[0.1; 50]));
        assert!(!moves_continuously(&[]));
    }

    /// `between` overrides the model's rule; `auto` holds a step log under a holding model
    /// and interpolates a ramp.
    #[test]
    fn between_chooses_hold_or_linear() {
        let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        let ramp = rate_limited(0.0, &[(1.0, 0.35)], &t, 0.0405);
        let steps = stepped(0.0, &[(1.0, 0.35)], &t);
        assert!(!held(None, InputRule::Hold, &ramp));
        assert!(held(None, InputRule::Hold, &steps));
        assert!(!held(None, InputRule::Interpolate, &steps));
        assert!(held(Some(Between::Hold), InputRule::Interpolate, &ramp));
        assert!(!held(Some(Between::Linear), InputRule::Hold, &steps));
    }
}
