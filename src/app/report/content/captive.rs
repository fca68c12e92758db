//! The captive runs stage: the tables fitted, the residuals and the noise per force component.

use crate::app::report::doc::{text, Col, Document, Table};
use crate::base::numfmt::num;
use crate::stages::captive::CaptiveResult;

pub fn write(d: &mut Document, c: &CaptiveResult) {
    d.heading(2, "Captive runs");
    d.para([text(format!(
        "The {} model's captive forces ({}) fitted to every condition of the captive runs by \
         weighted least squares (Gauss-Newton; a table row weighted by its component's noise, \
         found from the residuals; an averaged force history by the standard error of its \
         mean; a harmonic run by the standard errors of its Fourier parts), {} iterations. The coefficients, with σ from \
         the covariance at the solution, are in the comparison table (source captive) and \
         are held at these values, with their uncertainty, by the later stages.",
        c.model,
        c.forces.join(", "),
        c.iterations
    ))]);
    let mut header = vec!["table".to_string(), "conditions".into()];
    header.extend(c.forces.iter().map(|f| format!("{f} residual RMS")));
    let mut t = Table::new(header).col(0, Col::Text).numeric_from(1);
    for r in &c.runs {
        let mut row = vec![r.name.clone(), r.conditions.to_string()];
        row.extend(r.residual_rms.iter().map(|v| num(*v)));
        t.row(row);
    }
    d.table(t);
    if !c.noise.is_empty() {
        d.text(format!(
            "Noise of each component found by the fit (SI): {}.",
            c.forces
                .iter()
                .zip(&c.noise)
                .map(|(f, n)| format!("{f} {}", num(*n)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    harmonic_runs(d, c);
}

/// The harmonic (PMM) runs: the motion found and the whole periods used.
fn harmonic_runs(d: &mut Document, c: &CaptiveResult) {
    let runs: Vec<_> = c
        .runs
        .iter()
        .filter_map(|r| r.periods.as_ref().map(|p| (r, p)))
        .collect();
    if runs.is_empty() {
        return;
    }
    d.para([text(format!(
        "Harmonic runs: each force history reduced over whole periods of its motion to its \
         mean and the in-phase and quadrature parts of {} harmonics; the time before the \
         first period (captive.average_after) and the incomplete period at the end are not \
         used.",
        crate::stages::captive::harmonic::HARMONICS
    ))]);
    let mut t = Table::new(vec![
        "run".to_string(),
        "oscillating (amplitude, SI)".into(),
        "frequency, Hz".into(),
        "whole periods".into(),
        "used from, s".into(),
        "to, s".into(),
        "not used at the end, s".into(),
    ])
    .col(0, Col::Text)
    .col(1, Col::Text)
    .numeric_from(2);
    for (r, p) in runs {
        t.row(vec![
            r.name.clone(),
            p.oscillating
                .iter()
                .map(|(n, a)| format!("{n} {}", num(*a)))
                .collect::<Vec<_>>()
                .join(", "),
            num(p.frequency),
            p.periods.to_string(),
            num(p.from),
            num(p.to),
            num(p.unused_end),
        ]);
    }
    d.table(t);
}
