//! The static polar stage: fits, their quality, the agreement between speeds.

use super::fmt::{opt, serde_name};
use super::Figures;
use crate::app::report::doc::{text, Col, Document, Table};
use crate::base::numfmt::num;
use crate::stages::polar::{ChannelFit, PolarResult};

fn constants(f: &ChannelFit) -> String {
    f.names
        .iter()
        .zip(&f.values)
        .zip(&f.std_errors)
        .zip(&f.units)
        .map(|(((n, v), se), u)| {
            // a constant held by an active constraint has no variance: not "± 0"
            let se = match se {
                Some(s) if *s == 0.0 => " (held)".to_string(),
                Some(s) => format!(" ± {}", num(*s)),
                None => String::new(),
            };
            format!("{n} = {}{se} {u}", num(*v))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The fitted channels: model, constants, points, R², residual SD and active constraints
/// (binding ones marked).
fn fits_table(p: &PolarResult) -> Table {
    let mut t = Table::new([
        "channel",
        "model",
        "constants ± SE",
        "points",
        "R²",
        "residual SD",
        "active constraints",
    ])
    .col(1, Col::Text)
    .col(2, Col::Text)
    .col(3, Col::Num)
    .col(4, Col::Num)
    .col(5, Col::Num)
    .col(6, Col::Text);
    for f in [&p.pooled.drag, &p.pooled.lift, &p.pooled.moment] {
        let mut active = f.active_constraints.clone();
        for b in &f.binding_inequalities {
            if let Some(a) = active.iter_mut().find(|a| *a == b) {
                a.push_str(" (binding: the data pull against it)");
            }
        }
        t.row([
            f.channel.clone(),
            f.model.clone(),
            constants(f),
            f.n_points.to_string(),
            f.r_squared
                .map_or_else(|| "-".into(), |r| format!("{r:.5}")),
            opt(f.residual_std),
            if active.is_empty() {
                "none".into()
            } else {
                active.join("; ")
            },
        ]);
    }
    t
}

/// The section comparing each speed fitted alone with the pooled fit.
fn speeds_agreement(d: &mut Document<'_>, p: &PolarResult) {
    d.heading(3, "Agreement between speeds");
    d.text(
        "Each speed fitted alone. A small p-value says the speeds differ by more than their \
         standard errors explain (a Reynolds-number effect rather than noise).",
    );
    let mut header = vec!["coefficient".to_string(), "unit".into()];
    header.extend(
        p.per_speed
            .iter()
            .map(|s| format!("U = {} m/s", num(s.speed))),
    );
    header.extend(["pooled".to_string(), "χ² (dof)".into(), "p-value".into()]);
    let mut t = Table::new(header).numeric_from(2);
    for s in &p.spread {
        let mut row = vec![s.name.clone(), s.unit.clone()];
        row.extend(
            s.values
                .iter()
                .zip(&s.sigmas)
                .map(|(v, e)| super::fmt::pm(*v, *e)),
        );
        let pooled = p.coefficients.iter().find(|c| c.name == s.name);
        row.push(pooled.map_or("-".into(), |c| super::fmt::pm(c.value, c.sigma)));
        row.push(s.chi2.map_or("-".into(), |c| format!("{c:.2} ({})", s.dof)));
        row.push(s.p_value.map_or("-".into(), super::fmt::p_value));
        if s.p_value.is_some_and(|v| v < 0.01) {
            t.marked_row(row);
        } else {
            t.row(row);
        }
    }
    d.table(t);
}

/// Writes the static polars' section: the fits, the yaw moment's reading, the agreement
/// between speeds and the warnings.
pub fn write<'a>(d: &mut Document<'a>, p: &PolarResult, word: &str, figs: &Figures<'a>) {
    d.heading(2, "Static polars");
    let rf = &p.reference;
    d.text(format!(
        "Constrained least squares on the steady {word} points (data as {}, {} axes, {} \
         weights, fitting range {}), each channel separately; standard errors from the \
         residual variance; a constant an active constraint holds is marked (held): it is \
         imposed, not estimated.",
        serde_name(&rf.data),
        serde_name(&rf.axes),
        serde_name(&rf.weights),
        rf.alpha_max_deg
            .map_or_else(|| "all angles".into(), |a| format!("|α| ≤ {} deg", num(a)))
    ));
    let t = fits_table(p);
    d.table(t);
    d.text(format!(
        "Yaw moment (polar.moment.part = \"{}\"): {}.",
        rf.moment,
        rf.moment.statement()
    ));
    if p.per_speed.len() > 1 && !p.spread.is_empty() {
        speeds_agreement(d, p);
    }
    if !p.warnings.is_empty() {
        d.list(
            p.warnings
                .iter()
                .map(|w| vec![text(format!("{}. {}", w.message, w.meaning))])
                .collect(),
        );
    }
    figs.put(d, "polar");
}
