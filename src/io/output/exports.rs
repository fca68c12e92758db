//! Synthetic exports (`hydroid simulate`) keep their real CFD layout, so the record of what
//! hydroid wrote lives beside them: `.hydroid-exports.json` in the export's folder, file name
//! -> SHA-256 of what hydroid wrote. An existing file is overwritten only when it is listed
//! there and unchanged (or changed, with `--force`); an unlisted file, a folder, a symbolic
//! link or the simulation's own configuration never.

use super::paths::resolve;
use super::{write_atomic, Replace};
use crate::base::error::{Error, Result};
use crate::io::formats::input::file_sha256;
use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The record's file name.
pub const EXPORTS_RECORD: &str = ".hydroid-exports.json";
/// The record's format tag.
const FORMAT: &str = "hydroid-exports/1";

/// The record's contents.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Record {
    /// `"hydroid-exports/1"`.
    format: String,
    /// File name in this folder -> SHA-256 (hex) of what hydroid wrote.
    files: BTreeMap<String, String>,
}

/// Writes an export to `path` (atomically) and records it; `protected` are files it must
/// never be (the simulation configuration). Returns the resolved path written.
pub fn write_export(
    path: &Path,
    bytes: &[u8],
    protected: &[&Path],
    replace: Replace,
) -> Result<PathBuf> {
    let target = resolve(path)?;
    let refuse = |why: &str| {
        Error::Usage(format!(
            "refusing to write the export to {}: {why}",
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
    for p in protected {
        if std::fs::canonicalize(p).is_ok_and(|c| c == target)
            || resolve(p).is_ok_and(|r| r == target)
        {
            return Err(refuse("it is the simulation's configuration"));
        }
    }
    super::create_folder(dir, "the export")?;
    // one writer of the record at a time (several simulations into one folder)
    let _lock = lock_folder(dir);
    let record_path = dir.join(EXPORTS_RECORD);
    let mut record = read_record(&record_path)?;
    match std::fs::symlink_metadata(&target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(Error::io(&target, e)),
        Ok(m) if m.file_type().is_symlink() => {
            return Err(refuse(
                "it is a symbolic link (hydroid never writes through one); choose another --out",
            ))
        }
        Ok(m) if !m.is_file() => {
            return Err(refuse(&format!(
                "it is {}, not a file; give the path of a file to write",
                super::what_is(&m)
            )))
        }
        Ok(_) => match record.files.get(&name) {
            None => {
                return Err(refuse(&format!(
                    "the file exists and hydroid did not write it (it is not in {}); \
                     choose another --out, or move or delete it yourself",
                    record_path.display()
                )))
            }
            Some(sha) if *sha == file_sha256(&target)? => {}
            Some(_) if replace == Replace::EvenIfChanged => {}
            Some(_) => {
                return Err(refuse(
                    "hydroid wrote it, but it changed since; keep what you need and use \
                     --force to overwrite it anyway, or choose another --out",
                ))
            }
        },
    }
    write_atomic(&target, bytes)?;
    record.files.insert(name, file_sha256(&target)?);
    write_atomic(&record_path, &crate::io::output::to_json(&record)?)?;
    Ok(target)
}

/// The record in `path`, empty when there is none; refused when it is not hydroid's.
fn read_record(path: &Path) -> Result<Record> {
    let bad = |why: String| {
        Error::Usage(format!(
            "{}: {why}; hydroid keeps the list of exports it wrote there. Move it away to \
             start a new list",
            path.display()
        ))
    };
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Ok(Record {
                format: FORMAT.into(),
                files: BTreeMap::new(),
            })
        }
        Err(e) => return Err(Error::io(path, e)),
        Ok(m) if !m.is_file() => return Err(bad("not a file".into())),
        Ok(_) => {}
    }
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let r: Record = serde_json::from_str(&text)
        .map_err(|e| bad(format!("not a hydroid record of exports ({e})")))?;
    if r.format != FORMAT {
        return Err(bad(format!("format '{}', expected '{FORMAT}'", r.format)));
    }
    Ok(r)
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

    #[test]
    fn only_unchanged_files_hydroid_wrote_are_overwritten() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path().join("run.csv");
        let w = |replace| write_export(&p, b"t,u\n", &[], replace);
        w(Replace::IfUnchanged).unwrap();
        w(Replace::IfUnchanged).unwrap();
        std::fs::write(&p, "edited").unwrap();
        assert!(w(Replace::IfUnchanged).is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "edited");
        w(Replace::EvenIfChanged).unwrap();
        let mine = root.path().join("mine.csv");
        std::fs::write(&mine, "mine").unwrap();
        for replace in [Replace::IfUnchanged, Replace::EvenIfChanged] {
            assert!(write_export(&mine, b"x", &[], replace).is_err());
        }
        assert_eq!(std::fs::read_to_string(&mine).unwrap(), "mine");
        let cfg = root.path().join("sim.toml");
        std::fs::write(&cfg, "model = 1").unwrap();
        assert!(write_export(&cfg, b"x", &[&cfg], Replace::EvenIfChanged).is_err());
    }
}
