//! From fitted polar constants to manoeuvring coefficients (paper eq. 5, after Ridley, Fontan
//! & Corke 2003), with standard deviations from the covariance of the constants.
//!
//! With q = 0.5 rho A_ref (kg/m) and L_ref the moment reference length:
//!
//! ```text
//! Xuu = -q c          Xuv = -q b          Xvv = -q (a + c/2)      Yvv = q b
//! Yuvd = q c          Yuvl = q C_La       Nuvl = q L_ref C_Ma
//! ```
//!
//! That last line is the paper's lift-only reading of C_M. A CFD static drift run measures the
//! whole yaw moment, Munk moment included, so in the total reading (`polar.moment.part`, the
//! default) the slope gives the total coefficient instead: Nuv = q L_ref C_Ma.
//!
//! The paper refers C_M to A_f alone (effective L_ref = 1 m). Every coefficient is a linear
//! combination g'x of one channel's constants, so its variance is g' Cov g.

use super::ChannelFit;
use crate::model::coefficients::{directions_of, Coefficient, Direction, Source, YawMoment};

/// One coefficient of eq. 5 as a linear combination of a channel's constants.
struct Map {
    name: &'static str,
    channel: Channel,
    /// (factor, constant name); the coefficient is q * scale * sum(factor * constant).
    terms: &'static [(f64, &'static str)],
    /// Multiply by L_ref as well.
    moment: bool,
    relation: &'static str,
}

#[derive(Clone, Copy)]
enum Channel {
    Drag,
    Lift,
    Moment,
}

const MAPS: &[Map] = &[
    Map {
        name: "Xuu",
        channel: Channel::Drag,
        terms: &[(-1.0, "c")],
        moment: false,
        relation: "paper eq. 5: Xuu = -q c",
    },
    Map {
        name: "Xuv",
        channel: Channel::Drag,
        terms: &[(-1.0, "b")],
        moment: false,
        relation: "paper eq. 5: Xuv = -q b",
    },
    Map {
        name: "Xvv",
        channel: Channel::Drag,
        terms: &[(-1.0, "a"), (-0.5, "c")],
        moment: false,
        relation: "paper eq. 5: Xvv = -q (a + c/2)",
    },
    Map {
        name: "Yvv",
        channel: Channel::Drag,
        terms: &[(1.0, "b")],
        moment: false,
        relation: "paper eq. 5: Yvv = q b",
    },
    Map {
        name: "Yuvd",
        channel: Channel::Drag,
        terms: &[(1.0, "c")],
        moment: false,
        relation: "paper eq. 5: Yuvd = q c",
    },
    Map {
        name: "Yuvl",
        channel: Channel::Lift,
        terms: &[(1.0, "slope")],
        moment: false,
        relation: "paper eq. 5: Yuvl = q C_La",
    },
    Map {
        name: "Nuvl",
        channel: Channel::Moment,
        terms: &[(1.0, "slope")],
        moment: true,
        relation: "paper eq. 5: Nuvl = q L_ref C_Ma",
    },
];

/// The moment map in the total reading: the same slope, the whole yaw moment.
const TOTAL_MOMENT: Map = Map {
    name: "Nuv",
    channel: Channel::Moment,
    terms: &[(1.0, "slope")],
    moment: true,
    relation: "total yaw-moment slope, Munk moment included: Nuv = q L_ref C_Ma",
};

/// The maps of eq. 5 in the reading `part` of C_M.
fn maps(part: YawMoment) -> impl Iterator<Item = &'static Map> {
    MAPS.iter().map(move |m| match (m.channel, part) {
        (Channel::Moment, YawMoment::Total) => &TOTAL_MOMENT,
        _ => m,
    })
}

/// The coefficients this mapping gives (paper eq. 5) when C_M is the part `part` of the yaw
/// moment.
pub fn provides(part: YawMoment) -> Vec<&'static str> {
    maps(part).map(|m| m.name).collect()
}

/// Each coefficient this mapping gives in either reading of C_M with its relation to the
/// fitted constants (the lift-only moment map first).
pub fn relations() -> Vec<(&'static str, &'static str)> {
    MAPS.iter()
        .chain(std::iter::once(&TOTAL_MOMENT))
        .map(|m| (m.name, m.relation))
        .collect()
}

