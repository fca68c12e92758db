//! The command line (the top layer): command definitions (clap) and dispatch. Each command
//! lives in its own file; `src/main.rs` only calls [`main`].

mod analytic;
mod calibrate;
mod check;
mod coefficients;
mod compare;
mod export;
mod help;
mod init;
mod inspect;
mod json;
mod manoeuvre;
mod plan;
mod progress;
mod rerun;
mod run;
mod simulate;
mod warnings;

use crate::Error;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::io::Write;

/// hydroid: CFD exports and model-test logs of marine vehicles to manoeuvring models.
///
/// (The full description, which names every model of the registry, is written by
/// `help::with_models`.)
#[derive(Debug, Parser)]
#[command(name = "hydroid", version, about, long_about, max_term_width = 100)]
pub struct Cli {
    /// Also print the HEKF's settings, the prior of every estimated coefficient and the
    /// measurement noise of every run (on stderr).
    #[arg(long, short = 'v', global = true, conflicts_with = "quiet")]
    verbose: bool,
    /// Print only warnings and errors on stderr: no stage lines, no progress. Results still
    /// go to stdout.
    #[arg(long, short = 'q', global = true)]
    quiet: bool,
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
    Calibrate(calibrate::Args),
    Coefficients(coefficients::Args),
    Init(init::Args),
    Manoeuvre(manoeuvre::Args),
    Export(export::Args),
    Plan(plan::Args),
}

/// Parses the command line, runs the command and returns the exit code.
pub fn main() -> i32 {
    let parsed = help::with_models(Cli::command())
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            if code != 0 && std::env::args_os().any(|a| a == "--json") {
                // a script that asked for JSON gets its error as JSON too
                let message = e.to_string();
                let message = message.trim().trim_start_matches("error: ");
                let _ = json::write(&mut std::io::stdout(), &json::usage_error(message));
            }
            return code;
        }
    };
    let say = Say::new(cli.verbose, cli.quiet);
    let wants_json = cli.command.json();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let result = match cli.command {
        Command::Run(a) => run::run(a, &mut out, say),
        Command::Check(a) => check::run(a, &mut out),
        Command::Inspect(a) => inspect::run(a, &mut out),
        Command::Simulate(a) => simulate::run(a, &mut out),
        Command::Analytic(a) => analytic::run(a, &mut out),
        Command::Rerun(a) => rerun::run(a, &mut out, say),
        Command::Compare(a) => compare::run(a, &mut out),
        Command::Calibrate(a) => calibrate::run(a, &mut out, say),
        Command::Coefficients(a) => coefficients::run(a, &mut out),
        Command::Init(a) => init::run(a, &mut out, say),
        Command::Manoeuvre(a) => manoeuvre::run(a, &mut out),
        Command::Export(a) => export::run(a, &mut out),
        Command::Plan(a) => plan::run(a, &mut out, say),
    };
    let _ = out.flush();
    match result {
        Ok(code) => code,
        Err(CliError::BrokenPipe) => 0,
        Err(CliError::Hydroid(e)) => {
            eprintln!("error: {e}");
            if wants_json {
                // one JSON object on stdout, the exit code unchanged (docs/results.md)
                let _ = json::write(&mut out, &json::error(&e));
                let _ = out.flush();
            }
            e.exit_code()
        }
    }
}

impl Command {
    /// Whether the command was asked for JSON on stdout (`--json`): then an error is printed
    /// there as a JSON object too.
    fn json(&self) -> bool {
        match self {
            Command::Run(a) => a.json,
            Command::Check(a) => a.json,
            Command::Inspect(a) => a.json,
            Command::Analytic(a) => a.json(),
            Command::Compare(a) => a.json,
            Command::Calibrate(a) => a.json,
            Command::Coefficients(a) => a.json,
            Command::Manoeuvre(a) => a.json,
            Command::Plan(a) => a.json,
            Command::Simulate(_) | Command::Rerun(_) | Command::Init(_) | Command::Export(_) => {
                false
            }
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

/// How much a command says on stderr (results go to stdout whatever it is).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Verbosity {
    /// Warnings and errors only (`--quiet`).
    Quiet,
    /// Warnings, errors, stage lines and progress.
    Normal,
    /// Also the details a user tuning the filter wants (`--verbose`).
    Verbose,
}

/// Writes messages to stderr at the verbosity the user chose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Say {
    /// The chosen verbosity.
    pub verbosity: Verbosity,
}

impl Say {
    /// From the `--verbose` and `--quiet` flags (clap makes them exclusive).
    pub fn new(verbose: bool, quiet: bool) -> Self {
        let verbosity = if quiet {
            Verbosity::Quiet
        } else if verbose {
            Verbosity::Verbose
        } else {
            Verbosity::Normal
        };
        Say { verbosity }
    }

    /// A message for the normal level: what was done (stage lines, where output went).
    pub fn note(self, msg: &str) {
        if self.verbosity >= Verbosity::Normal {
            note(msg);
        }
    }

    /// A message only `--verbose` shows.
    pub fn detail(self, msg: &str) {
        if self.verbosity >= Verbosity::Verbose {
            note(msg);
        }
    }
}

/// Writes a warning to stderr, whatever the verbosity.
pub fn warning(msg: &str) {
    note(&format!("warning: {msg}"));
}

/// Writes a line to stderr.
fn note(msg: &str) {
    let _ = writeln!(std::io::stderr(), "{msg}");
}
