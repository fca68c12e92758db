//! The model's view of a captive table: the forces the model gives for the table's motion at
//! its expected coefficients (the configured values, the model's example values elsewhere:
//! [`crate::stages::plausible::Expectation`]) against the measured ones. When they disagree,
//! the mistakes a user makes with a captive table are each tried as a correction of the table
//! (the rudder's sign or unit, rpm and rev/s, a velocity or yaw-rate unit, Fy and Mz swapped,
//! a sign convention, the moment about another point) together with the unit factors a force
//! may carry (kgf, kN, a prime table's normalisation area), and the one that makes the model's
//! forces match the measured ones is named (docs/stages.md, "Captive plausibility").
//!
//! Each correction is judged by the evidence of the whole table: the correlation of each
//! lateral force with the model's (its shape: a sign, a swap, a rudder unit change it), its
//! gain against the model's (a unit: only where the model's sizes carry over to the vehicle),
//! the propeller's advance ratio J = u (1 - w) / (n D) against the working range (Carlton
//! 2012, ch. 6), the Froude number U / sqrt(g L) against the model's and the largest rudder
//! angle against 45 deg. The correction of least cost among those under which the table is
//! plausible is named; none when the table is plausible as read.

use super::words;
use crate::base::quantity::Quantity;
use crate::model::models::Model;
use crate::stages::captive::fit::Condition;
use crate::stages::captive::harmonic::PER_FORCE;
use crate::stages::plausible::{median_of, G, WORKING_ADVANCE};

/// Degrees per radian.
pub(super) const DEG: f64 = 180.0 / std::f64::consts::PI;

/// Largest rudder angle a table may hold (rad): beyond it a unit is wrong.
pub(super) const MAX_RUDDER: f64 = 45.0 / DEG;

/// Smallest largest rudder angle of a table whose rudder moves (rad): a rudder test turns
/// it by degrees, so one that reaches less than 1 deg is in radians read as degrees.
pub(super) const MIN_RUDDER: f64 = 1.0 / DEG;

/// The correlation of a force with the model's above which its shape agrees ...
const COS_OK: f64 = 0.9;
/// ... and above which a correction is clear.
const COS_CLEAR: f64 = 0.97;
/// The gain of a force over the model's (after its unit factor) within this factor agrees ...
const GAIN_OK: f64 = 1.6;
/// ... and within this one a correction is clear.
const GAIN_CLEAR: f64 = 1.3;
/// The table as read is clearly wrong when a force's correlation is below this ...
const COS_WRONG: f64 = 0.95;
/// Unexplained, a table is said wrong when a force's correlation is below this ...
const COS_UNEXPLAINED: f64 = 0.8;
/// ... or its gain off by more than this factor.
const GAIN_WRONG: f64 = 3.0;
/// The cost of naming one more mistake (a simpler explanation is preferred).
const PENALTY: f64 = 0.02;
/// How much lower the cost of an explanation must be than the table's as read to be named.
const MARGIN: f64 = 0.05;
/// Weight of the Froude number's distance from the model's in the cost (a weak hint: a
/// vehicle may run faster or slower than the model's example).
const FROUDE_WEIGHT: f64 = 0.25;
/// The Froude numbers a captive run may have (outside: a speed unit).
pub(super) const FROUDE_RANGE: (f64, f64) = (0.01, 1.0);

/// A velocity unit read as m/s (or m/s read as it): the factor read / true, the mistake and
/// the unit to give.
pub(super) const SPEEDS: [(f64, &str, &str); 6] = [
    (3.6, "km/h read as m/s", "km/h"),
    (100.0, "cm/s read as m/s", "cm/s"),
    (1000.0, "mm/s read as m/s", "mm/s"),
    (3600.0 / 1852.0, "knots read as m/s", "kn"),
    (1.0 / 3.6, "m/s read as km/h", "m/s"),
    (1852.0 / 3600.0, "m/s read as knots", "m/s"),
];

