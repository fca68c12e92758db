//! Writing into an existing output folder (`hydroid calibrate`, `hydroid plan`): the folder is
//! read at the command's start and written into at its end, possibly minutes later, while
//! another hydroid may replace it (`run --out` or `rerun` onto the same folder). A [`Claim`]
//! remembers the folder it read (the folder itself, not its name, and the SHA-256 of the
//! files the command read), and writes only into that folder, unchanged: otherwise nothing is
//! written and the message says why.
//!
//! Every writer of an output folder takes turns on an advisory lock (`flock`) on the folder
//! itself: a claim's write holds it exclusively while it checks the folder again, writes its
//! files (each atomically) and records them in the marker; the swap that puts a new output in
//! place of the folder ([`super::Staging::commit`]) holds it exclusively while it checks
//! and replaces the folder; a claim's start holds it shared while it reads the folder. So a
//! run never replaces a folder half-way through a claim's write (files written, the marker
//! not yet updated), and a claim never writes into a folder that was swapped out: the swap
//! moves the locked folder away, and the claim, once it has the lock, finds another folder
//! at the name.

use super::marker;
use crate::base::error::{Error, Result};
use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

/// An output folder a command read, to write into at its end.
#[derive(Debug)]
pub struct Claim {
    /// The folder, as given.
    dir: PathBuf,
    /// The folder opened at the start: it stays this folder whatever is renamed, and its
    /// lock is the one every writer takes.
    handle: File,
    /// What the command does, for messages ("calibrate", "plan").
    verb: String,
    /// The files the command read, with their SHA-256 at the start.
    read: BTreeMap<String, String>,
}

/// An advisory lock on a folder, held until dropped. (Released explicitly: the lock belongs
/// to the open folder, which other handles of the same opening keep open.)
#[derive(Debug)]
pub struct Held(File);

impl Drop for Held {
    fn drop(&mut self) {
        let _ = self.0.unlock();
    }
}

impl Claim {
    /// Claims the output folder `dir` of `hydroid run` for `verb`: it must be exactly as
    /// hydroid wrote it ([`marker::require_unchanged`]). `reads` are the files of the folder
    /// the command reads (results.json, config.toml ...): they must be the same when it
    /// writes.
    pub fn open(dir: &Path, verb: &str, reads: &[&str]) -> Result<Claim> {
        // only a folder is opened (opening a named pipe would wait for a writer): anything
        // else is refused saying what it is
        if !std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
            marker::require_unchanged(dir, verb)?;
            return Err(Error::io(dir, std::io::ErrorKind::NotADirectory.into()));
        }
        let handle = File::open(dir).map_err(|e| Error::io(dir, e))?;
        let claim = {
            let _shared = lock(&handle, Mode::Shared);
            // under the lock: no claim is half-way through its write
            marker::require_unchanged(dir, verb)?;
            let claim = Claim {
                dir: dir.to_path_buf(),
                verb: verb.to_string(),
                read: BTreeMap::new(),
                handle,
            };
            if !claim.same_folder()? {
                return Err(claim.replaced());
            }
            let listed = listed(dir)?;
            let read = reads
                .iter()
                .filter_map(|r| listed.get(*r).map(|sha| (r.to_string(), sha.clone())))
                .collect();
            Claim { read, ..claim }
        };
        Ok(claim)
    }

    /// The folder, as given.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Writes `files` (paths relative to the folder, contents) into the claimed folder, each
    /// atomically, and records them in its marker, under the folder's lock, if the folder at
    /// the claimed name is still the one read at the start, exactly as hydroid wrote it, with
    /// the files the command read unchanged. Otherwise nothing is written and the error says
    /// what happened.
    pub fn write(&self, files: &[(&str, &[u8])]) -> Result<()> {
        let _held = lock(&self.handle, Mode::Exclusive);
        self.still_as_read()?;
        for (name, bytes) in files {
            super::write_atomic(&self.dir.join(name), bytes)?;
        }
        let names: Vec<&str> = files.iter().map(|(n, _)| *n).collect();
        marker::record(&self.dir, &names)
    }

    /// Refuses (writing nothing) when the folder at the name is another one, changed since
    /// hydroid wrote it, or holds other versions of the files read at the start.
    fn still_as_read(&self) -> Result<()> {
        if !self.same_folder()? {
            return Err(self.replaced());
        }
        marker::require_unchanged(&self.dir, &self.verb).map_err(|e| {
            Error::Usage(format!(
                "{} changed while {} ran; nothing written: {e}",
                self.dir.display(),
                self.verb
            ))
        })?;
        let listed = listed(&self.dir)?;
        let changed: Vec<&str> = self
            .read
            .iter()
            .filter(|(name, sha)| listed.get(*name) != Some(sha))
            .map(|(name, _)| name.as_str())
            .collect();
        if !changed.is_empty() {
            return Err(Error::Usage(format!(
                "{} changed while {} ran ({} written again since it was read); nothing \
                 written: run `hydroid {} {}` again",
                self.dir.display(),
                self.verb,
                changed.join(", "),
                self.verb,
                self.dir.display()
            )));
        }
        Ok(())
    }

    /// Whether the name still leads to the folder opened at the start.
    fn same_folder(&self) -> Result<bool> {
        let now = match std::fs::symlink_metadata(&self.dir) {
            Ok(m) => m,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
            Err(e) => return Err(Error::io(&self.dir, e)),
        };
        let then = self
            .handle
            .metadata()
            .map_err(|e| Error::io(&self.dir, e))?;
        Ok(now.is_dir() && identity(&now) == identity(&then))
    }

    /// The error for a folder another run put in place of the one read.
    fn replaced(&self) -> Error {
        Error::Usage(format!(
            "{} was replaced by another run while {} ran; nothing written (the new output is \
             left as it is: run `hydroid {} {}` again for it)",
            self.dir.display(),
            self.verb,
            self.verb,
            self.dir.display()
        ))
    }
}

