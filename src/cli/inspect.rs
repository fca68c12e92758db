//! `hydroid inspect FILE`: what hydroid reads from one export.

use super::CmdResult;
use std::io::Write;
use std::path::PathBuf;

/// Show the detected format, columns, units, rows, time span and sampling of one file.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The CFD export to inspect.
    file: PathBuf,
    /// Read as this format instead of detecting it (auto, delimited, cfx, starccm, fluent,
    /// openfoam-forcecoeffs, openfoam-coefficient, openfoam-force, openfoam-forces,
    /// openfoam-sixdof).
    #[arg(long, default_value = "auto")]
    format: String,
    /// Print machine-readable JSON instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let _ = (args, out);
    Err(hydroid::Error::Usage("inspect is not built yet".into()).into())
}
