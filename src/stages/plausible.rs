//! What the plausibility checks of the stages share: a finding (a warning, and whether it is
//! a clear mistake that stops the run), the model's expectation of a run (its coefficients at
//! the starting point, the vehicle's propeller), how a quantity and a run's file are named in
//! messages, and the judgement of a propeller's advance ratio.

use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::hekf::Checks;
use crate::io::record::Record;
use crate::model::models::{Model, Vehicle};

/// A finding of a check: a warning, and whether it is a clear mistake that stops the run
/// (with `hekf.checks` or `captive.checks` = "error").
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// What was found and what it means.
    pub warning: Warning,
    /// A clear mistake: the data contradict the configuration and an alternative fits.
    pub blocking: bool,
}

impl Finding {
    /// A finding of stage `stage` about run `run`.
    pub fn of(stage: &str, run: &str, blocking: bool, message: String, meaning: String) -> Self {
        Finding {
            warning: Warning::new(stage, message, meaning).for_run(run),
            blocking,
        }
    }

    /// Where the finding goes: with `checks = "error"` a clear one is the problem that stops
    /// the run (its run, what was seen, what it means, and `key = "warn"` to run anyway:
    /// `Err`), anything else its warning (`Ok`).
    pub fn sorted(self, checks: Checks, key: &str) -> Result<Warning, String> {
        if !(self.blocking && checks == Checks::Error) {
            return Ok(self.warning);
        }
        let w = self.warning;
        Err(format!(
            "{}{}; {} ({key} = \"warn\" runs anyway)",
            w.run
                .as_ref()
                .map(|r| format!("run '{r}': "))
                .unwrap_or_default(),
            w.message,
            w.meaning
        ))
    }
}

/// What the model expects of a run, for the checks that compare the run with the model:
/// its coefficients at the starting point and the vehicle's propeller diameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Expectation {
    /// The model's coefficient vector: the configured values (`[coefficients]`, a prior's
    /// `initial`) where given, the model's example values elsewhere (they carry the model's
    /// sign conventions and sizes), completed by the relations.
    pub coefficients: Vec<f64>,
    /// Whether the sizes of the model's responses carry over to this vehicle: every
    /// coefficient taken from the example is non-dimensional (a dimensional one belongs to
    /// the example's vehicle, and then only the signs of the responses are judged).
    pub sizes_known: bool,
    /// `vehicle.particulars.propeller_diameter`, m, when given.
    pub propeller_diameter: Option<f64>,
    /// The wake fraction at the propeller in straight motion: the model's `wP0` when it has
    /// one, else 0.
    pub wake: f64,
    /// The vehicle's length, m.
    pub length: f64,
    /// The Froude number the model's example runs at ([`model_froude`]).
    pub froude_model: Option<f64>,
}

impl Expectation {
    /// The expectation of `model` for `vehicle`, with `configured` giving a coefficient's
    /// configured value by name.
    pub fn new<M: Model>(
        model: &M,
        configured: &dyn Fn(&str) -> Option<f64>,
        vehicle: &Vehicle,
    ) -> Self {
        let example = model.example();
        let mut sizes_known = true;
        let mut values: Vec<(&str, f64)> = Vec::new();
        for def in model.coefficients() {
            if let Some(v) = configured(def.name) {
                values.push((def.name, v));
            } else if let Some(&(_, v)) = example.coefficients.iter().find(|e| e.0 == def.name) {
                sizes_known &= def.unit == "-" || v == 0.0;
                values.push((def.name, v));
            }
        }
        let coefficients = model.coefficient_vector(&values);
        let wake = model
            .coefficient_index("wP0")
            .map(|i| coefficients[i])
            .filter(|w| w.is_finite())
            .map_or(0.0, |w| w.clamp(0.0, 0.9));
        Expectation {
            coefficients,
            sizes_known,
            propeller_diameter: propeller_diameter(vehicle),
            wake,
            length: vehicle.length,
            froude_model: model_froude(model),
        }
    }
}

/// `vehicle.particulars.propeller_diameter` in m (a number in m or a string with a unit),
/// whatever model reads the particulars.
fn propeller_diameter(vehicle: &Vehicle) -> Option<f64> {
    #[derive(serde::Deserialize)]
    struct Propeller {
        #[serde(
            default,
            deserialize_with = "crate::base::si::option::<_, crate::base::si::Length>"
        )]
        propeller_diameter: Option<f64>,
    }
    vehicle
        .particulars::<Propeller>("")
        .ok()?
        .propeller_diameter
        .filter(|d| d.is_finite() && *d > 0.0)
}

/// A quantity as messages name it: `r (column 'r' (9), read in deg/s)`, or the key alone
/// for a channel made in memory.
pub(crate) fn named(rec: &Record, q: Quantity) -> String {
    let unit = rec
        .units
        .get(&q)
        .map(|u| format!(", read in {u}"))
        .unwrap_or_default();
    match rec.columns.get(&q) {
        Some(c) => format!("{q} ({c}{unit})"),
        None => q.key().to_string(),
    }
}

