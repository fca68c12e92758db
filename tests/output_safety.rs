//! hydroid never loses a user's file: `run`, `rerun` and `simulate` replace only what
//! hydroid wrote (docs/outputs.md). Every case runs the binary in its own temporary copy of
//! configs/ and cfd_exports/.

use crate::common;

use common::{copy_example, root, text};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// A temporary copy of the bundled example: `proj/configs`, `proj/cfd_exports`, and a home
/// folder `home/` outside it (HOME points there for every command).
struct Example {
    tmp: tempfile::TempDir,
}

impl Example {
    fn new() -> Self {
        let tmp = tempfile::tempdir().unwrap();
        copy_example(&tmp.path().join("proj"));
        std::fs::create_dir(tmp.path().join("home")).unwrap();
        Example { tmp }
    }

    /// The folder holding proj/ and home/.
    fn top(&self) -> PathBuf {
        std::fs::canonicalize(self.tmp.path()).unwrap()
    }

    fn proj(&self) -> PathBuf {
        self.top().join("proj")
    }

    fn home(&self) -> PathBuf {
        self.top().join("home")
    }

    fn command(&self, cwd: &Path, args: &[&str]) -> Command {
        let mut c = Command::new(env!("CARGO_BIN_EXE_hydroid"));
        c.args(args).current_dir(cwd).env("HOME", self.home());
        c
    }

    /// Runs hydroid in `cwd` (relative to proj/: `../elsewhere` is a folder beside it).
    fn hydroid_in(&self, cwd: &str, args: &[&str]) -> Output {
        let dir = self.proj().join(cwd);
        self.command(&dir, args).output().unwrap()
    }

    /// Runs hydroid in proj/.
    fn hydroid(&self, args: &[&str]) -> Output {
        self.hydroid_in("", args)
    }

    /// Every file and folder under the top folder with its contents.
    fn snapshot(&self) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
        let mut m = BTreeMap::new();
        snapshot_into(&self.top(), &mut m);
        m
    }
}

fn snapshot_into(dir: &Path, m: &mut BTreeMap<PathBuf, Option<Vec<u8>>>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let t = e.file_type().unwrap();
        if t.is_dir() {
            m.insert(e.path(), None);
            snapshot_into(&e.path(), m);
        } else if t.is_symlink() {
            m.insert(
                e.path(),
                Some(
                    std::fs::read_link(e.path())
                        .unwrap()
                        .into_os_string()
                        .into_encoded_bytes(),
                ),
            );
        } else {
            m.insert(e.path(), Some(std::fs::read(e.path()).unwrap()));
        }
    }
}

/// The command was refused as a usage error, before any stage ran, with a message holding
/// every fragment of `says`, and nothing changed on disk.
#[track_caller]
fn refused(ex: &Example, before: &BTreeMap<PathBuf, Option<Vec<u8>>>, o: &Output, says: &[&str]) {
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "not refused: {e}");
    assert!(!e.contains("polar:"), "refused only after running: {e}");
    assert!(!e.contains("panicked"), "{e}");
    for s in says {
        assert!(e.contains(s), "expected '{s}' in: {e}");
    }
    let after = ex.snapshot();
    assert!(
        after == *before,
        "something changed on disk: {:?}",
        diff(before, &after)
    );
}

fn diff(
    a: &BTreeMap<PathBuf, Option<Vec<u8>>>,
    b: &BTreeMap<PathBuf, Option<Vec<u8>>>,
) -> Vec<PathBuf> {
    let mut d: Vec<PathBuf> = a
        .iter()
        .filter(|(k, v)| b.get(*k) != Some(v))
        .map(|(k, _)| k.clone())
        .collect();
    d.extend(b.keys().filter(|k| !a.contains_key(*k)).cloned());
    d
}

/// A run fast enough for a test (a fraction of a second in debug): polar and surge stages
/// with their figures, no filter (its inputs are protected all the same).
const QUICK: [&str; 2] = ["--set", "hekf.enabled=false"];

fn run_ok(ex: &Example, cwd: &str, args: &[&str]) -> Output {
    let mut a = vec!["run", "configs/spheroid.toml"];
    a.extend_from_slice(args);
    a.extend_from_slice(&QUICK);
    let o = ex.hydroid_in(cwd, &a);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    o
}

