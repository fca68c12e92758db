//! Cleaning up on SIGINT and SIGTERM: the staging folders and temporary files being written
//! are registered here; on the signal they are removed and hydroid exits with 128 + the
//! signal's number (130, 143), as a shell reports a process the signal ended.
//!
//! A commit holds the registry while it moves folders, so a signal never removes a folder
//! that holds the only copy of an output (see [`super::staging`]).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, Once};

/// The staging marker's file name.
pub const STAGING_MARKER: &str = ".hydroid-staging";

/// Paths being written, to remove if a signal ends the process.
static ACTIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static INSTALL: Once = Once::new();

/// The registry, locked (a panic elsewhere does not make it unusable).
pub(crate) fn lock() -> MutexGuard<'static, Vec<PathBuf>> {
    ACTIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Registers a path to remove if a signal ends the process.
pub(crate) fn register(path: &Path) {
    lock().push(path.to_path_buf());
}

/// Forgets a path (written, or removed by its owner).
pub(crate) fn forget(path: &Path) {
    lock().retain(|p| p != path);
}

/// Installs the handler of SIGINT and SIGTERM (once per process; later calls do nothing).
/// Without it a signal ends hydroid at once and the next run into the same folder sweeps
/// what it left (see [`super::sweep`]).
pub fn clean_up_on_signals() -> crate::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut result: std::io::Result<()> = Ok(());
    INSTALL.call_once(|| {
        match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
            Ok(mut signals) => {
                let spawned = std::thread::Builder::new()
                    .name("hydroid-signals".into())
                    .spawn(move || {
                        if let Some(sig) = signals.forever().next() {
                            // held until the process ends: nothing registers or commits
                            // after this point
                            let active = lock();
                            for p in active.iter() {
                                // the main thread goes on meanwhile and may add a file
                                // between the listing and the removal of a folder: try again
                                for _ in 0..20 {
                                    remove(p);
                                    if std::fs::symlink_metadata(p).is_err() {
                                        break;
                                    }
                                    std::thread::sleep(std::time::Duration::from_millis(5));
                                }
                            }
                            std::process::exit(128 + sig);
                        }
                    });
                if let Err(e) = spawned {
                    result = Err(e);
                }
            }
            Err(e) => result = Err(e),
        }
    });
    result.map_err(|e| crate::Error::Usage(format!("cannot handle SIGINT and SIGTERM: {e}")))
}

/// Removes a file or a folder (a link itself, never what it points to). In a folder the
/// staging marker goes last: if the removal is cut short, a later sweep still recognises
/// what is left as hydroid's.
pub(crate) fn remove(p: &Path) {
    match std::fs::symlink_metadata(p) {
        Ok(m) if m.is_dir() => {
            if let Ok(entries) = std::fs::read_dir(p) {
                for e in entries.flatten() {
                    if e.file_name() != STAGING_MARKER {
                        remove(&e.path());
                    }
                }
            }
            let _ = std::fs::remove_dir_all(p);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(p);
        }
        Err(_) => {}
    }
}
