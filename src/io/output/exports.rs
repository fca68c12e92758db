//! Exports keep the layout their readers expect (a synthetic CFD export of `hydroid simulate`
//! its real CFD layout, an FMU of `hydroid export fmu` the FMI archive), so the record of what
//! hydroid wrote lives beside them: `.hydroid-exports.json` in the export's folder, file name
//! -> SHA-256 of what hydroid wrote, the kind of export and what it was made from.
//!
//! An existing file is overwritten only when it is listed there as the same kind of export
//! and unchanged (or changed, with `--force`); a simulation's export only by a simulation of
//! the same configuration (or with `--force`). Never an unlisted file, a folder, a symbolic
//! link, a device, the record itself, a file inside the output folder of a run, or a file the
//! caller guards (the simulation's configuration; the inputs and configuration of the run an
//! FMU is exported from), whatever `--force` says. docs/outputs.md lists the rules.

use super::marker::MARKER;
use super::paths::{read_locations, relative, resolve};
use super::{write_atomic, Replace};
use crate::base::error::{Error, Result};
use crate::io::formats::input::{bytes_sha256, file_sha256, format_size, read_bytes, Limits};
use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The record's file name.
pub const EXPORTS_RECORD: &str = ".hydroid-exports.json";
/// The record's format tag.
const FORMAT: &str = "hydroid-exports/2";
/// The largest record read (64 MiB: some 300,000 exports).
const MAX_RECORD_BYTES: u64 = 64 << 20;
/// The first format: file name -> SHA-256, every entry a simulation's export.
const FORMAT_1: &str = "hydroid-exports/1";

/// What an export is. The record keeps it, and one kind never replaces the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ExportKind {
    /// A synthetic CFD export of `hydroid simulate`: what runs read as their input.
    Simulate,
    /// An FMU of `hydroid export fmu`.
    Fmu,
}

impl ExportKind {
    /// The export in words, for messages.
    fn words(self) -> &'static str {
        match self {
            ExportKind::Simulate => "the export",
            ExportKind::Fmu => "the FMU",
        }
    }
}

/// A file an export must never be written onto, whatever the record says, and what it is
/// (for the refusal: "an input of the run out/kvlcc2 (hekf.runs[0])").
#[derive(Debug, Clone, PartialEq)]
pub struct Guarded {
    /// The file.
    pub path: PathBuf,
    /// What it is.
    pub what: String,
}

/// What is being written: its kind, what it is made from (the simulation configuration, the
/// exported output folder: recorded), and the files it must never be.
#[derive(Debug, Clone, Copy)]
pub struct Export<'a> {
    /// The kind of export.
    pub kind: ExportKind,
    /// What it is made from.
    pub source: &'a Path,
    /// Files it must never be written onto.
    pub guarded: &'a [Guarded],
}

/// One file of the record.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    /// SHA-256 (hex) of what hydroid wrote.
    sha256: String,
    /// The kind of export.
    kind: ExportKind,
    /// What it was made from, relative to the record's folder (none in the first format).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    source: Option<String>,
}

/// The record's contents.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Record {
    /// `"hydroid-exports/2"`.
    format: String,
    /// File name in this folder -> what hydroid wrote there.
    files: BTreeMap<String, Entry>,
}

/// The first format, still read.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Record1 {
    files: BTreeMap<String, String>,
}

