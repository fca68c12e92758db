//! Plausibility of captive and PMM runs, before the fit (per run: the towing speed, the signs
//! and sizes of the sway force and yaw moment at small angles, and of a harmonic run the
//! signal-to-noise of each force harmonic and the apparent added mass against the vehicle's
//! analytic one) and after it (a lack-of-fit test of steady tables by near-neighbour pure
//! error). docs/stages.md, "Captive plausibility", says what each check catches and what it
//! cannot.
//!
//! The checks use no coefficient of the model: only the body axes (x forward, y to starboard,
//! z down; SNAME 1950), the vehicle's mass, length and draught or diameter, and physics that
//! holds for any hull. Their windows are ratios to slender-body scales (Newman 1977, Marine
//! Hydrodynamics, section 7.6): a hull's linear sway force scales with its sectional added
//! mass times U v, i.e. about (m / L) U v, its yaw damping with m L U r.

pub mod diagnosis;
pub mod table;
pub mod words;

pub(crate) use diagnosis::{Judge, Origin};
pub(crate) use words::Names;

use super::fit::Condition;
use super::harmonic::PER_FORCE;
use crate::base::numfmt::num;
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::model::models::Model;
use crate::stages::plausible::G;

/// Where the sway velocity, yaw rate, sway force and yaw moment sit in a model's state and
/// force vectors (None: the model has no such entry and the checks of it are skipped).
#[derive(Debug, Clone, Copy, Default)]
pub struct Layout {
    u: Option<usize>,
    v: Option<usize>,
    r: Option<usize>,
    fy: Option<usize>,
    mz: Option<usize>,
}

impl Layout {
    /// The layout of `model`.
    pub fn of<M: Model>(model: &M) -> Self {
        let state = |q: Quantity| model.states().iter().position(|s| s.quantity == q);
        let force = |q: Quantity| model.force_quantities().iter().position(|f| *f == q);
        Layout {
            u: state(Quantity::U),
            v: state(Quantity::V),
            r: state(Quantity::R),
            fy: force(Quantity::Fy),
            mz: force(Quantity::Mz),
        }
    }
}

/// The vehicle's scales the checks compare with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    /// Water density, kg/m^3.
    pub rho: f64,
    /// Length, m.
    pub length: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Analytic sway added mass, kg, and yaw added inertia, kg m^2, with where they are from.
    pub added: Option<(f64, f64, &'static str)>,
}

impl Reference {
    /// The scales of a vehicle: the added masses by strip theory from the draught d (a ship:
    /// flat-plate sections doubled in the free surface, m_a = pi/2 rho d^2 per unit length;
    /// Newman 1977, section 4.13, the leading term of Clarke et al. 1983 eq. 4), by Lamb's
    /// k-factors from the diameter (a body of revolution, [`crate::model::analytic::Spheroid`]),
    /// else none.
    pub fn new(
        rho: f64,
        length: f64,
        mass: f64,
        draught: Option<f64>,
        diameter: Option<f64>,
    ) -> Self {
        let added = match (draught, diameter) {
            (Some(d), _) if d > 0.0 => {
                let sway = 0.5 * std::f64::consts::PI * rho * d * d * length;
                Some((
                    sway,
                    sway * length * length / 12.0,
                    "strip theory from the draught",
                ))
            }
            (None, Some(dia)) => {
                crate::model::analytic::Spheroid::from_length_diameter(length, dia, rho)
                    .ok()
                    .map(|s| (-s.yvd(), -s.nrd(), "Lamb's k-factors of the spheroid"))
            }
            _ => None,
        };
        Reference {
            rho,
            length,
            mass,
            added,
        }
    }
}

