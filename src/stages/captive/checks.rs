//! The plausibility checks of a captive table as the stage runs them: the model's expectation
//! of the forces, how messages name a run's columns, and the checks of one table against its
//! own data and the model ([`plausibility::table`], [`plausibility::diagnosis`]).

use super::fit::Condition;
use super::{plausibility, prepare, reference_of, CaptiveConfig, View};
use crate::base::error::Error;
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::io::record::Record;
use crate::model::models::{with_model, Model, ModelVisitor, RunVehicle, Vehicle};
use crate::stages::plausible::{Expectation, Finding};
use plausibility::{Judge, Names, Origin};

/// Fewest steady rows the model's view of a table is judged on (a harmonic run: one
/// condition of many Fourier parts).
const MIN_ROWS: usize = 5;

/// The model's expectation: the configured (or known) values, the model's example values
/// elsewhere. A configured value of an estimated coefficient below a tenth of its typical
/// magnitude (`Yv_p = 0` as the start of a fit) is a placeholder, not a size.
pub(super) fn expectation<M: Model>(model: &M, cfg: &CaptiveConfig, view: &View) -> Expectation {
    let given = |n: &str| {
        let estimated = cfg.estimate.iter().any(|e| e == n);
        (view.expected)(n)
            .filter(|v| !estimated || v.abs() >= 0.1 * model.typical_magnitude(n) || v.is_nan())
    };
    Expectation::new(model, &given, view.vehicle)
}

/// The judge of the tables: the expectation, whether its sizes carry over (its example
/// values are non-dimensional, or the vehicle is the model's example vehicle), the
/// propeller, the model's Froude number and the areas a prime table may be normalised on.
pub(super) fn judge<'a, M: Model>(
    model: &'a M,
    cfg: &CaptiveConfig,
    view: &View,
    expectation: &'a Expectation,
) -> Judge<'a, M> {
    let example = M::example_vehicle();
    let near = |a: f64, b: f64| (a / b - 1.0).abs() < 0.01;
    let same_vehicle =
        near(view.vehicle.length, example.length) && near(view.vehicle.mass, example.mass);
    Judge {
        model,
        coefficients: &expectation.coefficients,
        sizes_known: expectation.sizes_known || same_vehicle,
        length: view.reference.length,
        propeller: expectation
            .propeller_diameter
            .map(|d| (d, expectation.wake)),
        froude_model: expectation.froude_model,
        areas: cfg
            .prime
            .map(|p| areas(p.length, p.area, view))
            .unwrap_or_default(),
        prime_area: cfg.prime.map(|p| p.area),
        prime_length_wrong: cfg.prime.is_some_and(|p| {
            plausibility::table::prime_length(p.length, view.reference.length)
                .is_some_and(|f| f.blocking)
        }),
    }
}

/// The normalisation areas a prime table may have been made with other than the configured
/// `area`: L^2 (the Abkowitz prime system), L d (the MMG method), L D, the frontal area
/// pi D^2 / 4 and the displacement's volume^(2/3), with `length` the prime system's.
fn areas(length: f64, area: f64, view: &View) -> Vec<(f64, String)> {
    let v = view.vehicle;
    let mut out = vec![(length * length, "L^2".to_string())];
    if let Some(d) = draught(v) {
        out.push((length * d, "L d (the draught)".to_string()));
    }
    if let Some(d) = v.diameter {
        out.push((length * d, "L D (the diameter)".to_string()));
        out.push((
            std::f64::consts::PI * d * d / 4.0,
            "the frontal area pi D^2 / 4".to_string(),
        ));
    }
    out.push((
        (v.mass / v.rho).powf(2.0 / 3.0),
        "the displacement volume^(2/3)".to_string(),
    ));
    out.retain(|(a, _)| (a / area - 1.0).abs() > 0.1);
    out
}

/// A length of `vehicle.particulars` (a number in m or a string with a unit).
fn particular(v: &Vehicle, key: &str) -> Option<f64> {
    #[derive(serde::Deserialize)]
    struct Length(
        #[serde(deserialize_with = "crate::base::si::value::<_, crate::base::si::Length>")] f64,
    );
    let value = v.particulars.get(key)?.clone();
    value.try_into::<Length>().ok().map(|l| l.0)
}

fn draught(v: &Vehicle) -> Option<f64> {
    particular(v, "draught").filter(|d| *d > 0.0)
}

/// How messages name run `index` read into `rec`.
pub(super) fn names(rec: &Record, index: usize, vehicle: &Vehicle) -> Names {
    let points = [
        (
            "rudder_x",
            "the rudder stock (vehicle.particulars.rudder_x)",
        ),
        ("x_g", "the centre of gravity (vehicle.particulars.x_g)"),
        (
            "propeller_x",
            "the propeller (vehicle.particulars.propeller_x)",
        ),
    ]
    .into_iter()
    .filter_map(|(k, what)| Some((particular(vehicle, k)?, what.to_string())))
    .collect();
    let prime = [Quantity::XPrime, Quantity::YPrime, Quantity::NPrime];
    Names {
        run: rec.name.clone(),
        file: crate::stages::plausible::file(rec),
        key: format!("captive.runs[{index}].columns"),
        scales: rec.columns.iter().map(|(q, c)| (*q, c.scale)).collect(),
        by_speed: rec.has(Quantity::Drift),
        prime_forces: prime.iter().any(|q| rec.has(*q)) && !rec.has(Quantity::Fy),
        prime_rate: !rec.has(Quantity::R) && rec.has(Quantity::RPrime),
        points,
        oscillation: None,
    }
}

