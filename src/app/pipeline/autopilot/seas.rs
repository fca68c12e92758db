//! The autopilot's recorded sea (`autopilot.disturbance_file`) read and checked before any
//! stage runs: its columns, their units against what the disturbance is (an angle for a wave
//! yaw or a rudder-equivalent disturbance, a moment for a yaw moment, a time for the time
//! column), its span against the closed loop's duration, and its magnitude against what a
//! sea does to a ship (a file in degrees read as radians is 57 times too large).

use crate::base::error::{Error, InputError, Place, Result};
use crate::base::quantity::Quantity;
use crate::base::units::Unit;
use crate::config::autopilot::{AngleUnit, AutopilotConfig};
use crate::dynamics::autopilot::seas::{DisturbanceKind, Recording, Seas};
use crate::io::formats::{self, FormatChoice, ReadOptions};
use crate::io::table::Table;
use std::path::Path;

/// Largest RMS of a recorded wave-induced yaw, rad (20 deg): a ship's wave yaw is a few
/// degrees (the bundled frigate's 1 deg); beyond this the file is in degrees read as radians,
/// or not a wave yaw.
pub const MAX_WAVE_YAW_RMS: f64 = 20.0 * std::f64::consts::PI / 180.0;

const EXPECTED: &str = "a time column (s) and the disturbance (autopilot.disturbance: a wave \
                        yaw or rudder angle in autopilot.disturbance_unit, a yaw moment in N m, \
                        unless the header states a unit): two columns, or the ones \
                        autopilot.disturbance_columns names; covering the closed loop's duration";

/// The seas `cfg` asks for: the generator, or its disturbance file (relative to `base`) read
/// with the table readers, in SI, refused when it does not cover the closed loop's duration,
/// when a column's unit is not its quantity's, or when its magnitude is beyond a sea's.
pub fn load_seas(cfg: &AutopilotConfig, base: &Path) -> Result<Seas> {
    let Some(file) = &cfg.disturbance_file else {
        return Ok(Seas::Generated);
    };
    let path = base.join(file);
    let table = formats::read(&path, FormatChoice::Auto, &ReadOptions::default())?;
    let place = Place::file(&path);
    let bad = |m: String| Error::from(InputError::new(place.clone(), m).expected(EXPECTED));
    let (t_i, v_i) = columns(cfg, &table).map_err(bad)?;
    let time = &table.columns[t_i];
    if let Some(u) = time.unit.as_ref().filter(|u| u.dim != Quantity::Time.dim()) {
        return Err(bad(format!(
            "the time column `{}` is in {} ({}), not a time",
            time.name,
            u.text,
            crate::base::units::dim_words(u.dim)
        )));
    }
    let value = &table.columns[v_i];
    if let Some(u) = &value.unit {
        unit_fits(cfg.disturbance, &value.name, u).map_err(bad)?;
    }
    // degrees accepted and converted here, at the edge
    let moment = cfg.disturbance == DisturbanceKind::YawMoment;
    let scale = match (value.unit.is_some(), cfg.disturbance_unit) {
        (false, AngleUnit::Deg) if !moment => std::f64::consts::PI / 180.0,
        _ => 1.0,
    };
    let values = value.values.iter().map(|v| v * scale).collect();
    let recording = Recording::new(cfg.disturbance, time.values.clone(), values)
        .map_err(|e| bad(e.to_string()))?;
    recording
        .covers(cfg.duration)
        .map_err(|e| bad(e.to_string()))?;
    let given = value
        .unit
        .as_ref()
        .map(|u| format!("in {} (its header)", u.text));
    magnitude(cfg, &recording, &value.name, given).map_err(bad)?;
    Ok(Seas::Recorded(recording))
}