/// Writes an export to `path` (atomically) and records it, when the rules of the module allow
/// it. Returns the resolved path written.
pub fn write_export(
    path: &Path,
    bytes: &[u8],
    export: &Export,
    replace: Replace,
) -> Result<PathBuf> {
    let target = resolve(path)?;
    let refuse = |why: &str| {
        Error::Usage(format!(
            "refusing to write {} to {}: {why}",
            export.kind.words(),
            target.display()
        ))
    };
    let (Some(dir), Some(name)) = (target.parent(), target.file_name()) else {
        return Err(refuse("it is not a file name"));
    };
    let name = name.to_string_lossy().into_owned();
    if name == EXPORTS_RECORD {
        return Err(refuse("that is the name of hydroid's record of exports"));
    }
    if let Some(g) = export
        .guarded
        .iter()
        .find(|g| read_locations(&g.path).contains(&target))
    {
        return Err(refuse(&format!(
            "it is {}; hydroid never writes onto it, even with --force; choose another name",
            g.what
        )));
    }
    if let Some(run) = dir.ancestors().find(|a| a.join(MARKER).is_file()) {
        return Err(refuse(&format!(
            "it is inside {}, the output folder of a run ({MARKER}), which the next run \
             replaces whole; write it outside that folder",
            run.display()
        )));
    }
    super::create_folder(dir, export.kind.words())?;
    // one writer of the record at a time (several simulations into one folder)
    let _lock = lock_folder(dir);
    let record_path = dir.join(EXPORTS_RECORD);
    let mut record = read_record(&record_path)?;
    let source = source_in(dir, export.source);
    let listed = record.files.get(&name);
    may_replace(&target, listed, export.kind, &source, replace, &record_path)
        .map_err(|why| refuse(&why))?;
    write_atomic(&target, bytes)?;
    let entry = Entry {
        sha256: bytes_sha256(bytes),
        kind: export.kind,
        source: Some(source),
    };
    record.files.insert(name, entry);
    write_atomic(&record_path, &crate::io::output::to_json(&record)?)?;
    Ok(target)
}

/// `source` as the record keeps it: relative to the record's folder `dir`, `/`-separated, so
/// that a project moved as a whole keeps its record valid.
fn source_in(dir: &Path, source: &Path) -> String {
    let real = std::fs::canonicalize(source)
        .or_else(|_| resolve(source))
        .unwrap_or_else(|_| source.to_path_buf());
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    relative(&dir, &real)
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// Why `target` (listed in the record as `listed`, if it is) may not be replaced by an export
/// of `kind` made from `source`; Ok when nothing is there or it may be.
fn may_replace(
    target: &Path,
    listed: Option<&Entry>,
    kind: ExportKind,
    source: &str,
    replace: Replace,
    record_path: &Path,
) -> std::result::Result<(), String> {
    let m = match std::fs::symlink_metadata(target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::io(target, e).to_string()),
        Ok(m) => m,
    };
    if m.file_type().is_symlink() {
        return Err(
            "it is a symbolic link (hydroid never writes through one); choose another name".into(),
        );
    }
    if !m.is_file() {
        return Err(format!(
            "it is {}, not a file; give the path of a file to write",
            super::what_is(&m)
        ));
    }
    let forced = replace == Replace::EvenIfChanged;
    let Some(entry) = listed else {
        return Err(format!(
            "the file exists and hydroid did not write it (it is not in {}); choose another \
             name, or move or delete it yourself",
            record_path.display()
        ));
    };
    if entry.kind != kind {
        return Err(match entry.kind {
            ExportKind::Simulate => format!(
                "it is a synthetic export `hydroid simulate` wrote (listed in {}), which runs \
                 read as their input; an FMU never replaces it, even with --force; choose \
                 another name",
                record_path.display()
            ),
            ExportKind::Fmu => format!(
                "it is an FMU `hydroid export fmu` wrote (listed in {}); a simulation never \
                 replaces it, even with --force; choose another name",
                record_path.display()
            ),
        });
    }
    if let Some(other) = entry.source.as_deref() {
        if kind == ExportKind::Simulate && other != source && !forced {
            return Err(format!(
                "it is the export of another simulation ({other}, relative to its folder, as \
                 {} records), which runs may read as their input; use --force to replace it \
                 anyway, or choose another --out",
                record_path.display()
            ));
        }
    }
    if entry.sha256 != file_sha256(target).map_err(|e| e.to_string())? && !forced {
        return Err(
            "hydroid wrote it, but it changed since; keep what you need and use --force to \
             overwrite it anyway, or choose another name"
                .into(),
        );
    }
    Ok(())
}

