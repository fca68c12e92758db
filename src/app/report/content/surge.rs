//! The surge stage: X_udot, its error budget, the speed bins.

use super::fmt::{opt, pm};
use super::Figures;
use crate::app::report::doc::{strong, text, Col, Document, Table};
use crate::base::numfmt::num;
use crate::stages::surge::SurgeResult;

pub fn write<'a>(d: &mut Document<'a>, s: &SurgeResult, figs: &Figures<'a>) {
    d.heading(2, "Surge run");
    d.text(format!("Method: {}.", s.method));
    d.para([
        strong(format!("X_udot = {} kg", pm(s.xud.value, s.xud.sigma))),
        text(format!(
            " (1σ: {} kg from the fit residuals, {} kg from the uncertainty of X_uu = {} kg/m, \
             {}); m − X_udot = {} kg.",
            opt(s.xud.sigma_statistical),
            opt(s.xud.sigma_from_xuu),
            pm(s.xuu.value, s.xuu.sigma),
            s.xuu.source,
            pm(s.inertia.value, s.inertia.sigma)
        )),
    ]);
    d.text(format!(
        "Fit: {} samples, residual SD of u {} m/s, R² {}, lag-1 autocorrelation of the \
         residuals {}.",
        s.n_samples,
        num(s.residual_std),
        s.r_squared.map_or("-".into(), |r| format!("{r:.6}")),
        s.residual_lag1.map_or("-".into(), |r| format!("{r:.2}"))
    ));
    if let Some(x) = &s.xuu_fitted {
        d.text(format!(
            "X_uu fitted with X_udot from the exported force: {} kg/m.",
            pm(x.value, x.sigma)
        ));
    }
    let mut t = Table::new([
        "speed bin (m/s)",
        "samples",
        "stretches",
        "X_udot (kg)",
        "σ statistical (kg)",
        "σ from X_uu (kg)",
        "note",
    ])
    .numeric_from(1)
    .col(6, Col::Text);
    for b in &s.bins {
        let (v, stat, xuu) = match &b.fit {
            Some(f) => (
                pm(f.xud.value, f.xud.sigma),
                opt(f.xud.sigma_statistical),
                opt(f.xud.sigma_from_xuu),
            ),
            None => ("-".into(), "-".into(), "-".into()),
        };
        t.row([
            format!("{} to {}", num(b.u_min), num(b.u_max)),
            b.n_samples.to_string(),
            b.n_segments.to_string(),
            v,
            stat,
            xuu,
            b.note.clone().unwrap_or_default(),
        ]);
    }
    d.table(t);
    if let Some(sp) = &s.bin_spread {
        if let (Some(c), Some(p)) = (sp.chi2, sp.p_value) {
            d.text(format!(
                "Spread between the bins: {} kg (χ² = {c:.1} on {} dof, p = {}).",
                num(sp.range),
                sp.dof,
                super::fmt::p_value(p)
            ));
        }
    }
    if !s.momentum.is_empty() {
        let mut t =
            Table::new(["run", "RMS of m u − ∫(F + X_prop) dt (N s)", "relative"]).numeric_from(1);
        for m in &s.momentum {
            t.row([
                m.record.clone(),
                num(m.rms),
                format!("{:.2} %", 100.0 * m.relative),
            ]);
        }
        d.text("Momentum balance of the runs that export both force and thrust (a check of the export):");
        d.table(t);
    }
    if !s.warnings.is_empty() {
        d.list(
            s.warnings
                .iter()
                .map(|w| vec![text(format!("{}. {}", w.message, w.meaning))])
                .collect(),
        );
    }
    figs.put(d, "surge_fit");
    figs.put(d, "surge_bins");
}
