//! Nomoto's steering indices and the linear course stability of any manoeuvring model with
//! a rudder: the sway-yaw equations linearised about straight motion at speed U (Fossen
//! 2011, Handbook of Marine Craft Hydrodynamics and Motion Control, 7.1 and 7.2: the linear
//! manoeuvring model and Nomoto's second- and first-order models), so that a hull model
//! identified from turning circles can be compared with K and T identified from a zig-zag.
//!
//! With nu = [v, r] and the rudder delta, the model's own dynamics give
//! nu_dot = A nu + b delta (A = d nu_dot / d nu by automatic differentiation, b by a central
//! difference in the rudder: the models take their inputs as plain numbers), and
//!
//! ```text
//! r / delta = K (1 + T3 s) / ((1 + T1 s)(1 + T2 s))               (Fossen 2011, 7.2)
//! T1 T2 = 1 / det A,  T1 + T2 = -tr A / det A,
//! K = (a21 b_v - a11 b_r) / det A,  K T3 = b_r / det A,
//! first order: T = T1 + T2 - T3                                    (Fossen 2011, 7.2)
//! ```
//!
//! The ship is course-stable (straight-line stable) when det A > 0 and tr A < 0, i.e. both
//! time constants positive (Fossen 2011, 7.1, the straight-line stability criterion).

use crate::base::quantity::Quantity;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::Model;
use serde::Serialize;

/// Nomoto's indices at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Nomoto {
    /// Speed of the straight motion linearised about, m/s (None for a Nomoto model, which
    /// holds K and T as coefficients).
    pub speed: Option<f64>,
    /// Steady-turn gain K, 1/s (yaw rate per rudder angle; positive when a positive rudder
    /// turns to a positive yaw rate).
    pub k: f64,
    /// First-order time constant T = T1 + T2 - T3, s.
    pub t: f64,
    /// T1, s (the larger root; None when the sway-yaw poles are complex).
    pub t1: Option<f64>,
    /// T2, s.
    pub t2: Option<f64>,
    /// T3, s.
    pub t3: f64,
    /// Whether the straight motion is stable (det A > 0 and tr A < 0).
    pub course_stable: bool,
}

/// The linear sway-yaw system about straight motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwayYaw {
    /// Speed, m/s.
    pub speed: f64,
    /// d[v_dot, r_dot] / d[v, r], row-major.
    pub a: [[f64; 2]; 2],
    /// d[v_dot, r_dot] / d delta.
    pub b: [f64; 2],
}

/// Why a model has no Nomoto indices.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct NotSteerable(pub String);

/// The linear sway-yaw system of `model` with coefficients `c` about the straight motion at
/// the state `x` (its sway and yaw rate are set to zero) with the inputs `inputs` (the
/// rudder is set to zero; a propeller keeps its value).
pub fn sway_yaw<M: Model>(
    model: &M,
    c: &[f64],
    x: &[f64],
    inputs: &[f64],
) -> Result<SwayYaw, NotSteerable> {
    let index = |q: Quantity| {
        model
            .state_index(q)
            .ok_or_else(|| NotSteerable(format!("the model {} has no {q} state", model.name())))
    };
    let (iu, iv, ir) = (
        index(Quantity::U)?,
        index(Quantity::V)?,
        index(Quantity::R)?,
    );
    let id = model
        .input_quantities()
        .iter()
        .position(|q| *q == Quantity::Rudder)
        .ok_or_else(|| NotSteerable(format!("the model {} has no rudder", model.name())))?;
    let mut x0 = x.to_vec();
    x0[iv] = 0.0;
    x0[ir] = 0.0;
    let mut u0 = inputs.to_vec();
    u0[id] = 0.0;
    let n = x0.len();
    let (mut f, mut jac) = (vec![0.0; n], vec![0.0; n * n]);
    crate::numerics::ad::jacobian(
        &x0,
        n,
        |xd, out| {
            let cd: Vec<_> = c
                .iter()
                .map(|&v| crate::numerics::ad::constant(v))
                .collect();
            model.derivatives(xd, &u0, &cd, out);
        },
        &mut f,
        &mut jac,
    );
    // d nu_dot / d delta by a central difference (0.1 deg: the forces are smooth in the
    // rudder angle about amidships)
    let h = 0.1f64.to_radians();
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    let mut up = u0.clone();
    up[id] = h;
    model.derivatives(&x0, &up, c, &mut fp);
    up[id] = -h;
    model.derivatives(&x0, &up, c, &mut fm);
    let a = [
        [jac[iv * n + iv], jac[iv * n + ir]],
        [jac[ir * n + iv], jac[ir * n + ir]],
    ];
    let b = [(fp[iv] - fm[iv]) / (2.0 * h), (fp[ir] - fm[ir]) / (2.0 * h)];
    if a.iter().flatten().chain(&b).any(|v| !v.is_finite()) {
        return Err(NotSteerable(
            "the linearised sway-yaw equations are not finite at this speed".into(),
        ));
    }
    Ok(SwayYaw {
        speed: x0[iu],
        a,
        b,
    })
}

