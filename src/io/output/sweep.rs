//! Staging folders a hydroid process left behind when it could not clean up (SIGKILL, the
//! out-of-memory killer, a power cut) are removed by the next run into the same folder.
//!
//! A staging folder `.NAME.partial-PID` holds the staging marker `.hydroid-staging` (JSON:
//! format `hydroid-staging/1`, the target `NAME`, the `pid`) on which its process holds an
//! exclusive lock for as long as it runs. A folder is swept only when it has that marker, for
//! the name it carries, and its lock is free: its owner is gone. Nothing is deleted for its
//! name alone. If the owner died in the middle of replacing an output, after moving the old
//! output aside (into `old/`) and before the new one took its place, the old output is put
//! back first.

use std::fs::{File, TryLockError};
use std::path::{Path, PathBuf};

use super::signals::STAGING_MARKER;
/// The staging marker's format tag.
pub(crate) const STAGING_FORMAT: &str = "hydroid-staging/1";
/// The sub-folder of a staging folder holding the old output during a replacement.
pub(crate) const ASIDE: &str = "old";

/// The staging marker's contents.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct StagingMarker {
    /// `"hydroid-staging/1"`.
    pub format: String,
    /// The name of the output folder being written (`NAME`).
    pub target: String,
    /// The process writing it.
    pub pid: u32,
}

/// The staging folder's name for an output named `name` written by process `pid`.
pub(crate) fn staging_name(name: &str, pid: u32) -> String {
    format!(".{name}.partial-{pid}")
}

/// The output name of a staging folder's name (`.NAME.partial-PID`), if it is one.
fn target_of(folder_name: &str) -> Option<&str> {
    let (head, pid) = folder_name.strip_prefix('.')?.rsplit_once(".partial-")?;
    (!head.is_empty() && !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())).then_some(head)
}

/// Removes the abandoned staging folders in `parent`; returns what it did, one line each.
pub fn sweep(parent: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return Vec::new();
    };
    let mut done = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(target) = target_of(&name) else {
            continue;
        };
        if !e.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        if let Some(what) = sweep_one(parent, &e.path(), target) {
            done.push(what);
        }
    }
    done
}

/// Sweeps one staging folder if it is hydroid's and abandoned.
fn sweep_one(parent: &Path, folder: &Path, target: &str) -> Option<String> {
    let marker = folder.join(STAGING_MARKER);
    if !std::fs::symlink_metadata(&marker).is_ok_and(|m| m.is_file()) {
        return None;
    }
    let file = File::open(&marker).ok()?;
    match file.try_lock() {
        Ok(()) => {}
        Err(TryLockError::WouldBlock) | Err(TryLockError::Error(_)) => return None,
    }
    let text = std::fs::read_to_string(&marker).ok()?;
    let m: StagingMarker = serde_json::from_str(&text).ok()?;
    if m.format != STAGING_FORMAT || m.target != target {
        return None;
    }
    let mut what = format!("removed the abandoned staging folder {}", folder.display());
    let aside = folder.join(ASIDE);
    let out = parent.join(target);
    if std::fs::symlink_metadata(&aside).is_ok_and(|a| a.is_dir())
        && std::fs::symlink_metadata(&out).is_err()
    {
        if std::fs::rename(&aside, &out).is_err() {
            return None;
        }
        what = format!(
            "put back the output {} an interrupted run had moved aside, and {what}",
            out.display()
        );
    }
    super::signals::remove(folder);
    drop(file);
    if std::fs::symlink_metadata(folder).is_ok() {
        return None;
    }
    Some(what)
}

/// Where a staging folder of `name` by process `pid` goes in `parent`.
pub(crate) fn staging_path(parent: &Path, name: &str, pid: u32) -> PathBuf {
    parent.join(staging_name(name, pid))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn staging(parent: &Path, name: &str, pid: u32, marker: Option<&str>) -> PathBuf {
        let f = staging_path(parent, name, pid);
        std::fs::create_dir_all(f.join("out")).unwrap();
        if let Some(m) = marker {
            std::fs::write(f.join(STAGING_MARKER), m).unwrap();
        }
        f
    }

    #[test]
    fn only_marked_and_unlocked_staging_folders_are_swept() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path();
        let ok = r#"{"format":"hydroid-staging/1","target":"out","pid":99999}"#;
        let stale = staging(p, "out", 99999, Some(ok));
        let unmarked = staging(p, "out", 99998, None);
        let wrong = staging(p, "res", 99997, Some(ok));
        let live = staging(p, "out", 99996, Some(ok));
        let held = File::open(live.join(STAGING_MARKER)).unwrap();
        held.lock().unwrap();
        let lookalike = p.join(".out.partial-x");
        std::fs::create_dir(&lookalike).unwrap();
        let done = sweep(p);
        assert_eq!(done.len(), 1, "{done:?}");
        assert!(!stale.exists());
        for kept in [&unmarked, &wrong, &live, &lookalike] {
            assert!(kept.exists(), "{}", kept.display());
        }
    }

    #[test]
    fn an_output_moved_aside_is_put_back() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path();
        let ok = r#"{"format":"hydroid-staging/1","target":"out","pid":99999}"#;
        let stale = staging(p, "out", 99999, Some(ok));
        std::fs::create_dir(stale.join(ASIDE)).unwrap();
        std::fs::write(stale.join(ASIDE).join("results.json"), "{}").unwrap();
        sweep(p);
        assert!(p.join("out/results.json").exists());
        assert!(!stale.exists());
    }
}