/// A mistake of a table, undone by [`Fix::apply`]. Unit factors are read / true.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Fix {
    /// The rudder angle of the opposite sign convention.
    RudderSign,
    /// The rudder read in the wrong angle unit (1 / 57.3: radians read as degrees).
    RudderUnit(f64),
    /// The propeller speed in the wrong unit (60: rpm read as rev/s).
    RpmUnit(f64),
    /// The velocities in the wrong unit ([`SPEEDS`]).
    Speed(usize),
    /// The yaw rate in the wrong unit (1 / 57.3: rad/s read as deg/s).
    RateUnit(f64),
    /// The sway force and the yaw moment in each other's columns.
    SwapFyMz,
    /// A quantity of the opposite sign convention.
    Flip(Quantity),
    /// The moment taken about the point x (m) of the body axis instead of the origin.
    Centre(f64),
}

/// What the diagnosis knows of the model, the vehicle and the table's columns.
pub(crate) struct Judge<'a, M: Model> {
    /// The model.
    pub model: &'a M,
    /// Its expected coefficient vector, completed by the relations.
    pub coefficients: &'a [f64],
    /// Whether the sizes of its forces carry over to this vehicle.
    pub sizes_known: bool,
    /// The vehicle's length, m.
    pub length: f64,
    /// The propeller's diameter (m) and wake fraction, when known.
    pub propeller: Option<(f64, f64)>,
    /// The Froude number of the model's example ([`crate::stages::plausible::model_froude`]).
    pub froude_model: Option<f64>,
    /// The normalisation areas a prime table may have been made with, other than the
    /// configured one: (area m^2, in words).
    pub areas: Vec<(f64, String)>,
    /// The configured normalisation area of prime tables, m^2.
    pub prime_area: Option<f64>,
    /// The prime system's length is clearly wrong (its own finding says so).
    pub prime_length_wrong: bool,
}

/// Where a table's forces and rate come from.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Origin {
    /// The forces are prime columns times 0.5 rho A U^2 (and L): a speed unit scales them.
    pub prime_forces: bool,
    /// The yaw rate is r' U / L: a speed unit scales it.
    pub prime_rate: bool,
}

/// The evidence of a table (as read, or corrected).
#[derive(Debug, Clone)]
pub(crate) struct Evidence {
    /// Per judged force component: its correlation with the model's and its gain over it
    /// (None: no signal).
    pub fits: Vec<Option<(f64, f64)>>,
    /// The median advance ratio.
    pub advance: Option<f64>,
    /// The median Froude number.
    pub froude: Option<f64>,
    /// The largest rudder angle, rad.
    pub rudder: Option<f64>,
}

/// An explanation: the corrections, the evidence under them, the unit factor of each judged
/// component (index into [`words::factors`], None: 1) and the cost.
#[derive(Debug, Clone)]
pub(crate) struct Explanation {
    pub fixes: Vec<Fix>,
    pub evidence: Evidence,
    pub factors: Vec<Option<usize>>,
    pub cost: f64,
    pub holds: bool,
    pub clear: bool,
}

