//! What the diagnosis of a captive table ([`super::diagnosis`]) says: the unit factors a
//! force may carry, each correction's mistake and fix with the configuration key to set, and
//! the finding that names them.

use super::diagnosis::{
    Explanation, Fix, Judge, DEG, FROUDE_RANGE, MAX_RUDDER, MIN_RUDDER, SPEEDS,
};
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use crate::model::models::Model;
use crate::stages::plausible::{Finding, WORKING_ADVANCE};
use std::collections::BTreeMap;

/// A factor a measured force carries: read / true, and the mistake in words.
#[derive(Debug, Clone)]
pub(super) struct Factor {
    pub gain: f64,
    pub words: String,
}

/// SI per `unit`, from the unit table every input is read with (base/units.rs), so that the
/// unit each message advises is one a configuration takes.
fn si_per(unit: &str) -> f64 {
    crate::base::units::Unit::parse(unit).map_or(f64::NAN, |u| u.factor)
}

/// Unit factors per force (the first [`UNITS`] of [`factors`]).
const UNITS: usize = 5;

/// The factors a measured component `q` may carry: units (kgf, kN, lbf read as N, and the
/// reverse), then, of a prime table with the configured area `prime_area`, each other
/// normalisation area in `areas` (the forces are then A_configured / A_table times the true).
pub(super) fn factors(
    q: Quantity,
    areas: &[(f64, String)],
    prime_area: Option<f64>,
) -> Vec<Factor> {
    let f = |gain: f64, words: &str| Factor {
        gain,
        words: words.to_string(),
    };
    let (kgf, lbf, lbf_ft) = (si_per("kgf"), si_per("lbf"), si_per("lbf ft"));
    let mut out = if q == Quantity::Mz || q == Quantity::Mx || q == Quantity::My {
        vec![
            f(1.0 / kgf, "kgf m read as N m: give `unit = \"kgf m\"`"),
            f(kgf, "N m read as kgf m: give `unit = \"N m\"`"),
            f(1e-3, "kN m read as N m: give `unit = \"kN m\"`"),
            f(
                1e3,
                "N mm read as N m (or N m read as kN m): give the moment's unit",
            ),
            f(1.0 / lbf_ft, "lbf ft read as N m: give `unit = \"lbf ft\"`"),
        ]
    } else {
        vec![
            f(1.0 / kgf, "kgf read as N: give `unit = \"kgf\"`"),
            f(kgf, "N read as kgf: give `unit = \"N\"`"),
            f(1e-3, "kN read as N: give `unit = \"kN\"`"),
            f(1e3, "N read as kN: give `unit = \"N\"`"),
            f(1.0 / lbf, "lbf read as N: give `unit = \"lbf\"`"),
        ]
    };
    debug_assert_eq!(out.len(), UNITS);
    if let Some(a) = prime_area {
        out.extend(areas.iter().map(|(alt, name)| {
            f(
                a / alt,
                &format!(
                    "the table looks normalised on {name} = {} m^2, not on captive.prime.area = \
                     {} m^2: give `area = \"{} m^2\"` in captive.prime",
                    num(*alt),
                    num(a),
                    num(*alt)
                ),
            )
        }));
    }
    out
}

/// Whether factor `k` of [`factors`] is a unit or a normalisation area.
pub(super) fn factor_kind(k: usize) -> &'static str {
    if k < UNITS {
        "unit"
    } else {
        "area"
    }
}

/// How the messages of one run name it: the run, its file, the key of its column entries,
/// the scale each column was read with, how its motion and forces are given, and the points
/// of the vehicle a moment may have been taken about.
#[derive(Debug, Clone, Default)]
pub(crate) struct Names {
    /// The run's name.
    pub run: String,
    /// Its file's name.
    pub file: String,
    /// The key of its column entries: `captive.runs[0].columns`.
    pub key: String,
    /// The `scale` of each mapped column.
    pub scales: BTreeMap<Quantity, f64>,
    /// The motion is given by speed and drift.
    pub by_speed: bool,
    /// The forces are prime columns.
    pub prime_forces: bool,
    /// The yaw rate is a prime column.
    pub prime_rate: bool,
    /// Named points of the body axis: (x m, what it is).
    pub points: Vec<(f64, String)>,
    /// The key of the run's prescribed oscillation (`captive.oscillations."pure sway"`),
    /// when its motion is the configuration's.
    pub oscillation: Option<String>,
}

