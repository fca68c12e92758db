//! Static polar stage: C_D, C_L, C_M over angle of attack to X_uu, X_uv, X_vv, Y_vv, Y_uvd,
//! Y_uvl, N_uvl (paper eq. 5-6, after Ridley, Fontan & Corke 2003).
//!
//! Each channel is a weighted least-squares fit under linear constraints, solved as a QP with
//! clarabel (`fit`): C_D = a alpha^2 + b alpha + c (paper eq. 6), C_L and C_M as
//! intercept + slope alpha (+ cubic alpha^3). The fit is made on all points together (pooled,
//! in coefficient form) and on each speed separately; the pooled constants are mapped to
//! coefficients by paper eq. 5 (`mapping.rs`). See docs/stages.md.

// crate::Error is large (its InputError variant); boxing it is a crate-wide choice.

mod channel;
use crate::config::polar as config;
mod data;
/// The constrained least squares the polar fits use (shared with the captive stage).
pub(crate) use crate::numerics::constrained_lsq as fit;
mod mapping;
mod plausibility;
pub mod replica;
mod result;

pub use config::{
    Bound, DragFit, PolarAxes, PolarConfig, PolarData, PolarWeights, SlopeFit, SlopeSign,
    DRAG_NAMES, SLOPE_NAMES,
};
pub use data::{steady_mean, PolarPoint};
pub use result::{ChannelFit, PolarFit, PolarResult, Reference, Residual, SpeedFit};

use crate::base::error::{Error, Result};
use crate::base::quantity::Quantity;
use crate::base::warning::Warning;
use crate::config::{FluidConfig, VehicleConfig};
use crate::io::record::{Needs, Record};
use crate::model::coefficients::{Coefficient, YawMoment};
use crate::stages::spread::{spread, Spread};
use channel::fit_all;

pub(crate) const STAGE: &str = "polar";

/// The coefficients this stage estimates (paper eq. 5) with its configuration: the moment
/// slope gives Nuv or Nuvl as `polar.moment.part` says.
pub fn provides(config: &PolarConfig) -> Vec<&'static str> {
    mapping::provides(config.moment_part())
}

/// Each coefficient this stage estimates with its relation to the fitted polar constants
/// (paper eq. 5), for the coefficient catalogue.
pub fn relations() -> Vec<(&'static str, &'static str)> {
    mapping::relations()
}

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
    let used = points_in_range(config, &points, &mut warnings)?;
    warnings.extend(plausibility::alpha_range(&used));
    let q = dynamic_pressure_area(vehicle, fluid);
    let l_ref = vehicle.reference_length;

    let pooled = fit_all(config, &used, "pooled fit")?;
    let part = config.moment_part();
    let coefficients =
        mapping::coefficients(&pooled.drag, &pooled.lift, &pooled.moment, q, l_ref, part);
    let directions =
        mapping::directions(&pooled.drag, &pooled.lift, &pooled.moment, q, l_ref, part);
    warnings.extend(binding_warnings(&pooled));
    warnings.extend(undetermined_warnings(&pooled, &coefficients, part));
    warnings.extend(linearity_warnings(config, &used));
    let per_speed = fit_per_speed(config, vehicle, fluid, &used, &mut warnings)?;
    let spread = speed_spread(&coefficients, &per_speed);
    Ok(PolarResult {
        directions,
        reference: reference(config, vehicle, fluid),
        pooled,
        per_speed,
        spread,
        coefficients,
        points,
        warnings,
    })
}

/// What the stage would refuse in its runs, for `hydroid check` and `hydroid run` before any
/// stage runs: runs without steady points, none within the fitting range, too few distinct
/// angles for a fit, constraints no fit satisfies. A polar is a few dozen points, so this is
/// the stage itself, run once more: whatever it would stop at, it stops at here. The
/// problem, if any (none without runs).
pub fn preflight(
    config: &PolarConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    records: &[Record],
) -> Option<Error> {
    if records.is_empty() {
        // no run given is the configuration's problem; none read, the inputs'
        return None;
    }
    run(config, vehicle, fluid, records).err()
}

/// q = 0.5 rho A_ref, kg/m: the force per squared speed and unit coefficient (paper eq. 5,
/// with A_ref = A_f).
fn dynamic_pressure_area(vehicle: &VehicleConfig, fluid: &FluidConfig) -> f64 {
    0.5 * fluid.rho * vehicle.reference_area
}

/// The points within the fitting range (`polar.alpha_max_deg`), with a warning for those
/// outside; none is an error.
fn points_in_range<'p>(
    config: &PolarConfig,
    points: &'p [PolarPoint],
    warnings: &mut Vec<Warning>,
) -> Result<Vec<&'p PolarPoint>> {
    let used: Vec<&PolarPoint> = points.iter().filter(|p| p.used).collect();
    let skipped = points.len() - used.len();
    if skipped > 0 {
        warnings.push(Warning::new(
            STAGE,
            format!(
                "{skipped} point(s) outside |alpha| <= {} deg were not fitted",
                config.alpha_max_deg.unwrap_or(90.0)
            ),
            "the coefficients describe the fitted range only",
        ));
    }
    if used.is_empty() {
        return Err(Error::numerical(
            STAGE,
            format!(
                "no point lies within the fitting range polar.alpha_max_deg{}",
                plausibility::degrees_as_radians_hint(points)
            ),
        ));
    }
    Ok(used)
}

