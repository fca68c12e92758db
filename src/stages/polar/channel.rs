//! One channel's fit: design matrix, configured constraints, clarabel solve, standard errors.

use super::fit::{self, Constraint, FitError, Kind};
use super::{
    ChannelFit, PolarConfig, PolarFit, PolarPoint, PolarWeights, Residual, SlopeFit, SlopeSign,
    DRAG_NAMES, SLOPE_NAMES, STAGE,
};
use crate::base::error::{Error, Result};

/// A standard error below this fraction of |value| (or 1e-12) is raised to it before
/// inverse-variance weighting, so that a perfectly steady history does not get infinite weight.
const SE_FLOOR: f64 = 1e-9;

/// The drag, lift and moment polars fitted to the points; `context` names the fit in
/// messages (the pooled fit, the fit at one speed).
pub(super) fn fit_all(
    config: &PolarConfig,
    pts: &[&PolarPoint],
    context: &str,
) -> Result<PolarFit> {
    Ok(PolarFit {
        n_points: pts.len(),
        drag: fit_channel(config, Chan::Drag, pts, context)?,
        lift: fit_channel(config, Chan::Lift, pts, context)?,
        moment: fit_channel(config, Chan::Moment, pts, context)?,
    })
}

#[derive(Clone, Copy, PartialEq)]
enum Chan {
    Drag,
    Lift,
    Moment,
}

impl Chan {
    /// The slope fit (`polar.lift` or `polar.moment`) and the symbol of a lift or moment
    /// channel (the drag channel's fit is `polar.drag`).
    fn slope(self, config: &PolarConfig) -> (&SlopeFit, &'static str) {
        if self == Chan::Lift {
            (&config.lift, "C_L")
        } else {
            (&config.moment, "C_M")
        }
    }

    /// The channel's name in keys and messages.
    fn name(self) -> &'static str {
        match self {
            Chan::Drag => "drag",
            Chan::Lift => "lift",
            Chan::Moment => "moment",
        }
    }
}

/// One channel fitted to the points: its constants with standard errors, the constraints
/// that are active, the residuals.
fn fit_channel(
    config: &PolarConfig,
    chan: Chan,
    pts: &[&PolarPoint],
    context: &str,
) -> Result<ChannelFit> {
    let key = format!("polar.{}", chan.name());
    let (names, units, model) = form(config, chan);
    let p = names.len();
    let a: Vec<Vec<f64>> = pts.iter().map(|pt| design_row(chan, p, pt.alpha)).collect();
    let (y, se): (Vec<f64>, Vec<Option<f64>>) = pts.iter().map(|pt| observation(chan, pt)).unzip();
    let w = weights(config, pts, &y, &se)?;
    let constraints = constraints(config, chan, &names, &key);
    let sol = fit::solve(&a, &y, &w, &constraints).map_err(|e| {
        let what = format!("{} polar ({context})", chan.name());
        fit_failure(e, &what, &model, &key, &constraints, pts)
    })?;
    let std_errors: Vec<Option<f64>> = (0..p)
        .map(|i| {
            sol.covariance
                .as_ref()
                .map(|c| c[i][i].max(0.0).sqrt() + 0.0)
        })
        .collect();
    let residuals = residuals(pts, &y, &sol.residuals);
    Ok(ChannelFit {
        channel: chan.name().to_string(),
        model,
        names: names.iter().map(|s| s.to_string()).collect(),
        units: units.iter().map(|s| s.to_string()).collect(),
        values: sol.x.iter().map(|v| v + 0.0).collect(),
        std_errors,
        covariance: sol.covariance,
        active_constraints: sol
            .active
            .iter()
            .map(|&i| constraints[i].label.clone())
            .collect(),
        binding_inequalities: sol
            .active
            .iter()
            .filter(|&&i| constraints[i].kind == Kind::Le)
            .map(|&i| constraints[i].label.clone())
            .collect(),
        n_points: pts.len(),
        dof: sol.dof,
        rss: sol.rss,
        residual_std: (sol.dof > 0).then(|| (sol.rss / sol.dof as f64).sqrt()),
        r_squared: sol.r_squared,
        residuals,
    })
}

/// The constants of a channel's model (names and units) and the model in words.
fn form(config: &PolarConfig, chan: Chan) -> (Vec<&'static str>, Vec<&'static str>, String) {
    match chan {
        Chan::Drag => (
            DRAG_NAMES.to_vec(),
            vec!["1/rad^2", "1/rad", "-"],
            "C_D = a alpha^2 + b alpha + c (paper eq. 6)".into(),
        ),
        Chan::Lift | Chan::Moment => {
            let (fit, sym) = chan.slope(config);
            if fit.cubic {
                (
                    SLOPE_NAMES.to_vec(),
                    vec!["-", "1/rad", "1/rad^3"],
                    format!("{sym} = intercept + slope alpha + cubic alpha^3"),
                )
            } else {
                (
                    SLOPE_NAMES[..2].to_vec(),
                    vec!["-", "1/rad"],
                    format!("{sym} = intercept + slope alpha"),
                )
            }
        }
    }
}

/// The row of the design matrix at `alpha` (rad) for a channel with `p` constants.
fn design_row(chan: Chan, p: usize, alpha: f64) -> Vec<f64> {
    match chan {
        Chan::Drag => vec![alpha * alpha, alpha, 1.0],
        _ => [1.0, alpha, alpha.powi(3)][..p].to_vec(),
    }
}

