//! Static polar stage: C_D, C_L, C_M over angle of attack to X_uu, X_uv, X_vv, Y_vv, Y_uvd,
//! Y_uvl, N_uvl (paper eq. 5-6, after Ridley, Fontan & Corke 2003).
//!
//! Each channel is a weighted least-squares fit under linear constraints, solved as a QP with
//! clarabel ([`fit`]): C_D = a alpha^2 + b alpha + c (paper eq. 6), C_L and C_M as
//! intercept + slope alpha (+ cubic alpha^3). The fit is made on all points together (pooled,
//! in coefficient form) and on each speed separately; the pooled constants are mapped to
//! coefficients by paper eq. 5 ([`mapping`]). See docs/stages.md.

// crate::Error is large (its InputError variant); boxing it is a crate-wide choice.
#![allow(clippy::result_large_err)]

mod config;
mod data;
pub mod fit;
mod mapping;

pub use config::{
    Bound, DragFit, PolarAxes, PolarConfig, PolarData, PolarWeights, SlopeFit, SlopeSign,
    DRAG_NAMES, SLOPE_NAMES,
};
pub use data::{steady_mean, PolarPoint};

use crate::coefficients::Coefficient;
use crate::config::{FluidConfig, VehicleConfig};
use crate::error::{Error, Result};
use crate::quantity::Quantity;
use crate::record::{Needs, Record};
use crate::stages::spread::{spread, Spread};
use fit::{Constraint, FitError, Kind};
use serde::Serialize;

const STAGE: &str = "polar";

/// A standard error below this fraction of |value| (or 1e-12) is raised to it before
/// inverse-variance weighting, so that a perfectly steady history does not get infinite weight.
const SE_FLOOR: f64 = 1e-9;

/// What the stage reads from each record.
pub fn needs(config: &PolarConfig) -> Needs<'static> {
    match config.data {
        PolarData::Coefficients => Needs {
            required: &[Quantity::Alpha, Quantity::Cd, Quantity::Cl, Quantity::Cm],
            optional: &[Quantity::Speed, Quantity::Time],
            min_rows: 1,
        },
        PolarData::Forces => Needs {
            required: &[
                Quantity::Alpha,
                Quantity::Fx,
                Quantity::Fy,
                Quantity::Mz,
                Quantity::Speed,
            ],
            optional: &[Quantity::Time],
            min_rows: 1,
        },
    }
}

/// Reads every run of `config` (paths relative to `base`) with what [`needs`] asks for.
pub fn load(config: &PolarConfig, base: &std::path::Path) -> Result<Vec<Record>> {
    let needs = needs(config);
    config
        .runs
        .iter()
        .map(|spec| crate::record::load(spec, base, &needs).map_err(Error::from))
        .collect()
}

/// The reference quantities used, stated so that a report can print them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub mu: f64,
    /// Reference area A_ref, m^2.
    pub reference_area: f64,
    /// Moment reference length L_ref, m (1 m reproduces the paper, whose C_M is referred to
    /// A_f only).
    pub reference_length: f64,
    /// q = 0.5 rho A_ref, kg/m (paper eq. 5).
    pub q: f64,
    /// Length in the Reynolds number Re = rho U L / mu (the vehicle length), m.
    pub reynolds_length: f64,
    /// What the files gave.
    pub data: PolarData,
    /// Axes of the given forces or coefficients.
    pub axes: PolarAxes,
    /// Fitting range, degrees (None: every point).
    pub alpha_max_deg: Option<f64>,
    /// Point weights.
    pub weights: PolarWeights,
    /// The definitions in words.
    pub statement: String,
}

/// A fitted residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residual {
    /// The record the point came from.
    pub record: String,
    /// Angle of attack, rad.
    pub alpha: f64,
    /// Observed coefficient.
    pub observed: f64,
    /// Fitted coefficient.
    pub fitted: f64,
    /// observed - fitted.
    pub residual: f64,
}

