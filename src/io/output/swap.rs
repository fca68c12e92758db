//! Putting a finished folder in place of another as atomically as the filesystem allows: on
//! Linux one `renameat2(RENAME_EXCHANGE)` swaps them, so the target always holds a whole
//! output; elsewhere (or on a filesystem without it) the old folder is first moved aside and
//! moved back if the new one cannot take its place. The old output is never deleted here: it
//! ends up at `new`'s path (or at `aside`), inside the staging folder, for the caller to
//! remove once the new output is in place.

use crate::base::error::{Error, Result};
use std::path::Path;

/// Moves the folder `new` to `target`. When `target` exists, what it held ends up at `new`
/// (atomic exchange) or at `aside` (two renames); returns where.
pub fn replace<'a>(new: &'a Path, target: &Path, aside: &'a Path) -> Result<Option<&'a Path>> {
    let exists = std::fs::symlink_metadata(target).is_ok();
    if !exists {
        rename_no_replace(new, target)?;
        return Ok(None);
    }
    if exchange(new, target)? {
        return Ok(Some(new));
    }
    std::fs::rename(target, aside).map_err(|e| Error::io(target, e))?;
    if let Err(e) = std::fs::rename(new, target) {
        // put the old output back; if even that fails it is kept at `aside`
        if std::fs::rename(aside, target).is_err() {
            return Err(Error::Usage(format!(
                "{}: could not move the new output in place ({e}), nor the old one back; \
                 the old output is in {}",
                target.display(),
                aside.display()
            )));
        }
        return Err(Error::io(target, e));
    }
    Ok(Some(aside))
}

/// Swaps two folders in one step; false when the filesystem cannot.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> Result<bool> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    use rustix::io::Errno;
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(Errno::INVAL | Errno::NOSYS | Errno::NOTSUP) => Ok(false),
        Err(e) => Err(Error::io(b, e.into())),
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_a: &Path, _b: &Path) -> Result<bool> {
    Ok(false)
}

/// Renames `from` to `to`, failing (rather than replacing) if something appeared at `to`.
#[cfg(target_os = "linux")]
fn rename_no_replace(from: &Path, to: &Path) -> Result<()> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    use rustix::io::Errno;
    match renameat_with(CWD, from, CWD, to, RenameFlags::NOREPLACE) {
        Ok(()) => Ok(()),
        Err(Errno::INVAL | Errno::NOSYS | Errno::NOTSUP) => {
            std::fs::rename(from, to).map_err(|e| Error::io(to, e))
        }
        Err(e) => Err(Error::io(to, e.into())),
    }
}

#[cfg(not(target_os = "linux"))]
fn rename_no_replace(from: &Path, to: &Path) -> Result<()> {
    std::fs::rename(from, to).map_err(|e| Error::io(to, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_old_folder_is_kept_until_the_new_one_is_in_place() {
        let root = tempfile::tempdir().unwrap();
        let (new, target, aside) = (
            root.path().join("new"),
            root.path().join("out"),
            root.path().join("aside"),
        );
        std::fs::create_dir(&new).unwrap();
        std::fs::write(new.join("a"), "1").unwrap();
        assert_eq!(replace(&new, &target, &aside).unwrap(), None);
        assert_eq!(std::fs::read_to_string(target.join("a")).unwrap(), "1");
        std::fs::create_dir(&new).unwrap();
        std::fs::write(new.join("a"), "2").unwrap();
        let old = replace(&new, &target, &aside).unwrap().unwrap();
        assert_eq!(std::fs::read_to_string(target.join("a")).unwrap(), "2");
        assert_eq!(std::fs::read_to_string(old.join("a")).unwrap(), "1");
    }
}