/// The checks of one table beyond the slender-body windows: two quantities on one column, a
/// drift angle in the wrong unit, forces that do not respond to the motion, and the model's
/// view of the table (its mistake named). Empty when the table is plausible; and whether
/// one of them names the table's mistake (a prime length found wrong explains a prime
/// table; a model's view that no correction explains names none: the windows may still).
pub(super) fn examine<M: Model>(
    judge: &Judge<M>,
    names: &Names,
    rec: &Record,
    conditions: &[Condition],
    est: &[usize],
) -> (Vec<Finding>, bool) {
    // with the prime length wrong, every prime column is read wrong: that finding says it
    if (names.prime_forces || names.prime_rate) && judge.prime_length_wrong {
        return (Vec::new(), true);
    }
    let mut out = crate::stages::plausible::identical_channels(rec, super::STAGE);
    out.extend(plausibility::table::drift_unit(rec, names));
    if !out.is_empty() {
        return (out, true);
    }
    let harmonic = conditions.iter().any(|c| c.harmonic.is_some());
    if !harmonic && conditions.len() < MIN_ROWS {
        return (out, false);
    }
    if let Some(f) = plausibility::table::unresponsive(judge, conditions, est, names) {
        out.push(f);
        return (out, true);
    }
    let origin = Origin {
        prime_forces: names.prime_forces,
        prime_rate: names.prime_rate,
    };
    let Some((read, best, wrong)) = judge.diagnose(conditions, origin) else {
        return (out, false);
    };
    let found = plausibility::words::finding(judge, names, &read, best.as_ref(), wrong);
    let explained = best.is_some() && found.is_some();
    out.extend(found);
    (out, explained)
}

/// What [`preflight`] found: the first problem that stops the stage, the clear mistakes of
/// its tables (each stops the run unless `captive.checks = "warn"`), and the warnings of the
/// plausibility checks (the stage repeats them with its result).
#[derive(Debug, Default)]
pub struct Preflight {
    /// The stage would stop here.
    pub error: Option<Error>,
    /// Clear mistakes of the tables, as messages (with `captive.checks = "error"`).
    pub problems: Vec<String>,
    /// The plausibility checks' warnings.
    pub warnings: Vec<Warning>,
}

/// The checks of the stage that need the runs but no fit (`prepare`), for `hydroid check`
/// and `hydroid run` before any stage runs. `available` names the coefficients the
/// configuration and the stages before this one will provide (the fit holds every
/// coefficient it does not estimate at one of those), `configured` the configuration's
/// values (the plausibility checks compare the tables with the model at them).
pub fn preflight(
    cfg: &CaptiveConfig,
    vehicle: &RunVehicle,
    available: &[String],
    configured: &std::collections::BTreeMap<String, f64>,
    runs: &[&Record],
) -> Preflight {
    struct Check<'a> {
        cfg: &'a CaptiveConfig,
        runs: &'a [&'a Record],
        vehicle: &'a Vehicle,
        available: &'a [String],
        configured: &'a std::collections::BTreeMap<String, f64>,
    }
    impl ModelVisitor for Check<'_> {
        type Output = Preflight;
        fn visit<M: Model>(self, model: &M) -> Preflight {
            // only whether a value exists matters before the fit
            let known = |n: &str| self.available.iter().any(|a| a == n).then_some(0.0);
            let expected = |n: &str| self.configured.get(n).copied();
            let view = View {
                vehicle: self.vehicle,
                reference: reference_of(self.vehicle),
                expected: &expected,
            };
            let prepared = match prepare(model, self.cfg, self.runs, &view, &known) {
                Ok(p) => p,
                Err(e) => {
                    return Preflight {
                        error: Some(e),
                        ..Preflight::default()
                    }
                }
            };
            let mut out = Preflight {
                warnings: prepared.warnings,
                ..Preflight::default()
            };
            for f in prepared.findings {
                match f.sorted(self.cfg.checks, "captive.checks") {
                    Ok(w) => out.warnings.push(w),
                    Err(problem) => out.problems.push(problem),
                }
            }
            out
        }
    }
    let check = Check {
        cfg,
        runs,
        vehicle: &vehicle.vehicle,
        available,
        configured,
    };
    // a model the vehicle cannot build is the configuration's problem, reported by its
    // validation ([`CaptiveConfig::validate`])
    with_model(cfg.model, vehicle, check).unwrap_or_default()
}
