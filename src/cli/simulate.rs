//! `hydroid simulate SIMCONFIG`: write a synthetic CFD export from a model.

use super::CmdResult;
use crate::io::output::Replace;
use std::io::Write;
use std::path::PathBuf;

/// Simulate a manoeuvre (or a steady polar sweep) with a model and known coefficients, add
/// seeded noise, and write it in a CFD export layout (see docs/simulate.md).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The simulation configuration (TOML).
    config: PathBuf,
    /// Output file (default: `export.file` of the configuration, relative to it).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Overwrite an export hydroid wrote even if it was changed since (a file hydroid did not
    /// write is never overwritten).
    #[arg(long)]
    force: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    crate::io::output::clean_up_on_signals()?;
    let loaded = crate::app::simulate::config::load(&args.config)?;
    if loaded.config.sweep.is_some() {
        let result = crate::app::simulate::sweep::simulate_sweep(&loaded)?;
        let dir = crate::app::simulate::sweep::write_sweep(
            &loaded,
            &args.config,
            &result,
            args.out.as_deref(),
            Replace::forced(args.force),
        )?;
        for w in &result.warnings {
            eprintln!("warning: {w}");
        }
        writeln!(out, "{}", crate::app::simulate::sweep::summary(&result))?;
        writeln!(
            out,
            "wrote {} ({} turning circles)",
            dir.display(),
            result.cases.len()
        )?;
        return Ok(0);
    }
    let (path, rows) = crate::app::simulate::run_file(
        &args.config,
        args.out.as_deref(),
        Replace::forced(args.force),
    )?;
    writeln!(out, "wrote {} ({rows} rows)", path.display())?;
    Ok(0)
}
