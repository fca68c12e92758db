//! The captive runs stage: the tables fitted, the residuals and the noise per force component.

use crate::numfmt::num;
use crate::report::doc::{text, Col, Document, Table};
use crate::stages::captive::CaptiveResult;

pub fn write(d: &mut Document, c: &CaptiveResult) {
    d.heading(2, "Captive runs");
    d.para([text(format!(
        "The {} model's steady forces ({}) fitted to every steady condition of the captive \
         tables by weighted least squares (Gauss-Newton, each force component weighted by its \
         own noise, found from its residuals), {} iterations. The coefficients, with σ from \
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
