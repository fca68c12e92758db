//! The marker hydroid leaves in every output folder it writes, `.hydroid-output.json`: the
//! format and every file written with its SHA-256. A folder is hydroid's to replace only
//! when it carries a valid marker and holds exactly the files it lists, unchanged.

use crate::base::error::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

/// The SHA-256 (hex) of a file of an output folder, streamed. The size limit of input files
/// (`Limits`, 2 GiB by default) does not apply: hydroid wrote these files itself, and a state
/// series of ten million samples (`states/NAME.csv`) is larger.
pub fn output_sha256(path: &Path) -> Result<String> {
    use sha2::{Digest, Sha256};
    use std::io::Read;
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        match file.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => hasher.update(&buf[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(Error::io(path, e)),
        }
    }
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// The marker's file name.
pub const MARKER: &str = ".hydroid-output.json";
/// The marker's format tag.
const FORMAT: &str = "hydroid-output/1";

/// The marker's contents.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Marker {
    /// `"hydroid-output/1"`.
    pub format: String,
    /// Every file written, path relative to the folder with `/` separators -> SHA-256, hex.
    pub files: BTreeMap<String, String>,
}

impl Marker {
    /// The marker of a folder as it is now (every regular file in it but the marker).
    pub fn of_folder(dir: &Path) -> Result<Self> {
        let mut files = BTreeMap::new();
        for entry in walk(dir)? {
            match entry.kind {
                Kind::File => {
                    files.insert(entry.rel.clone(), output_sha256(&dir.join(&entry.rel))?);
                }
                Kind::Folder => {}
                Kind::Other(what) => {
                    return Err(Error::Usage(format!(
                        "{}: a {what} in an output being written",
                        dir.join(&entry.rel).display()
                    )))
                }
            }
        }
        Ok(Marker {
            format: FORMAT.into(),
            files,
        })
    }

    /// Writes the marker into `dir`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MARKER);
        let text = crate::io::output::to_json(self)?;
        std::fs::write(&path, text).map_err(|e| Error::write(&path, e))
    }
}

/// The marker of the hydroid output `dir`, or an error naming it (unreadable, not a marker).
pub(super) fn read(dir: &Path) -> Result<Marker> {
    let path = dir.join(MARKER);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    serde_json::from_str(&text)
        .map_err(|e| Error::Usage(format!("{}: not a valid marker: {e}", path.display())))
}

/// Records the files `names` of the hydroid output `dir` in its marker as they are now (files
/// hydroid has just written there, such as calibration.json), so that the folder stays
/// hydroid's to replace. The marker is replaced atomically. Only a [`super::Claim`] calls it,
/// under the folder's lock, once it has checked the folder is the one it read.
pub(super) fn record(dir: &Path, names: &[&str]) -> Result<()> {
    let path = dir.join(MARKER);
    let mut marker = read(dir)?;
    for name in names {
        marker
            .files
            .insert((*name).to_string(), output_sha256(&dir.join(name))?);
    }
    crate::io::output::write_atomic(&path, &crate::io::output::to_json(&marker)?)
}

/// What is at a place an output folder is to be written to.
#[derive(Debug, Clone, PartialEq)]
pub enum Found {
    /// Nothing: the output can be written.
    Nothing,
    /// A hydroid output exactly as hydroid wrote it: it can be replaced.
    Unchanged,
    /// A hydroid output that changed since: replaced only when the user forces it.
    Changed(Vec<String>),
    /// Anything else (a folder without a valid marker, a file, a link): never replaced.
    Foreign(String),
}

/// Refuses a folder that is not an output of `hydroid run` exactly as hydroid wrote it (its
/// marker lists every file unchanged), naming what differs: `verb` (calibrate, plan) writes
/// into it.
pub fn require_unchanged(dir: &Path, verb: &str) -> Result<()> {
    match inspect(dir)? {
        Found::Unchanged => Ok(()),
        Found::Nothing => Err(Error::Usage(format!(
            "{}: no such output folder (give the folder `hydroid run` wrote)",
            dir.display()
        ))),
        Found::Foreign(why) => Err(Error::Usage(format!(
            "{} is not an output folder of `hydroid run`: {why}",
            dir.display()
        ))),
        Found::Changed(what) => Err(Error::Usage(format!(
            "refusing to {verb} {}: it changed since hydroid wrote it ({}); {verb} \
             reads and writes into an output exactly as `hydroid run` left it: `hydroid \
             rerun {}` first",
            dir.display(),
            what.join("; "),
            dir.display()
        ))),
    }
}