/// The record in `path`, empty when there is none; refused when it is not hydroid's. A
/// record of the first format lists simulations' exports.
fn read_record(path: &Path) -> Result<Record> {
    let bad = |why: String| {
        Error::Usage(format!(
            "{}: {why}; hydroid keeps the list of exports it wrote there. Move it away to \
             start a new list",
            path.display()
        ))
    };
    let mut record = Record {
        format: FORMAT.into(),
        files: BTreeMap::new(),
    };
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(record),
        Err(e) => return Err(Error::io(path, e)),
        Ok(m) if !m.is_file() => return Err(bad("not a file".into())),
        Ok(m) if m.len() > MAX_RECORD_BYTES => {
            return Err(bad(format!(
                "{}, larger than any record hydroid writes ({})",
                format_size(m.len()),
                format_size(MAX_RECORD_BYTES)
            )))
        }
        Ok(_) => {}
    }
    let limits = Limits {
        max_bytes: MAX_RECORD_BYTES,
        ..Limits::default()
    };
    let bytes = read_bytes(path, &limits)?;
    let text = String::from_utf8_lossy(&bytes);
    let not_ours = |e: serde_json::Error| bad(format!("not a hydroid record of exports ({e})"));
    let value: serde_json::Value = serde_json::from_str(&text).map_err(not_ours)?;
    match value.get("format").and_then(|f| f.as_str()) {
        Some(FORMAT) => serde_json::from_value(value).map_err(not_ours),
        Some(FORMAT_1) => {
            let mut first = value;
            if let Some(o) = first.as_object_mut() {
                o.remove("format");
            }
            let old: Record1 = serde_json::from_value(first).map_err(not_ours)?;
            for (name, sha256) in old.files {
                let entry = Entry {
                    sha256,
                    kind: ExportKind::Simulate,
                    source: None,
                };
                record.files.insert(name, entry);
            }
            Ok(record)
        }
        Some(other) => Err(bad(format!(
            "format '{other}', expected '{FORMAT}' (or '{FORMAT_1}')"
        ))),
        None => Err(bad("no format tag".into())),
    }
}