/// The files the marker of `dir` lists, with their SHA-256.
fn listed(dir: &Path) -> Result<BTreeMap<String, String>> {
    Ok(marker::read(dir)?.files)
}

/// How a folder is locked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Readers together.
    Shared,
    /// One writer alone.
    Exclusive,
}

/// Locks `handle` (waiting for it). None where the filesystem cannot lock: then the checks
/// alone stand (a folder swapped out is still seen, a swap during the write is not kept out).
fn lock(handle: &File, mode: Mode) -> Option<Held> {
    let f = handle.try_clone().ok()?;
    let locked = match mode {
        Mode::Shared => f.lock_shared(),
        Mode::Exclusive => f.lock(),
    };
    locked.ok().map(|()| Held(f))
}

/// Locks exclusively the folder at `target` for a writer that replaces it (the swap of
/// [`super::Staging::commit`]), making sure the lock is on the folder now at the name (it may
/// be swapped while the lock is awaited). None when there is no folder at the name (nothing
/// to wait for: a link, a file or nothing) or it cannot be locked.
pub fn lock_folder_at(target: &Path) -> Option<Held> {
    // a few tries: each failure means another writer put a new folder in place meanwhile
    for _ in 0..8 {
        let meta = std::fs::symlink_metadata(target).ok()?;
        if !meta.is_dir() {
            return None;
        }
        let handle = File::open(target).ok()?;
        let held = lock(&handle, Mode::Exclusive)?;
        let now = std::fs::symlink_metadata(target).ok()?;
        let locked = handle.metadata().ok()?;
        if now.is_dir() && identity(&now) == identity(&locked) {
            return Some(held);
        }
    }
    None
}

/// What makes a folder this folder, whatever its name: device and inode.
#[cfg(unix)]
fn identity(m: &std::fs::Metadata) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    (m.dev(), m.ino())
}