impl Names {
    /// The column entry of `q`: `captive.runs[0].columns.fy`.
    fn entry(&self, q: Quantity) -> String {
        let key = match q {
            Quantity::Fx if self.prime_forces => "x_prime",
            Quantity::Fy if self.prime_forces => "y_prime",
            Quantity::Mz if self.prime_forces => "n_prime",
            Quantity::R if self.prime_rate => "r_prime",
            q => q.key(),
        };
        format!("{}.{key}", self.key)
    }

    /// `scale = -1` to give, or to take away when the column has it.
    fn sign_fix(&self, q: Quantity) -> String {
        if self.scales.get(&q).is_some_and(|s| *s < 0.0) {
            format!("remove `scale = -1` from {}", self.entry(q))
        } else {
            format!("give `scale = -1` in {}", self.entry(q))
        }
    }

    /// The velocities' entries: `u and v` or `speed`.
    fn velocity_entries(&self) -> String {
        if self.by_speed {
            self.entry(Quantity::Speed)
        } else {
            format!(
                "{} and {}",
                self.entry(Quantity::U),
                self.entry(Quantity::V)
            )
        }
    }
}

/// A correction's mistake and fix in words.
pub(super) fn fix_words(fix: Fix, names: &Names, length: f64) -> String {
    match fix {
        Fix::RudderSign => format!(
            "the rudder angle has the opposite sign convention to the model's (a rudder \
             positive to port, or to starboard where the model's turns to port): {}",
            names.sign_fix(Quantity::Rudder)
        ),
        Fix::RudderUnit(f) | Fix::RpmUnit(f) | Fix::RateUnit(f) => unit_words(fix, f, names),
        Fix::Speed(k) => format!(
            "the velocities look like {}: give `unit = \"{}\"` in {}",
            SPEEDS[k].1,
            SPEEDS[k].2,
            names.velocity_entries()
        ),
        Fix::SwapFyMz => format!(
            "fy and mz look swapped (the column mapped to fy holds the yaw moment, the one \
             mapped to mz the sway force): exchange the columns of {} and {}",
            names.entry(Quantity::Fy),
            names.entry(Quantity::Mz)
        ),
        Fix::Flip(q @ Quantity::V) => format!(
            "v has the opposite sign convention (or the drift angle: beta = -atan(v / u), \
             positive drift moves the vehicle to port): {}",
            names.sign_fix(if names.by_speed { Quantity::Drift } else { q })
        ),
        Fix::Flip(q) => format!(
            "{q} has the opposite sign convention (positive to port): {}",
            names.sign_fix(q)
        ),
        Fix::Centre(x) => centre_words(x, names, length),
    }
}

/// A unit mix-up of the rudder, the propeller speed or the yaw rate (`f` read / true) in
/// words: each mixes two units, the first the true one when `f` is above 1.
fn unit_words(fix: Fix, f: f64, names: &Names) -> String {
    let (q, what, a, b) = match fix {
        Fix::RudderUnit(_) => (
            Quantity::Rudder,
            "the rudder angle",
            ("degrees", "deg"),
            ("radians", "rad"),
        ),
        Fix::RpmUnit(_) => (
            Quantity::Rpm,
            "the propeller speed",
            ("rpm", "rpm"),
            ("rev/s (rps)", "rps"),
        ),
        _ => (
            Quantity::R,
            "the yaw rate",
            ("deg/s", "deg/s"),
            ("rad/s", "rad/s"),
        ),
    };
    let (truth, read) = if f > 1.0 { (a, b) } else { (b, a) };
    format!(
        "{what} looks like {} read as {}: give `unit = \"{}\"` in {}",
        truth.0,
        read.0,
        truth.1,
        names.entry(q)
    )
}

