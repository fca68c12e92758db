//! The hostile corpus (issue 48): what a hostile or careless user does to the command line,
//! the configurations and the exports, kept as table-driven cases. Each case runs the
//! `hydroid` binary in a fresh copy of the bundled example (configs/, cfd_exports/) under a
//! time limit and an address-space limit, and is judged by the properties every case must
//! have, whatever it does:
//!
//! * no data loss: every file that was there before the case (the copy and the case's own
//!   set-up) is there after it, byte for byte, unless the case names it as one hydroid may
//!   replace (its own earlier output);
//! * no abort: the process ends by itself with an exit code, never by a signal (a failed
//!   allocation under the limit aborts), and never prints a Rust panic;
//! * no runaway: it ends within the time limit and under the memory limit;
//! * and what the case expects: refused with a message holding given words (the key,
//!   column or file to fix and the right cause), or warned with them, or fine.
//!
//! One file per area holds its cases (`hostile/<area>.rs`); each test runs its table on two
//! threads and reports every failing case at once.

#![allow(dead_code)]

use crate::common;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a case may take (debug build, a loaded two-core machine): far above any
/// legitimate case of the corpus, far below a runaway.
pub const TIME_LIMIT: Duration = Duration::from_secs(90);
/// The address space a case may use (`prlimit --as`): an allocation beyond it fails, which
/// aborts the process and fails the case.
pub const MEMORY_LIMIT: u64 = 3 << 30;

/// What a case expects of hydroid.
#[derive(Debug, Clone)]
pub enum Expect {
    /// A non-zero exit code (never a signal) and every one of these words in what it printed
    /// (standard error and output together, case-insensitive).
    Refused(Vec<String>),
    /// Exit code 0 and every one of these words in what it printed (a named warning).
    Warned(Vec<String>),
    /// Exit code 0.
    Fine,
    /// Exit code 0 and no warning printed: no line opens with "warning" (`check`'s
    /// "warnings:" list, `run`'s "warning: STAGE ..."; an input's notes are indented). A
    /// sound variation that must not raise a false alarm.
    Quiet,
    /// Any exit code (never a signal); only the common properties are checked.
    Any,
}

/// Refused, with these words.
pub fn refused(words: &[&str]) -> Expect {
    Expect::Refused(words.iter().map(|w| w.to_string()).collect())
}

/// Warned, with these words.
pub fn warned(words: &[&str]) -> Expect {
    Expect::Warned(words.iter().map(|w| w.to_string()).collect())
}

/// A set-up step run in the case's folder before its snapshot: writes files, edits a copy
/// of a configuration, runs hydroid to make an output folder the case then uses ...
pub type Setup = Box<dyn Fn(&Path) + Send + Sync>;

/// One case of the corpus.
pub struct Case {
    /// A short name, printed when the case fails.
    pub name: String,
    /// The command line after `hydroid`.
    pub args: Vec<String>,
    /// Environment variables set for the run.
    pub env: Vec<(String, String)>,
    /// Run before the snapshot (the files it makes are protected like the example's).
    pub setup: Option<Setup>,
    /// Files (relative to the case's folder) hydroid may replace: its own earlier output.
    pub may_change: Vec<String>,
    /// What hydroid should do.
    pub expect: Expect,
}

impl Case {
    /// A case running `args` (split on spaces) in a fresh copy of the example.
    pub fn new(name: &str, args: &str, expect: Expect) -> Self {
        Self::with_args(
            name,
            args.split_whitespace().map(str::to_string).collect(),
            expect,
        )
    }

    /// A case running exactly `args`.
    pub fn with_args(name: &str, args: Vec<String>, expect: Expect) -> Self {
        Case {
            name: name.to_string(),
            args,
            env: Vec::new(),
            setup: None,
            may_change: Vec::new(),
            expect,
        }
    }

    /// With a set-up step.
    pub fn setup(mut self, f: impl Fn(&Path) + Send + Sync + 'static) -> Self {
        self.setup = Some(Box::new(f));
        self
    }

    /// With an environment variable.
    pub fn env(mut self, key: &str, value: &str) -> Self {
        self.env.push((key.to_string(), value.to_string()));
        self
    }

    /// Allowing hydroid to replace these files (its own output).
    pub fn may_change(mut self, rel: &[&str]) -> Self {
        self.may_change.extend(rel.iter().map(|s| s.to_string()));
        self
    }
}

/// What the process did.
#[derive(Debug)]
pub struct Outcome {
    /// The exit code; None when a signal ended it.
    pub code: Option<i32>,
    /// Standard output and error, as text.
    pub printed: String,
    /// Whether the time limit killed it.
    pub timed_out: bool,
    /// Seconds it took.
    pub seconds: f64,
}

