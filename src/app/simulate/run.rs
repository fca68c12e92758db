//! Runs a simulation configuration: the synthetic export `hydroid simulate CONFIG` writes.

use super::{config, export, synth};
use crate::base::error::Result;
use crate::io::output::{write_export, Replace};
use std::path::{Path, PathBuf};

/// Runs a simulation configuration and writes its export; returns the file and row count.
/// An existing file is overwritten only if hydroid wrote it and it is unchanged (or changed,
/// with [`Replace::EvenIfChanged`]); never the configuration (see `output::exports`).
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
    write_export(&path, text.as_bytes(), &[config_path], replace)?;
    let rows = cols.values().next().map_or(0, Vec::len);
    Ok((path, rows))
}
