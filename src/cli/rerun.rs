//! `hydroid rerun OUTDIR`: run again exactly what made an output folder.

use super::{progress, warning, CmdResult, Say};
use hydroid::error::{Error, InputError, Place};
use hydroid::output::{Protected, Replace, Staging};
use hydroid::report::{self, RerunManifest};
use hydroid::{config, pipeline};
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
    /// Replace the output folder even if it changed since hydroid wrote it (files added,
    /// edited or removed there are lost). A folder hydroid did not write is never replaced.
    #[arg(long)]
    force: bool,
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> hydroid::Result<T> {
    let text = hydroid::config::read(path)?;
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

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    hydroid::output::clean_up_on_signals()?;
    let dir = &args.outdir;
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
    let mut changed = Vec::new();
    for i in &inputs {
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
        if !args.allow_changed_inputs {
            return Err(Error::numerical(
                "rerun",
                format!(
                "refusing to rerun {}: {} input{} changed:\n  - {}\nuse --allow-changed-inputs to run anyway",
                dir.display(),
                changed.len(),
                if changed.len() == 1 { "" } else { "s" },
                changed.join("\n  - ")
            ),
            )
            .into());
        }
        for c in &changed {
            warning(c);
        }
    }
    let target = args.out.clone().unwrap_or_else(|| dir.clone());
    // the inputs and the source configuration are protected; the recorded configuration is
    // part of the output folder a rerun replaces (it has been read)
    let mut protected = Protected::for_inputs(&loaded);
    if let Some(name) = manifest.config.file_name() {
        protected.config(&manifest.base_dir.join(name));
    }
    let staging = Staging::guarded(&target, &protected, Replace::forced(args.force))?;
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
    Ok(0)
}