/// One channel's constrained fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelFit {
    /// `drag`, `lift` or `moment`.
    pub channel: String,
    /// The fitted model.
    pub model: String,
    /// Names of the constants (`a`, `b`, `c` or `intercept`, `slope`, `cubic`).
    pub names: Vec<String>,
    /// Units of the constants.
    pub units: Vec<String>,
    /// Fitted values.
    pub values: Vec<f64>,
    /// Standard errors (zero for a constant fixed by an active constraint; None without
    /// residual degrees of freedom).
    pub std_errors: Vec<Option<f64>>,
    /// Covariance of the constants, in `names` order.
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The constraints active at the solution (equalities always are), as configured.
    pub active_constraints: Vec<String>,
    /// The inequality constraints among them: where the data pull against a constraint.
    pub binding_inequalities: Vec<String>,
    /// Points fitted.
    pub n_points: usize,
    /// Residual degrees of freedom (points minus free constants).
    pub dof: usize,
    /// Weighted residual sum of squares.
    pub rss: f64,
    /// sqrt(rss / dof), the residual standard deviation (relative weights).
    pub residual_std: Option<f64>,
    /// Weighted coefficient of determination.
    pub r_squared: Option<f64>,
    /// Residual of every point, for plots.
    pub residuals: Vec<Residual>,
}

impl ChannelFit {
    /// The fitted value of constant `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.values[i])
    }

    /// The standard error of constant `name`.
    pub fn std_error(&self, name: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == name)?;
        self.std_errors[i]
    }
}

/// The three channel fits over one set of points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarFit {
    /// Points fitted.
    pub n_points: usize,
    /// C_D = a alpha^2 + b alpha + c.
    pub drag: ChannelFit,
    /// C_L = intercept + slope alpha (+ cubic alpha^3).
    pub lift: ChannelFit,
    /// C_M = intercept + slope alpha (+ cubic alpha^3).
    pub moment: ChannelFit,
}

/// The fit at one speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedFit {
    /// Mean speed of the group, m/s.
    pub speed: f64,
    /// Reynolds number rho U L / mu with the vehicle length, -.
    pub reynolds: f64,
    /// Points at this speed in the fitting range.
    pub n_points: usize,
    /// The fit (None when this speed alone cannot be fitted; see `error`).
    pub fit: Option<PolarFit>,
    /// Coefficients from this speed's fit (paper eq. 5).
    pub coefficients: Vec<Coefficient>,
    /// Why this speed has no fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// Everything the polar stage found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarResult {
    /// Reference quantities and conventions used.
    pub reference: Reference,
    /// The fit over every point in range, all speeds together in coefficient form.
    pub pooled: PolarFit,
    /// The fit at each speed (empty when no record gives a speed).
    pub per_speed: Vec<SpeedFit>,
    /// Spread of each coefficient between speeds (two or more speeds).
    pub spread: Vec<Spread>,
    /// Coefficients from the pooled fit (paper eq. 5), `Source::Polar`.
    pub coefficients: Vec<Coefficient>,
    /// Every point read, with `used` telling whether it was in the fitting range.
    pub points: Vec<PolarPoint>,
    /// Things worth reading.
    pub warnings: Vec<String>,
}

impl PolarResult {
    /// The coefficients of the pooled fit.
    pub fn coefficients(&self) -> Vec<Coefficient> {
        self.coefficients.clone()
    }
}

