//! `hydroid rerun OUTDIR`: run again exactly what made an output folder.

use super::{progress, warning, CmdResult, Say};
use crate::app::pipeline;
use crate::app::report::{self, RerunManifest};
use crate::base::error::{Error, InputError, Place};
use crate::config;
use crate::io::output::{Protected, Replace, Staging};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Re-execute the run recorded in an output folder (its config.toml, with the inputs it
/// names), refusing when an input file changed since (its SHA-256 differs).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// An output folder written by `hydroid run`.
    outdir: PathBuf,
    /// Write the new results here instead of replacing OUTDIR.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Run even if input files changed since the recorded run.
    #[arg(long)]
    allow_changed_inputs: bool,
    /// Run the output folder's config.toml (or rerun.json, inputs.json) although it was
    /// edited since hydroid wrote it; without it an edited file is refused, naming it.
    #[arg(long)]
    edited: bool,
    /// Replace the output folder even if it changed since hydroid wrote it (files added,
    /// edited or removed there are lost). A folder hydroid did not write is never replaced.
    #[arg(long)]
    force: bool,
    /// Exit with status 3 when a consistency test failed (the innovations, a stage conflict,
    /// the noise-model sensitivity, a re-simulation: the warnings say which), for scripts and
    /// CI pipelines. The output folder is written as without it.
    #[arg(long)]
    strict: bool,
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> crate::Result<T> {
    let text = crate::config::read(path)?;
    serde_json::from_str(&text).map_err(|e| {
        InputError::new(
            Place::line(path, e.line()),
            format!(
                "not a hydroid {} file: {e}",
                path.file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
            ),
        )
        .into()
    })
}

#[derive(serde::Deserialize)]
struct Recorded {
    key: String,
    file: String,
    sha256: String,
}

/// The files of an output folder a rerun reads: what it runs is what they record.
const RECORDS: &[&str] = &[report::CONFIG_TOML, report::RERUN_JSON, report::INPUTS_JSON];

/// The files of an output folder `calibrate` and `plan` read: the records a rerun reads and
/// the results they check or build on. They must be the same when they write (a [`Claim`]).
///
/// [`Claim`]: crate::io::output::Claim
pub(super) const READ: &[&str] = &[
    report::CONFIG_TOML,
    report::RERUN_JSON,
    report::INPUTS_JSON,
    report::RESULTS_JSON,
];

/// Refuses an output folder whose recorded files were edited since hydroid wrote them (their
/// SHA-256 differs from the marker's), unless `--edited` accepts the edits; then says so.
fn check_edits(dir: &Path, accept: bool) -> crate::Result<()> {
    let edited = crate::io::output::marker::edited(dir, RECORDS)?;
    if edited.is_empty() {
        return Ok(());
    }
    let list: Vec<String> = edited
        .iter()
        .map(|f| dir.join(f).display().to_string())
        .collect();
    if accept {
        for f in &list {
            warning(&format!(
                "{f} was edited since hydroid wrote it; running it as edited (--edited)"
            ));
        }
        return Ok(());
    }
    Err(Error::Usage(format!(
        "refusing to rerun {}: {} edited since hydroid wrote {} (the SHA-256 differs from \
         the one {} records):\n  - {}\na rerun runs exactly what made the output; use \
         --edited to run the edited configuration, or `hydroid run {} --out NEW`",
        dir.display(),
        if list.len() == 1 {
            "this file was"
        } else {
            "these files were"
        },
        if list.len() == 1 { "it" } else { "them" },
        crate::io::output::marker::MARKER,
        list.join("\n  - "),
        dir.join(report::CONFIG_TOML).display()
    )))
}

/// The configuration an output folder records (its config.toml with the inputs it names, read
/// as if in the source configuration's folder) and its manifest, refusing edited records
/// (unless `edited`) and changed inputs (unless `allow_changed`; then a warning each).
pub(super) fn load_recorded(
    dir: &Path,
    edited: bool,
    allow_changed: bool,
) -> crate::Result<(config::LoadedConfig, RerunManifest)> {
    check_edits(dir, edited)?;
    let manifest: RerunManifest = read_json(&dir.join(report::RERUN_JSON))?;
    let inputs: Vec<Recorded> = read_json(&dir.join(report::INPUTS_JSON))?;
    let config_path = dir.join(report::CONFIG_TOML);
    let text = config::read(&config_path)?;
    // The recorded configuration (overrides applied) is read as if it were in the source
    // configuration's folder, which the manifest holds as an absolute path: its relative
    // paths resolve from there whatever the working folder. Its problems are placed in the
    // recorded file (OUTDIR/config.toml), whose lines they count.
    let source = manifest
        .base_dir
        .join(manifest.config.file_name().unwrap_or_default());
    let mut loaded = config::load_str(&source, &text, &[]).map_err(|e| match e {
        Error::Config(problems) => Error::Config(
            problems
                .into_iter()
                .map(|mut p| {
                    if p.file == source {
                        p.file = config_path.clone();
                    }
                    p
                })
                .collect(),
        ),
        e => e,
    })?;
    loaded.path = config_path.clone();
    loaded.overrides = manifest.overrides.clone();
    check_inputs(dir, &manifest, &inputs, allow_changed)?;
    Ok((loaded, manifest))
}

/// Refuses inputs whose contents changed since the recorded run (their SHA-256 differs),
/// unless `allow_changed`: then each is a warning.
fn check_inputs(
    dir: &Path,
    manifest: &RerunManifest,
    inputs: &[Recorded],
    allow_changed: bool,
) -> crate::Result<()> {
    let mut changed = Vec::new();
    for i in inputs {
        let path = manifest.base_dir.join(&i.file);
        match pipeline::file_sha256(&path) {
            Ok(h) if h == i.sha256 => {}
            Ok(_) => changed.push(format!(
                "{} ({}): contents changed since the recorded run",
                path.display(),
                i.key
            )),
            Err(e) => changed.push(format!("{} ({}): {e}", path.display(), i.key)),
        }
    }
    if !changed.is_empty() {
        if !allow_changed {
            return Err(Error::numerical(
                "rerun",
                format!(
                "refusing to rerun {}: {} input{} changed:\n  - {}\nuse --allow-changed-inputs to run anyway",
                dir.display(),
                changed.len(),
                if changed.len() == 1 { "" } else { "s" },
                changed.join("\n  - ")
            ),
            ));
        }
        for c in &changed {
            warning(c);
        }
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    crate::io::output::clean_up_on_signals()?;
    let dir = &args.outdir;
    let (mut loaded, manifest) = load_recorded(dir, args.edited, args.allow_changed_inputs)?;
    let target = args.out.clone().unwrap_or_else(|| dir.clone());
    // the inputs and the source configuration are protected; the recorded configuration is
    // part of the output folder a rerun replaces (it has been read)
    let mut protected = Protected::for_inputs(&loaded);
    if let Some(name) = manifest.config.file_name() {
        protected.config(&manifest.base_dir.join(name));
    }
    // the accepted edits of the recorded files do not stop their folder's replacement
    let replace = match Replace::forced(args.force) {
        Replace::IfUnchanged if args.edited && args.out.is_none() => Replace::IfOnlyEdited(RECORDS),
        r => r,
    };
    let staging = Staging::guarded(&target, &protected, replace)?;
    for s in staging.swept() {
        say.note(s);
    }
    let output = pipeline::run(&loaded, &mut progress::Cli::new(say))?;
    // the new output records the source configuration, as the first run did
    loaded.path = manifest.config.clone();
    report::write(&staging, &loaded, &output)?;
    let written = staging.commit()?;
    writeln!(
        out,
        "reran {} into {}",
        manifest.config.display(),
        written.display()
    )?;
    Ok(super::warnings::exit_status(
        args.strict,
        &output.result.warnings,
    ))
}
