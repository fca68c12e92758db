//! Title matter: what the report is about, the vehicle and its reference quantities, what
//! ran and on which files.

use super::fmt::{opt, serde_name};
use crate::app::report::doc::{code, text, Col, Document, Table};
use crate::app::results::RunResult;
use crate::base::numfmt::num;
use crate::config::DataSource;

pub fn write(d: &mut Document, r: &RunResult, plots: bool) {
    let analytic = if r.analytic.is_empty() {
        ""
    } else {
        " and a comparison with Fossen's analytic added mass"
    };
    d.para([
        text(format!(
            "Hydrodynamic coefficients of the {} identified from {} by hydroid {}, with their \
             uncertainties{analytic}{}. The numbers in this report come from ",
            r.vehicle.name,
            inputs_phrase(r),
            r.hydroid_version,
            r.reference
                .as_ref()
                .map(|x| format!("; compared with {}", x.name))
                .unwrap_or_default(),
        )),
        code("results.json"),
        text(format!(
            " (layout {}, described in docs/results.md).",
            r.schema
        )),
    ]);
    if !plots {
        d.para([
            text("Figures are off for this run ("),
            code("output.plots = false"),
            text("); the tables below hold every number."),
        ]);
    }
    vehicle(d, r);
    stages(d, r);
    inputs(d, r);
}

/// The inputs in words by their source: "3 CFD exports and 2 measured runs".
fn inputs_phrase(r: &RunResult) -> String {
    let count = |s: DataSource| r.inputs.iter().filter(|i| i.source == s).count();
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let parts: Vec<String> = [
        (count(DataSource::Cfd), "CFD export"),
        (count(DataSource::Measured), "measured run"),
    ]
    .into_iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, what)| format!("{n} {what}{}", plural(n)))
    .collect();
    if parts.is_empty() {
        "no input file".to_string()
    } else {
        parts.join(" and ")
    }
}

fn vehicle(d: &mut Document, r: &RunResult) {
    let v = &r.vehicle;
    d.heading(2, "Vehicle and reference quantities");
    let mut t = Table::new(["quantity", "symbol", "value", "unit"]).col(2, Col::Num);
    t.row(["vehicle", "", v.name.as_str(), ""]);
    t.row(["mass".to_string(), "m".into(), num(v.mass), "kg".into()]);
    t.row(["length".to_string(), "L".into(), num(v.length), "m".into()]);
    t.row([
        "diameter".to_string(),
        "D".into(),
        opt(v.diameter),
        "m".into(),
    ]);
    t.row([
        "yaw inertia".to_string(),
        "I_zz".into(),
        num(v.izz),
        "kg m^2".into(),
    ]);
    t.row([
        "density".to_string(),
        "ρ".into(),
        num(v.rho),
        "kg/m^3".into(),
    ]);
    t.row([
        "dynamic viscosity".to_string(),
        "μ".into(),
        num(v.mu),
        "Pa s".into(),
    ]);
    t.row([
        "reference area (force coefficients)".to_string(),
        "A_ref".into(),
        num(v.reference_area),
        "m^2".into(),
    ]);
    t.row([
        "reference length (moment coefficients)".to_string(),
        "L_ref".into(),
        num(v.reference_length),
        "m".into(),
    ]);
    t.row([
        "q = ½ ρ A_ref".to_string(),
        "q".into(),
        num(v.q),
        "kg/m".into(),
    ]);
    d.table(t);
    let convention = match &r.stages.polar {
        Some(p) => p.reference.statement.clone(),
        None => format!(
            "Force coefficients are referred to ½ ρ U² A_ref with A_ref = {} m^2, moment \
             coefficients to ½ ρ U² A_ref L_ref with L_ref = {} m; body axes x forward, y \
             starboard, z down (SNAME).",
            num(v.reference_area),
            num(v.reference_length)
        ),
    };
    let stop = if convention.ends_with('.') { "" } else { "." };
    d.para([text("Convention: "), text(convention), text(stop)]);
    if let Some(dia) = v.diameter {
        let frontal = std::f64::consts::PI * dia * dia / 4.0;
        let which = if (v.reference_area - frontal).abs() <= 1e-6 * frontal {
            "the frontal area π D²/4".to_string()
        } else {
            format!("not the frontal area π D²/4 = {} m^2", num(frontal))
        };
        let lref = if v.reference_length == 1.0 {
            "; L_ref = 1 m refers C_M to A_ref alone, as Rasekh & Mahdi (2020) do".to_string()
        } else if v.reference_length == v.length {
            "; L_ref is the vehicle length".to_string()
        } else {
            String::new()
        };
        d.text(format!("A_ref is {which}{lref}."));
    }
}