/// Every regular file under `dir` (symbolic links not followed), relative path -> SHA-256.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let Ok(t) = e.file_type() else { continue };
            let p = e.path();
            if t.is_dir() {
                stack.push(p);
            } else if t.is_file() {
                let Ok(bytes) = std::fs::read(&p) else {
                    continue;
                };
                let hex: String = Sha256::digest(&bytes)
                    .iter()
                    .map(|b| format!("{b:02x}"))
                    .collect();
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), hex);
            }
        }
    }
    out
}

/// Runs the hydroid binary in `dir` with `args` and `env`, under the limits.
pub fn run_limited(dir: &Path, args: &[String], env: &[(String, String)]) -> Outcome {
    let start = Instant::now();
    let bin = env!("CARGO_BIN_EXE_hydroid");
    let mut cmd = if Path::new("/usr/bin/prlimit").exists() {
        let mut c = Command::new("/usr/bin/prlimit");
        c.arg(format!("--as={MEMORY_LIMIT}")).arg("--").arg(bin);
        c
    } else {
        Command::new(bin)
    };
    cmd.args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd.spawn().expect("the hydroid binary starts");
    // drain the pipes while waiting, so that a talkative case cannot block on a full pipe
    let mut out_pipe = child.stdout.take().unwrap();
    let mut err_pipe = child.stderr.take().unwrap();
    let out_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = std::io::Read::read_to_end(&mut out_pipe, &mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = std::io::Read::read_to_end(&mut err_pipe, &mut s);
        s
    });
    let mut timed_out = false;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > TIME_LIMIT {
            timed_out = true;
            let _ = child.kill();
            break child.wait().unwrap();
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut printed = common::text(&err_reader.join().unwrap());
    printed.push('\n');
    printed.push_str(&common::text(&out_reader.join().unwrap()));
    Outcome {
        code: if timed_out { None } else { status.code() },
        printed,
        timed_out,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// Why `case`'s outcome breaks a property, if it does. `before` and `after` are the
/// snapshots of its folder.
fn judge(
    case: &Case,
    o: &Outcome,
    before: &BTreeMap<PathBuf, String>,
    after: &BTreeMap<PathBuf, String>,
) -> Option<String> {
    if o.timed_out {
        return Some(format!(
            "runaway: still running after {} s",
            TIME_LIMIT.as_secs()
        ));
    }
    let Some(code) = o.code else {
        return Some(format!("abort: ended by a signal\n{}", tail(&o.printed)));
    };
    if o.printed.contains("panicked") || o.printed.contains("RUST_BACKTRACE") {
        return Some(format!("panic\n{}", tail(&o.printed)));
    }
    for (p, sha) in before {
        let allowed = case.may_change.iter().any(|m| p.starts_with(m));
        if !allowed && after.get(p) != Some(sha) {
            return Some(format!(
                "data loss: {} {} (exit {code})",
                p.display(),
                if after.contains_key(p) {
                    "changed"
                } else {
                    "removed"
                }
            ));
        }
    }
    let lower = o.printed.to_lowercase();
    let missing = |words: &[String]| {
        words
            .iter()
            .filter(|w| !lower.contains(&w.to_lowercase()))
            .cloned()
            .collect::<Vec<_>>()
    };
    let bad = match &case.expect {
        Expect::Refused(words) if code == 0 => Some("accepted (exit 0), expected a refusal".into()),
        Expect::Refused(words) | Expect::Warned(words) if !missing(words).is_empty() => Some(
            format!("exit {code}, missing the words {:?}", missing(words)),
        ),
        Expect::Warned(_) | Expect::Fine | Expect::Quiet if code != 0 => {
            Some(format!("exit {code}, expected 0"))
        }
        Expect::Quiet if lower.lines().any(|l| l.starts_with("warning")) => {
            Some("a warning, expected none".into())
        }
        _ => None,
    };
    bad.map(|b| format!("{b}\n{}", tail(&o.printed)))
}

/// The last lines of what a case printed.
fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(12)..].join("\n")
}

/// Runs one case in a fresh copy of the example; why it fails, if it does.
pub fn run_case(case: &Case) -> Option<String> {
    let dir = common::example_copy();
    if let Some(setup) = &case.setup {
        setup(dir.path());
    }
    let before = snapshot(dir.path());
    let o = run_limited(dir.path(), &case.args, &case.env);
    let after = snapshot(dir.path());
    judge(case, &o, &before, &after)
}

