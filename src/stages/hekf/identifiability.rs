//! Identifiability: which estimated coefficients the runs cannot pin down, why, and which
//! manoeuvre would.
//!
//! A coefficient c_j enters the dynamics through its regressor g_j(x, u) = df/dc_j (automatic
//! differentiation, [`crate::numerics::ad`]): the motion its term needs. The data pin c_j only where
//! g_j is large next to the noise and not a multiple of another estimated coefficient's
//! regressor (then the two trade off: a strong correlation of the estimates, Ljung 1999,
//! "System Identification", section 13.2 on persistent excitation; Fossen 2011, section
//! 7.5 on manoeuvres for identification). For each coefficient the filter left uncertain
//! (sigma above [`UNCERTAIN`] of its value) or correlated (above [`CORRELATED`], with a sigma
//! above `LOOSE` of its value) this module
//! finds the quantities the term acts through (those whose zeroing removes the regressor),
//! how much of each the runs hold, and names a manoeuvre that moves them.

use super::identify::RunData;
use super::result::RunTraces;
use crate::base::quantity::Quantity;
use crate::model::coefficients::{CORRELATED, UNCERTAIN};
use crate::model::models::Model;
use crate::numerics::ad;
use serde::Serialize;

/// A correlated estimate is flagged only when its sigma is above this share of its value:
/// two estimates known to a per cent each are separately identified however correlated.
const LOOSE: f64 = 0.02;

/// Samples per run at which the regressors are evaluated (evenly spread).
const SAMPLES: usize = 400;

/// Zeroing a quantity that leaves less than this share of a regressor's RMS makes the
/// quantity one the term acts through.
const DRIVER: f64 = 0.2;

/// What one coefficient lacks, and what would supply it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Advice {
    /// The coefficient.
    pub coefficient: String,
    /// Why it is flagged: its relative sigma, or its correlation with another estimate.
    pub finding: String,
    /// The quantities its term acts through (keys: `p`, `rudder` ...).
    pub acts_through: Vec<String>,
    /// How much of them the runs hold (largest magnitude per run).
    pub in_these_runs: String,
    /// Why the runs do not determine it.
    pub why: String,
    /// A manoeuvre that would determine it, identified jointly with the runs.
    pub separate_by: String,
}

/// The inputs of [`advise`] that come from the identification.
pub struct Estimates<'a> {
    /// The full coefficient vector at the estimate.
    pub c: &'a [f64],
    /// Indices of the estimated coefficients in `c`.
    pub est: &'a [usize],
    /// Their names.
    pub names: &'a [String],
    /// Their total sigmas.
    pub sigmas: &'a [f64],
    /// Their correlation matrix.
    pub correlation: &'a [Vec<f64>],
}

/// The advice for every flagged estimate, in estimation order.
pub fn advise<M: Model>(
    model: &M,
    runs: &[RunData],
    traces: &[RunTraces],
    e: &Estimates,
) -> Vec<Advice> {
    let nb = e.est.len();
    let flagged: Vec<(usize, String)> = (0..nb)
        .filter_map(|j| finding(e, j).map(|f| (j, f)))
        .collect();
    if flagged.is_empty() {
        return Vec::new();
    }
    let candidates = candidates(model);
    let (g, peaks) = zeroed_regressors(model, runs, traces, e, &candidates);
    let drivers = drivers_of(model, &candidates, &g);
    flagged
        .into_iter()
        .map(|(j, finding)| advice_for(model, runs, e, &candidates, &drivers, &peaks, j, finding))
        .collect()
}

