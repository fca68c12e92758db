//! `hydroid run CONFIG`: run every enabled stage and write the output folder.

use super::{progress, CmdResult, Say};
use crate::app::{pipeline, report};
use crate::config;
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
    /// Replace the output folder even if it changed since hydroid wrote it (files added,
    /// edited or removed there are lost). A folder hydroid did not write is never replaced.
    #[arg(long)]
    force: bool,
    /// Print results.json (the file written to the output folder) on stdout instead of the
    /// table; every other message goes to stderr.
    #[arg(long)]
    pub(super) json: bool,
    /// Exit with status 3 when a consistency test failed (the innovations, a stage conflict,
    /// the noise-model sensitivity, a re-simulation: the warnings say which), for scripts and
    /// CI pipelines. The output folder is written as without it.
    #[arg(long)]
    strict: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    crate::io::output::clean_up_on_signals()?;
    let loaded = config::load(&args.config, &args.set)?;
    // before any stage runs: the user is not made to wait for a refusal
    let staging = report::staging(&loaded, args.out.as_deref(), args.force)?;
    for s in staging.swept() {
        say.note(s);
    }
    let mut progress = progress::Cli::new(say);
    let output = pipeline::run(&loaded, &mut progress)?;
    progress.say_warnings();
    report::write(&staging, &loaded, &output)?;
    let dir = staging.commit()?;
    if let Some(h) = &output.result.stages.hekf {
        say.detail(&format!(
            "hekf settings: {} preset, {} passes, {} sub-steps per sample, {} filter",
            h.preset, h.settings.passes, h.settings.substeps, h.settings.filter
        ));
        for t in &h.tuning {
            say.detail(&format!("hekf prior: {t}"));
        }
        for run in &h.runs {
            for n in &run.noise {
                say.detail(&format!(
                    "hekf noise of {} in '{}': sigma {:.3e} {} ({})",
                    n.quantity,
                    run.name,
                    n.sigma,
                    n.quantity.si_symbol(),
                    n.source
                ));
            }
        }
    }
    if args.json {
        // byte for byte the results.json written (it ends with a newline)
        out.write_all(&crate::io::output::to_json(&output.result)?)?;
        say.note(&format!("wrote {}", dir.display()));
    } else {
        report::table::write_text(out, &output.result)?;
        for m in &output.result.resimulation {
            if let Some(cmp) = &m.manoeuvre {
                writeln!(
                    out,
                    "\n{} ({}): {}, the identified model steered as the run ({})",
                    m.run,
                    if m.used_for_fit { "fit" } else { "validation" },
                    cmp.measured.kind(),
                    cmp.steering_text()
                )?;
                write!(out, "{}", cmp.table())?;
            }
        }
        if let Some(s) = &output.result.steering {
            writeln!(
                out,
                "\nNomoto's indices of the identified model ({}): {}",
                s.at,
                s.text()
            )?;
        }
        if let Some(a) = &output.result.autopilot {
            writeln!(
                out,
                "\nAutopilot tuned from K = {:.4} 1/s, T = {:.2} s (K_p {:.3}, K_d {:.3} s, K_i \
                 {:.4} 1/s), closed around the plant in waves:",
                a.k, a.t, a.gains.kp, a.gains.kd, a.gains.ki
            )?;
            for l in a.lines() {
                writeln!(out, "  {l}")?;
            }
        }
        writeln!(out, "\nwrote {}", dir.display())?;
    }
    // the warnings were said (grouped) before the results; a reminder of where they are kept
    let n = output.result.warnings.len();
    if n > 0 {
        say.note(&format!(
            "{n} warning{} above, grouped by kind (each in results.json and the report's \
             Warnings section): read them before using these coefficients",
            if n == 1 { "" } else { "s" }
        ));
    }
    Ok(super::warnings::exit_status(
        args.strict,
        &output.result.warnings,
    ))
}
