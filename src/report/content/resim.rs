//! The identified model re-simulated open loop against every run.

use super::fmt::{deg, opt};
use super::Figures;
use crate::quantity::Quantity;
use crate::report::doc::{Col, Document, Table};
use crate::results::RunResult;

pub fn write<'a>(d: &mut Document<'a>, r: &RunResult, figs: &Figures<'a>) {
    if r.resimulation.is_empty() {
        return;
    }
    d.heading(2, "Re-simulation");
    d.text(
        "The identified model (the final coefficient set) integrated open loop from each run's \
         first sample with the run's own inputs, compared with the CFD: RMS differences over \
         the run and the final position error as a share of the distance travelled. Fit runs \
         were used for identification; validation runs were not, so they show how the model \
         predicts a manoeuvre it has not seen.",
    );
    let mut t = Table::new([
        "run",
        "use",
        "RMS u (m/s)",
        "RMS v (m/s)",
        "RMS r (deg/s)",
        "RMS heading (deg)",
        "distance (m)",
        "final position error (% of distance)",
        "note",
    ])
    .numeric_from(2)
    .col(0, Col::Text)
    .col(8, Col::Text);
    for m in &r.resimulation {
        let rms = |q: Quantity, f: fn(f64) -> f64| opt(m.rms.get(&q).map(|v| f(*v)));
        let row = [
            m.run.clone(),
            if m.used_for_fit { "fit" } else { "validation" }.to_string(),
            rms(Quantity::U, |v| v),
            rms(Quantity::V, |v| v),
            rms(Quantity::R, deg),
            rms(Quantity::Yaw, deg),
            opt(m.distance),
            m.final_position_error_pct
                .map_or("-".into(), |p| format!("{p:.3} %")),
            m.stopped
                .as_ref()
                .map(|s| format!("stopped early: {s}"))
                .unwrap_or_default(),
        ];
        if m.stopped.is_some() {
            t.marked_row(row);
        } else {
            t.row(row);
        }
    }
    d.table(t);
    let (mut n_fit, mut n_val) = (0, 0);
    for m in &r.resimulation {
        let (kind, n) = if m.used_for_fit {
            n_fit += 1;
            ("fit", n_fit)
        } else {
            n_val += 1;
            ("validation", n_val)
        };
        figs.put(d, &format!("track_{kind}_{n}"));
        figs.put(d, &format!("states_{kind}_{n}"));
    }
}