/// The regressors of the estimates with each candidate quantity zeroed in turn (index 0:
/// nothing zeroed), flattened over the runs' samples, and each candidate's peak magnitude
/// per run.
#[allow(clippy::type_complexity)]
fn zeroed_regressors<M: Model>(
    model: &M,
    runs: &[RunData],
    traces: &[RunTraces],
    e: &Estimates,
    candidates: &[Zero],
) -> (Vec<Vec<Vec<f64>>>, Vec<Vec<f64>>) {
    let nb = e.est.len();
    // regressors per candidate zeroed (index 0: nothing zeroed), flattened over samples
    let mut g: Vec<Vec<Vec<f64>>> = vec![vec![Vec::new(); nb]; candidates.len() + 1];
    let mut peaks = vec![vec![0.0f64; runs.len()]; candidates.len()];
    for (r, (run, tr)) in runs.iter().zip(traces).enumerate() {
        let nx = model.nx();
        let k_len = tr.filtered.len() / nx.max(1);
        let step = (k_len / SAMPLES).max(1);
        let mut u = vec![0.0; model.input_quantities().len()];
        for k in (0..k_len).step_by(step) {
            let x = &tr.filtered[k * nx..(k + 1) * nx];
            run.inputs.at(tr.times[k], &mut u);
            for (ci, cand) in candidates.iter().enumerate() {
                let v = match *cand {
                    Zero::State(i) => x[i],
                    Zero::Input(i) => u[i],
                };
                peaks[ci][r] = peaks[ci][r].max(v.abs());
            }
            for (z, gz) in g.iter_mut().enumerate() {
                let (mut xz, mut uz) = (x.to_vec(), u.clone());
                match z.checked_sub(1).map(|ci| candidates[ci]) {
                    Some(Zero::State(i)) => xz[i] = 0.0,
                    Some(Zero::Input(i)) => uz[i] = 0.0,
                    None => {}
                }
                let jac = regressors(model, &xz, &uz, e);
                for (j, gj) in gz.iter_mut().enumerate() {
                    gj.extend((0..nx).map(|s| jac[s * nb + j]));
                }
            }
        }
    }
    (g, peaks)
}