impl<M: Model> Judge<'_, M> {
    /// Index of a state, an input, a force.
    fn state(&self, q: Quantity) -> Option<usize> {
        self.model.state_index(q)
    }

    fn input(&self, q: Quantity) -> Option<usize> {
        self.model.input_quantities().iter().position(|x| *x == q)
    }

    pub(super) fn force(&self, q: Quantity) -> Option<usize> {
        self.model.force_quantities().iter().position(|x| *x == q)
    }

    /// The force components judged: all but the surge force when there are others (its
    /// net of thrust and resistance is a small difference the model's example cannot know).
    pub(super) fn judged(&self) -> Vec<usize> {
        let forces = self.model.force_quantities();
        let all: Vec<usize> = (0..forces.len()).collect();
        let lateral: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&i| forces[i] != Quantity::Fx)
            .collect();
        if lateral.is_empty() {
            all
        } else {
            lateral
        }
    }

    /// The corrections worth trying on `table`: those whose quantity the table has and moves.
    fn fixes(&self, table: &[Condition]) -> Vec<Fix> {
        let moves = |i: Option<usize>, f: &dyn Fn(&Condition, usize) -> f64| {
            i.is_some_and(|i| table.iter().any(|c| f(c, i) != 0.0))
        };
        let input = |c: &Condition, i: usize| c.u[i];
        let steady = table.iter().all(|c| c.harmonic.is_none());
        let state = |c: &Condition, i: usize| if steady { c.x[i] } else { 0.0 };
        let mut out = Vec::new();
        if moves(self.input(Quantity::Rudder), &input) {
            out.extend([
                Fix::RudderSign,
                Fix::RudderUnit(1.0 / DEG),
                Fix::RudderUnit(DEG),
            ]);
        }
        if moves(self.input(Quantity::Rpm), &input) {
            out.extend([Fix::RpmUnit(60.0), Fix::RpmUnit(1.0 / 60.0)]);
        }
        // a harmonic run's motion is prescribed (its amplitude's own check judges it)
        if self.state(Quantity::U).is_some() && steady {
            out.extend((0..SPEEDS.len()).map(Fix::Speed));
        }
        if moves(self.state(Quantity::R), &state) {
            out.extend([
                Fix::RateUnit(1.0 / DEG),
                Fix::RateUnit(DEG),
                Fix::Flip(Quantity::R),
            ]);
        }
        if moves(self.state(Quantity::V), &state) {
            out.push(Fix::Flip(Quantity::V));
        }
        let (fy, mz) = (self.force(Quantity::Fy), self.force(Quantity::Mz));
        if fy.is_some() && mz.is_some() {
            out.push(Fix::SwapFyMz);
            if self.sizes_known {
                out.push(Fix::Centre(0.0));
            }
        }
        out.extend(
            [Quantity::Fy, Quantity::Mz]
                .into_iter()
                .filter(|q| self.force(*q).is_some())
                .map(Fix::Flip),
        );
        out
    }

    /// `table` with `fix` undone (None when it does not apply); a [`Fix::Centre`] finds its
    /// point by least squares.
    fn apply(
        &self,
        fix: Fix,
        table: &[Condition],
        origin: Origin,
    ) -> Option<(Fix, Vec<Condition>)> {
        if let Fix::Centre(_) = fix {
            let x = self.centre(table)?;
            let fixed = table
                .iter()
                .map(|c| self.apply_one(Fix::Centre(x), c, origin))
                .collect::<Option<_>>()?;
            return Some((Fix::Centre(x), fixed));
        }
        let fixed = table
            .iter()
            .map(|c| self.apply_one(fix, c, origin))
            .collect::<Option<Vec<_>>>()?;
        Some((fix, fixed))
    }

    /// One condition with `fix` undone.
    fn apply_one(&self, fix: Fix, c: &Condition, origin: Origin) -> Option<Condition> {
        let mut c = c.clone();
        let nf = self.model.force_quantities().len();
        let per = if c.harmonic.is_some() { PER_FORCE } else { 1 };
        let forces = |c: &mut Condition, i: usize, f: &dyn Fn(f64) -> f64| {
            for v in &mut c.f[i * per..(i + 1) * per] {
                *v = f(*v);
            }
        };
        match fix {
            Fix::RudderSign => c.u[self.input(Quantity::Rudder)?] *= -1.0,
            Fix::RudderUnit(f) => c.u[self.input(Quantity::Rudder)?] /= f,
            Fix::RpmUnit(f) => c.u[self.input(Quantity::Rpm)?] /= f,
            Fix::Speed(k) => {
                let k = SPEEDS[k].0;
                for q in [Quantity::U, Quantity::V, Quantity::W] {
                    if let Some(i) = self.state(q) {
                        scale_state(&mut c, i, 1.0 / k);
                    }
                }
                if origin.prime_rate {
                    scale_state(&mut c, self.state(Quantity::R)?, 1.0 / k);
                }
                if origin.prime_forces {
                    (0..nf).for_each(|i| forces(&mut c, i, &|v| v / (k * k)));
                }
            }
            Fix::RateUnit(f) => {
                c.harmonic.is_none().then_some(())?;
                c.x[self.state(Quantity::R)?] /= f;
            }
            Fix::Flip(q @ (Quantity::V | Quantity::R)) => {
                c.harmonic.is_none().then_some(())?;
                c.x[self.state(q)?] *= -1.0;
            }
            Fix::Flip(q) => forces(&mut c, self.force(q)?, &|v| -v),
            Fix::SwapFyMz => {
                let (a, b) = (self.force(Quantity::Fy)?, self.force(Quantity::Mz)?);
                // prime columns swapped: the force was multiplied by L, the moment not
                let l = if origin.prime_forces {
                    self.length
                } else {
                    1.0
                };
                for k in 0..per {
                    let (fa, fb) = (c.f[a * per + k], c.f[b * per + k]);
                    c.f[a * per + k] = fb / l;
                    c.f[b * per + k] = fa * l;
                }
            }
            Fix::Centre(x) => {
                let (a, b) = (self.force(Quantity::Fy)?, self.force(Quantity::Mz)?);
                for k in 0..per {
                    c.f[b * per + k] += x * c.f[a * per + k];
                }
            }
        }
        Some(c)
    }

    /// The point x (m) about which the table's moment is taken: mz = a N_model + b fy by
    /// least squares, x = -b (the moment about x is N - x F_y); None when the model's
    /// moment and the measured sway force cannot be told apart.
    fn centre(&self, table: &[Condition]) -> Option<f64> {
        let (a, b) = (self.force(Quantity::Fy)?, self.force(Quantity::Mz)?);
        let (mut spp, mut spf, mut sff, mut smp, mut smf) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for c in table {
            let p = self.predict(c);
            let per = if c.harmonic.is_some() { PER_FORCE } else { 1 };
            for k in 0..per {
                let (pm, fy, mz) = (p[b * per + k], c.f[a * per + k], c.f[b * per + k]);
                spp += pm * pm;
                spf += pm * fy;
                sff += fy * fy;
                smp += mz * pm;
                smf += mz * fy;
            }
        }
        let det = spp * sff - spf * spf;
        if det <= 1e-9 * spp * sff || !det.is_finite() {
            return None;
        }
        let slope = (spp * smf - spf * smp) / det;
        Some(-slope).filter(|x| x.abs() >= 0.1 * self.length && x.abs() <= self.length)
    }

    /// The model's values of a condition at the expected coefficients.
    pub(super) fn predict(&self, c: &Condition) -> Vec<f64> {
        let mut out = vec![0.0; c.f.len()];
        c.predict(self.model, self.coefficients, &mut out);
        out
    }

    /// The evidence of a table.
    pub(super) fn evidence(&self, table: &[Condition]) -> Evidence {
        let nf = self.model.force_quantities().len();
        let (mut mp, mut pp, mut mm) = (vec![0.0; nf], vec![0.0; nf], vec![0.0; nf]);
        for c in table {
            let p = self.predict(c);
            for (k, (m, p)) in c.f.iter().zip(&p).enumerate() {
                let i = c.component(k);
                mp[i] += m * p;
                pp[i] += p * p;
                mm[i] += m * m;
            }
        }
        let fits = self
            .judged()
            .into_iter()
            .map(|i| {
                let ok = pp[i] > 0.0 && mm[i] > 0.0 && (mp[i] / pp[i]).is_finite();
                ok.then(|| (mp[i] / (pp[i] * mm[i]).sqrt(), mp[i] / pp[i]))
            })
            .collect();
        Evidence {
            fits,
            advance: self.advance(table),
            froude: self.froude(table),
            rudder: self
                .input(Quantity::Rudder)
                .map(|i| table.iter().fold(0.0f64, |a, c| a.max(c.u[i].abs()))),
        }
    }

    /// The forward speed and the velocity of a condition (its mean over a harmonic run).
    fn speeds(&self, c: &Condition) -> (f64, f64) {
        let at = |q: Quantity| {
            self.state(q).map_or(0.0, |i| match &c.harmonic {
                Some(h) => h.states[i][0],
                None => c.x[i],
            })
        };
        let u = at(Quantity::U);
        (u, u.hypot(at(Quantity::V)).hypot(at(Quantity::W)))
    }

    /// The median advance ratio u (1 - w) / (n D) over the conditions moving ahead with the
    /// propeller turning ahead.
    fn advance(&self, table: &[Condition]) -> Option<f64> {
        let (d, wake) = self.propeller?;
        let n = self.input(Quantity::Rpm)?;
        median_of(
            table
                .iter()
                .filter(|c| c.u[n] > 0.0 && self.speeds(c).0 > 0.0)
                .map(|c| self.speeds(c).0 * (1.0 - wake) / (c.u[n] * d)),
        )
    }

    /// The median Froude number of the conditions moving ahead.
    fn froude(&self, table: &[Condition]) -> Option<f64> {
        median_of(
            table
                .iter()
                .filter(|c| self.speeds(c).0 > 0.0)
                .map(|c| self.speeds(c).1 / (G * self.length).sqrt()),
        )
    }

    /// The explanation of `fixes` with `evidence`: the best unit factor of each component,
    /// the cost, and whether the table is plausible under it (clearly so).
    fn explain(&self, fixes: Vec<Fix>, evidence: Evidence) -> Explanation {
        self.explain_with(fixes, evidence, true)
    }

    /// [`Self::explain`], with unit factors only when `factors` (else each gain as it is).
    fn explain_with(
        &self,
        fixes: Vec<Fix>,
        evidence: Evidence,
        factors_allowed: bool,
    ) -> Explanation {
        let judged = self.judged();
        let mut cost = PENALTY * fixes.len() as f64;
        let (mut holds, mut clear) = (true, true);
        let mut factors = Vec::new();
        for (fit, &i) in evidence.fits.iter().zip(&judged) {
            let Some((cos, gain)) = *fit else {
                factors.push(None);
                continue;
            };
            cost += 1.0 - cos;
            holds &= cos >= COS_OK;
            clear &= cos >= COS_CLEAR;
            if !self.sizes_known || gain <= 0.0 {
                factors.push(None);
                cost += if gain <= 0.0 { 1.0 } else { 0.0 };
                continue;
            }
            let candidates = if factors_allowed {
                words::factors(
                    self.model.force_quantities()[i],
                    &self.areas,
                    self.prime_area,
                )
            } else {
                Vec::new()
            };
            let (best, off) = std::iter::once((None, gain.ln().abs()))
                .chain(
                    candidates
                        .iter()
                        .enumerate()
                        .map(|(k, f)| (Some(k), (gain / f.gain).ln().abs())),
                )
                .min_by(|a, b| {
                    let cost = |x: &(Option<usize>, f64)| {
                        x.1 * x.1 + if x.0.is_some() { PENALTY } else { 0.0 }
                    };
                    cost(a).total_cmp(&cost(b))
                })
                .unwrap_or((None, 0.0));
            cost += off * off + if best.is_some() { PENALTY } else { 0.0 };
            holds &= off <= GAIN_OK.ln();
            clear &= off <= GAIN_CLEAR.ln();
            factors.push(best);
        }
        // an area factor is the table's normalisation: every component has the same one
        let chosen: Vec<usize> = factors.iter().flatten().copied().collect();
        if chosen.iter().any(|k| words::factor_kind(*k) == "area")
            && (chosen.windows(2).any(|w| w[0] != w[1])
                || chosen.len() < evidence.fits.iter().flatten().count())
        {
            holds = false;
        }
        let outside = |x: f64, (lo, hi): (f64, f64)| {
            if x < lo {
                (lo / x).ln()
            } else if x > hi {
                (x / hi).ln()
            } else {
                0.0
            }
        };
        if let Some(j) = evidence.advance {
            let d = outside(j, WORKING_ADVANCE);
            cost += d * d;
            holds &= d == 0.0;
        }
        if let Some(fr) = evidence.froude {
            let d = outside(fr, FROUDE_RANGE);
            cost += d * d
                + self
                    .froude_model
                    .map_or(0.0, |m| FROUDE_WEIGHT * (fr / m).ln().powi(2));
            holds &= d == 0.0;
        }
        if let Some(r) = evidence.rudder.filter(|r| *r > 0.0) {
            let d = outside(r, (MIN_RUDDER, MAX_RUDDER));
            cost += d * d;
            holds &= d == 0.0;
        }
        Explanation {
            fixes,
            evidence,
            factors,
            cost,
            clear: clear && holds,
            holds,
        }
    }

    /// Whether the table as read is clearly wrong (not a model that misses it a little): a
    /// force's correlation with the model's below `cos`, its gain off by more than
    /// [`GAIN_WRONG`], or the advance ratio, Froude number or rudder angle out of range.
    fn wrong(&self, e: &Evidence, cos: f64) -> bool {
        let judged = e.fits.iter().flatten().any(|(c, gain)| {
            *c < cos
                || (self.sizes_known && (gain.abs().ln().abs() > GAIN_WRONG.ln() || *gain <= 0.0))
        });
        let outside = |x: Option<f64>, (lo, hi): (f64, f64)| x.is_some_and(|x| x < lo || x > hi);
        judged
            || outside(e.advance, WORKING_ADVANCE)
            || outside(e.froude, FROUDE_RANGE)
            || outside(e.rudder.filter(|r| *r > 0.0), (MIN_RUDDER, MAX_RUDDER))
    }

    /// The diagnosis of a table: None when it is clearly plausible as read, or when no
    /// correction makes it clearly plausible at a cost lower by [`MARGIN`] while it is not
    /// clearly wrong; else the explanation as read (its evidence), the best one under which
    /// it is plausible (None: none is; the table is then clearly wrong) and whether the
    /// table as read is clearly wrong.
    pub(crate) fn diagnose(
        &self,
        table: &[Condition],
        origin: Origin,
    ) -> Option<(Explanation, Option<Explanation>, bool)> {
        let read = self.explain(Vec::new(), self.evidence(table));
        if read.clear && read.factors.iter().all(Option::is_none) {
            return None;
        }
        let wrong = self.wrong(&read.evidence, COS_WRONG);
        let fixes = self.fixes(table);
        let mut best: Option<Explanation> = read.holds.then(|| read.clone());
        let consider = |best: &mut Option<Explanation>, e: Explanation| {
            if e.holds && best.as_ref().is_none_or(|b| e.cost < b.cost) {
                *best = Some(e);
            }
        };
        let mut singles = Vec::new();
        for &f in &fixes {
            if let Some((f, fixed)) = self.apply(f, table, origin) {
                consider(&mut best, self.explain(vec![f], self.evidence(&fixed)));
                singles.push((f, fixed));
            }
        }
        if best.as_ref().is_none_or(|b| !b.clear) {
            for (k, (f, fixed)) in singles.iter().enumerate() {
                for &g in fixes.iter().skip(k + 1) {
                    if same_quantity(*f, g) {
                        continue;
                    }
                    if let Some((g, both)) = self.apply(g, fixed, origin) {
                        consider(&mut best, self.explain(vec![*f, g], self.evidence(&both)));
                    }
                }
            }
        }
        // a correction is named when it makes the table clearly plausible, or plausible
        // where it was not, at a clearly lower cost; a unit factor alone when the gain is
        // outside the agreeing range
        // the table as read with each gain as it is: what a unit factor is judged against
        let plain = self.explain_with(Vec::new(), read.evidence.clone(), false);
        let named = best.filter(|b| {
            let changes = !b.fixes.is_empty() || b.factors.iter().any(Option::is_some);
            changes && (b.clear || !plain.holds) && b.cost < plain.cost - MARGIN
        });
        // unexplained, a table is said wrong only when far from the model: a model may miss
        // a real table by more than a correction misses a wrong one
        let unexplained = named.is_none() && self.wrong(&read.evidence, COS_UNEXPLAINED);
        (named.is_some() || unexplained).then_some((read, named, wrong))
    }
}

/// Whether two corrections act on the same quantity (never combined).
fn same_quantity(a: Fix, b: Fix) -> bool {
    use std::mem::discriminant;
    match (a, b) {
        (Fix::Flip(x), Fix::Flip(y)) => x == y,
        (Fix::RudderSign | Fix::RudderUnit(_), Fix::RudderSign | Fix::RudderUnit(_)) => {
            discriminant(&a) == discriminant(&b)
        }
        (Fix::RateUnit(_), Fix::Flip(Quantity::R)) | (Fix::Flip(Quantity::R), Fix::RateUnit(_)) => {
            false
        }
        _ => discriminant(&a) == discriminant(&b),
    }
}

/// A state of a condition multiplied by `f` (of a harmonic run: its mean and parts).
fn scale_state(c: &mut Condition, i: usize, f: f64) {
    c.x[i] *= f;
    if let Some(h) = &mut c.harmonic {
        h.states[i].iter_mut().for_each(|v| *v *= f);
    }
}
