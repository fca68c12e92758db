//! Runs a simulation configuration: the synthetic export `hydroid simulate CONFIG` writes.

use super::{config, export, synth};
use crate::base::error::Result;
use crate::io::output::exports::{Export, ExportKind, Guarded};
use crate::io::output::{write_export, Replace};
use std::path::{Path, PathBuf};

/// Runs a simulation configuration and writes its export; returns the file and row count.
/// An existing file is overwritten only if a simulation of this configuration wrote it and it
/// is unchanged (or changed, or another simulation's, with [`Replace::EvenIfChanged`]); never
/// the configuration or an FMU (see `output::exports`).
pub fn run_file(
    config_path: &Path,
    out: Option<&Path>,
    replace: Replace,
) -> Result<(PathBuf, usize)> {
    let loaded = config::load(config_path)?;
    let Some(export_cfg) = &loaded.config.export else {
        return Err(crate::base::error::Error::Usage(format!(
            "{} is a sweep: `hydroid simulate` writes it as a folder (sim::sweep)",
            config_path.display()
        )));
    };
    let cols = synth::synthesize(&loaded.config)?;
    let title = loaded
        .config
        .title
        .clone()
        .unwrap_or_else(|| "hydroid simulate".into());
    let text = export::render(loaded.layout, export_cfg, &cols, &title)?;
    let path = match out {
        Some(p) => p.to_path_buf(),
        None => loaded.base_dir.join(&export_cfg.file),
    };
    let guarded = [Guarded {
        path: config_path.to_path_buf(),
        what: "the simulation's configuration".into(),
    }];
    let export = Export {
        kind: ExportKind::Simulate,
        source: config_path,
        guarded: &guarded,
    };
    write_export(&path, text.as_bytes(), &export, replace)?;
    let rows = cols.values().next().map_or(0, Vec::len);
    Ok((path, rows))
}