/// Per estimate, the candidate quantities whose zeroing makes its regressor vanish (the
/// quantities its term acts through); speed only when it is the only one.
fn drivers_of<M: Model>(model: &M, candidates: &[Zero], g: &[Vec<Vec<f64>>]) -> Vec<Vec<usize>> {
    let rms = |v: &[f64]| (v.iter().map(|a| a * a).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let nb = g[0].len();
    (0..nb)
        .map(|j| {
            let full = rms(&g[0][j]);
            let d: Vec<usize> = (0..candidates.len())
                .filter(|&ci| full > 0.0 && rms(&g[ci + 1][j]) < DRIVER * full)
                .collect();
            // speed multiplies almost every term: it is named only when alone
            let without_u: Vec<usize> = d
                .iter()
                .copied()
                .filter(|&ci| quantity(model, candidates[ci]) != Quantity::U)
                .collect();
            if without_u.is_empty() {
                d
            } else {
                without_u
            }
        })
        .collect()
}

/// The advice for one flagged estimate: what its term acts through, how large those
/// quantities are in these runs, why the runs leave it undetermined and which manoeuvre
/// would determine it.
#[allow(clippy::too_many_arguments)]
fn advice_for<M: Model>(
    model: &M,
    runs: &[RunData],
    e: &Estimates,
    candidates: &[Zero],
    drivers: &[Vec<usize>],
    peaks: &[Vec<f64>],
    j: usize,
    finding: String,
) -> Advice {
    if let Some(rate) = acceleration_term(&e.names[j]) {
        return added_mass(&e.names[j], rate, finding);
    }
    let qs: Vec<Quantity> = drivers[j]
        .iter()
        .map(|&ci| quantity(model, candidates[ci]))
        .collect();
    let in_these_runs = drivers[j]
        .iter()
        .map(|&ci| {
            let q = quantity(model, candidates[ci]);
            let per_run = peaks[ci]
                .iter()
                .zip(runs)
                .map(|(p, run)| format!("{} in '{}'", magnitude(q, *p), run.name))
                .collect::<Vec<_>>()
                .join(", ");
            format!("|{q}| at most {per_run}")
        })
        .collect::<Vec<_>>()
        .join("; ");
    let why = match partner(e, j).filter(|_| finding.contains("correlation")) {
        Some(b) => {
            let through: Vec<&str> = drivers[b]
                .iter()
                .map(|&ci| quantity(model, candidates[ci]).key())
                .collect();
            format!(
                "its term and {}'s{} move together in these runs, so the data trade \
                 one for the other",
                e.names[b],
                if through.is_empty() {
                    String::new()
                } else {
                    format!(" (through {})", through.join(" and "))
                }
            )
        }
        None => "its term stays small next to the noise in these runs".to_string(),
    };
    Advice {
        coefficient: e.names[j].clone(),
        finding,
        acts_through: qs.iter().map(|q| q.key().to_string()).collect(),
        in_these_runs: if in_these_runs.is_empty() {
            "its term does not vanish with any single motion quantity".into()
        } else {
            in_these_runs
        },
        why,
        separate_by: qs
            .first()
            .map_or(GENERAL, |q| manoeuvre_for(*q, &model.input_quantities()))
            .to_string(),
    }
}

/// The rate whose derivative an added-mass (acceleration) coefficient multiplies, from its
/// SNAME name: `Nrd` and `Nrdot` (N_rdot) act through r_dot.
fn acceleration_term(name: &str) -> Option<char> {
    let rest = name
        .strip_suffix("dot")
        .or_else(|| name.strip_suffix('d'))?;
    let mut c = rest.chars();
    let (force, rate) = (c.next()?, c.next()?);
    ("XYZKMN".contains(force) && "uvwpqr".contains(rate) && c.next().is_none()).then_some(rate)
}

/// The advice for an added-mass coefficient: free-running motion fixes it only relative to
/// the rest of its equation (Ljung 1999, section 13.2; docs/hekf.md).
fn added_mass(name: &str, rate: char, finding: String) -> Advice {
    Advice {
        coefficient: name.to_string(),
        finding,
        acts_through: vec![format!("{rate}_dot")],
        in_these_runs: format!("an added-mass term: it multiplies the acceleration {rate}_dot"),
        why: "free-running motion determines an added mass only relative to the inertia and \
              the other terms of its equation: scaling them together leaves the motion \
              unchanged, and forces of a free-running run do not help (Newton ties them to \
              the motion)"
            .to_string(),
        separate_by: "a captive run with acceleration (PMM pure sway or pure yaw), an \
                      acceleration run, or a known value (a static polar fixes the scale of \
                      the equation)"
            .to_string(),
    }
}

/// Why estimate `j` is flagged, if it is.
fn finding(e: &Estimates, j: usize) -> Option<String> {
    let value = e.c[e.est[j]];
    let rel = e.sigmas[j] / value.abs();
    let mut parts = Vec::new();
    if value == 0.0 || rel > UNCERTAIN {
        parts.push(format!(
            "sigma is {} the value",
            if value == 0.0 {
                "larger than".to_string()
            } else {
                crate::base::numfmt::proportion(rel)
            }
        ));
    }
    if let Some(b) = partner(e, j).filter(|_| value == 0.0 || rel > LOOSE) {
        parts.push(format!(
            "correlation {:+.2} with {}",
            e.correlation[j][b], e.names[b]
        ));
    }
    (!parts.is_empty()).then(|| parts.join("; "))
}

/// The estimate most correlated with `j`, when above [`CORRELATED`].
fn partner(e: &Estimates, j: usize) -> Option<usize> {
    (0..e.est.len())
        .filter(|&b| b != j && e.correlation[j][b].abs() > CORRELATED)
        .max_by(|&a, &b| {
            e.correlation[j][a]
                .abs()
                .total_cmp(&e.correlation[j][b].abs())
        })
}

/// A model quantity that can be zeroed: a state or an input.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Zero {
    State(usize),
    Input(usize),
}

/// The velocities, rates and control inputs of the model.
fn candidates<M: Model>(model: &M) -> Vec<Zero> {
    // u, v, w, p, q, r: the body velocities and rates
    let motion = &Quantity::MOTION[..6];
    const CONTROLS: [Quantity; 3] = [Quantity::Rudder, Quantity::SternPlanes, Quantity::BowPlanes];
    let states = model
        .states()
        .iter()
        .enumerate()
        .filter(|(_, s)| motion.contains(&s.quantity))
        .map(|(i, _)| Zero::State(i));
    let inputs = model
        .input_quantities()
        .into_iter()
        .enumerate()
        .filter(|(_, q)| CONTROLS.contains(q))
        .map(|(i, _)| Zero::Input(i));
    states.chain(inputs).collect()
}

fn quantity<M: Model>(model: &M, z: Zero) -> Quantity {
    match z {
        Zero::State(i) => model.states()[i].quantity,
        Zero::Input(i) => model.input_quantities()[i],
    }
}