/// Window of |Y_v| L / (m U) (calibrated on the published sets: KVLCC2 1.09, NPS AUV II 1.4;
/// kN read as N gives 1/1000 of it).
pub const YV_WINDOW: (f64, f64) = (0.05, 20.0);
/// Window of |N_r| / (m L U) (KVLCC2 0.17, NPS AUV II 0.22, the 1.2 m spheroid's
/// pure yaw run 0.0092: a bare body damps yaw by its quadratic term only; a yaw rate in rad/s
/// read as deg/s gives 57 times it, kN m read as N m 1/1000).
pub const NR_WINDOW: (f64, f64) = (0.002, 2.0);
/// Largest |Y_r| / (m U) (KVLCC2 0.29; a yaw rate in rad/s read as deg/s gives 57 times it).
pub const YR_LARGEST: f64 = 5.0;
/// Window of a pure sway run's apparent added mass against the analytic one (KVLCC2 1.08;
/// a sway amplitude stated twice too large gives half of it).
pub const SWAY_MASS_WINDOW: (f64, f64) = (0.6, 1.7);
/// Window of a pure yaw run's apparent added inertia against the analytic one (KVLCC2 0.64).
pub const YAW_MASS_WINDOW: (f64, f64) = (0.3, 2.5);
/// Window of the Froude number U / sqrt(g L) of a captive run.
pub const FROUDE_WINDOW: (f64, f64) = diagnosis::FROUDE_RANGE;
/// Smallest signal-to-noise ratio of a force's first harmonic in a harmonic run.
pub const MIN_SNR: f64 = 3.0;
/// Largest drift angle (deg) and non-dimensional yaw rate r L / U of a "small angle" row.
const SMALL: (f64, f64) = (10.0, 0.3);

/// The checks of one run's conditions before the fit: its warnings, or an error when the
/// run cannot be non-dimensionalised (no forward speed). With `explained` (the model's view
/// of the table, [`diagnosis`], or the F test named its mistake already) only the forward
/// speed and a harmonic run's signal-to-noise are checked: the slender-body windows would
/// name a consequence of that mistake as another one (Fy and Mz swapped make the yaw
/// moment rise with the yaw rate, a sign, where the swap is the cause).
pub fn before(
    run: &str,
    conditions: &[Condition],
    layout: &Layout,
    reference: &Reference,
    explained: bool,
) -> Result<Vec<Warning>, String> {
    let mut out = speed(conditions, layout, reference, explained)?;
    for c in conditions.iter().filter(|c| c.harmonic.is_some()) {
        out.extend(harmonic(c, layout, reference, explained));
    }
    if !explained {
        let steady: Vec<&Condition> = conditions.iter().filter(|c| c.harmonic.is_none()).collect();
        out.extend(small_angles(&steady, layout, reference));
    }
    Ok(out.into_iter().map(|w| w.for_run(run)).collect())
}

/// The sign and size checks of [`before`] over the conditions of force histories averaged
/// one per run (a CFD programme: a run per drift angle), which no run can make alone.
pub fn across_runs(
    averaged: &[&Condition],
    layout: &Layout,
    reference: &Reference,
) -> Vec<Warning> {
    small_angles(averaged, layout, reference)
        .into_iter()
        .map(|mut w| {
            w.message = w.message.replace("steady rows", "averaged force histories");
            w
        })
        .collect()
}

fn warning(message: String, meaning: &str) -> Warning {
    Warning::new(super::STAGE, message, meaning)
}

