//! The identified model re-simulated open loop against every run.

use super::fmt::opt;
use super::Figures;
use crate::app::report::doc::{strong, text, Col, Document, Table};
use crate::app::report::plots::panels::{shown, unit_of};
use crate::app::results::{data_word, RunResult};
use crate::base::quantity::Quantity;

pub fn write<'a>(d: &mut Document<'a>, r: &RunResult, figs: &Figures<'a>) {
    if r.resimulation.is_empty() {
        return;
    }
    let word = data_word(&r.inputs, "hekf.").unwrap_or("run's");
    d.heading(2, "Re-simulation");
    d.text(format!(
        "The identified model (the final coefficient set) integrated open loop from each run's \
         first sample with the run's own inputs, compared with the {word} data: RMS \
         differences over the run and the final position error as a share of the distance \
         travelled. Fit runs were used for identification; validation runs were not, so they \
         show how the model predicts a manoeuvre it has not seen."
    ));
    d.table(metrics_table(r));
    for stem in run_stems(r) {
        for family in ["track", "states", "vertical", "roll", "other"] {
            figs.put(d, &format!("{family}_{stem}"));
        }
    }
    manoeuvres(d, r, figs);
    if let Some(a) = &r.autopilot {
        d.heading(3, "Autopilot in waves");
        d.text(format!(
            "A PID heading autopilot tuned from the identified K = {:.4} 1/s and T = {:.2} s by \
             pole placement (w_n = {} rad/s, zeta = {}: K_p = {:.3}, K_d = {:.3} s, K_i = {:.4} \
             1/s), with a third-order heading reference model, closed around the identified \
             model in the same waves, once per feed: the raw compass and gyro, the compass and \
             its difference, the wave filter's low-frequency heading and yaw rate (the hybrid \
             EKF on the same model, run online), an ordinary low-pass filter on the compass, \
             or the plant's true low-frequency heading (the ideal). Heading error is the low-frequency heading's from the reference.",
            a.k,
            a.t,
            crate::base::numfmt::num(a.gains.omega_n),
            crate::base::numfmt::num(a.gains.zeta),
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
        for c in &a.feeds {
            t.row([
                c.feed.describe().to_string(),
                format!("{:.3}", c.heading_error_rms.to_degrees()),
                format!("{:.3}", c.rudder_rms.to_degrees()),
                format!("{:.3}", c.rudder_rate_rms.to_degrees()),
            ]);
        }
        d.table(t);
        figs.put(d, "autopilot");
        figs.put(d, "heading_spectrum");
        paper_figures(d, a, figs);
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
}

/// The figure name suffix of each re-simulated run, in order: `fit_1`, `validation_1`.
fn run_stems(r: &RunResult) -> Vec<String> {
    let (mut n_fit, mut n_val) = (0, 0);
    r.resimulation
        .iter()
        .map(|m| {
            if m.used_for_fit {
                n_fit += 1;
                format!("fit_{n_fit}")
            } else {
                n_val += 1;
                format!("validation_{n_val}")
            }
        })
        .collect()
}

/// The quantities the re-simulation compared, in the order of the figures.
const COMPARED: [Quantity; 10] = [
    Quantity::Yaw,
    Quantity::R,
    Quantity::V,
    Quantity::U,
    Quantity::Z,
    Quantity::Pitch,
    Quantity::W,
    Quantity::Q,
    Quantity::Roll,
    Quantity::P,
];

/// The re-simulation's RMS differences of every compared quantity, the distance and the
/// final position error, one row per run.
fn metrics_table(r: &RunResult) -> Table {
    let mut quantities: Vec<Quantity> = COMPARED
        .into_iter()
        .filter(|q| r.resimulation.iter().any(|m| m.rms.contains_key(q)))
        .collect();
    for m in &r.resimulation {
        for q in m.rms.keys() {
            if !quantities.contains(q) {
                quantities.push(*q);
            }
        }
    }
    let mut header = vec!["run".to_string(), "use".to_string()];
    header.extend(quantities.iter().map(|q| {
        let s = shown(*q);
        let name = s.label.rsplit_once(" (").map_or(s.label.as_str(), |x| x.0);
        format!("RMS {name} ({})", unit_of(&s.label))
    }));
    header.extend([
        "distance (m)".to_string(),
        "final position error (% of distance)".to_string(),
        "note".to_string(),
    ]);
    let last = header.len() - 1;
    let mut t = Table::new(header)
        .numeric_from(2)
        .col(0, Col::Text)
        .col(last, Col::Text);
    for m in &r.resimulation {
        let mut row = vec![
            m.run.clone(),
            if m.used_for_fit { "fit" } else { "validation" }.to_string(),
        ];
        row.extend(
            quantities
                .iter()
                .map(|q| opt(m.rms.get(q).map(|v| v * shown(*q).factor))),
        );
        row.extend([
            opt(m.distance),
            m.final_position_error_pct
                .map_or("-".into(), |p| format!("{p:.3} %")),
            m.stopped
                .as_ref()
                .map(|s| format!("stopped early: {s}"))
                .unwrap_or_default(),
        ]);
        if m.stopped.is_some() {
            t.marked_row(row);
        } else {
            t.row(row);
        }
    }
    t
}

/// Each ship manoeuvre beside the identified model's, steered the same way, with the IMO
/// criteria.
fn manoeuvres<'a>(d: &mut Document<'a>, r: &RunResult, figs: &Figures<'a>) {
    let runs: Vec<_> = r
        .resimulation
        .iter()
        .zip(run_stems(r))
        .filter_map(|(m, stem)| m.manoeuvre.as_ref().map(|c| (m, c, stem)))
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
    for (m, cmp, stem) in runs {
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
        let mut t = Table::new(crate::dynamics::manoeuvre::ComparisonTable::HEADER)
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
        figs.put(d, &format!("turning_{stem}"));
        figs.put(d, &format!("zigzag_{stem}"));
    }
}

/// The paper's figures (Dinh, Hoang & Pham 2016, fig. 6-8): what they show, the filtered
/// heading's error RMS of both filters in every feed's loop, where the series are, and the
/// figures.
fn paper_figures<'a>(
    d: &mut Document<'a>,
    a: &crate::dynamics::autopilot::AutopilotResult,
    figs: &Figures<'a>,
) {
    d.heading(4, "The paper's figures");
    d.text(
        "The error of the filtered against the true low-frequency heading with an ordinary \
         low-pass filter (a second-order Butterworth filter on the compass, its cut-off below \
         the waves) and with the EKF wave filter, the heading's response to the course change, \
         and the rudder angle. Both filters read the same compass in every loop: the one that \
         feeds the autopilot, the other beside it without steering. Each loop's series are \
         in the table's file (docs/results.md, \"Autopilot series\").",
    );
    let mut t = Table::new([
        "autopilot fed",
        "EKF heading error RMS (deg)",
        "low-pass heading error RMS (deg)",
        "series",
    ])
    .numeric_from(1)
    .col(0, Col::Text)
    .col(3, Col::Text);
    let deg = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.4}", v.to_degrees()));
    for c in &a.feeds {
        t.row([
            c.feed.describe().to_string(),
            deg(c.ekf_error_rms),
            deg(c.lowpass_error_rms),
            c.series_file.clone().unwrap_or_default(),
        ]);
    }
    d.table(t);
    for name in [
        "autopilot_filter_error",
        "autopilot_course_change",
        "autopilot_rudder",
    ] {
        figs.put(d, name);
    }
}
