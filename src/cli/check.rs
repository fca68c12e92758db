//! `hydroid check CONFIG`: validate a configuration and every input it names.

use super::{json, CmdResult};
use crate::app::check;
use crate::base::warning::Warning;
use std::io::Write;
use std::path::PathBuf;

/// Validate the configuration and every input file it names; print what would run.
///
/// Every problem is listed, not only the first, and the plausibility checks' warnings about
/// the runs. Exit code 2 when the configuration has problems (a clear mistake the
/// plausibility checks find in a run is one), 1 when only input files do, 0 when all is
/// well (warnings or not).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run configuration (TOML).
    config: PathBuf,
    /// Override a configuration key, e.g. `--set hekf.passes=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// The output folder `run --out DIR` would write, checked as run checks it (default:
    /// `output.dir` of the configuration).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print machine-readable JSON on stdout: what would run, every input, and the problems
    /// as {file, line, column, key, message}; the exit code is the same.
    #[arg(long)]
    pub(super) json: bool,
}

/// Runs the command.
pub fn run(args: Args, stdout: &mut impl Write) -> CmdResult {
    // the text is printed at the end, unless --json prints JSON instead
    let mut text = Vec::new();
    let (loaded, found) = check::check(&args.config, &args.set, args.out.as_deref(), &mut text)?;
    let code = found.exit_code();
    if args.json {
        json::write(
            stdout,
            &check::json_report(&args.config, loaded.as_ref(), found),
        )?;
        return Ok(code);
    }
    stdout.write_all(&text)?;
    print_warnings(stdout, &found.warnings)?;
    if found.ok() {
        writeln!(stdout, "ok: the configuration and every input are usable")?;
        return Ok(0);
    }
    let total = found.config_problems.len() + found.input_problems.len();
    eprintln!(
        "{total} problem{} found:",
        if total == 1 { "" } else { "s" }
    );
    for p in &found.config_problems {
        eprintln!("  - {p}");
    }
    for (_, e) in &found.input_problems {
        eprintln!("  - {e}");
    }
    Ok(code)
}

/// The plausibility checks' warnings, under `warnings:`, each with its meaning indented.
fn print_warnings(out: &mut impl Write, warnings: &[Warning]) -> std::io::Result<()> {
    if warnings.is_empty() {
        return Ok(());
    }
    writeln!(out, "warnings:")?;
    for w in warnings {
        writeln!(out, "  - {}", w.to_string().replace('\n', "\n    "))?;
    }
    Ok(())
}
