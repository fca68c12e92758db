//! Fuzzing the configuration loaders (run and simulate) with mutated copies of the bundled
//! configurations: lines dropped, duplicated and swapped; values replaced by other TOML
//! types, huge, negative or non-finite numbers and random unit strings; random keys.
//! Property: the loader returns a configuration or configuration problems, never panics,
//! and no message shows Rust's vocabulary. The stages are not run. Fixed seed, bounded
//! number of cases (a few seconds in debug).

use hydroid::base::error::Error;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use std::path::{Path, PathBuf};

const FORBIDDEN: &[&str] = &[
    "usize", "isize", "u32", "u64", "f64", "struct ", "Some(", "None", "untagged", "borrowed", "::",
];

/// The bundled configurations: (path, is a simulate configuration, text).
fn corpus() -> Vec<(PathBuf, bool, String)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut v = Vec::new();
    for (dir, sim) in [("configs", false), ("configs/simulate", true)] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        files.sort();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            v.push((f, sim, text));
        }
    }
    assert!(v.len() >= 6, "{} configurations", v.len());
    v
}

/// A TOML value of any type, often an awkward one.
fn value() -> impl Strategy<Value = String> {
    let units = prop::sample::select(vec![
        "N", "kg", "m/s", "deg", "rad", "s", "ms", "m", "kg m^2", "Pa s", "kg/m^3", "deg/s", "rpm",
        "kn", "furlong", "", "1", "%", "m^", "N m", "m^2", "1/s", "°", "e",
    ]);
    let numbers = prop::sample::select(vec![
        "0",
        "-0.0",
        "1",
        "-1",
        "2.5",
        "1e308",
        "-1e308",
        "5e-324",
        "1e-300",
        "nan",
        "+inf",
        "-inf",
        "9223372036854775807",
        "-9223372036854775808",
        "1e12",
        "1e-9",
        "100000000",
    ]);
    prop_oneof![
        numbers.clone().prop_map(str::to_string),
        (numbers.clone(), units).prop_map(|(n, u)| format!("\"{n} {u}\"")),
        any::<f64>().prop_map(|f| {
            if f.is_finite() {
                format!("{f:e}")
            } else {
                "nan".to_string()
            }
        }),
        any::<i64>().prop_map(|i| i.to_string()),
        "[abcdxyz ./,\"-]{0,12}".prop_map(|s| format!("{s:?}")),
        Just("true".to_string()),
        Just("[]".to_string()),
        Just("[1, \"a\", 2.5]".to_string()),
        Just("{ a = 1 }".to_string()),
        Just("{}".to_string()),
        Just("1979-05-27T07:32:00Z".to_string()),
        Just("\"3 deg\"".to_string()),
        Just("\"22 N\"".to_string()),
    ]
}

/// A key, known or not.
fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "mass",
            "length",
            "rho",
            "mu",
            "passes",
            "substeps",
            "estimate",
            "thrust",
            "u",
            "yaw",
            "seed",
            "digits",
            "separator",
            "duration",
            "dt",
            "kind",
            "enabled",
            "file",
            "layout",
            "index",
            "scale",
            "noise",
            "initial",
            "time",
            "alpha_deg",
            "speeds",
        ])
        .prop_map(str::to_string),
        "[a-z_]{1,10}",
    ]
}

#[derive(Debug, Clone)]
enum Mutation {
    Drop(usize),
    Duplicate(usize),
    Swap(usize, usize),
    Value(usize, String),
    Insert(usize, String, String),
    Rename(usize, String),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = any::<prop::sample::Index>();
    prop_oneof![
        at.clone().prop_map(|i| Mutation::Drop(i.index(usize::MAX))),
        at.clone()
            .prop_map(|i| Mutation::Duplicate(i.index(usize::MAX))),
        (at.clone(), at.clone())
            .prop_map(|(a, b)| Mutation::Swap(a.index(usize::MAX), b.index(usize::MAX))),
        (at.clone(), value()).prop_map(|(i, v)| Mutation::Value(i.index(usize::MAX), v)),
        (at.clone(), value()).prop_map(|(i, v)| Mutation::Value(i.index(usize::MAX), v)),
        (at.clone(), key(), value()).prop_map(|(i, k, v)| Mutation::Insert(
            i.index(usize::MAX),
            k,
            v
        )),
        (at, key()).prop_map(|(i, k)| Mutation::Rename(i.index(usize::MAX), k)),
    ]
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for m in muts {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        match m {
            Mutation::Drop(i) => {
                lines.remove(i % n);
            }
            Mutation::Duplicate(i) => {
                let l = lines[i % n].clone();
                lines.insert(i % n, l);
            }
            Mutation::Swap(a, b) => lines.swap(a % n, b % n),
            Mutation::Value(i, v) => {
                // the value of a key line (the first `k = v` at or after i)
                if let Some(j) = (0..n)
                    .map(|d| (i + d) % n)
                    .find(|&j| lines[j].contains(" = "))
                {
                    let (k, _) = lines[j].split_once(" = ").unwrap();
                    lines[j] = format!("{k} = {v}");
                }
            }
            Mutation::Insert(i, k, v) => lines.insert(i % (n + 1), format!("{k} = {v}")),
            Mutation::Rename(i, k) => {
                if let Some(j) = (0..n)
                    .map(|d| (i + d) % n)
                    .find(|&j| lines[j].contains(" = "))
                {
                    let (_, v) = lines[j].split_once(" = ").unwrap();
                    lines[j] = format!("{k} = {v}");
                }
            }
        }
    }
    lines.join("\n")
}

fn check(path: &Path, sim: bool, text: &str) -> Result<(), TestCaseError> {
    let problems = if sim {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join(path.file_name().unwrap());
        std::fs::write(&file, text).unwrap();
        match hydroid::app::simulate::config::load(&file) {
            Ok(_) => Vec::new(),
            Err(Error::Config(p)) => p,
            Err(e) => {
                return Err(TestCaseError::fail(format!(
                    "not a configuration error: {e}"
                )))
            }
        }
    } else {
        let (loaded, p) = hydroid::config::load_lenient(path, text, &[]);
        if let Some(l) = &loaded {
            // what `check` and `run` do next, short of reading the inputs
            let _ = l.effective_toml();
            let _ = hydroid::app::pipeline::stage_inputs(&l.config);
        }
        p
    };
    for p in &problems {
        // the words hydroid chose (the file name is a random temporary one)
        let m = format!("{}: {}", p.key.as_deref().unwrap_or(""), p.message);
        for f in FORBIDDEN {
            prop_assert!(!m.contains(f), "'{}' in: {}\n--- config:\n{}", f, m, text);
        }
    }
    Ok(())
}

#[test]
fn mutated_configurations_load_or_give_problems_in_words() {
    let corpus = corpus();
    let config = Config {
        cases: 2000,
        failure_persistence: None,
        ..Config::default()
    };
    let seed = [7u8; 32];
    let mut runner =
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &seed));
    let strategy = (0..corpus.len(), prop::collection::vec(mutation(), 1..8));
    let start = std::time::Instant::now();
    runner
        .run(&strategy, |(which, muts)| {
            let (path, sim, text) = &corpus[which];
            let mutated = apply(text, &muts);
            check(path, *sim, &mutated)
        })
        .unwrap();
    assert!(
        start.elapsed().as_secs() < 60,
        "the fuzz run took {:?}",
        start.elapsed()
    );
}