/// The gradient g of a coefficient with respect to its channel's constants (in `fit.names`
/// order): the coefficient is g'x.
fn gradient(m: &Map, fit: &ChannelFit, q: f64, l_ref: f64) -> Vec<f64> {
    let scale = if m.moment { q * l_ref } else { q };
    fit.names
        .iter()
        .map(|n| {
            m.terms
                .iter()
                .filter(|(_, t)| t == n)
                .map(|(f, _)| f * scale)
                .sum()
        })
        .collect()
}

impl Channel {
    /// The channel's name, as its fit carries it ([`ChannelFit::channel`]).
    fn name(self) -> &'static str {
        match self {
            Channel::Drag => "drag",
            Channel::Lift => "lift",
            Channel::Moment => "moment",
        }
    }
}

/// The coefficients that `part`'s mapping takes from the fit of the channel named `channel`
/// (`drag`, `lift`, `moment`).
pub fn names_from(channel: &str, part: YawMoment) -> Vec<&'static str> {
    maps(part)
        .filter(|m| m.channel.name() == channel)
        .map(|m| m.name)
        .collect()
}

fn channel_fit<'a>(
    m: &Map,
    drag: &'a ChannelFit,
    lift: &'a ChannelFit,
    moment: &'a ChannelFit,
) -> &'a ChannelFit {
    match m.channel {
        Channel::Drag => drag,
        Channel::Lift => lift,
        Channel::Moment => moment,
    }
}

/// The coefficients of paper eq. 5 from the three channel fits; `q` = 0.5 rho A_ref, kg/m;
/// `l_ref` = moment reference length, m; `part`: what C_M holds (total: the slope gives Nuv,
/// lift-only: Nuvl).
pub fn coefficients(
    drag: &ChannelFit,
    lift: &ChannelFit,
    moment: &ChannelFit,
    q: f64,
    l_ref: f64,
    part: YawMoment,
) -> Vec<Coefficient> {
    maps(part)
        .map(|m| {
            let fit = channel_fit(m, drag, lift, moment);
            let g = gradient(m, fit, q, l_ref);
            let value: f64 = g.iter().zip(&fit.values).map(|(g, x)| g * x).sum();
            let sigma = fit.covariance.as_ref().map(|cov| {
                let mut var = 0.0;
                for (i, gi) in g.iter().enumerate() {
                    for (j, gj) in g.iter().enumerate() {
                        var += gi * cov[i][j] * gj;
                    }
                }
                var.max(0.0).sqrt()
            });
            let note = if m.moment {
                format!("{}, q = {q:.6} kg/m, L_ref = {l_ref} m", m.relation)
            } else {
                format!("{}, q = 0.5 rho A_ref = {q:.6} kg/m", m.relation)
            };
            // a fit with as many free constants as points has no residual to measure its
            // noise by: the sigma is not zero but undetermined, and the note says so
            let note = if fit.covariance.is_none() {
                format!(
                    "{note}; sigma undetermined: the {} fit has {} points for its free \
                     constants (no degree of freedom)",
                    fit.channel, fit.n_points
                )
            } else {
                note
            };
            let c = Coefficient::new(m.name, value + 0.0, sigma, Source::Polar).with_note(note);
            // no variance at all: the constants it comes from are held by constraints
            match sigma {
                Some(s) if s == 0.0 && !fit.active_constraints.is_empty() => {
                    c.held(&fit.active_constraints.join("; "))
                }
                _ => c,
            }
        })
        .collect()
}