#[test]
fn the_exports_folder_is_never_an_output() {
    let ex = Example::new();
    let before = ex.snapshot();
    let abs = ex.proj().join("cfd_exports");
    for out in [
        "cfd_exports",
        "cfd_exports/",
        "./cfd_exports//",
        "configs/../cfd_exports",
        abs.to_str().unwrap(),
    ] {
        let o = ex.hydroid(&["run", "configs/spheroid.toml", "--out", out]);
        refused(
            &ex,
            &before,
            &o,
            &["refusing", "it is the folder of the input"],
        );
    }
    // nor a folder holding an input, from another working folder
    std::fs::create_dir(ex.top().join("work")).unwrap();
    let before = ex.snapshot();
    let o = ex.hydroid_in(
        "../work",
        &["run", "../proj/configs/spheroid.toml", "--out", "../proj"],
    );
    refused(&ex, &before, &o, &["refusing", "it holds the input"]);
}

#[test]
fn inputs_and_the_configuration_reached_through_links_are_protected() {
    let ex = Example::new();
    let p = ex.proj();
    // the exports live elsewhere; the project reaches them through a link
    let real = ex.top().join("data/exports");
    std::fs::create_dir(ex.top().join("data")).unwrap();
    std::fs::rename(p.join("cfd_exports"), &real).unwrap();
    std::os::unix::fs::symlink(&real, p.join("cfd_exports")).unwrap();
    std::os::unix::fs::symlink(p.join("configs"), p.join("cfglink")).unwrap();
    let before = ex.snapshot();
    let real_str = real.to_str().unwrap();
    for (config, out, says) in [
        (
            "configs/spheroid.toml",
            real_str,
            "it is the folder of the input",
        ),
        ("configs/spheroid.toml", "../data", "it holds the input"),
        ("configs/spheroid.toml", "cfd_exports", "symbolic link"),
        (
            "cfglink/spheroid.toml",
            "configs",
            "it is the configuration's folder",
        ),
        ("cfglink/spheroid.toml", "cfglink/", "symbolic link"),
    ] {
        let o = ex.hydroid(&["run", config, "--out", out]);
        refused(&ex, &before, &o, &[says]);
    }
}

/// The staging folder a run killed (pid 99999) left in `proj` for the output folder `out`:
/// its marker and `inner/results.json` holding `results`.
fn killed_run_staging(proj: &Path, inner: &str, results: &str) -> PathBuf {
    let stale = proj.join(".out.partial-99999");
    std::fs::create_dir_all(stale.join(inner)).unwrap();
    std::fs::write(
        stale.join(".hydroid-staging"),
        r#"{"format":"hydroid-staging/1","target":"out","pid":99999}"#,
    )
    .unwrap();
    std::fs::write(stale.join(inner).join("results.json"), results).unwrap();
    stale
}

#[test]
fn an_output_a_killed_run_had_moved_aside_is_put_back() {
    let ex = Example::new();
    let p = ex.proj();
    // killed between moving the old output aside and moving the new one in place
    let stale = killed_run_staging(&p, "old", "the old output");
    // any later run into the same folder puts it back
    let o = run_ok(&ex, "", &["--out", "other"]);
    assert!(text(&o.stderr).contains("put back"), "{}", text(&o.stderr));
    assert_eq!(
        std::fs::read_to_string(p.join("out/results.json")).unwrap(),
        "the old output"
    );
    assert!(!stale.exists());
    assert!(p.join("other/results.json").exists());
}

#[test]
fn the_configuration_its_folder_and_output_dir_empty_are_refused() {
    let ex = Example::new();
    let before = ex.snapshot();
    for (out, says) in [
        ("configs", "it is the configuration's folder"),
        ("configs/", "it is the configuration's folder"),
        ("configs/spheroid.toml", "it is the configuration file"),
    ] {
        let o = ex.hydroid(&["run", "configs/spheroid.toml", "--out", out]);
        refused(&ex, &before, &o, &[says]);
    }
    // output.dir = "" is the configuration's own folder
    let o = ex.hydroid(&["run", "configs/spheroid.toml", "--set", "output.dir=\"\""]);
    refused(&ex, &before, &o, &["it is the configuration's folder"]);
    // the same from inside configs/ (relative paths resolve against the configuration)
    let o = ex.hydroid_in(
        "configs",
        &["run", "spheroid.toml", "--set", "output.dir=\"\""],
    );
    refused(&ex, &before, &o, &["refusing"]);
}

