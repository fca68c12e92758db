//! `hydroid inspect FILE`: what hydroid reads from one export.

use super::{warning, CmdResult};
use crate::io::formats::{Format, FormatChoice};
use crate::Error;
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
    pub(super) json: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let choice = FormatChoice::parse(&args.format).ok_or_else(|| {
        let names: Vec<&str> = std::iter::once("auto")
            .chain(Format::ALL.iter().map(|f| f.name()))
            .collect();
        Error::Usage(format!(
            "unknown format '{}'; expected one of {}{}",
            args.format,
            names.join(", "),
            crate::base::suggest::did_you_mean(&args.format, names.iter().copied())
        ))
    })?;
    let report = crate::app::inspect::inspect(&args.file, choice).map_err(Error::from)?;
    if args.json {
        let text = serde_json::to_string_pretty(&report)
            .map_err(|e| Error::Usage(format!("cannot write the report as JSON: {e}")))?;
        writeln!(out, "{text}")?;
        for w in &report.warnings {
            warning(w);
        }
    } else {
        report.write_text(out)?;
    }
    Ok(0)
}