/// The forward speed of each condition: an error when it is 0 on every one (nothing to
/// non-dimensionalise by: u not mapped, or 0), a warning naming the rows where u <= 0 and
/// when the Froude number is outside [`FROUDE_WINDOW`] (a speed unit).
fn speed(
    conditions: &[Condition],
    l: &Layout,
    reference: &Reference,
    explained: bool,
) -> Result<Vec<Warning>, String> {
    let Some(iu) = l.u else { return Ok(Vec::new()) };
    let u: Vec<f64> = conditions.iter().map(|c| c.x[iu]).collect();
    if u.iter().all(|u| *u <= 0.0) {
        return Err(format!(
            "the forward speed u is {} on every row: a captive force is read against the \
             towing speed (its non-dimensional form divides by U^2); map the u column \
             (columns.u, or speed and drift) or give `constants = {{ u = ... }}`",
            if u.iter().all(|u| *u == 0.0) {
                "0"
            } else {
                "0 or negative"
            }
        ));
    }
    let mut out = Vec::new();
    let stopped: Vec<&str> = conditions
        .iter()
        .zip(&u)
        .filter(|(_, u)| **u <= 0.0)
        .map(|(c, _)| c.place.as_str())
        .collect();
    if !stopped.is_empty() {
        out.push(warning(
            format!("u <= 0 on {} rows: {}", stopped.len(), stopped.join(", ")),
            "a captive row without forward speed cannot be compared with the others by the \
             model's non-dimensional forces; a missing value read as 0, or a row of another \
             test",
        ));
    }
    let mut fr: Vec<f64> = u
        .iter()
        .filter(|u| **u > 0.0)
        .map(|u| u / (G * reference.length).sqrt())
        .collect();
    fr.sort_by(f64::total_cmp);
    let median = fr[fr.len() / 2];
    if !explained && (median < FROUDE_WINDOW.0 || median > FROUDE_WINDOW.1) {
        out.push(warning(
            format!(
                "the towing speed gives a Froude number U / sqrt(g L) of {} (median), outside \
                 {} to {} for L = {} m",
                num(median),
                FROUDE_WINDOW.0,
                FROUDE_WINDOW.1,
                num(reference.length)
            ),
            "the speed's unit is likely wrong (cm/s or mm/s read as m/s, or a full-scale \
             speed with a model's length): every force is then compared with the wrong U^2",
        ));
    }
    Ok(out)
}

/// A linear slope with its standard error.
#[derive(Debug, Clone, Copy)]
struct Slope {
    value: f64,
    se: f64,
}

impl Slope {
    fn significant(&self) -> bool {
        self.value.abs() > 3.0 * self.se
    }
}

/// Least-squares slopes of y on the columns of `x` (with an intercept; columns without
/// spread dropped), each with its standard error; None for a dropped column or too few rows.
fn slopes(x: &[Vec<f64>], y: &[f64]) -> Vec<Option<Slope>> {
    let n = y.len();
    let k = x.first().map_or(0, Vec::len);
    let keep: Vec<usize> = (0..k)
        .filter(|&j| {
            let (lo, hi) = crate::numerics::signal::range(x.iter().map(|r| r[j]));
            hi - lo > 1e-9 * (hi.abs() + lo.abs()).max(1e-300)
        })
        .collect();
    let mut out = vec![None; k];
    if n < keep.len() + 3 {
        return out;
    }
    let a = nalgebra::DMatrix::from_fn(n, keep.len() + 1, |i, j| {
        if j == 0 {
            1.0
        } else {
            x[i][keep[j - 1]]
        }
    });
    let yv = nalgebra::DVector::from_column_slice(y);
    if let Some(s) = crate::numerics::lsq::scaled_least_squares(&a, &yv, n - keep.len() - 1) {
        for (j, &col) in keep.iter().enumerate() {
            out[col] = Some(Slope {
                value: s.theta[j + 1],
                se: s.covariance[j + 1][j + 1].max(0.0).sqrt(),
            });
        }
    }
    out
}