#[test]
fn the_working_folder_its_parents_home_and_root_are_refused() {
    let ex = Example::new();
    let before = ex.snapshot();
    let home = ex.home();
    for (out, says) in [
        (".", "it is the working folder"),
        ("./", "it is the working folder"),
        ("..", "it holds the working folder"),
        ("../..", "it holds the working folder"),
        ("/", "it is the filesystem root"),
        (home.to_str().unwrap(), "it is your home folder"),
        // the shell expands an unquoted ~; a quoted one is not taken for a folder named ~
        ("~", "does not expand '~'"),
        ("~/out", "does not expand '~'"),
    ] {
        let o = ex.hydroid(&["run", "configs/spheroid.toml", "--out", out]);
        refused(&ex, &before, &o, &[says]);
    }
    // the folder of a configuration that is the working folder
    let o = ex.hydroid_in("configs", &["run", "spheroid.toml", "--out", "."]);
    refused(&ex, &before, &o, &["refusing", "working folder"]);
}

#[test]
fn a_folder_hydroid_did_not_write_a_file_or_a_link_is_never_replaced() {
    let ex = Example::new();
    let p = ex.proj();
    std::fs::create_dir(p.join("mydata")).unwrap();
    std::fs::write(p.join("mydata/notes.txt"), "mine").unwrap();
    std::fs::create_dir(p.join("empty")).unwrap();
    std::fs::write(p.join("notes.txt"), "mine").unwrap();
    std::os::unix::fs::symlink(p.join("cfd_exports"), p.join("exports_link")).unwrap();
    std::os::unix::fs::symlink(p.join("mydata"), p.join("data_link")).unwrap();
    std::os::unix::fs::symlink(p.join("cfd_exports/surge_run.csv"), p.join("run.csv")).unwrap();
    let before = ex.snapshot();
    for (out, says) in [
        ("mydata", "hydroid did not write"),
        ("empty", "hydroid did not write"),
        ("notes.txt", "is a file"),
        ("data_link", "symbolic link"),
        ("data_link/", "symbolic link"),
        ("exports_link", "symbolic link"),
        ("run.csv", "symbolic link"),
        ("notes.txt/out", "not a folder"),
    ] {
        for force in [false, true] {
            let mut a = vec!["run", "configs/spheroid.toml", "--out", out];
            if force {
                a.push("--force");
            }
            let o = ex.hydroid(&a);
            refused(&ex, &before, &o, &[says]);
        }
        // `check --out` refuses it as run would (issue 24, item 4)
        let o = ex.hydroid(&["check", "configs/spheroid.toml", "--out", out]);
        refused(&ex, &before, &o, &["configs/spheroid.toml: --out: ", says]);
    }
}

#[test]
fn a_hydroid_output_is_replaced_when_unchanged_and_only_forced_when_changed() {
    let ex = Example::new();
    // the default folder twice: the second run replaces the first (the normal workflow)
    run_ok(&ex, "", &[]);
    let out = ex.proj().join("out/spheroid");
    let results = std::fs::read(out.join("results.json")).unwrap();
    assert!(out.join(".hydroid-output.json").is_file());
    run_ok(&ex, "", &[]);
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), results);
    // a user's file added: refused, naming it, unless forced
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = ex.snapshot();
    let mut a = vec!["run", "configs/spheroid.toml"];
    a.extend_from_slice(&QUICK);
    let o = ex.hydroid(&a);
    refused(&ex, &before, &o, &["added: notes.txt", "--force"]);
    // check warns that run would refuse it (issue 24, item 4)
    let c = ex.hydroid(&["check", "configs/spheroid.toml"]);
    assert_eq!(c.status.code(), Some(0), "{}", text(&c.stderr));
    let says = text(&c.stdout);
    assert!(
        says.contains("added: notes.txt") && says.contains("without --force"),
        "{says}"
    );
    std::fs::remove_file(out.join("notes.txt")).unwrap();
    // a file edited inside it: the same
    std::fs::write(out.join("coefficients.csv"), "edited").unwrap();
    let before = ex.snapshot();
    let o = ex.hydroid(&a);
    refused(&ex, &before, &o, &["changed: coefficients.csv"]);
    a.push("--force");
    let o = ex.hydroid(&a);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), results);
    assert_ne!(
        std::fs::read(out.join("coefficients.csv")).unwrap(),
        b"edited"
    );
    // nothing else was left beside it
    let names: Vec<_> = std::fs::read_dir(ex.proj().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["spheroid"]);
}