/// The moment taken about another point than the origin.
fn centre_words(x: f64, names: &Names, length: f64) -> String {
    let known = names
        .points
        .iter()
        .filter(|(p, _)| (p - x).abs() <= 0.05 * length)
        .map(|(p, what)| format!(", at {what} (x = {} m)", num(*p)))
        .next()
        .unwrap_or_default();
    format!(
        "the yaw moment looks taken about a point {} m {} of the model's origin (x = {} m, {} \
         L{known}), not about the origin the model's moment is about: give the moment about \
         the origin in {}, N = N_x + x F_y with x = {} m (the moment about x is N - x F_y)",
        num(x.abs()),
        if x < 0.0 { "aft" } else { "forward" },
        num(x),
        num(x / length),
        names.entry(Quantity::Mz),
        num(x)
    )
}

/// The evidence of an explanation in words: each judged force's correlation with the
/// model's and (with `sized`) its gain, and what is outside its range.
fn evidence_words<M: Model>(judge: &Judge<M>, e: &Explanation, factors: bool) -> String {
    let forces = judge.model.force_quantities();
    let mut parts: Vec<String> = judge
        .judged()
        .iter()
        .zip(&e.evidence.fits)
        .zip(&e.factors)
        .filter_map(|((&i, fit), factor)| {
            let (cos, gain) = (*fit)?;
            let size = if judge.sizes_known {
                let f = factor
                    .filter(|_| factors)
                    .map(|k| factors_of(judge, forces[i])[k].gain)
                    .unwrap_or(1.0);
                format!(", {} times its size", num(gain / f))
            } else {
                String::new()
            };
            Some(format!("{} correlation {cos:.2}{size}", forces[i].key()))
        })
        .collect();
    if let Some(j) = e.evidence.advance {
        if j < WORKING_ADVANCE.0 || j > WORKING_ADVANCE.1 {
            parts.push(format!(
                "advance ratio J = u (1 - w) / (n D) {} (a working propeller: {} to {})",
                num(j),
                WORKING_ADVANCE.0,
                WORKING_ADVANCE.1
            ));
        }
    }
    if let Some(fr) = e.evidence.froude {
        let far = |m: f64| (fr / m).ln().abs() > 2f64.ln();
        let outside = fr < FROUDE_RANGE.0 || fr > FROUDE_RANGE.1;
        let speed = e.fixes.iter().any(|f| matches!(f, Fix::Speed(_)));
        if outside || speed || judge.froude_model.is_some_and(far) {
            let model = judge
                .froude_model
                .map(|m| format!(" (the model's example: {})", num(m)))
                .unwrap_or_default();
            parts.push(format!("Froude number U / sqrt(g L) {}{model}", num(fr)));
        }
    }
    if let Some(r) = e
        .evidence
        .rudder
        .filter(|r| *r > MAX_RUDDER || (*r > 0.0 && *r < MIN_RUDDER))
    {
        parts.push(format!("rudder angles up to {} deg", num(r * DEG)));
    }
    parts.join(", ")
}

/// The factors of component `q` the judge considers.
fn factors_of<M: Model>(judge: &Judge<M>, q: Quantity) -> Vec<Factor> {
    factors(q, &judge.areas, judge.prime_area)
}

