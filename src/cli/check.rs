//! `hydroid check CONFIG`: validate a configuration and every input it names.

use super::CmdResult;
use std::io::Write;
use std::path::PathBuf;

/// Validate the configuration and every input file it names; print what would run.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration (TOML).
    config: PathBuf,
    /// Override a configuration key, e.g. `--set hekf.passes=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let _ = (args, out);
    Err(hydroid::Error::Usage("check is not built yet".into()).into())
}