/// A device given as the output is named as what it is, not "a folder" or "a file", and
/// never written (issue 24, item 7).
#[test]
#[cfg(target_os = "linux")]
fn a_device_as_the_output_is_named_as_a_device() {
    let ex = Example::new();
    let before = ex.snapshot();
    let device = "is a character device (such as /dev/null, /dev/full or a terminal)";
    for args in [
        vec!["run", "configs/spheroid.toml", "--out", "/dev/full"],
        vec!["check", "configs/spheroid.toml", "--out", "/dev/full"],
        vec![
            "simulate",
            "configs/simulate/surge_run.toml",
            "--out",
            "/dev/full",
        ],
        vec!["init", "/dev/full"],
        vec!["init", "/dev/full/hydroid.toml"],
    ] {
        let o = ex.hydroid(&args);
        refused(&ex, &before, &o, &[device, "/dev/full"]);
        let e = text(&o.stderr);
        assert!(
            !e.contains("a folder, not a file") && !e.contains("os error"),
            "{e}"
        );
    }
}

#[test]
fn simulate_never_overwrites_a_file_it_did_not_write() {
    let ex = Example::new();
    let before = ex.snapshot();
    let sim = "configs/simulate/surge_run.toml";
    for (out, force, says) in [
        ("configs/spheroid.toml", false, "hydroid did not write it"),
        ("configs/spheroid.toml", true, "hydroid did not write it"),
        (sim, true, "the simulation's configuration"),
        ("configs", true, "it is a folder"),
        (
            "cfd_exports/.hydroid-exports.json",
            true,
            "record of exports",
        ),
    ] {
        let mut a = vec!["simulate", sim, "--out", out];
        if force {
            a.push("--force");
        }
        let o = ex.hydroid(&a);
        refused(&ex, &before, &o, &["refusing", says]);
    }
    std::os::unix::fs::symlink(
        ex.proj().join("cfd_exports/surge_run.csv"),
        ex.proj().join("link.csv"),
    )
    .unwrap();
    let before = ex.snapshot();
    let o = ex.hydroid(&["simulate", sim, "--out", "link.csv", "--force"]);
    refused(&ex, &before, &o, &["symbolic link"]);
    // the bundled export is listed beside it: regenerating it works
    let o = ex.hydroid(&["simulate", sim]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        ex.snapshot() == before,
        "regenerating changed the bundled export"
    );
    // an edited export is overwritten only when forced
    let export = ex.proj().join("cfd_exports/surge_run.csv");
    std::fs::write(&export, "edited").unwrap();
    let before = ex.snapshot();
    let o = ex.hydroid(&["simulate", sim]);
    refused(&ex, &before, &o, &["changed", "--force"]);
    let o = ex.hydroid(&["simulate", sim, "--force"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(
        std::fs::read(&export).unwrap(),
        std::fs::read(root().join("cfd_exports/surge_run.csv")).unwrap()
    );
    // a new file is written and listed, then overwritten
    for _ in 0..2 {
        let o = ex.hydroid(&["simulate", sim, "--out", "new/run.csv"]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    }
    let record = std::fs::read_to_string(ex.proj().join("new/.hydroid-exports.json")).unwrap();
    assert!(record.contains("\"run.csv\""), "{record}");
}

#[test]
fn the_bundled_exports_are_listed_with_their_hashes() {
    let record: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("cfd_exports/.hydroid-exports.json")).unwrap(),
    )
    .unwrap();
    let files = record["files"].as_object().unwrap();
    let mut exports: Vec<String> = std::fs::read_dir(root().join("cfd_exports"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    exports.sort();
    assert_eq!(files.keys().cloned().collect::<Vec<_>>(), exports);
    assert_eq!(record["format"], "hydroid-exports/2");
    for (name, entry) in files {
        assert_eq!(
            entry["sha256"].as_str().unwrap(),
            hydroid::app::pipeline::file_sha256(&root().join("cfd_exports").join(name)).unwrap(),
            "cfd_exports/.hydroid-exports.json is stale for {name}: regenerate the export with \
             hydroid simulate"
        );
        // each was written by the simulation whose export.file it is
        assert_eq!(entry["kind"], "simulate", "{name}");
        let source = root()
            .join("cfd_exports")
            .join(entry["source"].as_str().unwrap());
        let sim = std::fs::read_to_string(&source).unwrap();
        assert!(
            sim.contains(&format!("file = \"../../cfd_exports/{name}\"")),
            "{name}: {}",
            source.display()
        );
    }
}

#[test]
fn a_read_only_parent_is_a_clear_error_and_leaves_nothing() {
    use std::os::unix::fs::PermissionsExt;
    let ex = Example::new();
    let ro = ex.proj().join("ro");
    std::fs::create_dir(&ro).unwrap();
    std::fs::set_permissions(&ro, PermissionsExt::from_mode(0o555)).unwrap();
    // root writes into a folder without write permission anyway; not into /proc
    let ro = if std::fs::write(ro.join("probe"), "").is_ok() {
        std::fs::remove_file(ro.join("probe")).unwrap();
        PathBuf::from("/proc")
    } else {
        ro
    };
    let before = ex.snapshot();
    let out = ro.join("out");
    let o = ex.hydroid(&[
        "run",
        "configs/spheroid.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&ex, &before, &o, &["cannot write in", ro.to_str().unwrap()]);
    let out = ro.join("sub/out");
    let o = ex.hydroid(&[
        "run",
        "configs/spheroid.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(
        &ex,
        &before,
        &o,
        &["cannot create the folder", ro.to_str().unwrap()],
    );
    std::fs::set_permissions(ex.proj().join("ro"), PermissionsExt::from_mode(0o755)).unwrap();
}

/// The staging folders in `dir`.
fn partials(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.contains(".partial-") || n.ends_with(".old"))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn a_signal_during_a_run_leaves_no_staging_folder() {
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let ex = Example::new();
        let out = ex.proj().join("out");
        // several passes keep the run busy long enough to be interrupted
        let mut child = ex
            .command(
                &ex.proj(),
                &[
                    "run",
                    "configs/spheroid.toml",
                    "--out",
                    "out",
                    "--set",
                    "hekf.passes=8",
                ],
            )
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let started = Instant::now();
        while partials(&ex.proj()).is_empty() {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the run ended before it was interrupted"
            );
            assert!(
                started.elapsed() < Duration::from_secs(60),
                "no staging folder appeared"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        let k = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(k.success());
        let o = child.wait_with_output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(code),
            "SIG{signal}: {}",
            text(&o.stderr)
        );
        assert_eq!(partials(&ex.proj()), Vec::<String>::new(), "SIG{signal}");
        assert!(!out.exists(), "SIG{signal} left an output");
    }
}

#[test]
fn abandoned_staging_folders_are_swept_only_when_they_are_hydroids() {
    let ex = Example::new();
    let p = ex.proj();
    // what a killed run leaves: the staging marker, its lock free
    let stale = killed_run_staging(&p, "out", "{}");
    // a folder that only looks like one
    let lookalike = p.join(".out.partial-99998");
    std::fs::create_dir(&lookalike).unwrap();
    std::fs::write(lookalike.join("notes.txt"), "mine").unwrap();
    let o = run_ok(&ex, "", &["--out", "out"]);
    assert!(!stale.exists(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("abandoned staging folder"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(lookalike.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(p.join("out/results.json").exists());
}

#[test]
fn rerun_works_from_any_folder_and_quotes_the_recorded_configuration() {
    let ex = Example::new();
    // at another depth than the configuration: its relative paths do not work from there
    run_ok(&ex, "", &["--out", "results/deep/out"]);
    let out = ex.proj().join("results/deep/out");
    let results = std::fs::read(out.join("results.json")).unwrap();
    let rerun_json = std::fs::read(out.join("rerun.json")).unwrap();
    // from another working folder, with a relative path to the output
    std::fs::create_dir(ex.top().join("elsewhere")).unwrap();
    let o = ex.hydroid_in("../elsewhere", &["rerun", "../proj/results/deep/out"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), results);
    assert_eq!(std::fs::read(out.join("rerun.json")).unwrap(), rerun_json);
    // into a folder hydroid did not write: refused
    std::fs::create_dir(ex.top().join("elsewhere/mine")).unwrap();
    std::fs::write(ex.top().join("elsewhere/mine/notes.txt"), "mine").unwrap();
    let before = ex.snapshot();
    let o = ex.hydroid_in(
        "../elsewhere",
        &[
            "rerun",
            "../proj/results/deep/out",
            "--out",
            "mine",
            "--force",
        ],
    );
    refused(&ex, &before, &o, &["hydroid did not write"]);
    // a problem in the recorded configuration is placed in it, at its own line
    let cfg = out.join("config.toml");
    let t = std::fs::read_to_string(&cfg).unwrap();
    let line = 1 + t.lines().position(|l| l.starts_with("mass = ")).unwrap();
    std::fs::write(&cfg, t.replacen("mass = 50.0", "mass = -50.0", 1)).unwrap();
    let o = ex.hydroid_in(
        "../elsewhere",
        &["rerun", "../proj/results/deep/out", "--edited"],
    );
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains(&format!("out/config.toml:{line}: vehicle.mass")),
        "{e}"
    );
    assert!(!e.contains("spheroid.toml"), "{e}");
}