/// Runs the polar stage on records already read.
pub fn run(
    config: &PolarConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    records: &[Record],
) -> Result<PolarResult> {
    if records.is_empty() {
        return Err(Error::numerical(STAGE, "no polar run to fit"));
    }
    let (points, mut warnings) = data::points(config, vehicle, fluid, records)?;
    let used: Vec<&PolarPoint> = points.iter().filter(|p| p.used).collect();
    let skipped = points.len() - used.len();
    if skipped > 0 {
        warnings.push(format!(
            "{skipped} point(s) outside |alpha| <= {} deg were not fitted",
            config.alpha_max_deg.unwrap_or(90.0)
        ));
    }
    if used.is_empty() {
        return Err(Error::numerical(
            STAGE,
            "no point lies within the fitting range polar.alpha_max_deg",
        ));
    }
    let q = 0.5 * fluid.rho * vehicle.reference_area; // paper eq. 5: q = 0.5 rho A_f
    let l_ref = vehicle.reference_length;

    let pooled = fit_all(config, &used, "pooled fit")?;
    let coefficients = mapping::coefficients(&pooled.drag, &pooled.lift, &pooled.moment, q, l_ref);
    for ch in [&pooled.drag, &pooled.lift, &pooled.moment] {
        for c in &ch.binding_inequalities {
            warnings.push(format!(
                "the {} constraint {c} binds in the pooled fit: the data pull the other way",
                ch.channel
            ));
        }
    }
    let alpha_span = used.iter().map(|p| p.alpha.abs()).fold(0.0, f64::max);
    for (name, fit) in [("lift", &config.lift), ("moment", &config.moment)] {
        if alpha_span > 15f64.to_radians() && !fit.cubic {
            warnings.push(format!(
                "the fitted points reach {:.1} deg: a straight line through C_{} there is not the \
                 slope at zero; set polar.{name}.cubic = true or polar.alpha_max_deg",
                alpha_span.to_degrees(),
                if name == "lift" { "L" } else { "M" }
            ));
        }
    }

    let mut per_speed = Vec::new();
    if let Some(groups) = speed_groups(&used, config.speed_tolerance)? {
        for (speed, members) in groups {
            let pts: Vec<&PolarPoint> = members.iter().map(|&i| used[i]).collect();
            let reynolds = fluid.rho * speed * vehicle.length / fluid.mu; // Re = rho U L / mu
            let context = format!("fit at {speed:.4} m/s");
            let (fit, error) = match fit_all(config, &pts, &context) {
                Ok(f) => (Some(f), None),
                Err(e) => (None, Some(e.to_string())),
            };
            let coefficients = fit.as_ref().map_or_else(Vec::new, |f| {
                mapping::coefficients(&f.drag, &f.lift, &f.moment, q, l_ref)
            });
            if let Some(e) = &error {
                warnings.push(format!("no separate fit at {speed:.4} m/s: {e}"));
            }
            per_speed.push(SpeedFit {
                speed,
                reynolds,
                n_points: pts.len(),
                fit,
                coefficients,
                error,
            });
        }
    }
    let fitted: Vec<&SpeedFit> = per_speed.iter().filter(|s| s.fit.is_some()).collect();
    let spread: Vec<Spread> = coefficients
        .iter()
        .filter_map(|c| {
            let est: Vec<(f64, Option<f64>)> = fitted
                .iter()
                .filter_map(|s| s.coefficients.iter().find(|k| k.name == c.name))
                .map(|k| (k.value, k.sigma))
                .collect();
            spread(&c.name, &c.unit, &est)
        })
        .collect();

    let statement = format!(
        "C_D = -X / (0.5 rho U^2 A_ref), C_L = Y / (0.5 rho U^2 A_ref), C_M = N / (0.5 rho U^2 \
         A_ref L_ref) in body axes (x forward, y starboard, alpha = atan(v/u)), with A_ref = {} \
         m^2 and L_ref = {} m{}; q = 0.5 rho A_ref = {:.6} kg/m; Re = rho U L / mu with L = {} m",
        vehicle.reference_area,
        l_ref,
        if (l_ref - 1.0).abs() < 1e-12 {
            " (the paper's convention: C_M referred to A_f only)"
        } else {
            ""
        },
        q,
        vehicle.length
    );
    Ok(PolarResult {
        reference: Reference {
            rho: fluid.rho,
            mu: fluid.mu,
            reference_area: vehicle.reference_area,
            reference_length: l_ref,
            q,
            reynolds_length: vehicle.length,
            data: config.data,
            axes: config.axes,
            alpha_max_deg: config.alpha_max_deg,
            weights: config.weights,
            statement,
        },
        pooled,
        per_speed,
        spread,
        coefficients,
        points,
        warnings,
    })
}

/// Speed groups: (mean speed, indices of the points at it).
type SpeedGroups = Vec<(f64, Vec<usize>)>;

