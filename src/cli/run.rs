//! `hydroid run CONFIG`: run every enabled stage and write the output folder.

use super::CmdResult;
use std::io::Write;
use std::path::PathBuf;

/// Run every stage the configuration enables and write results, tables, plots and reports.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration (TOML).
    config: PathBuf,
    /// Output folder (default: `output.dir` of the configuration, relative to it).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Override a configuration key, e.g. `--set hekf.passes=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let _ = (args, out);
    Err(hydroid::Error::Usage("run is not built yet".into()).into())
}