impl SwayYaw {
    /// Nomoto's indices (Fossen 2011, 7.2), or why there are none (a rudder that
    /// moves no yaw, a singular system).
    pub fn nomoto(&self) -> Result<Nomoto, NotSteerable> {
        let [[a11, a12], [a21, a22]] = self.a;
        let [bv, br] = self.b;
        let det = a11 * a22 - a12 * a21;
        let tr = a11 + a22;
        let gain_num = a21 * bv - a11 * br;
        if det == 0.0 || gain_num == 0.0 {
            return Err(NotSteerable(
                "the linear sway-yaw system has no steady turn (det A = 0 or no rudder \
                 moment): K is not defined"
                    .into(),
            ));
        }
        let (sum, prod) = (-tr / det, 1.0 / det);
        let disc = sum * sum - 4.0 * prod;
        let (t1, t2) = if disc >= 0.0 {
            let s = disc.sqrt();
            (Some(0.5 * (sum + s)), Some(0.5 * (sum - s)))
        } else {
            (None, None)
        };
        let t3 = br / gain_num;
        Ok(Nomoto {
            speed: Some(self.speed),
            k: gain_num / det,
            t: sum - t3,
            t1,
            t2,
            t3,
            course_stable: det > 0.0 && tr < 0.0,
        })
    }
}

/// Nomoto's indices with one-sigma uncertainties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SteeringIndices {
    /// The indices.
    #[serde(flatten)]
    pub nomoto: Nomoto,
    /// One-sigma uncertainty of K, 1/s (None when the coefficients carry none).
    pub k_sigma: Option<f64>,
    /// One-sigma uncertainty of T, s.
    pub t_sigma: Option<f64>,
    /// Where they come from: "linearised at the approach of run 'turn' (u = 1.179 m/s, rpm
    /// 710.8)".
    pub at: String,
}

impl SteeringIndices {
    /// In words: "K = -1.107 +- 0.032 1/s, T = -86.7 +- 2.1 s (T1 = 2.09 s, T2 = -83.5 s,
    /// T3 = 5.33 s): course-unstable".
    pub fn text(&self) -> String {
        let n = &self.nomoto;
        let pm = |v: f64, s: Option<f64>| match s {
            Some(s) => format!(
                "{} ± {}",
                crate::base::numfmt::num(v),
                crate::base::numfmt::num(s)
            ),
            None => crate::base::numfmt::num(v),
        };
        let roots = match (n.t1, n.t2) {
            (Some(a), Some(b)) => format!(
                " (T1 = {} s, T2 = {} s, T3 = {} s)",
                crate::base::numfmt::num(a),
                crate::base::numfmt::num(b),
                crate::base::numfmt::num(n.t3)
            ),
            (Some(_), None) => String::new(),
            _ => format!(
                " (complex sway-yaw poles, T3 = {} s)",
                crate::base::numfmt::num(n.t3)
            ),
        };
        format!(
            "K = {} 1/s, T = {} s{roots}: {}",
            pm(n.k, self.k_sigma),
            pm(n.t, self.t_sigma),
            if n.course_stable {
                "course-stable"
            } else {
                "course-unstable (a negative time constant: the ship needs the rudder to keep \
                 a straight course)"
            }
        )
    }
}

/// Nomoto's indices of `model` with the coefficients of `set` about the state `x` and the
/// inputs `inputs`, with their sigmas from the set's uncertainty directions (each direction
/// moves the indices linearly; the variances add over directions: the correlations between
/// the coefficients, and the uncertainty of every stage upstream, are carried).
pub fn steering_indices<M: Model>(
    model: &M,
    set: &CoefficientSet,
    x: &[f64],
    inputs: &[f64],
    at: String,
) -> Result<SteeringIndices, NotSteerable> {
    with_sigmas(model, set, at, |c| sway_yaw(model, c, x, inputs)?.nomoto())
}