/// The sway force and yaw moment against v and r over the steady rows at small angles
/// (|beta| <= 10 deg, |r| L / U <= 0.3), the inputs regressed out: Y_v < 0 (the force
/// opposes the sway; a hull's lift at drift), N_r < 0 (yaw damping), and the sizes of Y_v,
/// N_r and Y_r against the slender-body scales.
fn small_angles(rows: &[&Condition], l: &Layout, reference: &Reference) -> Vec<Warning> {
    let (Some(iu), Some(iv), Some(ir)) = (l.u, l.v, l.r) else {
        return Vec::new();
    };
    let small: Vec<&&Condition> = rows
        .iter()
        .filter(|c| {
            let (u, v, r) = (c.x[iu], c.x[iv], c.x[ir]);
            let speed = u.hypot(v);
            u > 0.0
                && (-v).atan2(u).abs() <= SMALL.0.to_radians()
                && (r * reference.length / speed).abs() <= SMALL.1
        })
        .collect();
    if small.is_empty() {
        return Vec::new();
    }
    let speed = small.iter().map(|c| c.x[iu].hypot(c.x[iv])).sum::<f64>() / small.len() as f64;
    let x: Vec<Vec<f64>> = small
        .iter()
        .map(|c| {
            [c.x[iv], c.x[ir]]
                .into_iter()
                .chain(c.u.iter().copied())
                .collect()
        })
        .collect();
    let mut out = Vec::new();
    let scale = Scales::new(reference, speed);
    if let Some(fy) = l.fy {
        let y: Vec<f64> = small.iter().map(|c| c.f[fy]).collect();
        let s = slopes(&x, &y);
        out.extend(s[0].and_then(|yv| scale.yv(yv, "small drift angles of the steady rows")));
        out.extend(s[1].and_then(|yr| scale.yr(yr)));
    }
    if let Some(mz) = l.mz {
        let y: Vec<f64> = small.iter().map(|c| c.f[mz]).collect();
        out.extend(
            slopes(&x, &y)[1].and_then(|nr| scale.nr(nr, "small yaw rates of the steady rows")),
        );
    }
    out
}

/// The slender-body scales of the sway and yaw derivatives at speed U.
struct Scales {
    /// m U / L (Y_v), m U (Y_r), m L U (N_r).
    yv: f64,
    yr: f64,
    nr: f64,
}

impl Scales {
    fn new(r: &Reference, speed: f64) -> Self {
        Scales {
            yv: r.mass * speed / r.length,
            yr: r.mass * speed,
            nr: r.mass * r.length * speed,
        }
    }

    /// Y_v: its sign (< 0) and size (in [`YV_WINDOW`] of m U / L).
    fn yv(&self, s: Slope, from: &str) -> Option<Warning> {
        let rises = || {
            warning(
                format!(
                    "the sway force rises with the sway velocity at {from}: dFy/dv = {} N s/m \
                     (Y_v > 0; expected < 0, the force opposing v)",
                    num(s.value)
                ),
                "the sign of fy is likely flipped (a force positive to port: `scale = -1` on \
                 its column), or that of v or the drift angle (beta = -atan(v / u): positive \
                 drift moves the ship to port); every derivative fitted from fy changes sign",
            )
        };
        damping(s, self.yv, YV_WINDOW, rises, |ratio| {
            warning(
                format!(
                    "the sway force per sway velocity at {from} is |dFy/dv| = {} N s/m, {} \
                     times m U / L (expected {} to {})",
                    num(s.value.abs()),
                    num(ratio),
                    YV_WINDOW.0,
                    YV_WINDOW.1
                ),
                "the force's unit is likely wrong (kN read as N gives 1/1000, N read as kN \
                 1000 times), or the velocity's (cm/s as m/s), or the prime system's \
                 normalisation (captive.prime); every fitted derivative carries the factor",
            )
        })
    }

    /// Y_r: its size (below [`YR_LARGEST`] times m U).
    fn yr(&self, s: Slope) -> Option<Warning> {
        let ratio = s.value.abs() / self.yr;
        (s.significant() && ratio > YR_LARGEST).then(|| {
            warning(
                format!(
                    "the sway force per yaw rate is |dFy/dr| = {} N s, {} times m U (expected \
                     below {YR_LARGEST})",
                    num(s.value.abs()),
                    num(ratio)
                ),
                "the yaw rate is likely too small by its unit: rad/s read as deg/s gives 1/57 \
                 of it and 57 times Y_r (and N_r); give the r column's unit",
            )
        })
    }

