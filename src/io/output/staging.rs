//! An output folder assembled under a temporary name next to its target and put in place
//! whole, under the rules of [`super`]: it never replaces anything but an unchanged hydroid
//! output (or a changed one when forced), nor a protected place.
//!
//! Layout while a run writes `PARENT/NAME`:
//!
//! ```text
//! PARENT/.NAME.partial-PID/
//!     .hydroid-staging    staging marker, locked by the running process (see super::sweep)
//!     out/                the output being written; becomes PARENT/NAME
//!     old/                during a replacement without atomic exchange: the old output
//! ```

use super::marker::{inspect, Found, Marker, MARKER};
use super::protect::Protected;
use super::signals;
use super::signals::STAGING_MARKER;
use super::sweep::{staging_path, sweep, StagingMarker, ASIDE, STAGING_FORMAT};
use crate::base::error::{Error, Result};
use std::fs::File;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

/// Whether an existing hydroid output that changed since it was written may be replaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Replace {
    /// Only an output exactly as hydroid wrote it (the default).
    #[default]
    IfUnchanged,
    /// Also a hydroid output with files added, changed or removed (`--force`).
    EvenIfChanged,
    /// Also a hydroid output whose only changes are edits of these files (`rerun --edited`:
    /// the recorded configuration the rerun has read and accepted).
    IfOnlyEdited(&'static [&'static str]),
}

impl Replace {
    /// `--force` given or not.
    pub fn forced(force: bool) -> Self {
        if force {
            Replace::EvenIfChanged
        } else {
            Replace::IfUnchanged
        }
    }
}

/// An output folder being assembled. Files go into a staging folder next to the target;
/// [`Staging::commit`] puts it in place of the target, and dropping without committing
/// removes the staging folder.
#[derive(Debug)]
pub struct Staging {
    /// The resolved target.
    target: PathBuf,
    /// `.NAME.partial-PID`.
    root: PathBuf,
    /// `root/out`.
    out: PathBuf,
    replace: Replace,
    /// What the sweep of abandoned staging folders did.
    swept: Vec<String>,
    /// The staging marker, locked while this process lives.
    _lock: File,
    done: bool,
}

impl Staging {
    /// Starts assembling `target`, protecting only the working and home folders (a run
    /// protects its configuration and inputs too: [`Staging::guarded`]).
    pub fn new(target: &Path) -> Result<Self> {
        Self::guarded(target, &Protected::new(), Replace::IfUnchanged)
    }

    /// The checks [`Staging::guarded`] makes of `target` before a run, without writing
    /// anything (for `hydroid check`): an error when the target may never be written (a
    /// protected place, a folder hydroid did not write, a file), `Some(why)` when it is a
    /// hydroid output that changed since (a run replaces it only with `--force`).
    pub fn preview(target: &Path, protected: &Protected) -> Result<Option<String>> {
        let (target, parent, _) = placed(target, protected)?;
        can_write_in(&parent, &target)?;
        match check_replaceable(&target, Replace::IfUnchanged) {
            Ok(()) => Ok(None),
            Err(e) if matches!(inspect(&target)?, Found::Changed(_)) => Ok(Some(e.to_string())),
            Err(e) => Err(e),
        }
    }