/// The channel's coefficient at a point, with its standard error when the point has one.
fn observation(chan: Chan, pt: &PolarPoint) -> (f64, Option<f64>) {
    match chan {
        Chan::Drag => (pt.cd, pt.cd_se),
        Chan::Lift => (pt.cl, pt.cl_se),
        Chan::Moment => (pt.cm, pt.cm_se),
    }
}

/// The weight of each point (`polar.weights`): uniform, or the inverse variance of its steady
/// mean (with the standard error floored, [`SE_FLOOR`]).
fn weights(
    config: &PolarConfig,
    pts: &[&PolarPoint],
    y: &[f64],
    se: &[Option<f64>],
) -> Result<Vec<f64>> {
    match config.weights {
        PolarWeights::Uniform => Ok(vec![1.0; pts.len()]),
        PolarWeights::InverseVariance => pts
            .iter()
            .zip(y)
            .zip(se)
            .map(|((pt, yi), s)| {
                let s = s.ok_or_else(|| {
                    Error::numerical(
                        STAGE,
                        format!(
                            "polar.weights = \"inverse_variance\" needs the standard error of \
                             each steady mean, which only steady-run histories give; the point \
                             of '{}' at {:.3} deg has none",
                            pt.record, pt.alpha_deg
                        ),
                    )
                })?;
                let floor = (SE_FLOOR * yi.abs()).max(1e-12);
                Ok(1.0 / s.max(floor).powi(2))
            })
            .collect(),
    }
}

/// Why the fit of `what` (a channel's polar in a context) failed, in the user's terms.
fn fit_failure(
    e: FitError,
    what: &str,
    model: &str,
    key: &str,
    constraints: &[Constraint],
    pts: &[&PolarPoint],
) -> Error {
    match e {
        FitError::Infeasible => Error::numerical(
            STAGE,
            format!(
                "the constraints on the {what} are infeasible: no {model} satisfies all of: \
                 {}; relax one of them in [{key}]",
                constraints
                    .iter()
                    .map(|c| c.label.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ),
        FitError::Underdetermined { free, rank } => {
            let mut angles: Vec<f64> = pts.iter().map(|p| p.alpha).collect();
            angles.sort_by(|x, y| x.partial_cmp(y).expect("finite"));
            angles.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
            Error::numerical(
                STAGE,
                format!(
                    "the {what} has {} point(s) at {} distinct angle(s), which determine \
                     only {rank} of the {free} free constants of {model}",
                    pts.len(),
                    angles.len()
                ),
            )
        }
        FitError::Solver(s) => Error::numerical(
            STAGE,
            format!("the QP solver stopped without a solution for the {what}: {s}"),
        ),
    }
}

/// Observed and fitted value of each point and their difference.
fn residuals(pts: &[&PolarPoint], y: &[f64], r: &[f64]) -> Vec<Residual> {
    pts.iter()
        .zip(y)
        .zip(r)
        .map(|((pt, yi), r)| Residual {
            record: pt.record.clone(),
            alpha: pt.alpha,
            observed: *yi,
            fitted: yi - r,
            residual: *r,
        })
        .collect()
}

/// The configured constraints of one channel, each labelled with its key.
fn constraints(config: &PolarConfig, chan: Chan, names: &[&str], key: &str) -> Vec<Constraint> {
    let p = names.len();
    let unit = |k: usize, sign: f64| -> Vec<f64> {
        let mut g = vec![0.0; p];
        g[k] = sign;
        g
    };
    let mut out = Vec::new();
    let mut push =
        |g: Vec<f64>, kind: Kind, h: f64, label: String| out.push(Constraint { g, kind, h, label });
    let bounds = match chan {
        Chan::Drag => {
            let d = &config.drag;
            if d.a_nonnegative {
                push(
                    unit(0, -1.0),
                    Kind::Le,
                    0.0,
                    format!("a >= 0 ({key}.a_nonnegative)"),
                );
            }
            if d.c_nonnegative {
                push(
                    unit(2, -1.0),
                    Kind::Le,
                    0.0,
                    format!("c >= 0 ({key}.c_nonnegative)"),
                );
            }
            if d.symmetric {
                push(
                    unit(1, 1.0),
                    Kind::Eq,
                    0.0,
                    format!("b = 0 ({key}.symmetric)"),
                );
            }
            &d.bounds
        }
        Chan::Lift | Chan::Moment => {
            let (f, sym) = chan.slope(config);
            if f.through_origin {
                push(
                    unit(0, 1.0),
                    Kind::Eq,
                    0.0,
                    format!("{sym}(0) = 0 ({key}.through_origin)"),
                );
            }
            match f.slope {
                SlopeSign::Free => {}
                SlopeSign::Positive => push(
                    unit(1, -1.0),
                    Kind::Le,
                    0.0,
                    format!("slope >= 0 ({key}.slope = \"positive\")"),
                ),
                SlopeSign::Negative => push(
                    unit(1, 1.0),
                    Kind::Le,
                    0.0,
                    format!("slope <= 0 ({key}.slope = \"negative\")"),
                ),
            }
            &f.bounds
        }
    };
    for (name, b) in bounds {
        let Some(k) = names.iter().position(|n| n == name) else {
            continue;
        };
        if let Some(lo) = b.min {
            push(
                unit(k, -1.0),
                Kind::Le,
                -lo,
                format!("{name} >= {lo} ({key}.bounds.{name}.min)"),
            );
        }
        if let Some(hi) = b.max {
            push(
                unit(k, 1.0),
                Kind::Le,
                hi,
                format!("{name} <= {hi} ({key}.bounds.{name}.max)"),
            );
        }
    }
    out
}