/// A warning for each inequality constraint that binds in the pooled fit.
fn binding_warnings(pooled: &PolarFit) -> Vec<Warning> {
    let mut warnings = Vec::new();
    for ch in [&pooled.drag, &pooled.lift, &pooled.moment] {
        for c in &ch.binding_inequalities {
            warnings.push(Warning::new(
                STAGE,
                format!(
                    "the {} constraint {c} binds in the pooled fit: the data pull the other way",
                    ch.channel
                ),
                "the fitted coefficient sits on the constraint, so its sigma understates how \
                 far the data would move it; check the signs of the exported coefficients",
            ));
        }
    }
    warnings
}

/// A warning for each channel of the pooled fit with no degree of freedom (as many points as
/// free constants): its fit passes through every point, so the residuals say nothing of the
/// noise and the sigmas of the coefficients from it are undetermined (reported without a
/// sigma, never as exact).
fn undetermined_warnings(
    pooled: &PolarFit,
    coefficients: &[Coefficient],
    part: YawMoment,
) -> Vec<Warning> {
    [&pooled.drag, &pooled.lift, &pooled.moment]
        .into_iter()
        .filter(|ch| ch.covariance.is_none())
        .map(|ch| {
            let names = mapping::names_from(&ch.channel, part);
            let from: Vec<&str> = coefficients
                .iter()
                .filter(|c| c.sigma.is_none() && names.contains(&c.name.as_str()))
                .map(|c| c.name.as_str())
                .collect();
            Warning::new(
                STAGE,
                format!(
                    "the {} fit ({}) has {} points for its free constants: no degree of \
                     freedom is left, so the sigmas of {} are undetermined",
                    ch.channel,
                    ch.model,
                    ch.n_points,
                    if from.is_empty() {
                        "its constants".to_string()
                    } else {
                        from.join(", ")
                    }
                ),
                "the fit passes through every point and cannot tell its noise: the values are \
                 as uncertain as the points, by an unknown amount. Add points at more distinct \
                 angles than the fit has constants (or fix a constant, e.g. \
                 polar.drag.symmetric) to get sigmas",
            )
        })
        .collect()
}

/// A warning for each linear slope fitted over angles (beyond 15 deg) where the nonlinear
/// part biases it.
fn linearity_warnings(config: &PolarConfig, used: &[&PolarPoint]) -> Vec<Warning> {
    let mut warnings = Vec::new();
    let alpha_span = used.iter().map(|p| p.alpha.abs()).fold(0.0, f64::max);
    for (name, fit) in [("lift", &config.lift), ("moment", &config.moment)] {
        if alpha_span > 15f64.to_radians() && !fit.cubic {
            warnings.push(Warning::new(
                STAGE,
                format!(
                    "the fitted points reach {:.1} deg: a straight line through C_{} there is \
                     not the slope at zero",
                    alpha_span.to_degrees(),
                    if name == "lift" { "L" } else { "M" }
                ),
                format!(
                    "the linear {name} coefficients are biased by the nonlinear part; set \
                     polar.{name}.cubic = true or polar.alpha_max_deg"
                ),
            ));
        }
    }
    warnings
}

/// The fit at each speed separately (when the points have speeds), with its Reynolds number;
/// a speed that cannot be fitted alone gives a warning, not an error.
fn fit_per_speed(
    config: &PolarConfig,
    vehicle: &VehicleConfig,
    fluid: &FluidConfig,
    used: &[&PolarPoint],
    warnings: &mut Vec<Warning>,
) -> Result<Vec<SpeedFit>> {
    let q = dynamic_pressure_area(vehicle, fluid);
    let l_ref = vehicle.reference_length;
    let mut per_speed = Vec::new();
    let Some(groups) = speed_groups(used, config.speed_tolerance)? else {
        return Ok(per_speed);
    };
    for (speed, members) in groups {
        let pts: Vec<&PolarPoint> = members.iter().map(|&i| used[i]).collect();
        let reynolds = fluid.rho * speed * vehicle.length / fluid.mu; // Re = rho U L / mu
        let context = format!("fit at {speed:.4} m/s");
        let (fit, error) = match fit_all(config, &pts, &context) {
            Ok(f) => (Some(f), None),
            Err(e) => (None, Some(e.to_string())),
        };
        let coefficients = fit.as_ref().map_or_else(Vec::new, |f| {
            mapping::coefficients(&f.drag, &f.lift, &f.moment, q, l_ref, config.moment_part())
        });
        if let Some(e) = &error {
            warnings.push(Warning::new(
                STAGE,
                format!("no separate fit at {speed:.4} m/s: {e}"),
                "the pooled coefficients stand, but their dependence on speed (Reynolds \
                 number) is not checked at this speed",
            ));
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
    Ok(per_speed)
}

/// The spread of each pooled coefficient between the speeds that have a fit.
fn speed_spread(coefficients: &[Coefficient], per_speed: &[SpeedFit]) -> Vec<Spread> {
    let fitted: Vec<&SpeedFit> = per_speed.iter().filter(|s| s.fit.is_some()).collect();
    coefficients
        .iter()
        .filter_map(|c| {
            let est: Vec<(f64, Option<f64>)> = fitted
                .iter()
                .filter_map(|s| s.coefficients.iter().find(|k| k.name == c.name))
                .map(|k| (k.value, k.sigma))
                .collect();
            spread(&c.name, &c.unit, &est)
        })
        .collect()
}

/// The reference quantities used, with the definitions in words.
fn reference(config: &PolarConfig, vehicle: &VehicleConfig, fluid: &FluidConfig) -> Reference {
    let q = dynamic_pressure_area(vehicle, fluid);
    let l_ref = vehicle.reference_length;
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
    Reference {
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
        moment: config.moment_part(),
        statement,
    }
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