    /// N_r: its sign (< 0) and size (in [`NR_WINDOW`] of m L U).
    fn nr(&self, s: Slope, from: &str) -> Option<Warning> {
        let rises = || {
            warning(
                format!(
                    "the yaw moment rises with the yaw rate at {from}: dMz/dr = {} N m s (N_r \
                     > 0; expected < 0, yaw damping)",
                    num(s.value)
                ),
                "the sign of mz or of r is likely flipped (a moment or rate positive to port: \
                 `scale = -1` on its column); every derivative fitted from it changes sign",
            )
        };
        damping(s, self.nr, NR_WINDOW, rises, |ratio| {
            warning(
                format!(
                    "the yaw moment per yaw rate at {from} is |dMz/dr| = {} N m s, {} times m L \
                     U (expected {} to {})",
                    num(s.value.abs()),
                    num(ratio),
                    NR_WINDOW.0,
                    NR_WINDOW.1
                ),
                "a unit is likely wrong: the yaw rate's (rad/s read as deg/s gives 57 times \
                 it, deg/s read as rad/s 1/57) or the moment's (kN m read as N m gives \
                 1/1000); every fitted derivative carries the factor",
            )
        })
    }
}

/// A damping derivative's check: when its slope `s` is significant, the warning `rises` when
/// it is positive (expected < 0), else `outside` with |s| / `scale` when that is outside
/// `window`.
fn damping(
    s: Slope,
    scale: f64,
    window: (f64, f64),
    rises: impl FnOnce() -> Warning,
    outside: impl FnOnce(f64) -> Warning,
) -> Option<Warning> {
    if !s.significant() {
        return None;
    }
    if s.value > 0.0 {
        return Some(rises());
    }
    let ratio = s.value.abs() / scale;
    (ratio < window.0 || ratio > window.1).then(|| outside(ratio))
}

/// A harmonic (PMM) run: the signal-to-noise of each lateral force's first harmonic, and,
/// of a pure sway or pure yaw run, the in-phase part's sign and size and the apparent added
/// mass from the part in phase with the acceleration.
fn harmonic(c: &Condition, l: &Layout, reference: &Reference, explained: bool) -> Vec<Warning> {
    let Some(motion) = &c.harmonic else {
        return Vec::new();
    };
    let sigma = c.sigma.as_deref().unwrap_or(&[]);
    let amp = |i: Option<usize>| i.map_or(0.0, |i| motion.states[i][1].hypot(motion.states[i][2]));
    let (av, ar) = (amp(l.v), amp(l.r));
    let mut out = Vec::new();
    for (f, name) in [(l.fy, "fy"), (l.mz, "mz")] {
        let Some(f) = f else { continue };
        let (a, b) = (c.f[f * PER_FORCE + 1], c.f[f * PER_FORCE + 2]);
        let se = match (sigma.get(f * PER_FORCE + 1), sigma.get(f * PER_FORCE + 2)) {
            (Some(x), Some(y)) => x.hypot(*y),
            _ => continue,
        };
        let snr = a.hypot(b) / se.max(f64::MIN_POSITIVE);
        if snr < MIN_SNR {
            out.push(warning(
                format!(
                    "{name} has no first harmonic above its noise: amplitude {}, standard \
                     error {} (signal-to-noise {}, expected at least {MIN_SNR})",
                    num(a.hypot(b)),
                    num(se),
                    num(snr)
                ),
                "the force record does not respond to the motion: the wrong column (another \
                 gauge, a channel of noise), or a motion too small for the gauge; the \
                 derivatives fitted from it are noise (an added mass may come out with the \
                 wrong sign)",
            ));
            return out;
        }
    }
    if explained {
        return out;
    }
    let speed = l.u.map_or(0.0, |i| motion.states[i][0]);
    let scale = Scales::new(reference, speed);
    let pure = |a: f64, b: f64| a > 0.0 && b <= 1e-3 * a;
    // the motion's share in sway and in yaw: a pure run has only one
    let (sway, yaw) = (
        av / speed.max(1e-300),
        ar * reference.length / speed.max(1e-300),
    );
    type Damping = fn(&Scales, Slope, &str) -> Option<Warning>;
    // the analytic sway added mass and yaw added inertia, with their source
    let (mass, inertia) = (
        reference.added.map(|a| (a.0, a.2)),
        reference.added.map(|a| (a.1, a.2)),
    );
    let runs: [(_, _, _, Damping, _, _, _, _); 2] = [
        (
            l.v,
            l.fy,
            pure(sway, yaw),
            Scales::yv,
            "sway",
            av,
            mass,
            SWAY_MASS_WINDOW,
        ),
        (
            l.r,
            l.mz,
            pure(yaw, sway),
            Scales::nr,
            "yaw",
            ar,
            inertia,
            YAW_MASS_WINDOW,
        ),
    ];
    for (state, force, is_pure, damping, kind, amplitude, analytic, window) in runs {
        let (Some(i), Some(f), true) = (state, force, is_pure) else {
            continue;
        };
        let (inphase, quad) = parts(c, motion, i, f);
        let slope = Slope {
            value: inphase,
            se: 0.0,
        };
        out.extend(damping(
            &scale,
            slope,
            &format!("the pure {kind} run's first harmonic"),
        ));
        out.extend(added_check(-quad, analytic, amplitude, kind, window));
    }
    out
}

