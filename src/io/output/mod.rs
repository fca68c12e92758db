//! Writing outputs without ever losing a user's files.
//!
//! * An output folder is assembled under a temporary name next to its target and put in
//!   place whole ([`Staging`]), so a failed or interrupted run never leaves a half-written
//!   result.
//! * It replaces only an earlier hydroid output, recognised by the marker hydroid writes into
//!   every output folder ([`marker`]) and unchanged since (or changed, when forced); never a
//!   folder without the marker, a file or a link, and never a protected place: the
//!   configuration, an input or a folder holding one, the working folder or one above it,
//!   the home folder, the root ([`Protected`]).
//! * Exports (a simulation's synthetic CFD export, an FMU) are overwritten only when a record
//!   beside them says hydroid wrote them, as the same kind of export, unchanged; never onto
//!   a file the caller guards (a configuration, an input of the run an FMU is made from) or
//!   into a run's output folder ([`exports`]).
//! * A command that adds files to an existing output folder (`calibrate`, `plan`) writes them
//!   only into the folder it read at its start, unchanged, taking turns with every other
//!   writer of the folder on a lock ([`claim`]).
//! * SIGINT and SIGTERM remove what was being written ([`signals`]); what a killed process
//!   left is swept by the next run ([`sweep`]).
//!
//! docs/outputs.md describes the rules as a user meets them.

pub mod claim;
pub mod exports;
pub mod marker;
pub mod paths;
pub mod protect;
pub mod signals;
pub mod staging;
pub mod swap;
pub mod sweep;

pub use claim::Claim;
pub use exports::write_export;
pub use protect::Protected;
pub use signals::clean_up_on_signals;
pub use staging::{Replace, Staging};

use crate::base::error::{Error, Result};
use std::path::Path;

/// Pretty JSON with a final newline.
pub fn to_json<T: serde::Serialize>(value: &T) -> Result<Vec<u8>> {
    let mut v = serde_json::to_vec_pretty(value)
        .map_err(|e| Error::Usage(format!("cannot serialise the results: {e}")))?;
    v.push(b'\n');
    Ok(v)
}

/// What is at a place, in words, for a message: "a file", "a folder", "a character device
/// (such as /dev/null or /dev/full)" ...
pub fn what_is(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_symlink() {
        return "a symbolic link";
    }
    if t.is_dir() {
        return "a folder";
    }
    if t.is_file() {
        return "a file";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device (such as /dev/null, /dev/full or a terminal)";
        }
        if t.is_block_device() {
            return "a block device (a disk)";
        }
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "neither a file nor a folder"
}

/// Creates the folder `dir` (and those above it) for `what`; the error names the folder and
/// says what is in the way (a file or a device where a folder was expected) or what the
/// system said, without its error number.
pub fn create_folder(dir: &Path, what: &str) -> Result<()> {
    match std::fs::create_dir_all(dir) {
        Ok(()) => Ok(()),
        Err(e) => {
            // the first place on the path that exists and is not a folder
            let blocking = dir.ancestors().find_map(|a| {
                std::fs::metadata(a)
                    .ok()
                    .filter(|m| !m.is_dir())
                    .map(|m| (a, what_is(&m)))
            });
            Err(Error::Usage(match blocking {
                Some((at, kind)) => format!(
                    "cannot create the folder {} for {what}: {} is {kind}, not a folder",
                    dir.display(),
                    at.display()
                ),
                None => format!(
                    "cannot create the folder {} for {what}: {}",
                    dir.display(),
                    crate::base::error::io_reason(&e)
                ),
            }))
        }
    }
}

/// Writes `bytes` to `path` atomically (temporary file in the same folder, then rename). The
/// temporary file is removed if a signal ends the process meanwhile. The caller decides
/// whether `path` may be replaced ([`write_export`] does for exports). An error names
/// `path`, never the temporary file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    create_folder(dir, &path.display().to_string())?;
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    signals::register(&tmp);
    let written = std::fs::write(&tmp, bytes)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|e| Error::write(path, e));
    if written.is_err() {
        signals::remove(&tmp);
    }
    signals::forget(&tmp);
    written
}

/// Writes `bytes` to a new file at `path`, refusing when anything is there already (a file,
/// a folder, a link, even a dangling one): for a file hydroid creates once and never replaces,
/// such as the template of `hydroid init`. Missing folders above it are created. The file is
/// removed if writing it fails or a signal ends the process meanwhile.
pub fn write_new(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_folder(dir, &path.display().to_string())?;
    }
    let mut file = match std::fs::File::create_new(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            let what = std::fs::symlink_metadata(path).map_or("something", |m| what_is(&m));
            return Err(Error::Usage(format!(
                "refusing to write {}: it already exists ({what}; hydroid never overwrites \
                 anything there); choose another name or move it away first",
                path.display()
            )));
        }
        Err(e) => {
            return Err(Error::Usage(format!(
                "cannot create the file {}: {} (expected a folder where a new file can be \
                 written)",
                path.display(),
                crate::base::error::io_reason(&e)
            )))
        }
    };
    // registered only once created: a signal must never remove what was there before
    signals::register(path);
    let written = file
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .map_err(|e| Error::write(path, e));
    if written.is_err() {
        signals::remove(path);
    }
    signals::forget(path);
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn a_failed_write_names_the_target_not_the_temporary_file() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("turn.csv");
        let tmp = root
            .path()
            .join(format!(".turn.csv.tmp-{}", std::process::id()));
        // the temporary file is on a full disk
        std::os::unix::fs::symlink("/dev/full", &tmp).unwrap();
        let e = write_atomic(&target, b"t,u\n").unwrap_err().to_string();
        assert_eq!(
            e,
            format!("cannot write {}: No space left on device", target.display())
        );
        assert!(!target.exists());
        // a device where a folder is expected is named as what it is
        let e = write_new(Path::new("/dev/full/hydroid.toml"), b"x")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "cannot create the folder /dev/full for /dev/full/hydroid.toml: /dev/full is a \
             character device (such as /dev/null, /dev/full or a terminal), not a folder"
        );
        assert!(!e.contains("os error"), "{e}");
    }

    #[test]
    fn a_new_file_never_replaces_anything() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path().join("sub/a.toml");
        write_new(&p, b"x").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "x");
        let e = write_new(&p, b"y").unwrap_err().to_string();
        assert!(e.contains("already exists"), "{e}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "x");
        #[cfg(unix)]
        {
            let link = root.path().join("dangling.toml");
            std::os::unix::fs::symlink(root.path().join("nowhere"), &link).unwrap();
            assert!(write_new(&link, b"y").is_err());
            assert!(!root.path().join("nowhere").exists());
        }
    }

    #[test]
    fn atomic_write_leaves_no_temporary() {
        let root = tempfile::tempdir().unwrap();
        let p = root.path().join("a.csv");
        write_atomic(&p, b"x").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "x");
        assert_eq!(std::fs::read_dir(root.path()).unwrap().count(), 1);
    }
}