/// Nomoto's K and T of a model that is itself a Nomoto model ([`Model::nomoto_gains`]),
/// with their sigmas as [`steering_indices`] gives them.
pub fn nomoto_model_indices<M: Model>(
    model: &M,
    set: &CoefficientSet,
) -> Result<SteeringIndices, NotSteerable> {
    with_sigmas(model, set, "its own coefficients K and 1/T".into(), |c| {
        let (k, t) = model
            .nomoto_gains(c)
            .ok_or_else(|| NotSteerable(format!("{} is not a Nomoto model", model.name())))?
            .map_err(NotSteerable)?;
        Ok(Nomoto {
            speed: None,
            k,
            t,
            t1: Some(t),
            t2: None,
            t3: 0.0,
            course_stable: t > 0.0,
        })
    })
}

/// The indices `of` the completed coefficients of `set`, and their sigmas along the set's
/// uncertainty directions.
fn with_sigmas<M: Model>(
    model: &M,
    set: &CoefficientSet,
    at: String,
    of: impl Fn(&[f64]) -> Result<Nomoto, NotSteerable>,
) -> Result<SteeringIndices, NotSteerable> {
    let names = model.coefficient_names();
    let base = crate::dynamics::sim::complete_coefficients(model, set)
        .map_err(|missing| NotSteerable(format!("no value for {}", missing.join(", "))))?;
    let nomoto = of(&base)?;
    let (mut vk, mut vt, mut any) = (0.0, 0.0, false);
    for d in &set.directions {
        let mut c = base.clone();
        let mut moved = false;
        for (i, n) in names.iter().enumerate() {
            if let Some(delta) = d.deltas.get(*n) {
                if !model.is_derived(n) {
                    c[i] += delta;
                    moved = true;
                }
            }
        }
        if !moved {
            continue;
        }
        model.relations().apply(&mut c);
        let moved = of(&c)?;
        vk += (moved.k - nomoto.k).powi(2);
        vt += (moved.t - nomoto.t).powi(2);
        any = true;
    }
    Ok(SteeringIndices {
        nomoto,
        k_sigma: any.then(|| vk.sqrt()),
        t_sigma: any.then(|| vt.sqrt()),
        at,
    })
}