/// df/dc for the estimated coefficients at (x, u): row-major nx x nb.
fn regressors<M: Model>(model: &M, x: &[f64], u: &[f64], e: &Estimates) -> Vec<f64> {
    let (nx, nb) = (model.nx(), e.est.len());
    let at: Vec<f64> = e.est.iter().map(|&i| e.c[i]).collect();
    let mut value = vec![0.0; nx];
    let mut jac = vec![0.0; nx * nb];
    ad::jacobian(
        &at,
        nx,
        |b, dx| {
            let xd: Vec<ad::Dual> = x.iter().map(|v| ad::constant(*v)).collect();
            let mut cd: Vec<ad::Dual> = e.c.iter().map(|v| ad::constant(*v)).collect();
            for (k, &i) in e.est.iter().enumerate() {
                cd[i] = b[k];
            }
            model.relations().apply(&mut cd);
            model.derivatives(&xd, u, &cd, dx);
        },
        &mut value,
        &mut jac,
    );
    jac
}

/// A magnitude in the unit a naval architect reads: degrees for angles and rates.
fn magnitude(q: Quantity, v: f64) -> String {
    let n = crate::base::numfmt::num;
    match q.si_symbol() {
        "rad" => format!("{} deg", n(v.to_degrees())),
        "rad/s" => format!("{} deg/s", n(v.to_degrees())),
        s => format!("{} {s}", n(v)),
    }
}

/// The advice when no single quantity drives the term.
const GENERAL: &str = "a run that excites this term more";

/// The manoeuvre that moves a quantity, with the control surfaces the model has (`inputs`).
fn manoeuvre_for(q: Quantity, inputs: &[Quantity]) -> &'static str {
    let has = |c: Quantity| inputs.contains(&c);
    match q {
        Quantity::V | Quantity::R | Quantity::Rudder if has(Quantity::Rudder) => {
            "a horizontal zig-zag on the rudder (sway and yaw rate varying out of step)"
        }
        Quantity::V | Quantity::R => {
            "a run in which sway velocity and yaw rate vary more and out of step (without a \
             rudder: another initial drift angle and yaw rate)"
        }
        Quantity::W | Quantity::Q | Quantity::SternPlanes | Quantity::BowPlanes
            if has(Quantity::SternPlanes) || has(Quantity::BowPlanes) =>
        {
            "a vertical zig-zag on the stern (or bow) planes (heave and pitch rate varying out \
             of step)"
        }
        Quantity::W | Quantity::Q => {
            "a run in which heave velocity and pitch rate vary more and out of step"
        }
        Quantity::P if has(Quantity::Rudder) => {
            "a run with more roll rate: a harder or faster horizontal zig-zag (the body rolls in \
             and out of each turn)"
        }
        Quantity::P => "a run with more roll rate",
        _ => "a change of speed (an rpm or thrust step, an acceleration run)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn added_mass_names_are_read_from_the_sname_convention() {
        assert_eq!(acceleration_term("Nrd"), Some('r'));
        assert_eq!(acceleration_term("Yvd"), Some('v'));
        assert_eq!(acceleration_term("Mqdot"), Some('q'));
        assert_eq!(acceleration_term("Xudot"), Some('u'));
        for other in ["Nr", "Ndr", "Yvvd", "Kd", "Xuu", "Nuvd", "Md", "inv_T"] {
            assert_eq!(acceleration_term(other), None, "{other}");
        }
    }

    #[test]
    fn the_manoeuvre_uses_the_controls_the_vehicle_has() {
        let auv = [Quantity::Rudder, Quantity::SternPlanes, Quantity::Rpm];
        assert!(manoeuvre_for(Quantity::R, &auv).contains("zig-zag on the rudder"));
        assert!(manoeuvre_for(Quantity::Q, &auv).contains("stern"));
        let spheroid = [Quantity::Thrust];
        assert!(!manoeuvre_for(Quantity::R, &spheroid).contains("rudder zig"));
        assert!(manoeuvre_for(Quantity::V, &spheroid).contains("initial drift"));
        assert!(!manoeuvre_for(Quantity::P, &spheroid).contains("zig-zag"));
    }
}