/// The first harmonic of force `f` projected on the motion of state `i` (per unit of it)
/// and on its rate (per unit of the acceleration): the damping and the added-mass part.
/// With x = a cos(phi) + b sin(phi), x_dot = omega (b cos(phi) - a sin(phi)).
fn parts(
    c: &Condition,
    motion: &super::harmonic::HarmonicMotion,
    i: usize,
    f: usize,
) -> (f64, f64) {
    let [_, a, b] = motion.states[i];
    let (fc, fs) = (c.f[f * PER_FORCE + 1], c.f[f * PER_FORCE + 2]);
    let a2 = a * a + b * b;
    (
        (fc * a + fs * b) / a2,
        (fc * b - fs * a) / (a2 * motion.omega),
    )
}

/// A harmonic run's apparent added mass (or inertia) against the analytic one.
fn added_check(
    apparent: f64,
    analytic: Option<(f64, &str)>,
    amplitude: f64,
    kind: &str,
    window: (f64, f64),
) -> Option<Warning> {
    let (reference, source) = analytic?;
    let ratio = apparent / reference;
    (ratio < window.0 || ratio > window.1).then(|| {
        warning(
            format!(
                "the pure {kind} run's force in phase with the acceleration gives an added \
                 {} of {} ({} times the {} from {source}; expected {} to {})",
                if kind == "yaw" { "inertia" } else { "mass" },
                num(apparent),
                num(ratio),
                num(reference),
                window.0,
                window.1
            ),
            &format!(
                "{}the stated motion amplitude ({}) is likely wrong: twice the true amplitude \
                 halves every derivative of the run (a displacement amplitude given as the \
                 velocity's, or a double amplitude); check captive.oscillations or the motion \
                 columns' units",
                if ratio < 0.0 {
                    "a negative added mass is not physical: the force may not respond to the \
                     motion, its sign is flipped, or the stated phase is off by 90 or 180 deg \
                     (a displacement's phase given for the velocity's: check the phase in \
                     captive.oscillations); else "
                } else {
                    ""
                },
                num(amplitude)
            ),
        )
    })
}