/// Looks at `target` (resolved, see [`super::paths::resolve`]).
pub fn inspect(target: &Path) -> Result<Found> {
    let meta = match std::fs::symlink_metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Found::Nothing),
        Err(e) => return Err(Error::io(target, e)),
    };
    if meta.file_type().is_symlink() {
        return Ok(Found::Foreign("it is a symbolic link".into()));
    }
    if !meta.is_dir() {
        return Ok(Found::Foreign(format!(
            "it is {}, not a folder",
            super::what_is(&meta)
        )));
    }
    let marker_path = target.join(MARKER);
    let marker = match std::fs::symlink_metadata(&marker_path) {
        Ok(m) if m.is_file() => {
            std::fs::read_to_string(&marker_path).map_err(|e| Error::io(&marker_path, e))?
        }
        Ok(_) => return Ok(Found::Foreign(format!("its {MARKER} is not a file"))),
        Err(_) => {
            return Ok(Found::Foreign(format!(
                "it is a folder hydroid did not write (it has no {MARKER})"
            )))
        }
    };
    let marker: Marker = match serde_json::from_str(&marker) {
        Ok(m) => m,
        Err(e) => return Ok(Found::Foreign(format!("its {MARKER} is not valid: {e}"))),
    };
    if marker.format != FORMAT {
        return Ok(Found::Foreign(format!(
            "its {MARKER} has format '{}', this hydroid knows '{FORMAT}'",
            marker.format
        )));
    }
    if let Some(bad) = marker.files.keys().find(|k| !is_plain_relative(k)) {
        return Ok(Found::Foreign(format!(
            "its {MARKER} lists '{bad}', which is not a path inside the folder"
        )));
    }
    let changes = differences(target, &marker)?;
    Ok(if changes.is_empty() {
        Found::Unchanged
    } else {
        Found::Changed(changes)
    })
}

/// The files among `names` in the hydroid output `dir` whose contents differ from the SHA-256
/// its marker records (edited since hydroid wrote them). Empty when the folder has no valid
/// marker (an output of an earlier hydroid: there is nothing to compare with) or the marker
/// does not list a name.
pub fn edited(dir: &Path, names: &[&str]) -> Result<Vec<String>> {
    let Ok(text) = std::fs::read_to_string(dir.join(MARKER)) else {
        return Ok(Vec::new());
    };
    let Ok(marker) = serde_json::from_str::<Marker>(&text) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for name in names {
        if let Some(sha) = marker.files.get(*name) {
            let path = dir.join(name);
            if !path.is_file() || output_sha256(&path)? != *sha {
                out.push((*name).to_string());
            }
        }
    }
    Ok(out)
}

/// What differs between the folder and its marker, one line each.
fn differences(dir: &Path, marker: &Marker) -> Result<Vec<String>> {
    let mut changes = Vec::new();
    let mut seen = Vec::new();
    // folders that hold a listed file belong to the output
    let listed_folders: Vec<&str> = marker
        .files
        .keys()
        .flat_map(|k| k.match_indices('/').map(move |(i, _)| &k[..i]))
        .collect();
    for entry in walk(dir)? {
        match (&entry.kind, marker.files.get(&entry.rel)) {
            (Kind::File, Some(sha)) => {
                seen.push(entry.rel.clone());
                if output_sha256(&dir.join(&entry.rel))? != *sha {
                    changes.push(format!("changed: {}", entry.rel));
                }
            }
            (Kind::File, None) => changes.push(format!("added: {}", entry.rel)),
            (Kind::Folder, _) if listed_folders.contains(&entry.rel.as_str()) => {}
            (Kind::Folder, _) => changes.push(format!("added folder: {}", entry.rel)),
            (Kind::Other(what), _) => changes.push(format!("added {what}: {}", entry.rel)),
        }
    }
    for k in marker.files.keys() {
        if !seen.contains(k) {
            changes.push(format!("removed or replaced: {k}"));
        }
    }
    Ok(changes)
}

/// A relative path of plain names (no root, no `.` or `..`), `/`-separated.
fn is_plain_relative(p: &str) -> bool {
    !p.is_empty()
        && !p.contains('\\')
        && Path::new(p)
            .components()
            .all(|c| matches!(c, Component::Normal(_)))
        && p.split('/').all(|s| !s.is_empty() && s != "." && s != "..")
}

