//! The hybrid EKF stage: settings and tuning, fixed coefficients, the estimate after each
//! pass, measurement noise and innovation consistency.

use super::fmt::{opt, pct, pm};
use super::Figures;
use crate::app::report::doc::{text, Col, Document, Table};
use crate::app::results::CORRELATED;
use crate::base::numfmt::num;
use crate::stages::hekf::HekfResult;

pub fn write<'a>(d: &mut Document<'a>, h: &HekfResult, figs: &Figures<'a>) {
    d.heading(2, "Hybrid extended Kalman filter");
    let s = &h.settings;
    d.text(format!(
        "Model {}, {} filter, tuning preset {}: {} pass{}, {} RK4 sub-step{} per sample, smoother {}{}. \
         The estimated coefficients are appended to the state (paper eq. 22); every other \
         coefficient is held at the value below.",
        h.model,
        s.filter,
        h.preset,
        s.passes,
        if s.passes == 1 { "" } else { "es" },
        s.substeps,
        if s.substeps == 1 { "" } else { "s" },
        if s.smoother { "on" } else { "off" },
        if s.decimate > 1 {
            format!(
                ", one sample in {} of each run used (hekf.decimate)",
                s.decimate
            )
        } else {
            String::new()
        }
    ));
    d.heading(3, "Tuning choices");
    let mut items: Vec<_> = h.tuning.iter().map(|t| vec![text(t.clone())]).collect();
    let nb = h.estimated.len();
    if s.process_noise.len() >= nb {
        let (states, coefs) = s.process_noise.split_at(s.process_noise.len() - nb);
        items.push(vec![text(format!(
            "Process noise spectral density (SI²/s, in state order): states {}; coefficients {}.",
            states
                .iter()
                .map(|v| num(*v))
                .collect::<Vec<_>>()
                .join(", "),
            coefs.iter().map(|v| num(*v)).collect::<Vec<_>>().join(", ")
        ))]);
    }
    d.list(items);
    fixed(d, h);
    passes(d, h);
    figs.put(d, "hekf_convergence");
    correlation(d, h);
    figs.put(d, "hekf_correlation");
    identifiability(d, h);
    modes(d, h);
    noise(d, h);
    nis(d, h);
    figs.put_prefixed(d, "nis_fit_");
}

fn fixed(d: &mut Document, h: &HekfResult) {
    d.heading(3, "Fixed coefficients");
    let mut t =
        Table::new(["coefficient", "value ± σ", "unit", "source", "note"]).col(4, Col::Text);
    for c in &h.fixed {
        t.row([
            c.name.clone(),
            pm(c.value, c.sigma),
            c.unit.clone(),
            c.source.to_string(),
            c.note.clone().unwrap_or_default(),
        ]);
    }
    d.table(t);
}

fn passes(d: &mut Document, h: &HekfResult) {
    d.heading(3, "Estimates after each pass");
    let mut header = vec!["coefficient".to_string(), "unit".into()];
    header.extend(h.passes.iter().map(|p| format!("pass {}", p.pass)));
    header.extend([
        "final ± σ (total)".to_string(),
        "σ from the data alone".into(),
    ]);
    let mut t = Table::new(header).numeric_from(2);
    for (j, c) in h.coefficients.iter().enumerate() {
        let mut row = vec![c.name.clone(), c.unit.clone()];
        row.extend(h.passes.iter().map(|p| opt(p.values.get(j).copied())));
        row.push(pm(c.value, c.sigma));
        row.push(opt(h.sigma_filter.get(j).copied()));
        t.row(row);
    }
    d.table(t);
    d.text(
        "The total σ adds to the filter's own (from the data, with the fixed coefficients taken \
         as exact) the change of the estimate when each uncertain fixed coefficient moves by \
         its σ (consider analysis: the filter re-run per direction).",
    );
}

fn correlation(d: &mut Document, h: &HekfResult) {
    let c = &h.correlation;
    let mut pairs = Vec::new();
    for i in 0..c.names.len() {
        for j in i + 1..c.names.len() {
            let rho = c.matrix[i][j];
            if rho.abs() > CORRELATED {
                pairs.push(format!("{} and {} ({rho:+.2})", c.names[i], c.names[j]));
            }
        }
    }
    if pairs.is_empty() {
        d.text(format!(
            "No two estimates are correlated above {CORRELATED}: the data separate them."
        ));
    } else {
        d.text(format!(
            "Strongly correlated pairs (|ρ| > {CORRELATED}): {}. This manoeuvre does not \
             separate them well: an error in one is compensated by the other, and a second, \
             different manoeuvre would.",
            pairs.join(", ")
        ));
    }
}