/// Near-neighbour lack of fit of steady conditions (Daniel & Wood 1980, section 7.7; Joglekar,
/// Schuenemeyer & LaRiccia 1989): each condition paired with its nearest one in the space
/// of its motion and inputs (each coordinate over its range), the differences of their
/// residuals give the pure noise sigma_nn^2 = sum (e_i - e_j)^2 / (2 n) free of a misfit that
/// varies smoothly with the condition; the ratio of the residual variance to it, per force
/// component (1 without misfit). `residuals[k][i]` is condition k's residual of component i.
pub fn misfit_ratios(
    conditions: &[&Condition],
    residuals: &[Vec<f64>],
    dof_share: f64,
) -> Vec<f64> {
    let n = conditions.len();
    let nf = residuals.first().map_or(0, Vec::len);
    if n < 8 {
        return vec![1.0; nf];
    }
    let coords: Vec<Vec<f64>> = conditions
        .iter()
        .map(|c| c.x.iter().chain(&c.u).copied().collect())
        .collect();
    let dims = coords[0].len();
    let spans: Vec<f64> = (0..dims)
        .map(|j| {
            let (lo, hi) = crate::numerics::signal::range(coords.iter().map(|c| c[j]));
            hi - lo
        })
        .collect();
    let distance = |a: &[f64], b: &[f64]| -> f64 {
        (0..dims)
            .filter(|&j| spans[j] > 0.0)
            .map(|j| ((a[j] - b[j]) / spans[j]).powi(2))
            .sum()
    };
    let nearest: Vec<usize> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| j != i)
                .min_by(|&a, &b| {
                    distance(&coords[i], &coords[a]).total_cmp(&distance(&coords[i], &coords[b]))
                })
                .unwrap_or(i)
        })
        .collect();
    (0..nf)
        .map(|f| {
            let rss: f64 = residuals.iter().map(|r| r[f] * r[f]).sum();
            let s2 = rss / (n as f64 * dof_share).max(1.0);
            let nn = nearest
                .iter()
                .enumerate()
                .map(|(i, &j)| (residuals[i][f] - residuals[j][f]).powi(2))
                .sum::<f64>()
                / (2.0 * n as f64);
            if nn <= 1e-24 * s2.max(f64::MIN_POSITIVE) || s2 == 0.0 {
                1.0
            } else {
                s2 / nn
            }
        })
        .collect()
}

/// Which conditions to keep when the outer quarter of the steady rows' range is left out:
/// each steady row's lateral motion m = max(|v / U| / max |v / U|, |r L / U| / max |r L /
/// U|) (drift and yaw rate each over their own range), rows with m above 3/4 dropped (a
/// table to 30 deg drift keeps its rows to 22.5 deg); harmonic and averaged conditions
/// always kept.
pub fn inner(conditions: &[Condition], l: &Layout, length: f64) -> Vec<bool> {
    let (Some(iu), Some(iv), Some(ir)) = (l.u, l.v, l.r) else {
        return vec![true; conditions.len()];
    };
    let steady = |c: &Condition| c.sigma.is_none() && c.harmonic.is_none();
    let lateral = |c: &Condition| {
        let speed = c.x[iu].hypot(c.x[iv]).max(f64::MIN_POSITIVE);
        ((c.x[iv] / speed).abs(), (c.x[ir] * length / speed).abs())
    };
    let (mut vmax, mut rmax) = (0.0f64, 0.0f64);
    for c in conditions.iter().filter(|c| steady(c)) {
        let (v, r) = lateral(c);
        (vmax, rmax) = (vmax.max(v), rmax.max(r));
    }
    let m = |c: &Condition| {
        let (v, r) = lateral(c);
        let part = |x: f64, max: f64| if max > 0.0 { x / max } else { 0.0 };
        part(v, vmax).max(part(r, rmax))
    };
    conditions
        .iter()
        .map(|c| !steady(c) || m(c) <= INNER_RANGE)
        .collect()
}

