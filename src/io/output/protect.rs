//! Places an output may never replace, whatever is in them: the filesystem root, the home
//! folder, the working folder, the configuration and every input, with the folders that hold
//! them. Checked on resolved paths (see [`super::paths`]) before any stage runs.

use super::paths::{contains, read_locations, resolve};
use crate::base::error::{Error, Result};
use std::path::{Path, PathBuf};

/// One protected place: an output may be neither it nor a folder holding it.
#[derive(Debug, Clone)]
struct Place {
    path: PathBuf,
    what: String,
    /// A file (then its folder is named as such in a refusal), or a folder.
    file: bool,
}

/// The set of places an output must not replace.
#[derive(Debug, Clone)]
pub struct Protected {
    places: Vec<Place>,
}

impl Default for Protected {
    fn default() -> Self {
        Self::new()
    }
}

impl Protected {
    /// The working folder and the home folder (each with every folder above it, the root
    /// included).
    pub fn new() -> Self {
        let mut p = Protected { places: Vec::new() };
        if let Ok(cwd) = std::env::current_dir().and_then(std::fs::canonicalize) {
            p.add(cwd, "the working folder".into(), false);
        }
        if let Some(home) = std::env::home_dir().and_then(|h| std::fs::canonicalize(h).ok()) {
            p.add(home, "your home folder".into(), false);
        }
        p
    }

    /// Protects a configuration file and the folder it is in.
    pub fn config(&mut self, path: &Path) {
        for l in read_locations(path) {
            if let Some(folder) = l.parent() {
                self.add(
                    folder.to_path_buf(),
                    "the configuration's folder".into(),
                    false,
                );
            }
            self.add(l, "the configuration file".into(), true);
        }
    }

    /// Protects an input file (named by its configuration key, e.g. `hekf.runs[0]`).
    pub fn input(&mut self, path: &Path, key: &str) {
        for l in read_locations(path) {
            self.add(l, format!("the input {} ({key})", path.display()), true);
        }
    }

    fn add(&mut self, path: PathBuf, what: String, file: bool) {
        self.places.push(Place { path, what, file });
    }

    /// Refuses `target` (resolved) when it is a protected place or holds one.
    pub fn check(&self, target: &Path) -> Result<()> {
        if target.parent().is_none() {
            return Err(refusal(target, "it is the filesystem root"));
        }
        for p in &self.places {
            if p.path == target {
                return Err(refusal(target, &format!("it is {}", p.what)));
            }
            if p.file && p.path.parent() == Some(target) {
                return Err(refusal(
                    target,
                    &format!("it is the folder of {} ({})", p.what, p.path.display()),
                ));
            }
            if contains(target, &p.path) {
                return Err(refusal(
                    target,
                    &format!("it holds {} ({})", p.what, p.path.display()),
                ));
            }
        }
        Ok(())
    }

    /// Resolves `target` and checks it.
    pub fn check_path(&self, target: &Path) -> Result<PathBuf> {
        let resolved = resolve(target)?;
        self.check(&resolved)?;
        Ok(resolved)
    }
}

fn refusal(target: &Path, why: &str) -> Error {
    Error::Usage(format!(
        "refusing to write the output to {}: {why}. An output never replaces the \
         configuration, an input, a folder holding one, the working folder or the home folder; \
         choose another --out (or output.dir)",
        target.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_their_folders_and_ancestors_are_refused() {
        let root = tempfile::tempdir().unwrap();
        let real = std::fs::canonicalize(root.path()).unwrap();
        let exports = real.join("data/exports");
        std::fs::create_dir_all(&exports).unwrap();
        std::fs::write(exports.join("run.csv"), "t,u\n").unwrap();
        let mut p = Protected { places: Vec::new() };
        p.input(&exports.join("run.csv"), "surge.runs[0]");
        for t in [
            exports.join("run.csv"),
            exports.clone(),
            real.join("data"),
            real.clone(),
            PathBuf::from("/"),
        ] {
            assert!(p.check(&t).is_err(), "{}", t.display());
        }
        assert!(p.check(&exports.join("out")).is_ok());
        assert!(p.check(&real.join("out")).is_ok());
    }
}