/// The finding of a diagnosis: what the table shows against the model as read and, when an
/// explanation holds, under it, with its mistakes and fixes. Blocking when the table as read
/// is clearly wrong and the explanation clear. None when nothing is to be said (a table
/// not clearly wrong that no explanation fits: the fit's lack-of-fit test speaks).
pub(crate) fn finding<M: Model>(
    judge: &Judge<M>,
    names: &Names,
    read: &Explanation,
    best: Option<&Explanation>,
    wrong: bool,
) -> Option<Finding> {
    let against = format!(
        "in {}, against the forces the {} model gives for the table's motion at its \
         configured (else example) coefficients: {}",
        names.file,
        judge.model.name(),
        evidence_words(judge, read, false)
    );
    let Some(best) = best else {
        return wrong.then(|| {
            Finding::of(
                super::super::STAGE,
                &names.run,
                false,
                against,
                "no single mistake of units, signs, swapped columns or moment centre explains \
                 the table: check which columns are mapped, their units and sign conventions \
                 (the fitted coefficients would absorb the mistake)"
                    .to_string(),
            )
        });
    };
    let mut meaning: Vec<String> = best
        .fixes
        .iter()
        .map(|f| fix_words(*f, names, judge.length))
        .collect();
    meaning.extend(factor_words(judge, names, best));
    meaning.extend(motion_sign(judge, names, best));
    if meaning.is_empty() {
        return None;
    }
    let message = format!(
        "{against}; {} {}",
        if best.fixes.is_empty() {
            "with a unit factor"
        } else {
            "corrected"
        },
        evidence_words(judge, best, true)
    );
    let mut meaning = meaning.join("; ");
    meaning.push_str(". Every coefficient fitted from the table would carry the mistake");
    Some(Finding::of(
        super::super::STAGE,
        &names.run,
        wrong && best.clear,
        message,
        meaning,
    ))
}

/// The unit factors of an explanation in words, one sentence per distinct factor with the
/// components that carry it.
fn factor_words<M: Model>(judge: &Judge<M>, names: &Names, e: &Explanation) -> Vec<String> {
    let forces = judge.model.force_quantities();
    let mut by_words: Vec<(String, Vec<String>)> = Vec::new();
    for (&i, factor) in judge.judged().iter().zip(&e.factors) {
        let Some(k) = factor else { continue };
        let words = factors_of(judge, forces[i])[*k].words.clone();
        // a normalisation area is the table's, not a column's
        let entry = (factor_kind(*k) == "unit").then(|| names.entry(forces[i]));
        match by_words.iter_mut().find(|(w, _)| *w == words) {
            Some((_, entries)) => entries.extend(entry),
            None => by_words.push((words, entry.into_iter().collect())),
        }
    }
    by_words
        .into_iter()
        .map(|(words, entries)| {
            if entries.is_empty() {
                words
            } else {
                format!("{} looks like {words}", entries.join(" and "))
            }
        })
        .collect()
}

/// Of a run whose motion is the configuration's, every lateral force of the other sign is
/// also the prescribed motion of the other sign (the forces of a pure sway or yaw run are
/// odd in its motion): the amplitude's sign or a phase 180 deg off, named as the other
/// possible cause.
fn motion_sign<M: Model>(judge: &Judge<M>, names: &Names, e: &Explanation) -> Option<String> {
    let key = names.oscillation.as_ref()?;
    let forces = judge.model.force_quantities();
    let lateral: Vec<Quantity> = judge.judged().iter().map(|&i| forces[i]).collect();
    let every = lateral.len() > 1
        && e.fixes.len() == lateral.len()
        && lateral.iter().all(|q| e.fixes.contains(&Fix::Flip(*q)));
    every.then(|| {
        format!(
            "or, as every lateral force changes sign together, the prescribed motion has the \
             opposite sign: check the amplitude's sign and the phase in {key} (a phase off by \
             180 deg)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every unit a factor's message advises is one the unit table reads, and its gain is that
    /// unit's (lbf was advised before the table knew it).
    #[test]
    fn each_advised_unit_is_read_by_the_unit_table() {
        for q in [Quantity::Fy, Quantity::Mz] {
            for f in factors(q, &[], None) {
                let Some(at) = f.words.find("`unit = \"") else {
                    continue;
                };
                let unit = f.words[at + 9..].split('"').next().unwrap();
                let parsed = crate::base::units::Unit::parse(unit);
                assert!(parsed.is_ok(), "{unit}: {parsed:?}");
            }
        }
        assert!((1.0 / factors(Quantity::Fy, &[], None)[4].gain - 4.448_221_615).abs() < 1e-9);
        assert!((1.0 / factors(Quantity::Mz, &[], None)[4].gain - 1.355_817_948).abs() < 1e-9);
    }
}