fn identifiability(d: &mut Document, h: &HekfResult) {
    d.heading(3, "Identifiability");
    if h.identifiability.is_empty() {
        d.text(
            "Every estimate is determined by these runs: no σ above 10 % of its value, and no \
             correlation above 0.9 with a σ above 2 %.",
        );
        return;
    }
    d.text(
        "The estimates these runs leave undetermined (σ above 10 % of the value, or a \
         correlation above 0.9 with a σ above 2 %), the quantities each term acts through \
         (those whose removal removes the term's effect on the motion, found by automatic \
         differentiation along the filtered states), how much of them the runs hold, and a \
         manoeuvre that would determine it. Several runs identified jointly share the \
         coefficients: add such a run to [[hekf.runs]].",
    );
    let mut t = Table::new([
        "coefficient",
        "finding",
        "acts through",
        "in these runs",
        "why",
        "would be determined by",
    ])
    .col(1, Col::Text)
    .col(3, Col::Text)
    .col(4, Col::Text)
    .col(5, Col::Text);
    for a in &h.identifiability {
        t.row([
            a.coefficient.clone(),
            a.finding.clone(),
            a.acts_through.join(", "),
            a.in_these_runs.clone(),
            a.why.clone(),
            a.separate_by.clone(),
        ]);
    }
    d.table(t);
}

/// Joint mode beside consider mode, coefficient by coefficient.
fn modes(d: &mut Document, h: &HekfResult) {
    let Some(m) = &h.modes else { return };
    d.heading(3, "Joint and consider estimates");
    d.text(
        "The same runs identified twice: in consider mode the HEKF starts from its own prior \
         (what the free-running runs give on their own, the earlier stages' estimates of these \
         coefficients not used), in joint mode the earlier stage's estimate and covariance \
         are the prior (the result above). \"Pinned by\" says which data fix the \
         coefficient: the stage whose σ is less than half the other's, or both.",
    );
    let mut t = Table::new([
        "coefficient",
        "earlier stage",
        "stage value ± σ",
        "consider (runs alone) ± σ",
        "joint ± σ",
        "pinned by",
    ])
    .col(1, Col::Text)
    .col(5, Col::Text);
    let pm = |(v, s): (f64, f64)| format!("{} ± {}", num(v), num(s));
    for r in &m.rows {
        t.row([
            r.name.clone(),
            r.stage.clone().unwrap_or_else(|| "-".into()),
            r.stage_estimate.map_or_else(|| "-".into(), pm),
            format!(
                "{}{}",
                pm(r.consider),
                if r.undetermined_by_runs {
                    " (not determined)"
                } else {
                    ""
                }
            ),
            pm(r.joint),
            r.pinned_by.clone(),
        ]);
    }
    d.table(t);
}

fn noise(d: &mut Document, h: &HekfResult) {
    d.heading(3, "Measurement noise");
    let mut t = Table::new([
        "run",
        "quantity",
        "σ used",
        "unit",
        "source",
        "innovation RMS (last pass)",
    ])
    .col(0, Col::Text)
    .col(2, Col::Num)
    .col(5, Col::Num);
    for run in &h.runs {
        for (k, n) in run.noise.iter().enumerate() {
            let i = run
                .measured
                .iter()
                .position(|m| m == n.quantity.key())
                .and_then(|i| run.innovation_rms.get(i).copied())
                .or_else(|| run.innovation_rms.get(k).copied());
            t.row([
                run.name.clone(),
                n.quantity.key().to_string(),
                num(n.sigma),
                n.quantity.si_symbol().to_string(),
                n.source.clone(),
                opt(i),
            ]);
        }
    }
    d.table(t);
    let between: Vec<String> = h
        .runs
        .iter()
        .filter(|r| !r.between.is_empty())
        .map(|r| {
            let rules: Vec<String> = r.between.iter().map(|(q, b)| format!("{q} {b}")).collect();
            format!("{}: {}", r.name, rules.join(", "))
        })
        .collect();
    if !between.is_empty() {
        d.text(format!(
            "Inputs between samples (`between`, docs/config.md): {}.",
            between.join("; ")
        ));
    }
}

fn nis(d: &mut Document, h: &HekfResult) {
    d.heading(3, "Innovation consistency (NIS)");
    d.text(
        "For a consistent filter the normalised innovation squared of a sample is χ² with as \
         many degrees of freedom as measurements, its mean over K samples lies in the 95 % \
         bounds below, and about 5 % of the samples fall outside the per-sample bounds \
         (Bar-Shalom, Li & Kirubarajan 2001, section 5.4). A mean above its bounds says the \
         innovations are larger than the noise model allows (model error or noise set too \
         small), below says the noise is set too large.",
    );
    let mut t = Table::new([
        "run",
        "dof",
        "samples",
        "mean NIS",
        "95 % bounds of the mean",
        "95 % bounds per sample",
        "outside",
        "consistent",
    ])
    .numeric_from(1)
    .col(0, Col::Text)
    .col(7, Col::Tag);
    for run in &h.runs {
        let Some(n) = &run.nis else { continue };
        let row = [
            run.name.clone(),
            n.dof.to_string(),
            n.samples.to_string(),
            num(n.mean),
            format!("{} to {}", num(n.mean_bounds[0]), num(n.mean_bounds[1])),
            format!("{} to {}", num(n.sample_bounds[0]), num(n.sample_bounds[1])),
            pct(n.fraction_outside),
            if n.consistent { "yes" } else { "no" }.to_string(),
        ];
        if n.consistent {
            t.row(row);
        } else {
            t.marked_row(row);
        }
    }
    d.table(t);
}
