//! Command definitions (clap) and dispatch. Each command lives in its own file.

mod analytic;
mod check;
mod compare;
mod inspect;
mod progress;
mod rerun;
mod run;
mod simulate;

use clap::{Parser, Subcommand};
use hydroid::Error;
use std::io::Write;

/// hydroid: CFD exports of marine vehicles to manoeuvring models.
///
/// Reads what CFD codes export (CFX, STAR-CCM+, Fluent, OpenFOAM, plain CSV), fits static
/// polars and a surge run, identifies the remaining coefficients with a hybrid extended
/// Kalman filter, and reports every coefficient with its uncertainty against Fossen's
/// analytic values and the source paper.
#[derive(Debug, Parser)]
#[command(name = "hydroid", version, about, long_about, max_term_width = 100)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Run(run::Args),
    Check(check::Args),
    Inspect(inspect::Args),
    Simulate(simulate::Args),
    Analytic(analytic::Args),
    Rerun(rerun::Args),
    Compare(compare::Args),
}

/// Parses the command line, runs the command and returns the exit code.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return code;
        }
    };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let result = match cli.command {
        Command::Run(a) => run::run(a, &mut out),
        Command::Check(a) => check::run(a, &mut out),
        Command::Inspect(a) => inspect::run(a, &mut out),
        Command::Simulate(a) => simulate::run(a, &mut out),
        Command::Analytic(a) => analytic::run(a, &mut out),
        Command::Rerun(a) => rerun::run(a, &mut out),
        Command::Compare(a) => compare::run(a, &mut out),
    };
    let _ = out.flush();
    match result {
        Ok(code) => code,
        Err(CliError::BrokenPipe) => 0,
        Err(CliError::Hydroid(e)) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    }
}

/// What a command can fail with.
#[derive(Debug)]
pub enum CliError {
    /// stdout was closed by the reader (`hydroid ... | head`): stop quietly.
    BrokenPipe,
    /// Anything else.
    Hydroid(Error),
}

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        CliError::Hydroid(e)
    }
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            CliError::BrokenPipe
        } else {
            CliError::Hydroid(Error::Usage(format!(
                "cannot write to standard output: {e}"
            )))
        }
    }
}

/// Result of a command: the exit code, or an error.
pub type CmdResult = Result<i32, CliError>;

/// Writes a note to stderr (progress and warnings; results go to stdout).
pub fn note(msg: &str) {
    let _ = writeln!(std::io::stderr(), "{msg}");
}
