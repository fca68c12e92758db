//! Stage conflicts as warnings: a later stage's estimate of a coefficient that an earlier
//! stage also gave is tested against it before it replaces it (docs/stages.md, "Stage
//! conflicts").

use crate::base::numfmt::num;
use crate::base::warning::Warning;
use crate::config::Config;
use crate::model::coefficients::{Coefficient, CoefficientSet, Conflict, Source};

/// Combined sigmas apart beyond which two stages' estimates conflict.
pub(super) const LIMIT: f64 = 3.0;

/// One warning per coefficient of `incoming` (from `stage`) that conflicts with `known`.
pub(super) fn warnings(
    known: &CoefficientSet,
    incoming: &[Coefficient],
    stage: &str,
    cfg: &Config,
) -> Vec<Warning> {
    known
        .conflicts(incoming, LIMIT)
        .iter()
        .map(|c| warning(c, stage, cfg))
        .collect()
}

fn warning(c: &Conflict, stage: &str, cfg: &Config) -> Warning {
    let (e, l) = (&c.earlier, &c.later);
    let earlier = match e.source {
        Source::Symmetry => {
            "the symmetry relations (paper eq. 4) over the earlier stages gave".to_string()
        }
        s => format!("the {s} stage gave"),
    };
    Warning::new(
        stage,
        format!(
            "{stage} and an earlier stage disagree on {}: {stage} gives {} ± {} {}, {earlier} \
             {} ± {}, {} sigma apart; the {stage} value is used",
            l.name,
            num(l.value),
            num(l.sigma.unwrap_or(0.0)),
            l.unit,
            num(e.value),
            num(e.sigma.unwrap_or(0.0)),
            num(c.z)
        ),
        causes(&l.name, cfg),
    )
    .failed(crate::base::warning::Test::StageConflict)
}

/// The likely causes of a conflict on `name`, in the user's settings.
fn causes(name: &str, cfg: &Config) -> String {
    let common = "the two stages' files read with different conventions: a unit (kN as N, \
                  deg/s as rad/s), a sign or axis (y to port, z up), the reference area, length \
                  or moment centre";
    match cfg.polar.as_ref() {
        Some(p) if name.starts_with('N') => format!(
            "both cannot be right. Likely: the polar's C_M read as the wrong part of the yaw \
             moment (`polar.moment.part` is \"{}\": \"total\" when the CFD moment includes the \
             Munk moment, \"lift-only\" when it is the lift part), or {common}",
            p.moment_part()
        ),
        _ => format!("both cannot be right. Likely: {common}"),
    }
}