/// An exclusive lock on a folder, held while the returned file lives (none where folders
/// cannot be locked: then concurrent simulations into one folder may lose a record entry,
/// which only makes a later overwrite refuse).
fn lock_folder(dir: &Path) -> Option<File> {
    let f = File::open(dir).ok()?;
    f.lock().ok()?;
    Some(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sim(source: &Path) -> Export<'_> {
        Export {
            kind: ExportKind::Simulate,
            source,
            guarded: &[],
        }
    }

    #[test]
    fn only_unchanged_files_hydroid_wrote_are_overwritten() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path().join("run.csv");
        let src = root.path().join("sim.toml");
        let w = |replace| write_export(&p, b"t,u\n", &sim(&src), replace);
        w(Replace::IfUnchanged).unwrap();
        w(Replace::IfUnchanged).unwrap();
        std::fs::write(&p, "edited").unwrap();
        assert!(w(Replace::IfUnchanged).is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "edited");
        w(Replace::EvenIfChanged).unwrap();
        let mine = root.path().join("mine.csv");
        std::fs::write(&mine, "mine").unwrap();
        for replace in [Replace::IfUnchanged, Replace::EvenIfChanged] {
            assert!(write_export(&mine, b"x", &sim(&src), replace).is_err());
        }
        assert_eq!(std::fs::read_to_string(&mine).unwrap(), "mine");
        std::fs::write(&src, "model = 1").unwrap();
        let guarded = [Guarded {
            path: src.clone(),
            what: "the simulation's configuration".into(),
        }];
        let export = Export {
            guarded: &guarded,
            ..sim(&src)
        };
        let e = write_export(&src, b"x", &export, Replace::EvenIfChanged).unwrap_err();
        assert!(e.to_string().contains("simulation's configuration"), "{e}");
        assert_eq!(std::fs::read_to_string(&src).unwrap(), "model = 1");
    }

    #[test]
    fn one_kind_never_replaces_the_other_and_sources_are_kept() {
        let root = tempfile::tempdir().unwrap();
        let csv = root.path().join("exports/turn.csv");
        let a = root.path().join("a.toml");
        let b = root.path().join("b.toml");
        write_export(&csv, b"t\n", &sim(&a), Replace::IfUnchanged).unwrap();
        let fmu = Export {
            kind: ExportKind::Fmu,
            source: root.path(),
            guarded: &[],
        };
        for replace in [Replace::IfUnchanged, Replace::EvenIfChanged] {
            let e = write_export(&csv, b"PK", &fmu, replace).unwrap_err();
            assert!(e.to_string().contains("an FMU never replaces it"), "{e}");
        }
        assert_eq!(std::fs::read(&csv).unwrap(), b"t\n");
        // another simulation's export: only with --force
        let e = write_export(&csv, b"u\n", &sim(&b), Replace::IfUnchanged).unwrap_err();
        assert!(
            e.to_string().contains("another simulation (../a.toml"),
            "{e}"
        );
        write_export(&csv, b"u\n", &sim(&b), Replace::EvenIfChanged).unwrap();
        // an FMU is replaced by an FMU, never by a simulation
        let v = root.path().join("exports/v.fmu");
        write_export(&v, b"PK1", &fmu, Replace::IfUnchanged).unwrap();
        write_export(&v, b"PK2", &fmu, Replace::IfUnchanged).unwrap();
        let e = write_export(&v, b"t\n", &sim(&a), Replace::EvenIfChanged).unwrap_err();
        assert!(
            e.to_string().contains("a simulation never replaces it"),
            "{e}"
        );
        let text = std::fs::read_to_string(root.path().join("exports").join(EXPORTS_RECORD));
        let record: serde_json::Value = serde_json::from_str(&text.unwrap()).unwrap();
        assert_eq!(record["format"], FORMAT);
        assert_eq!(record["files"]["turn.csv"]["kind"], "simulate");
        assert_eq!(record["files"]["turn.csv"]["source"], "../b.toml");
        assert_eq!(record["files"]["v.fmu"]["kind"], "fmu");
        assert_eq!(record["files"]["v.fmu"]["source"], "..");
    }

    #[test]
    fn a_record_of_the_first_format_lists_simulations() {
        let root = tempfile::tempdir().unwrap();
        let csv = root.path().join("turn.csv");
        std::fs::write(&csv, "t\n").unwrap();
        let sha = file_sha256(&csv).unwrap();
        let first = format!(r#"{{"format": "{FORMAT_1}", "files": {{"turn.csv": "{sha}"}}}}"#);
        std::fs::write(root.path().join(EXPORTS_RECORD), first).unwrap();
        let fmu = Export {
            kind: ExportKind::Fmu,
            source: root.path(),
            guarded: &[],
        };
        assert!(write_export(&csv, b"PK", &fmu, Replace::EvenIfChanged).is_err());
        // any simulation replaces it (the first format does not say which wrote it)
        let src = root.path().join("any.toml");
        write_export(&csv, b"u\n", &sim(&src), Replace::IfUnchanged).unwrap();
        std::fs::write(root.path().join(EXPORTS_RECORD), r#"{"format": "x/9"}"#).unwrap();
        let e = write_export(&csv, b"v\n", &sim(&src), Replace::IfUnchanged).unwrap_err();
        assert!(e.to_string().contains("format 'x/9'"), "{e}");
    }

    #[test]
    fn nothing_is_written_inside_a_run_output() {
        let root = tempfile::tempdir().unwrap();
        let run = root.path().join("out/run");
        std::fs::create_dir_all(run.join("states")).unwrap();
        std::fs::write(run.join(MARKER), "{}").unwrap();
        let src = root.path().join("sim.toml");
        for p in [run.join("v.fmu"), run.join("states/new/x.csv")] {
            let e = write_export(&p, b"x", &sim(&src), Replace::EvenIfChanged).unwrap_err();
            assert!(e.to_string().contains("output folder of a run"), "{e}");
            assert!(!p.exists());
        }
        assert!(!run.join("states/new").exists());
    }
}