fn stages(d: &mut Document, r: &RunResult) {
    d.heading(2, "What ran");
    let mut items = Vec::new();
    match &r.stages.polar {
        Some(p) => {
            let used = p.points.iter().filter(|x| x.used).count();
            let speeds: Vec<String> = p
                .per_speed
                .iter()
                .map(|s| format!("{} m/s (Re = {:.2e})", num(s.speed), s.reynolds))
                .collect();
            items.push(vec![text(format!(
                "Static polar (paper eq. 5-6): {} points{}, {} in the fitting range; data as {}, \
                 {} axes, {} weights.",
                p.points.len(),
                if speeds.is_empty() {
                    String::new()
                } else {
                    format!(" at {}", speeds.join(" and "))
                },
                used,
                serde_name(&p.reference.data),
                serde_name(&p.reference.axes),
                serde_name(&p.reference.weights),
            ))]);
        }
        None => items.push(vec![text("Static polar: not run.")]),
    }
    match &r.stages.surge {
        Some(s) => items.push(vec![text(format!(
            "Surge acceleration (paper eq. 21): X_udot from {} run{} ({} samples), drag term \
             from {}.",
            s.runs.len(),
            if s.runs.len() == 1 { "" } else { "s" },
            s.n_samples,
            serde_name(&s.drag_from)
        ))]),
        None => items.push(vec![text("Surge acceleration: not run.")]),
    }
    match &r.stages.hekf {
        Some(h) => {
            let val = r.resimulation.iter().filter(|m| !m.used_for_fit).count();
            items.push(vec![text(format!(
                "Hybrid extended Kalman filter (paper eq. 9-19, 22): model {}, preset {}, \
                 estimating {} from {} manoeuvre{}; {} validation run{} re-simulated only.",
                h.model,
                h.preset,
                h.estimated.join(", "),
                h.runs.len(),
                if h.runs.len() == 1 { "" } else { "s" },
                val,
                if val == 1 { "" } else { "s" }
            ))]);
        }
        None => items.push(vec![text("Hybrid EKF: not run.")]),
    }
    d.list(items);
}

fn inputs(d: &mut Document, r: &RunResult) {
    d.heading(3, "Inputs");
    let mut t = Table::new([
        "key",
        "name",
        "file",
        "format",
        "source",
        "rows",
        "time span (s)",
        "SHA-256 (first 16 hex digits)",
    ])
    .col(1, Col::Text)
    .col(5, Col::Num);
    for i in &r.inputs {
        t.row([
            i.key.clone(),
            i.name.clone(),
            i.file.clone(),
            i.format.clone(),
            i.source.word().to_string(),
            i.rows.to_string(),
            i.time_span
                .map_or_else(|| "-".into(), |s| format!("{} to {}", num(s[0]), num(s[1]))),
            format!("{}…", i.sha256.get(..16).unwrap_or(&i.sha256)),
        ]);
    }
    d.table(t);
    let read: Vec<String> = r
        .inputs
        .iter()
        .filter(|i| i.quantities.values().any(|u| u.contains("deg")))
        .map(|i| i.name.clone())
        .collect();
    if !read.is_empty() {
        d.text(format!(
            "Angles given in degrees were converted to radians on reading ({}); every value \
             in results.json is SI.",
            read.join(", ")
        ));
    }
}