/// The file of a run, as messages name it (its file name).
pub(crate) fn file(rec: &Record) -> String {
    rec.source.file_name().map_or_else(
        || rec.source.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    )
}

/// The advance ratios J = U (1 - w) / (n D) a propeller driving its vehicle works at: about
/// 0.1 (a tug, a slow turn) to 1.5 (a lightly loaded fast propeller) (Carlton 2012, Marine
/// Propellers and Propulsion, ch. 6).
pub const WORKING_ADVANCE: (f64, f64) = (0.1, 1.5);

/// What an advance ratio `j` outside [`WORKING_ADVANCE`] means: a propeller speed 60 times
/// too large (rpm read as rev/s) makes J 60 times too small, and the reverse. (clear, the
/// meaning): clear when a factor of 60 brings J into the range; None when J is inside.
pub fn propeller_unit(j: f64) -> Option<(bool, &'static str)> {
    let inside = |x: f64| (WORKING_ADVANCE.0..=WORKING_ADVANCE.1).contains(&x);
    if inside(j) {
        None
    } else if inside(60.0 * j) {
        Some((
            true,
            "the propeller speed looks like rpm read as rev/s (rps): give `unit = \"rpm\"` in \
             the rpm column entry",
        ))
    } else if inside(j / 60.0) {
        Some((
            true,
            "the propeller speed looks like rev/s (rps) read as rpm: give `unit = \"rps\"` in \
             the rpm column entry",
        ))
    } else {
        Some((
            false,
            "no factor of 60 makes it plausible: check the propeller speed's unit and the \
             vehicle's propeller_diameter",
        ))
    }
}

/// Standard gravity, m/s^2 (Froude numbers).
pub const G: f64 = 9.80665;

/// The Froude number U / sqrt(g L) the model's example runs at (its example state's speed on
/// its example vehicle): the speed-length ratio the model is made for. None when the
/// example state has no forward speed.
pub fn model_froude<M: Model>(model: &M) -> Option<f64> {
    let example = model.example();
    let at = |q: Quantity| {
        model
            .state_index(q)
            .and_then(|i| example.state.get(i).copied())
            .unwrap_or(0.0)
    };
    let speed = at(Quantity::U)
        .hypot(at(Quantity::V))
        .hypot(at(Quantity::W));
    let length = M::example_vehicle().length;
    (speed > 0.0 && length > 0.0).then(|| speed / (G * length).sqrt())
}

/// Quantities with identical values: one column mapped to several quantities (each group
/// named once; control surfaces commanded together are a manoeuvre, not a mistake).
pub(crate) fn identical_channels(rec: &Record, stage: &str) -> Vec<Finding> {
    let chans: Vec<(&Quantity, &Vec<f64>)> = rec
        .channels
        .iter()
        .filter(|(q, v)| **q != Quantity::Time && v.iter().any(|x| *x != v[0]))
        .collect();
    // groups of identical channels, each named once
    let mut seen = vec![false; chans.len()];
    let mut out = Vec::new();
    for i in 0..chans.len() {
        if seen[i] {
            continue;
        }
        let group: Vec<&Quantity> = (i..chans.len())
            .filter(|&j| chans[j].1 == chans[i].1)
            .inspect(|&j| seen[j] = true)
            .map(|j| chans[j].0)
            .collect();
        // control surfaces commanded together (the helix of Mousavian et al. 2015 steps
        // rudder and stern planes to the same angle) are a manoeuvre, not a mapping mistake
        let commanded = group.iter().all(|q| is_control(**q)) && piecewise_constant(chans[i].1);
        if group.len() > 1 && !commanded {
            let names = group.iter().map(|q| q.key()).collect::<Vec<_>>().join(", ");
            out.push(Finding::of(
                stage,
                &rec.name,
                true,
                format!(
                    "{names} hold identical values in all {} rows",
                    chans[i].1.len()
                ),
                format!(
                    "one column is almost certainly mapped to several quantities; check the \
                     run's `columns` for {names}"
                ),
            ));
        }
    }
    out
}

/// Control inputs a manoeuvre may command to identical values.
fn is_control(q: Quantity) -> bool {
    matches!(
        q,
        Quantity::Rudder
            | Quantity::SternPlanes
            | Quantity::BowPlanes
            | Quantity::Rpm
            | Quantity::Thrust
    )
}

/// A series that changes in at most one sample in ten (steps, not a measured signal).
fn piecewise_constant(v: &[f64]) -> bool {
    let changes = v.windows(2).filter(|w| w[1] != w[0]).count();
    changes * 10 <= v.len()
}

/// The median of `v` (the upper of the two middle values of an even count; None when empty).
pub(crate) fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// The median of the finite values of an iterator.
pub(crate) fn median_of(v: impl IntoIterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = v.into_iter().filter(|x| x.is_finite()).collect();
    median(&mut v)
}