    /// Starts assembling `target` after checking that it may be written: not a protected
    /// place, and nothing there but an unchanged hydroid output (or a changed one with
    /// [`Replace::EvenIfChanged`]). Abandoned staging folders beside it are swept first.
    pub fn guarded(target: &Path, protected: &Protected, replace: Replace) -> Result<Self> {
        let (target, parent, name) = placed(target, protected)?;
        create_parent(&parent)?;
        // first, as it may put back an output a killed run had moved aside
        let swept = sweep(&parent);
        check_replaceable(&target, replace)?;
        let pid = std::process::id();
        let root = staging_path(&parent, &name, pid);
        // created and registered under the registry's lock: a signal between the two would
        // otherwise leave the folder behind (the handler takes the same lock)
        let created = {
            let mut active = signals::lock();
            let made = std::fs::create_dir(&root);
            if made.is_ok() {
                active.push(root.clone());
            }
            made
        };
        created.map_err(|e| {
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                Error::Usage(format!(
                    "{}: a staging folder of this name already exists and is in use or not \
                     hydroid's; remove it yourself if no hydroid is running",
                    root.display()
                ))
            } else {
                Error::Usage(format!(
                    "cannot write in {}: {} (the output goes to {})",
                    parent.display(),
                    crate::base::error::io_reason(&e),
                    target.display()
                ))
            }
        })?;
        let lock = match lock_staging(&root, &name, pid) {
            Ok(l) => l,
            Err(e) => {
                signals::forget(&root);
                signals::remove(&root);
                return Err(e);
            }
        };
        let s = Staging {
            out: root.join("out"),
            root,
            target,
            replace,
            swept,
            _lock: lock,
            done: false,
        };
        std::fs::create_dir(&s.out).map_err(|e| Error::write(&s.out, e))?;
        Ok(s)
    }

    /// The folder to write into.
    pub fn dir(&self) -> &Path {
        &self.out
    }

    /// What was done to abandoned staging folders beside the target, one line each (for
    /// the user to read).
    pub fn swept(&self) -> &[String] {
        &self.swept
    }

    /// Where the output goes (resolved).
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// An error about a file being written in the staging folder, said of the file it will
    /// be in the output (`out/results.json`, not `.out.partial-PID/out/results.json`): the
    /// staging folder is hydroid's business, the target is the user's.
    pub fn as_target(&self, e: Error) -> Error {
        let moved = |p: PathBuf| match p.strip_prefix(&self.out) {
            Ok(rel) => self.target.join(rel),
            Err(_) => p,
        };
        match e {
            Error::Write { path, source } => Error::Write {
                path: moved(path),
                source,
            },
            Error::Io { path, source } => Error::Io {
                path: moved(path),
                source,
            },
            e => e,
        }
    }

    /// Creates a sub-folder (path relative to the output) and returns it. Only folders below
    /// the staging folder are created: if it was removed (a signal), this fails.
    pub fn create_dir(&self, rel: &str) -> Result<PathBuf> {
        let mut path = self.out.clone();
        for c in Path::new(rel).components() {
            let Component::Normal(n) = c else {
                return Err(Error::Usage(format!(
                    "'{rel}': not a path inside the output folder"
                )));
            };
            path.push(n);
            match std::fs::create_dir(&path) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && path.is_dir() => {}
                Err(e) => return Err(self.as_target(Error::write(&path, e))),
            }
        }
        Ok(path)
    }

    /// Writes a file (path relative to the folder).
    pub fn write(&self, rel: &str, bytes: &[u8]) -> Result<()> {
        let path = self.file_path(rel)?;
        std::fs::write(&path, bytes).map_err(|e| self.as_target(Error::write(&path, e)))
    }

    /// Writes a file (path relative to the folder) as `fill` streams it, through a buffer:
    /// for a file too large to assemble in memory first. Like every file of the folder, it
    /// is in the output only once the whole folder is put in place ([`Staging::commit`]).
    pub fn write_stream(
        &self,
        rel: &str,
        fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<()> {
        let path = self.file_path(rel)?;
        let written = File::create(&path).and_then(|f| {
            let mut w = std::io::BufWriter::with_capacity(1 << 16, f);
            fill(&mut w)?;
            w.into_inner().map(drop).map_err(|e| e.into_error())
        });
        written.map_err(|e| self.as_target(Error::write(&path, e)))
    }

    /// The staged path of a file (path relative to the folder), its folders created.
    fn file_path(&self, rel: &str) -> Result<PathBuf> {
        let dir = match rel.rsplit_once('/') {
            Some((d, _)) => self.create_dir(d)?,
            None => self.out.clone(),
        };
        let name = rel.rsplit('/').next().unwrap_or(rel);
        if name.is_empty() || name == "." || name == ".." || name == MARKER {
            return Err(Error::Usage(format!(
                "'{rel}': not a file name hydroid writes"
            )));
        }
        Ok(dir.join(name))
    }

    /// Puts the staged folder in place of the target (checked again: it may have changed
    /// while the run went on), with its marker; the old output is removed only once the new
    /// one is in place. The old output's lock ([`super::claim`]) is held meanwhile, so that
    /// a command adding files to it is not half-way through.
    pub fn commit(mut self) -> Result<PathBuf> {
        {
            // no claim is writing into the old output while it is checked and swapped out
            // (taken first: a signal while it is awaited ends the run as usual)
            let _held = super::claim::lock_folder_at(&self.target);
            // a signal now waits until the folders are where they belong
            let _moving = signals::lock();
            check_replaceable(&self.target, self.replace)?;
            Marker::of_folder(&self.out)?
                .write(&self.out)
                .map_err(|e| self.as_target(e))?;
            super::swap::replace(&self.out, &self.target, &self.root.join(ASIDE))?;
            self.done = true;
        }
        // what is left (the staging marker and the old output) is garbage now
        signals::remove(&self.root);
        signals::forget(&self.root);
        Ok(self.target.clone())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.done {
            signals::remove(&self.root);
            signals::forget(&self.root);
        }
    }
}