/// Nomoto's indices of the model `name` at the approach of the run `rec` (its states averaged
/// over the samples before the rudder first moves, the propeller at its first sample; sway,
/// yaw rate and rudder zero), or None when the
/// model has no rudder or no sway and yaw states.
pub fn at_approach(
    name: crate::model::models::ModelName,
    vehicle: &crate::model::models::RunVehicle,
    set: &CoefficientSet,
    rec: &crate::io::record::Record,
) -> Option<Result<SteeringIndices, NotSteerable>> {
    struct Visit<'a> {
        set: &'a CoefficientSet,
        rec: &'a crate::io::record::Record,
    }
    impl crate::model::models::ModelVisitor for Visit<'_> {
        type Output = Option<Result<SteeringIndices, NotSteerable>>;
        fn visit<M: Model>(self, model: &M) -> Self::Output {
            let has = |q| model.state_index(q).is_some();
            // a Nomoto model: its own K and T
            if let Ok(c) = crate::dynamics::sim::complete_coefficients(model, self.set) {
                if model.nomoto_gains(&c).is_some() {
                    return Some(nomoto_model_indices(model, self.set));
                }
            }
            let rudder = model.input_quantities().contains(&Quantity::Rudder);
            if !(rudder && has(Quantity::U) && has(Quantity::V) && has(Quantity::R)) {
                return None;
            }
            // the approach: the samples before the rudder first moves by more than 0.1 deg;
            // the states averaged over it (the speed linearised about is then not one noisy
            // sample: 0.02 m/s of log noise on u moved K of a 150 m ship by 1.5 %)
            let approach = self.rec.channel(Quantity::Rudder).map_or(1, |d| {
                d.iter()
                    .position(|v| (v - d[0]).abs() > 0.1f64.to_radians())
                    .unwrap_or(d.len())
                    .max(1)
            });
            let x: Vec<f64> = model
                .states()
                .iter()
                .map(|s| {
                    self.rec.channel(s.quantity).map_or(0.0, |v| {
                        let n = approach.min(v.len()).max(1);
                        v[..n].iter().sum::<f64>() / n as f64
                    })
                })
                .collect();
            let series =
                crate::dynamics::sim::InputSeries::from_record(model.inputs(), self.rec).ok()?;
            let mut u = vec![0.0; series.len()];
            let t0 = self
                .rec
                .time()
                .and_then(|t| t.first().copied())
                .unwrap_or(0.0);
            series.at(t0, &mut u);
            let inputs: Vec<String> = model
                .input_quantities()
                .iter()
                .zip(&u)
                .filter(|(q, _)| **q != Quantity::Rudder)
                .map(|(q, v)| format!("{q} {} {}", crate::base::numfmt::num(*v), q.si_symbol()))
                .collect();
            let speed = model.state_index(Quantity::U).map_or(0.0, |i| x[i]);
            let mut at = format!(
                "linearised at the approach of run '{}' (u = {} m/s",
                self.rec.name,
                crate::base::numfmt::num(speed)
            );
            for i in inputs {
                at.push_str(", ");
                at.push_str(&i);
            }
            at.push(')');
            Some(steering_indices(model, self.set, &x, &u, at))
        }
    }
    crate::model::models::with_model(name, vehicle, Visit { set, rec }).ok()?
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A first-order Nomoto ship written as sway-yaw with no sway coupling:
    /// r_dot = -r / T + K / T delta, v_dot = -v / T_v.
    #[test]
    fn an_uncoupled_system_gives_back_its_k_and_t() {
        let (k, t, tv) = (0.2, 25.0, 4.0);
        let sys = SwayYaw {
            speed: 8.0,
            a: [[-1.0 / tv, 0.0], [0.0, -1.0 / t]],
            b: [0.0, k / t],
        };
        let n = sys.nomoto().unwrap();
        assert!((n.k - k).abs() < 1e-12, "{n:?}");
        // T1 T2 = t tv and T1 + T2 = t + tv; T3 = tv cancels the sway pole: T = t
        assert!((n.t - t).abs() < 1e-9, "{n:?}");
        assert!((n.t1.unwrap() - t).abs() < 1e-9 && (n.t2.unwrap() - tv).abs() < 1e-9);
        assert!(n.course_stable);
    }

    /// Hand-computed: A = [[-0.5, -1.0], [-0.05, -0.4]], b = [0.1, -0.02]:
    /// det = 0.2 - 0.05 = 0.15, tr = -0.9, K = (-0.05*0.1 - 0.5*0.02)/0.15 = -0.1,
    /// T1 + T2 = 6, T1 T2 = 6.667, T3 = -0.02 / (-0.015) = 1.333, T = 4.667.
    #[test]
    fn a_coupled_system_matches_the_hand_computation() {
        let sys = SwayYaw {
            speed: 5.0,
            a: [[-0.5, -1.0], [-0.05, -0.4]],
            b: [0.1, -0.02],
        };
        let n = sys.nomoto().unwrap();
        assert!((n.k + 0.1).abs() < 1e-12, "{n:?}");
        assert!((n.t3 - 4.0 / 3.0).abs() < 1e-12, "{n:?}");
        assert!((n.t - (6.0 - 4.0 / 3.0)).abs() < 1e-12, "{n:?}");
        // 36 - 26.67 > 0: real time constants
        let (t1, t2) = (n.t1.unwrap(), n.t2.unwrap());
        assert!((t1 + t2 - 6.0).abs() < 1e-12 && (t1 * t2 - 1.0 / 0.15).abs() < 1e-9);
    }

    #[test]
    fn an_unstable_ship_is_said_to_be() {
        let sys = SwayYaw {
            speed: 5.0,
            a: [[-0.5, -1.0], [-0.5, -0.4]],
            b: [0.1, -0.02],
        };
        let n = sys.nomoto().unwrap();
        assert!(!n.course_stable, "det < 0: {n:?}");
        let none = SwayYaw {
            speed: 5.0,
            a: [[-0.5, 0.0], [0.0, -0.4]],
            b: [0.0, 0.0],
        };
        assert!(none.nomoto().is_err());
    }
}
