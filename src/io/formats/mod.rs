//! Readers for what CFD codes export, one per file family, all yielding a [`Table`].
//!
//! Layouts are described in docs/formats.md; samples of real exports are under
//! tests/fixtures/formats/.

mod cfx;
mod columns;
mod cut;
mod delimited;
pub mod detect;
mod fluent;
pub mod input;
mod layout;
mod openfoam;
mod starccm;
mod text;

use crate::base::error::{InputError, Place};
use crate::io::table::Table;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// A file layout hydroid can read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Format {
    /// Generic delimited table: comma, semicolon, tab or whitespace; optional header.
    #[serde(rename = "delimited")]
    Delimited,
    /// ANSYS CFX-Post / monitor CSV with units in `[ ... ]`.
    #[serde(rename = "cfx")]
    Cfx,
    /// Siemens STAR-CCM+ CSV with units in `( ... )`.
    #[serde(rename = "starccm")]
    StarCcm,
    /// ANSYS Fluent report file (.out) or history.
    #[serde(rename = "fluent")]
    Fluent,
    /// OpenFOAM forceCoeffs.dat (OpenFOAM.org and older).
    #[serde(rename = "openfoam-forcecoeffs")]
    OpenFoamForceCoeffs,
    /// OpenFOAM ESI coefficient.dat.
    #[serde(rename = "openfoam-coefficient")]
    OpenFoamCoefficient,
    /// OpenFOAM ESI force.dat or moment.dat.
    #[serde(rename = "openfoam-force")]
    OpenFoamForce,
    /// OpenFOAM legacy forces.dat with bracketed vectors.
    #[serde(rename = "openfoam-forces")]
    OpenFoamForcesLegacy,
    /// OpenFOAM sixDoFRigidBodyState motion output.
    #[serde(rename = "openfoam-sixdof")]
    OpenFoamSixDof,
}

impl Format {
    /// Every format, in documentation order.
    pub const ALL: [Format; 9] = [
        Format::Delimited,
        Format::Cfx,
        Format::StarCcm,
        Format::Fluent,
        Format::OpenFoamForceCoeffs,
        Format::OpenFoamCoefficient,
        Format::OpenFoamForce,
        Format::OpenFoamForcesLegacy,
        Format::OpenFoamSixDof,
    ];

    /// The name used on the command line and in configurations.
    pub fn name(self) -> &'static str {
        match self {
            Format::Delimited => "delimited",
            Format::Cfx => "cfx",
            Format::StarCcm => "starccm",
            Format::Fluent => "fluent",
            Format::OpenFoamForceCoeffs => "openfoam-forcecoeffs",
            Format::OpenFoamCoefficient => "openfoam-coefficient",
            Format::OpenFoamForce => "openfoam-force",
            Format::OpenFoamForcesLegacy => "openfoam-forces",
            Format::OpenFoamSixDof => "openfoam-sixdof",
        }
    }

    /// Looks a format up by name.
    pub fn from_name(name: &str) -> Option<Format> {
        Format::ALL.iter().copied().find(|f| f.name() == name)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A format chosen by the user: a fixed one, or detected from the content.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FormatChoice {
    /// Detect from the file content.
    #[default]
    Auto,
    /// Read as this format.
    Fixed(Format),
}

impl FormatChoice {
    /// Parses `auto` or a format name.
    pub fn parse(s: &str) -> Option<FormatChoice> {
        if s == "auto" {
            Some(FormatChoice::Auto)
        } else {
            Format::from_name(s).map(FormatChoice::Fixed)
        }
    }
}

/// Options a configuration can give a reader.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReadOptions {
    /// Column names for a file without a header line.
    pub names: Option<Vec<String>>,
    /// Lines at the top of the file that are not part of the table, whatever they hold
    /// (title lines of a model-test log); kept as `title` metadata.
    pub skip_lines: usize,
    /// The sampling interval (s) that rebuilds a time column printed with too few digits
    /// (see `crate::io::time_stamps`); detected from the stamps when not given.
    pub dt: Option<f64>,
}

/// Reads `path` as `choice`, converting columns with stated units to SI.
///
/// This is [`read_raw`] followed by [`Table::finish`]: values in SI, repeated time stamps of
/// a restart reduced to their last row, and a decreasing time axis rejected. The file must
/// be a regular file within the [`input::Limits`] the environment sets.
pub fn read(path: &Path, choice: FormatChoice, options: &ReadOptions) -> Result<Table, InputError> {
    read_within(path, choice, options, &input::Limits::for_file(path)?)
}

/// [`read`] with explicit limits on the file size and line length.
pub fn read_within(
    path: &Path,
    choice: FormatChoice,
    options: &ReadOptions,
    limits: &input::Limits,
) -> Result<Table, InputError> {
    let mut table = read_raw_within(path, choice, options, limits)?;
    table.finish(options.dt)?;
    Ok(table)
}

/// Reads `path` as `choice` without [`Table::finish`]: values as written in the file, every
/// row kept. Column units, the time column, metadata and warnings are set.
pub fn read_raw(
    path: &Path,
    choice: FormatChoice,
    options: &ReadOptions,
) -> Result<Table, InputError> {
    read_raw_within(path, choice, options, &input::Limits::for_file(path)?)
}

/// [`read_raw`] with explicit limits on the file size and line length.
pub fn read_raw_within(
    path: &Path,
    choice: FormatChoice,
    options: &ReadOptions,
    limits: &input::Limits,
) -> Result<Table, InputError> {
    let bytes = input::read_bytes(path, limits)?;
    let decoded = text::decode(path, bytes)?;
    let mut src = text::Source::new(path, &decoded);
    let titles = src.skip_lines(options.skip_lines)?;
    text::check_width(&src, limits.max_columns)?;
    let format = match choice {
        FormatChoice::Fixed(f) => f,
        FormatChoice::Auto => detect::detect_source(&src)?,
    };
    let table = match format {
        Format::Delimited => delimited::read(&src, options, delimited::GENERIC)?,
        Format::Cfx => cfx::read(&src, options)?,
        Format::StarCcm => starccm::read(&src, options)?,
        Format::Fluent => fluent::read(&src, options)?,
        Format::OpenFoamForceCoeffs | Format::OpenFoamCoefficient | Format::OpenFoamForce => {
            openfoam::read_scalar(&src, options, format)?
        }
        Format::OpenFoamForcesLegacy => openfoam::read_forces(&src, options)?,
        Format::OpenFoamSixDof => openfoam::read_sixdof(&src, options)?,
    };
    let mut table = table;
    table.meta.splice(0..0, titles);
    let last_column = table.columns.last().map(|c| c.name.as_str());
    if let Some(w) = cut::check_cut_off(&src, &table.lines, last_column)? {
        table.warnings.push(w);
    }
    if table.rows() == 0 {
        return Err(InputError::new(
            Place::file(path),
            format!("no data rows (read as {format})"),
        )
        .expected("rows of numbers after the header"));
    }
    Ok(table)
}
