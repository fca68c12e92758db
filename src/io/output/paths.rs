//! Paths as the filesystem sees them: a place to write to is resolved to its real location
//! (symbolic links and `..` of the folders above it resolved, a trailing slash or `.`
//! dropped) before anything is compared or written, so that two spellings of one place are
//! recognised as one. The final name itself is not followed when it is a symbolic link:
//! hydroid never writes through a link.

use crate::base::error::{Error, Result};
use std::path::{Component, Path, PathBuf};

/// The absolute, real location of `p`, which need not exist: its nearest existing ancestor
/// canonicalised, the rest appended. A final symbolic link is kept as it is (not followed).
pub fn resolve(p: &Path) -> Result<PathBuf> {
    if let Some(Component::Normal(first)) = p.components().next() {
        if first.to_string_lossy().starts_with('~') {
            return Err(Error::Usage(format!(
                "{}: hydroid does not expand '~' (the shell does, when it is not quoted); \
                 write the folder out in full",
                p.display()
            )));
        }
    }
    let p = if p.as_os_str().is_empty() {
        Path::new(".")
    } else {
        p
    };
    let abs = std::path::absolute(p).map_err(|e| Error::io(p, e))?;
    // components() drops a trailing slash and every `.` but a leading one
    let abs: PathBuf = abs.components().collect();
    match (abs.parent(), abs.file_name()) {
        (Some(parent), Some(name)) => Ok(resolve_folder(parent)?.join(name)),
        // the root, or a path ending in `..`: a folder that must exist
        _ => std::fs::canonicalize(&abs).map_err(|e| Error::io(&abs, e)),
    }
}

/// The real location of a folder that is to hold something: canonical when it exists (and
/// then it must be a folder), else its parent's resolved location and its name.
fn resolve_folder(p: &Path) -> Result<PathBuf> {
    match std::fs::canonicalize(p) {
        Ok(c) if c.is_dir() => Ok(c),
        Ok(c) => Err(Error::Usage(format!(
            "{}: this is a file, not a folder (resolved to {})",
            p.display(),
            c.display()
        ))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => match (p.parent(), p.file_name()) {
            // a dangling symbolic link is "not found" too: it cannot hold anything
            _ if std::fs::symlink_metadata(p).is_ok() => Err(Error::Usage(format!(
                "{}: a symbolic link that points nowhere",
                p.display()
            ))),
            (Some(parent), Some(name)) => Ok(resolve_folder(parent)?.join(name)),
            _ => Err(Error::io(p, e)),
        },
        Err(e) => Err(Error::io(p, e)),
    }
}

/// True when `inner` is `outer` or lies inside it (both resolved).
pub fn contains(outer: &Path, inner: &Path) -> bool {
    inner.starts_with(outer)
}

/// `to` as a path relative to the folder `from` (both absolute and resolved):
/// `relative("/p/cfd_exports", "/p/configs/sim.toml")` is `../configs/sim.toml`.
pub fn relative(from: &Path, to: &Path) -> PathBuf {
    let f: Vec<Component> = from.components().collect();
    let t: Vec<Component> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut out: PathBuf = std::iter::repeat_n(Component::ParentDir, f.len() - common).collect();
    out.extend(&t[common..]);
    out
}

/// The resolved location of a file that is read (an input, a configuration): the file itself
/// with every link followed, and the place its name is in (the link's own folder when the
/// name is a link). Both matter: replacing either folder would lose the file.
pub fn read_locations(p: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    if let Ok(named) = resolve(p) {
        v.push(named);
    }
    if let Ok(real) = std::fs::canonicalize(p) {
        if !v.contains(&real) {
            v.push(real);
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_of_one_place_resolve_alike() {
        let root = tempfile::tempdir().unwrap();
        let real = std::fs::canonicalize(root.path()).unwrap();
        std::fs::create_dir(real.join("a")).unwrap();
        let want = real.join("a").join("out");
        for p in [
            real.join("a/out"),
            real.join("a/out/"),
            real.join("a/./out"),
            real.join("a/b/../out"),
        ] {
            // a/b does not exist: `..` after it cannot be resolved, the others can
            match resolve(&p) {
                Ok(r) => assert_eq!(r, want, "{}", p.display()),
                Err(_) => assert!(p.to_string_lossy().contains("b/..")),
            }
        }
        std::fs::create_dir(real.join("a/b")).unwrap();
        assert_eq!(resolve(&real.join("a/b/../out")).unwrap(), want);
        std::os::unix::fs::symlink(real.join("a"), real.join("link")).unwrap();
        assert_eq!(resolve(&real.join("link/out")).unwrap(), want);
        // a final link is not followed
        assert_eq!(resolve(&real.join("link")).unwrap(), real.join("link"));
        assert_eq!(resolve(&real.join("link/")).unwrap(), real.join("link"));
    }

    #[test]
    fn relative_paths_climb_to_the_common_folder() {
        let rel = |a: &str, b: &str| relative(Path::new(a), Path::new(b));
        assert_eq!(
            rel("/p/cfd_exports", "/p/configs/sim.toml"),
            Path::new("../configs/sim.toml")
        );
        assert_eq!(rel("/p", "/p/a.toml"), Path::new("a.toml"));
        assert_eq!(rel("/p/a/b", "/q"), Path::new("../../../q"));
        assert_eq!(rel("/p", "/p"), Path::new(""));
    }

    #[test]
    fn a_file_on_the_way_and_a_tilde_are_refused() {
        let root = tempfile::tempdir().unwrap();
        let f = root.path().join("notes.txt");
        std::fs::write(&f, "x").unwrap();
        assert!(resolve(&f.join("out")).is_err());
        assert!(resolve(Path::new("~/out")).is_err());
    }
}