/// Runs a table of cases on two threads; fails listing every case that broke a property.
/// Returns the number of cases run (the corpus's count).
pub fn run_table(area: &str, cases: Vec<Case>) -> usize {
    let n = cases.len();
    let failures: Vec<String> = common::parallel::on_two_threads(n, |_, k| {
        run_case(&cases[k]).map(|why| {
            format!(
                "[{}] hydroid {}: {why}",
                cases[k].name,
                cases[k].args.join(" ")
            )
        })
    })
    .into_iter()
    .flatten()
    .collect();
    assert!(
        failures.is_empty(),
        "{area}: {} of {n} hostile cases failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    // the corpus's size, for `cargo test hostile:: -- --nocapture` (issue 48 asks for >= 600)
    eprintln!("hostile cases: {n} ({area})");
    n
}

/// Copies the output folder of `hydroid run CONFIG ARGS...` into `dir/out/NAME` (as a set-up
/// step). The run is made once per test binary in a copy of the example and kept, so that
/// many cases can share an identified model without paying for its run each time; the copy
/// keeps its marker valid (the marker lists paths relative to the folder).
pub fn copy_run_output(dir: &Path, config: &str, args: &[&str], name: &str) {
    use std::sync::{Mutex, OnceLock};
    static CACHE: OnceLock<Mutex<BTreeMap<String, tempfile::TempDir>>> = OnceLock::new();
    let key = format!("{config} {}", args.join(" "));
    let cache = CACHE.get_or_init(|| Mutex::new(BTreeMap::new()));
    let mut cache = cache.lock().unwrap_or_else(|e| e.into_inner());
    let made = cache.entry(key).or_insert_with(|| {
        let copy = common::example_copy();
        let mut all = vec!["run", config, "--out", "out/made"];
        all.extend_from_slice(args);
        let o = common::hydroid_in(copy.path(), &all);
        assert!(
            o.status.success(),
            "the set-up run {all:?} failed: {}",
            common::text(&o.stderr)
        );
        copy
    });
    copy_tree(&made.path().join("out/made"), &dir.join("out").join(name));
}

/// Copies a folder tree (regular files and folders).
pub fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let t = e.file_type().unwrap();
        if t.is_dir() {
            copy_tree(&e.path(), &to.join(e.file_name()));
        } else if t.is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

mod basics;
mod check;
mod lines;
mod setkeys;
mod writers;

#[test]
fn the_judge_catches_every_property() {
    let case = |expect| Case::new("t", "run x", expect);
    let o = |code, printed: &str, timed_out| Outcome {
        code,
        printed: printed.to_string(),
        timed_out,
        seconds: 0.0,
    };
    let file = |s: &str| BTreeMap::from([(PathBuf::from("cfd_exports/a.csv"), s.to_string())]);
    let same = file("1");
    let fine = case(Expect::Fine);
    assert!(judge(&fine, &o(Some(0), "", false), &same, &same).is_none());
    let lost = judge(&fine, &o(Some(0), "", false), &same, &file("2")).unwrap();
    assert!(lost.starts_with("data loss"), "{lost}");
    let gone = judge(&fine, &o(Some(2), "", false), &same, &BTreeMap::new()).unwrap();
    assert!(gone.contains("removed"), "{gone}");
    let mine = case(Expect::Fine).may_change(&["cfd_exports"]);
    assert!(judge(&mine, &o(Some(0), "", false), &same, &file("2")).is_none());
    assert!(judge(&fine, &o(None, "", false), &same, &same)
        .unwrap()
        .starts_with("abort"));
    assert!(judge(&fine, &o(None, "", true), &same, &same)
        .unwrap()
        .starts_with("runaway"));
    let panic = o(Some(101), "thread 'main' panicked at", false);
    assert!(judge(&case(Expect::Any), &panic, &same, &same)
        .unwrap()
        .starts_with("panic"));
    let no = case(refused(&["Column 4", "deg"]));
    assert!(judge(&no, &o(Some(2), "bad column 4 in deg", false), &same, &same).is_none());
    assert!(judge(&no, &o(Some(2), "bad column 4", false), &same, &same).is_some());
    assert!(judge(&no, &o(Some(0), "column 4 deg", false), &same, &same).is_some());
    let warn = case(warned(&["extrapolat"]));
    assert!(judge(
        &warn,
        &o(Some(0), "warning: extrapolates", false),
        &same,
        &same
    )
    .is_none());
    assert!(judge(
        &warn,
        &o(Some(1), "warning: extrapolates", false),
        &same,
        &same
    )
    .is_some());
    assert!(judge(&fine, &o(Some(3), "", false), &same, &same).is_some());
    let quiet = case(Expect::Quiet);
    assert!(judge(&quiet, &o(Some(0), "ok: usable", false), &same, &same).is_none());
    let note = "  run: a.csv\n      warning: Froude-scaled\nok";
    assert!(judge(&quiet, &o(Some(0), note, false), &same, &same).is_none());
    let said = "warning: captive: x\nwrote out";
    assert!(judge(&quiet, &o(Some(0), said, false), &same, &same).is_some());
    assert!(judge(&quiet, &o(Some(0), "warnings:\n - x", false), &same, &same).is_some());
    assert!(judge(&quiet, &o(Some(2), "ok", false), &same, &same).is_some());
}

mod captive;
mod exports;
mod fmu;
mod freerunning;
mod limits;