/// Groups points by speed (relative tolerance); None when no point has a speed.
fn speed_groups(points: &[&PolarPoint], tol: f64) -> Result<Option<SpeedGroups>> {
    let with: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].speed.is_some())
        .collect();
    if with.is_empty() {
        return Ok(None);
    }
    if with.len() < points.len() {
        let missing = points.iter().find(|p| p.speed.is_none()).map(|p| &p.record);
        return Err(Error::numerical(
            STAGE,
            format!(
                "some polar runs give a speed and others do not (e.g. '{}'): give every run a \
                 speed column or constant, or none",
                missing.map_or("", |s| s.as_str())
            ),
        ));
    }
    let mut order = with;
    order.sort_by(|&i, &j| {
        points[i]
            .speed
            .partial_cmp(&points[j].speed)
            .expect("finite")
    });
    let mut groups: Vec<(f64, Vec<usize>)> = Vec::new();
    let mut first = f64::NAN;
    for i in order {
        let s = points[i].speed.expect("filtered");
        match groups.last_mut() {
            Some((_, members)) if s <= first * (1.0 + tol) => members.push(i),
            _ => {
                first = s;
                groups.push((s, vec![i]));
            }
        }
    }
    for (speed, members) in &mut groups {
        *speed = members
            .iter()
            .map(|&i| points[i].speed.expect("filtered"))
            .sum::<f64>()
            / members.len() as f64;
    }
    Ok(Some(groups))
}

fn fit_all(config: &PolarConfig, pts: &[&PolarPoint], context: &str) -> Result<PolarFit> {
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
    fn name(self) -> &'static str {
        match self {
            Chan::Drag => "drag",
            Chan::Lift => "lift",
            Chan::Moment => "moment",
        }
    }
}

fn fit_channel(
    config: &PolarConfig,
    chan: Chan,
    pts: &[&PolarPoint],
    context: &str,
) -> Result<ChannelFit> {
    let key = format!("polar.{}", chan.name());
    let (names, units, model): (Vec<&str>, Vec<&str>, String) = match chan {
        Chan::Drag => (
            DRAG_NAMES.to_vec(),
            vec!["1/rad^2", "1/rad", "-"],
            "C_D = a alpha^2 + b alpha + c (paper eq. 6)".into(),
        ),
        Chan::Lift | Chan::Moment => {
            let fit = if chan == Chan::Lift {
                &config.lift
            } else {
                &config.moment
            };
            let sym = if chan == Chan::Lift { "C_L" } else { "C_M" };
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
    };
    let p = names.len();
    let row = |alpha: f64| -> Vec<f64> {
        match chan {
            Chan::Drag => vec![alpha * alpha, alpha, 1.0],
            _ => [1.0, alpha, alpha.powi(3)][..p].to_vec(),
        }
    };
    let a: Vec<Vec<f64>> = pts.iter().map(|pt| row(pt.alpha)).collect();
    let (y, se): (Vec<f64>, Vec<Option<f64>>) = pts
        .iter()
        .map(|pt| match chan {
            Chan::Drag => (pt.cd, pt.cd_se),
            Chan::Lift => (pt.cl, pt.cl_se),
            Chan::Moment => (pt.cm, pt.cm_se),
        })
        .unzip();
    let w: Vec<f64> = match config.weights {
        PolarWeights::Uniform => vec![1.0; pts.len()],
        PolarWeights::InverseVariance => pts
            .iter()
            .zip(&y)
            .zip(&se)
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
            .collect::<Result<_>>()?,
    };

    let constraints = constraints(config, chan, &names, &key);
    let sol = fit::solve(&a, &y, &w, &constraints).map_err(|e| {
        let what = format!("{} polar ({context})", chan.name());
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
    })?;
    let std_errors: Vec<Option<f64>> = (0..p)
        .map(|i| {
            sol.covariance
                .as_ref()
                .map(|c| c[i][i].max(0.0).sqrt() + 0.0)
        })
        .collect();
    let residuals = pts
        .iter()
        .zip(&y)
        .zip(&sol.residuals)
        .map(|((pt, yi), r)| Residual {
            record: pt.record.clone(),
            alpha: pt.alpha,
            observed: *yi,
            fitted: yi - r,
            residual: *r,
        })
        .collect();
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
            let f = if chan == Chan::Lift {
                &config.lift
            } else {
                &config.moment
            };
            let sym = if chan == Chan::Lift { "C_L" } else { "C_M" };
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