/// The time and disturbance columns: those `disturbance_columns` names, or the file's two.
fn columns(cfg: &AutopilotConfig, table: &Table) -> std::result::Result<(usize, usize), String> {
    let names = || {
        let n: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
        n.join(", ")
    };
    match &cfg.disturbance_columns {
        Some(c) => {
            let find = |key: &str, name: &str| {
                table
                    .columns
                    .iter()
                    .position(|col| col.name == name)
                    .ok_or_else(|| {
                        format!(
                            "no column `{name}` (autopilot.disturbance_columns.{key}); the file \
                             has {}",
                            names()
                        )
                    })
            };
            Ok((find("time", &c.time)?, find("disturbance", &c.disturbance)?))
        }
        None if table.columns.len() == 2 => {
            let t_i = table.time.unwrap_or(0);
            Ok((t_i, 1 - t_i))
        }
        None => Err(format!(
            "{} columns and no autopilot.disturbance_columns",
            table.columns.len()
        )),
    }
}

/// Refuses a disturbance column whose header unit is not its quantity's: an angle for a wave
/// yaw or a rudder-equivalent disturbance, a moment for a yaw moment.
fn unit_fits(kind: DisturbanceKind, name: &str, u: &Unit) -> std::result::Result<(), String> {
    let (expected, what) = match kind {
        DisturbanceKind::YawMoment => (Quantity::Mz, "a yaw moment (N m)"),
        DisturbanceKind::WaveYaw => (Quantity::Yaw, "an angle (rad or deg): a wave yaw"),
        DisturbanceKind::Rudder => (Quantity::Rudder, "an angle (rad or deg): a rudder angle"),
    };
    if u.dim == expected.dim() {
        return Ok(());
    }
    Err(format!(
        "the disturbance column `{name}` is in {} ({}), not {what} (autopilot.disturbance = \
         \"{}\")",
        u.text,
        crate::base::units::dim_words(u.dim),
        kind_key(kind)
    ))
}

/// The disturbance kind as the configuration writes it.
fn kind_key(kind: DisturbanceKind) -> &'static str {
    match kind {
        DisturbanceKind::WaveYaw => "wave_yaw",
        DisturbanceKind::Rudder => "rudder",
        DisturbanceKind::YawMoment => "yaw_moment",
    }
}

/// Refuses a wave yaw or rudder disturbance whose magnitude no sea gives: a wave yaw of more
/// than [`MAX_WAVE_YAW_RMS`] RMS or half a turn, a rudder-equivalent angle beyond the rudder
/// limit RMS or 90 deg at its peak; naming the unit it was read in and the likely fix.
fn magnitude(
    cfg: &AutopilotConfig,
    r: &Recording,
    name: &str,
    given: Option<String>,
) -> std::result::Result<(), String> {
    let (rms, peak) = r.rms_and_peak(cfg.duration);
    let (rms_limit, peak_limit, what) = match cfg.disturbance {
        DisturbanceKind::WaveYaw => (
            MAX_WAVE_YAW_RMS,
            std::f64::consts::PI,
            "a heading disturbance (a ship's wave-induced yaw is a few degrees RMS)",
        ),
        DisturbanceKind::Rudder => (
            cfg.rudder_limit,
            std::f64::consts::FRAC_PI_2,
            "a rudder-equivalent disturbance (beyond autopilot.rudder_limit no rudder holds \
             it)",
        ),
        DisturbanceKind::YawMoment => return Ok(()),
    };
    if rms <= rms_limit && peak <= peak_limit {
        return Ok(());
    }
    let in_radians = given.is_none() && cfg.disturbance_unit == AngleUnit::Rad;
    let read_in = given.unwrap_or_else(|| match cfg.disturbance_unit {
        AngleUnit::Rad => "in rad (autopilot.disturbance_unit, the default)".into(),
        AngleUnit::Deg => "in deg (autopilot.disturbance_unit)".into(),
    });
    let fix = if in_radians {
        "; is the file in degrees? set autopilot.disturbance_unit = \"deg\" (or state the unit \
         in its header)"
    } else {
        "; check the file's values and its header's unit"
    };
    Err(format!(
        "the {} column `{name}`, read {read_in}, has an RMS of {} rad ({} deg) and a peak of \
         {} rad: implausible for {what}: at most {} deg RMS and {} deg at the peak{fix}",
        kind_key(cfg.disturbance),
        crate::base::numfmt::num(rms),
        crate::base::numfmt::num(rms.to_degrees()),
        crate::base::numfmt::num(peak),
        crate::base::numfmt::short_four(rms_limit.to_degrees()),
        crate::base::numfmt::short_four(peak_limit.to_degrees())
    ))
}