/// The checks of an output's place that read nothing in it: not a protected place, and a
/// name in a folder, short enough for the staging folder's name beside it. The resolved
/// target, its folder and its name.
fn placed(target: &Path, protected: &Protected) -> Result<(PathBuf, PathBuf, String)> {
    let target = protected.check_path(target)?;
    let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else {
        return Err(Error::Usage(format!(
            "{}: not a folder an output can be written to",
            target.display()
        )));
    };
    let (parent, name) = (parent.to_path_buf(), name.to_string_lossy().into_owned());
    // the staging folder's name, `.NAME.partial-PID`, must be a file name too
    let staging = super::sweep::staging_name(&name, u32::MAX).len();
    let longest = NAME_BYTES - (staging - name.len());
    if staging > NAME_BYTES {
        return Err(Error::Usage(format!(
            "{}: the output folder's name is {} bytes long; hydroid assembles the output beside \
             it under the name .NAME.partial-PID, and a name is at most {NAME_BYTES} bytes: \
             give an output folder name of at most {longest} bytes",
            target.display(),
            name.len()
        )));
    }
    Ok((target, parent, name))
}

/// The most bytes of a file or folder name (Linux, macOS and Windows file systems).
const NAME_BYTES: usize = 255;

/// Whether an output can be assembled in `parent` (for `hydroid check`, which writes
/// nothing that stays): a folder is made in its nearest existing folder and removed at once,
/// as a run makes its staging folder there. The error is a run's.
fn can_write_in(parent: &Path, target: &Path) -> Result<()> {
    let Some(existing) = parent.ancestors().find(|a| a.is_dir()) else {
        return Ok(());
    };
    let trial = existing.join(format!(".hydroid-check-{}", std::process::id()));
    match std::fs::create_dir(&trial) {
        Ok(()) => {
            let _ = std::fs::remove_dir(&trial);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(Error::Usage(format!(
            "cannot write in {}: {} (the output goes to {})",
            existing.display(),
            crate::base::error::io_reason(&e),
            target.display()
        ))),
    }
}

/// Refuses a target that holds anything but a hydroid output that may be replaced.
fn check_replaceable(target: &Path, replace: Replace) -> Result<()> {
    match inspect(target)? {
        Found::Nothing | Found::Unchanged => Ok(()),
        Found::Changed(_) if replace == Replace::EvenIfChanged => Ok(()),
        Found::Changed(changes) if only_edits_of(&changes, replace) => Ok(()),
        Found::Changed(changes) => {
            const SHOWN: usize = 20;
            let mut list = changes
                .iter()
                .take(SHOWN)
                .map(|c| format!("\n  - {c}"))
                .collect::<String>();
            if changes.len() > SHOWN {
                list.push_str(&format!("\n  - and {} more", changes.len() - SHOWN));
            }
            Err(Error::Usage(format!(
                "refusing to replace {}: it is a hydroid output, but it changed since hydroid \
                 wrote it:{list}\nkeep what you need and use --force to replace it anyway, or \
                 choose another --out",
                target.display()
            )))
        }
        Found::Foreign(why) => Err(Error::Usage(format!(
            "refusing to replace {}: {why}. hydroid only replaces an output folder it wrote \
             (one with an unchanged {MARKER}), with or without --force; choose another --out \
             (or output.dir), or move or delete it yourself",
            target.display()
        ))),
    }
}

/// True when `replace` accepts edits of some files and `changes` are edits of those only.
fn only_edits_of(changes: &[String], replace: Replace) -> bool {
    let Replace::IfOnlyEdited(files) = replace else {
        return false;
    };
    changes.iter().all(|c| {
        c.strip_prefix("changed: ")
            .is_some_and(|f| files.contains(&f))
    })
}

/// Creates the folder an output goes into (and those above it), with a clear message.
fn create_parent(parent: &Path) -> Result<()> {
    super::create_folder(parent, "the output")
}

/// Creates the staging marker, locks it, then says what it is (in that order: a sweep never
/// sees a valid marker unlocked).
fn lock_staging(root: &Path, name: &str, pid: u32) -> Result<File> {
    let path = root.join(STAGING_MARKER);
    let mut f = File::create_new(&path).map_err(|e| Error::write(&path, e))?;
    f.lock().map_err(|e| Error::io(&path, e))?;
    let m = StagingMarker {
        format: STAGING_FORMAT.into(),
        target: name.into(),
        pid,
    };
    let text = serde_json::to_vec(&m).map_err(|e| Error::Usage(e.to_string()))?;
    f.write_all(&text).map_err(|e| Error::write(&path, e))?;
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(d: &Path) -> usize {
        std::fs::read_dir(d).unwrap().count()
    }

    #[test]
    fn staged_folder_replaces_the_old_one_only_on_commit() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let s = Staging::new(&target).unwrap();
        s.write("old.txt", b"old").unwrap();
        s.commit().unwrap();
        {
            let s = Staging::new(&target).unwrap();
            s.write("results.json", b"{}").unwrap();
            // dropped without commit: the old output stays, the staging folder goes
        }
        assert!(target.join("old.txt").exists());
        assert_eq!(entries(root.path()), 1);
        let s = Staging::new(&target).unwrap();
        s.write("plots/a.svg", b"<svg/>").unwrap();
        s.commit().unwrap();
        assert!(!target.join("old.txt").exists());
        assert!(target.join("plots/a.svg").exists());
        assert!(target.join(MARKER).exists());
        assert_eq!(entries(root.path()), 1);
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_full_disk_names_the_file_in_the_output_not_the_staging_folder() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let s = Staging::new(&target).unwrap();
        // every write to /dev/full fails as on a full disk
        std::os::unix::fs::symlink("/dev/full", s.dir().join("results.json")).unwrap();
        let e = s.write("results.json", b"{}").unwrap_err().to_string();
        let resolved = std::fs::canonicalize(root.path()).unwrap().join("out");
        assert_eq!(
            e,
            format!(
                "cannot write {}: No space left on device",
                resolved.join("results.json").display()
            )
        );
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_streamed_file_is_written_whole_and_a_failure_names_it_in_the_output() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let s = Staging::new(&target).unwrap();
        s.write_stream("states/a.csv", |w| {
            for k in 0..100_000 {
                writeln!(w, "{k}")?;
            }
            Ok(())
        })
        .unwrap();
        let text = std::fs::read_to_string(s.dir().join("states/a.csv")).unwrap();
        assert_eq!(text.lines().count(), 100_000);
        assert!(text.ends_with("99999\n"));
        // what the filling says is the error, of the file as it will be in the output
        let e = s
            .write_stream("states/b.csv", |_| Err(std::io::Error::other("spool lost")))
            .unwrap_err()
            .to_string();
        let resolved = std::fs::canonicalize(root.path()).unwrap().join("out");
        let b = resolved.join("states/b.csv");
        assert_eq!(e, format!("cannot write {}: spool lost", b.display()));
        // a full disk, met when the buffer is flushed
        std::os::unix::fs::symlink("/dev/full", s.dir().join("states/c.csv")).unwrap();
        let e = s
            .write_stream("states/c.csv", |w| w.write_all(b"x"))
            .unwrap_err()
            .to_string();
        let c = resolved.join("states/c.csv");
        assert_eq!(
            e,
            format!("cannot write {}: No space left on device", c.display())
        );
        std::fs::remove_file(s.dir().join("states/c.csv")).unwrap();
        s.commit().unwrap();
        assert!(target.join("states/a.csv").is_file());
    }

    #[test]
    fn a_changed_output_is_replaced_only_when_forced() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let s = Staging::new(&target).unwrap();
        s.write("results.json", b"{}").unwrap();
        s.commit().unwrap();
        std::fs::write(target.join("notes.txt"), "mine").unwrap();
        let e = Staging::new(&target).unwrap_err().to_string();
        assert!(
            e.contains("added: notes.txt") && e.contains("--force"),
            "{e}"
        );
        let s = Staging::guarded(&target, &Protected::new(), Replace::EvenIfChanged).unwrap();
        s.commit().unwrap();
        assert!(!target.join("notes.txt").exists());
    }

    #[test]
    fn a_name_too_long_for_the_staging_folder_is_refused_before_anything_is_written() {
        let root = tempfile::tempdir().unwrap();
        let ok = root.path().join("n".repeat(235));
        Staging::new(&ok).unwrap().commit().unwrap();
        assert!(ok.is_dir());
        let long = root.path().join("n".repeat(236));
        for e in [
            Staging::new(&long).unwrap_err().to_string(),
            Staging::preview(&long, &Protected::new())
                .unwrap_err()
                .to_string(),
        ] {
            assert!(
                e.contains("is 236 bytes long") && e.contains("of at most 235 bytes"),
                "{e}"
            );
        }
        assert_eq!(entries(root.path()), 1);
    }

    #[test]
    fn a_place_hydroid_cannot_write_in_is_seen_by_the_preview() {
        let root = tempfile::tempdir().unwrap();
        // the preview's trial folder is gone again
        assert_eq!(
            Staging::preview(&root.path().join("a/b/out"), &Protected::new()).unwrap(),
            None
        );
        assert_eq!(entries(root.path()), 0);
        // /proc takes no folder, even for root
        let e = Staging::preview(Path::new("/proc/hydroid-out"), &Protected::new())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("cannot write in /proc: "), "{e}");
    }

    #[test]
    fn a_change_during_the_run_is_seen_at_commit() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        Staging::new(&target).unwrap().commit().unwrap();
        let s = Staging::new(&target).unwrap();
        std::fs::write(target.join("notes.txt"), "mine").unwrap();
        assert!(s.commit().is_err());
        assert!(target.join("notes.txt").exists());
        assert_eq!(entries(root.path()), 1);
    }
}