/// What one entry of a folder is (links are never followed).
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    File,
    Folder,
    Other(&'static str),
}

struct Entry {
    /// Relative to the walked folder, `/`-separated.
    rel: String,
    kind: Kind,
}

/// Every entry below `dir` but the marker, parents before their contents, sorted by name.
fn walk(dir: &Path) -> Result<Vec<Entry>> {
    let mut out = Vec::new();
    walk_into(dir, &PathBuf::new(), &mut out)?;
    Ok(out)
}

fn walk_into(root: &Path, rel: &Path, out: &mut Vec<Entry>) -> Result<()> {
    let dir = root.join(rel);
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .map_err(|e| Error::io(&dir, e))?
        .collect::<std::io::Result<_>>()
        .map_err(|e| Error::io(&dir, e))?;
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let name = rel.join(e.file_name());
        if name == Path::new(MARKER) {
            continue;
        }
        let t = e.file_type().map_err(|err| Error::io(&e.path(), err))?;
        let kind = if t.is_symlink() {
            Kind::Other("symbolic link")
        } else if t.is_dir() {
            Kind::Folder
        } else if t.is_file() {
            Kind::File
        } else {
            Kind::Other("special file")
        };
        let rel_str = name
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        let is_dir = kind == Kind::Folder;
        out.push(Entry { rel: rel_str, kind });
        if is_dir {
            walk_into(root, &name, out)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_file_hashes_as_an_input_file_does() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        std::fs::write(&path, "abc").unwrap();
        // FIPS 180-2, appendix B.1
        let abc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
        assert_eq!(output_sha256(&path).unwrap(), abc);
        let big = dir.path().join("b.csv");
        std::fs::write(&big, vec![b'x'; 3 << 16]).unwrap();
        assert_eq!(
            output_sha256(&big).unwrap(),
            crate::io::formats::input::file_sha256(&big).unwrap()
        );
        assert!(output_sha256(&dir.path().join("none")).is_err());
    }

    fn output(dir: &Path) {
        std::fs::create_dir_all(dir.join("plots")).unwrap();
        std::fs::write(dir.join("results.json"), "{}").unwrap();
        std::fs::write(dir.join("plots/a.svg"), "<svg/>").unwrap();
        Marker::of_folder(dir).unwrap().write(dir).unwrap();
    }

    #[test]
    fn a_marked_folder_is_unchanged_until_touched() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path().join("out");
        assert_eq!(inspect(&d).unwrap(), Found::Nothing);
        output(&d);
        assert_eq!(inspect(&d).unwrap(), Found::Unchanged);
        std::fs::write(d.join("notes.txt"), "mine").unwrap();
        std::fs::write(d.join("plots/a.svg"), "<svg></svg>").unwrap();
        std::fs::remove_file(d.join("results.json")).unwrap();
        std::fs::create_dir(d.join("mine")).unwrap();
        let Found::Changed(c) = inspect(&d).unwrap() else {
            panic!("not seen as changed")
        };
        assert_eq!(
            c,
            [
                "added folder: mine",
                "added: notes.txt",
                "changed: plots/a.svg",
                "removed or replaced: results.json"
            ]
        );
    }

    #[test]
    fn folders_without_a_valid_marker_files_and_links_are_foreign() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path().join("out");
        std::fs::create_dir(&d).unwrap();
        assert!(matches!(inspect(&d).unwrap(), Found::Foreign(_)));
        for bad in [
            "not json",
            r#"{"format":"hydroid-output/9","files":{}}"#,
            r#"{"format":"hydroid-output/1","files":{"../x":"00"}}"#,
        ] {
            std::fs::write(d.join(MARKER), bad).unwrap();
            assert!(matches!(inspect(&d).unwrap(), Found::Foreign(_)), "{bad}");
        }
        let f = root.path().join("notes.txt");
        std::fs::write(&f, "x").unwrap();
        assert!(matches!(inspect(&f).unwrap(), Found::Foreign(_)));
        let l = root.path().join("link");
        let good = root.path().join("good");
        output(&good);
        std::os::unix::fs::symlink(&good, &l).unwrap();
        assert!(matches!(inspect(&l).unwrap(), Found::Foreign(_)));
    }
}
