//! The identified model re-simulated open loop against every run.

use super::fmt::{deg, opt};
use super::Figures;
use crate::quantity::Quantity;
use crate::report::doc::{strong, text, Col, Document, Table};
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
    manoeuvres(d, r);
    if let Some(a) = &r.autopilot {
        d.heading(3, "Autopilot in waves");
        d.text(format!(
            "A PID heading autopilot tuned from the identified K = {:.4} 1/s and T = {:.2} s by \
             pole placement (w_n = {} rad/s, zeta = {}: K_p = {:.3}, K_d = {:.3} s, K_i = {:.4} \
             1/s), with a third-order heading reference model, closed around the identified \
             model in the same waves: once fed the raw compass and gyro, once the wave \
             filter's low-frequency heading and yaw rate (the hybrid EKF on the same model, \
             run online). Heading error is the low-frequency heading's from the reference.",
            a.k,
            a.t,
            crate::numfmt::num(a.gains.omega_n),
            crate::numfmt::num(a.gains.zeta),
            a.gains.kp,
            a.gains.kd,
            a.gains.ki
        ));
        let mut t = Table::new([
            "autopilot fed",
            "heading error RMS (deg)",
            "rudder RMS (deg)",
            "rudder rate RMS (deg/s)",
        ])
        .numeric_from(1)
        .col(0, Col::Text);
        for (what, c) in [
            ("raw compass and gyro", &a.raw),
            ("wave filter", &a.filtered),
        ] {
            t.row([
                what.to_string(),
                format!("{:.3}", c.heading_error_rms.to_degrees()),
                format!("{:.3}", c.rudder_rms.to_degrees()),
                format!("{:.3}", c.rudder_rate_rms.to_degrees()),
            ]);
        }
        d.table(t);
        figs.put(d, "autopilot");
        figs.put(d, "heading_spectrum");
    }
    if let Some(s) = &r.steering {
        d.heading(3, "Steering indices (Nomoto)");
        d.text(format!(
            "Nomoto's indices of the identified model ({}; Fossen 2011, 7.1-7.2): {}. The \
             sigmas carry the coefficients' uncertainties and correlations. A zig-zag \
             identified directly with a Nomoto model gives K and T to compare.",
            s.at,
            s.text()
        ));
    }
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

/// Each ship manoeuvre beside the identified model's, steered the same way, with the IMO
/// criteria.
fn manoeuvres(d: &mut Document<'_>, r: &RunResult) {
    let runs: Vec<_> = r
        .resimulation
        .iter()
        .filter_map(|m| m.manoeuvre.as_ref().map(|c| (m, c)))
        .collect();
    if runs.is_empty() {
        return;
    }
    d.heading(3, "Manoeuvres");
    d.text(
        "Each turning circle and zig-zag measured as the IMO explanatory notes (MSC/Circ.1053) \
         and ITTC 7.5-04-02-01 define them, beside the identified model sailing the same \
         manoeuvre: steered by the helm from the run's first state with the run's rudder \
         angle, execute heading, rudder rate and execute time, and the run's propeller \
         (docs/manoeuvres.md). The limits are the IMO criteria (MSC.137(76) 5.3); a value \
         marked (fail) exceeds its limit.",
    );
    for (m, cmp) in runs {
        d.para([
            strong(format!("{}: {}", m.run, cmp.measured.kind())),
            text(format!(
                " ({}); the model steered with {}.",
                if m.used_for_fit {
                    "fit run"
                } else {
                    "validation run"
                },
                cmp.steering_text()
            )),
        ]);
        let c = cmp.table();
        let mut t = Table::new(crate::manoeuvre::ComparisonTable::HEADER)
            .numeric_from(2)
            .col(0, Col::Text)
            .col(1, Col::Text)
            .col(4, Col::Text);
        for row in c.cells() {
            t.row(row);
        }
        d.table(t);
        d.list(c.notes.iter().map(|n| vec![text(n.clone())]).collect());
        if let Some(note) = &cmp.model_note {
            d.text(format!("Identified model: {note}."));
        }
    }
}
