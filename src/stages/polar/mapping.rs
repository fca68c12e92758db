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
use crate::coefficients::{directions_of, Coefficient, Direction, Source, YawMoment};

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
            Coefficient::new(m.name, value + 0.0, sigma, Source::Polar).with_note(note)
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
            for m in maps(part).filter(|m| std::ptr::eq(channel_fit(m, drag, lift, moment), fit))
            {
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