/// Share of the range of the steady rows' lateral motion kept by [`inner`].
pub const INNER_RANGE: f64 = 0.75;

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// A steady grid of drift angles and rudder angles at one speed, x = (u, v, r), u =
    /// (rudder).
    fn grid() -> Vec<Condition> {
        let mut out = Vec::new();
        for b in (-20..=20).step_by(4) {
            for d in [-20.0, 0.0, 20.0] {
                let beta = f64::from(b).to_radians();
                out.push(Condition {
                    x: vec![beta.cos(), -beta.sin(), 0.0],
                    u: vec![f64::to_radians(d)],
                    f: vec![0.0],
                    sigma: None,
                    place: String::new(),
                    harmonic: None,
                });
            }
        }
        out
    }

    /// White-noise residuals give ratios near 1 (within 0.6 to 1.4 over twelve seeds); a
    /// misfit that varies smoothly with the drift angle (a v^3 term the model lacks, 6 times
    /// the noise at the largest drift) gives more than 2 on every seed.
    #[test]
    fn the_misfit_ratio_is_near_one_for_noise_and_large_for_a_smooth_misfit() {
        let conditions = grid();
        let refs: Vec<&Condition> = conditions.iter().collect();
        let (mut lo, mut hi, mut smooth_lo) = (f64::INFINITY, 0.0f64, f64::INFINITY);
        for seed in 0..12 {
            let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
            let noise = Normal::new(0.0, 1.0).unwrap();
            let e: Vec<f64> = conditions.iter().map(|_| noise.sample(&mut rng)).collect();
            let white: Vec<Vec<f64>> = e.iter().map(|e| vec![*e]).collect();
            let f = misfit_ratios(&refs, &white, 1.0)[0];
            (lo, hi) = (lo.min(f), hi.max(f));
            let vmax = 20f64.to_radians().sin();
            let smooth: Vec<Vec<f64>> = conditions
                .iter()
                .zip(&e)
                .map(|(c, e)| vec![e + 6.0 * (c.x[1] / vmax).powi(3)])
                .collect();
            smooth_lo = smooth_lo.min(misfit_ratios(&refs, &smooth, 1.0)[0]);
        }
        println!("white noise {lo} to {hi}, smooth misfit from {smooth_lo}");
        assert!(lo > 0.6 && hi < 1.4, "white noise: {lo} to {hi}");
        assert!(smooth_lo > 2.0, "smooth misfit: {smooth_lo}");
    }

    /// Averaged force histories, one per drift angle: Fy = -v (Y_v L / (m U) = 1 with m = L =
    /// U = 1) says nothing; flipped, the sign is named.
    #[test]
    fn averaged_runs_are_checked_across_runs() {
        let layout = Layout {
            u: Some(0),
            v: Some(1),
            r: Some(2),
            fy: Some(0),
            mz: None,
        };
        let reference = Reference::new(1000.0, 1.0, 1.0, None, None);
        for sign in [1.0, -1.0] {
            let conditions: Vec<Condition> = grid()
                .into_iter()
                .enumerate()
                .map(|(k, mut c)| {
                    let wiggle = 1e-3 * ((k * 7919) % 13) as f64;
                    c.f = vec![-sign * c.x[1] + wiggle];
                    c.sigma = Some(vec![1e-3]);
                    c
                })
                .collect();
            let refs: Vec<&Condition> = conditions.iter().collect();
            let w = across_runs(&refs, &layout, &reference);
            if sign > 0.0 {
                assert!(w.is_empty(), "{w:?}");
            } else {
                assert!(w.len() == 1 && w[0].message.contains("averaged force histories"));
                assert!(w[0].meaning.contains("sign of fy"), "{w:?}");
            }
        }
    }

    #[test]
    fn the_outer_quarter_of_the_drift_range_is_left_out() {
        let conditions = grid();
        let keep = inner(
            &conditions,
            &Layout {
                u: Some(0),
                v: Some(1),
                r: Some(2),
                fy: None,
                mz: None,
            },
            7.0,
        );
        for (c, k) in conditions.iter().zip(keep) {
            let beta = (-c.x[1]).atan2(c.x[0]).to_degrees().abs();
            assert_eq!(k, beta < 16.0, "{beta}");
        }
    }
}