#[cfg(not(unix))]
fn identity(_m: &std::fs::Metadata) -> (u64, u64) {
    (0, 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::output::marker::Marker;
    use crate::io::output::Staging;

    /// An output folder as `hydroid run` leaves it, with a results.json of `text`.
    fn output(target: &Path, text: &str) {
        let s = Staging::new(target).unwrap();
        s.write("results.json", text.as_bytes()).unwrap();
        s.write("states/a.csv", b"t\n0\n").unwrap();
        s.commit().unwrap();
    }

    #[test]
    fn a_claim_writes_and_records_into_the_folder_it_read() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        output(&out, "{}");
        let c = Claim::open(&out, "calibrate", &["results.json"]).unwrap();
        c.write(&[("calibration.json", b"{}"), ("calibration.md", b"# c")])
            .unwrap();
        assert_eq!(marker::inspect(&out).unwrap(), marker::Found::Unchanged);
        assert!(out.join("calibration.md").is_file());
        // written again over its own files: the folder is still hydroid's
        c.write(&[("calibration.json", b"{\"a\":1}")]).unwrap();
        assert_eq!(marker::inspect(&out).unwrap(), marker::Found::Unchanged);
        // and a run replaces it as its own
        output(&out, "{}");
        assert!(!out.join("calibration.json").exists());
    }

    #[test]
    fn a_folder_replaced_between_the_start_and_the_write_is_not_written() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        output(&out, "{\"run\":1}");
        let c = Claim::open(&out, "calibrate", &["results.json"]).unwrap();
        // another run puts its output in place, even one with the same files
        output(&out, "{\"run\":1}");
        let before = Marker::of_folder(&out).unwrap();
        let e = c.write(&[("calibration.json", b"{}")]).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{} was replaced by another run while calibrate ran; nothing written (the new \
                 output is left as it is: run `hydroid calibrate {}` again for it)",
                out.display(),
                out.display()
            )
        );
        assert!(!out.join("calibration.json").exists());
        assert_eq!(Marker::of_folder(&out).unwrap(), before);
        assert_eq!(marker::inspect(&out).unwrap(), marker::Found::Unchanged);
        // nor when the folder is gone, or a file stands at its name
        let c = Claim::open(&out, "plan", &[]).unwrap();
        std::fs::rename(&out, root.path().join("moved")).unwrap();
        std::fs::write(&out, "x").unwrap();
        assert!(c.write(&[("plan.json", b"{}")]).is_err());
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "x");
        assert!(!root.path().join("moved/plan.json").exists());
    }

    #[test]
    fn a_folder_edited_meanwhile_is_not_written() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        output(&out, "{}");
        let c = Claim::open(&out, "plan", &["results.json"]).unwrap();
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        let e = c.write(&[("plan.json", b"{}")]).unwrap_err().to_string();
        assert!(
            e.contains("changed while plan ran; nothing written") && e.contains("notes.txt"),
            "{e}"
        );
        assert!(!out.join("plan.json").exists());
        // a file read, written again and recorded (by hand) in the same folder
        std::fs::remove_file(out.join("notes.txt")).unwrap();
        std::fs::write(out.join("results.json"), "{\"other\":1}").unwrap();
        marker::record(&out, &["results.json"]).unwrap();
        let e = c.write(&[("plan.json", b"{}")]).unwrap_err().to_string();
        assert!(e.contains("(results.json written again"), "{e}");
        assert!(!out.join("plan.json").exists());
    }

    #[test]
    #[cfg(unix)]
    fn a_named_pipe_is_refused_without_being_opened() {
        let root = tempfile::tempdir().unwrap();
        let fifo = root.path().join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return;
        }
        let e = Claim::open(&fifo, "calibrate", &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("not an output folder") && e.contains("named pipe"),
            "{e}"
        );
    }

    #[test]
    fn a_claim_of_what_is_not_an_output_is_refused() {
        let root = tempfile::tempdir().unwrap();
        let plain = root.path().join("notes");
        std::fs::create_dir(&plain).unwrap();
        let e = Claim::open(&plain, "calibrate", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("not an output folder"), "{e}");
        let e = Claim::open(&root.path().join("none"), "plan", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("no such output folder"), "{e}");
    }

    #[test]
    fn the_swap_waits_for_a_claims_lock_on_the_folder() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        output(&out, "{}");
        let held = lock_folder_at(&out).expect("a folder can be locked");
        // a second exclusive lock on the same folder is refused while the first is held
        let other = File::open(&out).unwrap();
        assert!(other.try_lock().is_err());
        drop(held);
        assert!(other.try_lock().is_ok());
        drop(other);
        // nothing, or a file, at the name: nothing to lock
        assert!(lock_folder_at(&root.path().join("none")).is_none());
        std::fs::write(root.path().join("f"), "x").unwrap();
        assert!(lock_folder_at(&root.path().join("f")).is_none());
    }
}