/// The uncertainty of the coefficients as independent directions: the eigen-directions of
/// each channel's covariance of constants (the channels are fitted separately, so their
/// errors are independent), each mapped through eq. 5 to every coefficient of that channel.
/// Together they reproduce the coefficients' sigmas and their correlations (Xuu and Yuvd,
/// both from c, move together). The moment's directions move Nuv or Nuvl as `part` names it.
pub fn directions(
    drag: &ChannelFit,
    lift: &ChannelFit,
    moment: &ChannelFit,
    q: f64,
    l_ref: f64,
    part: YawMoment,
) -> Vec<Direction> {
    let mut out = Vec::new();
    for (label, fit) in [
        ("polar drag", drag),
        ("polar lift", lift),
        ("polar moment", moment),
    ] {
        let Some(cov) = &fit.covariance else { continue };
        let names: Vec<&str> = fit.names.iter().map(String::as_str).collect();
        for d in directions_of(label, &names, cov) {
            let mut deltas = std::collections::BTreeMap::new();
            for m in maps(part).filter(|m| std::ptr::eq(channel_fit(m, drag, lift, moment), fit)) {
                let g = gradient(m, fit, q, l_ref);
                let delta: f64 = fit
                    .names
                    .iter()
                    .zip(&g)
                    .map(|(n, gi)| gi * d.deltas.get(n).copied().unwrap_or(0.0))
                    .sum();
                if delta != 0.0 {
                    deltas.insert(m.name.to_string(), delta);
                }
            }
            if !deltas.is_empty() {
                out.push(Direction {
                    source: d.source,
                    deltas,
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(channel: &str, names: &[&str], values: &[f64], sd: f64) -> ChannelFit {
        let n = names.len();
        ChannelFit {
            channel: channel.into(),
            model: String::new(),
            names: names.iter().map(|s| s.to_string()).collect(),
            units: vec![String::new(); n],
            values: values.to_vec(),
            std_errors: vec![Some(sd); n],
            covariance: Some(
                (0..n)
                    .map(|i| (0..n).map(|j| if i == j { sd * sd } else { 0.0 }).collect())
                    .collect(),
            ),
            active_constraints: Vec::new(),
            binding_inequalities: Vec::new(),
            n_points: 10,
            dof: 8,
            rss: 0.0,
            residual_std: None,
            r_squared: None,
            residuals: Vec::new(),
        }
    }

    #[test]
    fn the_moment_slope_gives_nuv_when_total_and_nuvl_when_lift_only() {
        let drag = fit("drag", &["a", "b", "c"], &[0.293, -0.0273, 0.0826], 1e-3);
        let lift = fit("lift", &["intercept", "slope"], &[0.0, -1.013], 1e-2);
        let moment = fit("moment", &["intercept", "slope"], &[0.0, -0.56], 0.02);
        let (q, l_ref) = (16.1, 1.2);
        for (part, name, other) in [
            (YawMoment::Total, "Nuv", "Nuvl"),
            (YawMoment::LiftOnly, "Nuvl", "Nuv"),
        ] {
            let cs = coefficients(&drag, &lift, &moment, q, l_ref, part);
            let c = cs.iter().find(|c| c.name == name).expect(name);
            assert!(
                cs.iter().all(|c| c.name != other),
                "{part}: {other} given too"
            );
            // q L_ref C_Ma, sigma q L_ref SE(C_Ma)
            assert!((c.value - q * l_ref * -0.56).abs() < 1e-12, "{}", c.value);
            assert!((c.sigma.unwrap() - q * l_ref * 0.02).abs() < 1e-12);
            assert_eq!(provides(part).iter().filter(|n| **n == name).count(), 1);
            let ds = directions(&drag, &lift, &moment, q, l_ref, part);
            let moved: Vec<&str> = ds
                .iter()
                .filter(|d| d.source.starts_with("polar moment"))
                .flat_map(|d| d.deltas.keys().map(String::as_str))
                .collect();
            assert!(
                !moved.is_empty() && moved.iter().all(|n| *n == name),
                "{moved:?}"
            );
        }
        let total = coefficients(&drag, &lift, &moment, q, l_ref, YawMoment::Total);
        let note = total.iter().find(|c| c.name == "Nuv").unwrap().note.clone();
        assert!(note.unwrap().contains("Munk moment included"));
    }

    /// A constant an active constraint holds has no variance: the coefficients it alone
    /// gives are held, without a sigma (not "0 ± 0"), and their note names the constraint.
    #[test]
    fn a_constant_held_by_a_constraint_gives_held_coefficients_not_zero_sigmas() {
        let mut drag = fit("drag", &["a", "b", "c"], &[0.293, 0.0, 0.0826], 1e-3);
        if let Some(cov) = drag.covariance.as_mut() {
            cov[1][1] = 0.0;
        }
        drag.active_constraints = vec!["b = 0 (polar.drag.symmetric)".into()];
        let lift = fit("lift", &["intercept", "slope"], &[0.0, -1.013], 1e-2);
        let moment = fit("moment", &["intercept", "slope"], &[0.0, -0.56], 0.02);
        let cs = coefficients(&drag, &lift, &moment, 16.1, 1.2, YawMoment::LiftOnly);
        for name in ["Xuv", "Yvv"] {
            let c = cs.iter().find(|c| c.name == name).expect(name);
            assert!(c.is_held() && c.sigma.is_none(), "{name}: {c:?}");
            assert!(
                c.note.as_deref().unwrap().contains("polar.drag.symmetric"),
                "{c:?}"
            );
        }
        let xuu = cs.iter().find(|c| c.name == "Xuu").unwrap();
        assert!(!xuu.is_held() && xuu.sigma.is_some_and(|s| s > 0.0));
    }
}
