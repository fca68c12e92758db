//! Fuzzing the readers: random bytes, and every fixture under tests/fixtures/ (formats, bad,
//! edge) mutated the way real files go wrong: cut off, separators, quotes and brackets put in
//! the wrong place, huge numbers, NaN, non-ASCII text, very long lines, repeated or missing
//! lines. Each file goes through `formats::read` with every format choice, `inspect` and the
//! record loader. The property: every call returns (a table or an error), never panics, never
//! hangs.
//!
//! Deterministic: a fixed seed, and the corpus in sorted order. The number of cases keeps the
//! file well under a minute in a debug build; `HYDROID_FUZZ_CASES=5000 HYDROID_FUZZ_SEED=7
//! cargo test --release --test suite fuzz_readers::` runs a longer search from another seed.

use hydroid::base::quantity::Quantity;
use hydroid::config::InputSpec;
use hydroid::io::formats::{self, Format, FormatChoice, ReadOptions};
use hydroid::io::record::{self, Needs};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

/// Cases per property: the default, or `HYDROID_FUZZ_CASES`.
fn cases(default: u32) -> u32 {
    std::env::var("HYDROID_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        rng_seed: RngSeed::Fixed(
            std::env::var("HYDROID_FUZZ_SEED")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(20_261_123),
        ),
        failure_persistence: None,
        // A failing case is shrunk a little, never for long.
        max_shrink_iters: 64,
        max_shrink_time: 60_000,
        ..ProptestConfig::default()
    }
}

/// Every fixture: (file name, bytes), sorted.
fn corpus() -> &'static [(String, Vec<u8>)] {
    static CORPUS: OnceLock<Vec<(String, Vec<u8>)>> = OnceLock::new();
    CORPUS.get_or_init(|| {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let mut files = Vec::new();
        for dir in ["formats", "bad", "edge"] {
            for entry in std::fs::read_dir(root.join(dir)).unwrap() {
                let path = entry.unwrap().path();
                if path.is_file() {
                    let name = path.file_name().unwrap().to_string_lossy().into_owned();
                    files.push((name, std::fs::read(&path).unwrap()));
                }
            }
        }
        files.sort();
        assert!(files.len() >= 40, "{} fixtures", files.len());
        files
    })
}

/// Texts a mutation inserts.
const SNIPPETS: &[&[u8]] = &[
    b",",
    b";",
    b"\t",
    b" ",
    b"\"",
    b"\"\"",
    b"(",
    b")",
    b"((",
    b"))",
    b"[",
    b"]",
    b"[ m s^-1 ]",
    b" (deg)",
    b"1e308",
    b"1e999",
    b"-1e-400",
    b"179769313486231570000000000000000000000000000000000000000000000000000000000000000000",
    b"NaN",
    b"nan",
    b"-inf",
    b"0.",
    b"1.2e",
    b"1,5",
    b"\xc3\xa9",
    b"\xc2\xb0",
    b"\xe2\x80\x93",
    b"\xef\xbb\xbf",
    b"\x96",
    b"\xb0",
    b"\xff\xfe",
    b"\x00",
    b"\x01\x02\x03",
    b"\r",
    b"\n",
    b"\r\n",
    b"#",
    b"# Time ",
    b"%",
    b"//",
    b"[Data]\n",
    b"Time [ s ],",
    b"# Angle Units : degrees\n",
    b"((((((((((((((((((((((((((((((((((((((((",
    b",,,,,,,,,,,,,,,,",
];

/// One way to damage a file. Positions are fractions of the file, so that a mutation means
/// the same thing on any fixture.
#[derive(Debug, Clone)]
enum Mutation {
    /// Keep only the first fraction of the bytes (a file cut off while being written).
    Truncate(f64),
    /// Insert `SNIPPETS[k]` at a position.
    Insert(f64, usize),
    /// Overwrite one byte.
    Replace(f64, u8),
    /// Repeat the line at a position.
    DuplicateLine(f64),
    /// Remove the line at a position.
    DropLine(f64),
    /// Remove the first line (usually the header).
    DropHeader,
    /// Insert a line of `n` cells separated by the byte given.
    LongLine(f64, usize, u8),
    /// Repeat a snippet `n` times at a position (a very long cell or run of separators).
    Repeat(f64, usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = 0.0..=1.0f64;
    let snippet = 0..SNIPPETS.len();
    prop_oneof![
        at.clone().prop_map(Mutation::Truncate),
        (at.clone(), snippet.clone()).prop_map(|(a, k)| Mutation::Insert(a, k)),
        (at.clone(), any::<u8>()).prop_map(|(a, b)| Mutation::Replace(a, b)),
        at.clone().prop_map(Mutation::DuplicateLine),
        at.clone().prop_map(Mutation::DropLine),
        Just(Mutation::DropHeader),
        (
            at.clone(),
            1..3000usize,
            prop::sample::select(b",; \t".to_vec())
        )
            .prop_map(|(a, n, d)| Mutation::LongLine(a, n, d)),
        (at, snippet, 1..2000usize).prop_map(|(a, k, n)| Mutation::Repeat(a, k, n)),
    ]
}

/// Byte offset of fraction `at` of `bytes`.
fn offset(bytes: &[u8], at: f64) -> usize {
    ((bytes.len() as f64 * at) as usize).min(bytes.len())
}

/// (start, end) of the line holding fraction `at`, terminator included.
fn line_at(bytes: &[u8], at: f64) -> (usize, usize) {
    let o = offset(bytes, at);
    let start = bytes[..o]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let end = bytes[o..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |p| o + p + 1);
    (start, end)
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    match *m {
        Mutation::Truncate(at) => bytes.truncate(offset(bytes, at)),
        Mutation::Insert(at, k) => {
            let o = offset(bytes, at);
            bytes.splice(o..o, SNIPPETS[k].iter().copied());
        }
        Mutation::Replace(at, b) => {
            let o = offset(bytes, at);
            if o < bytes.len() {
                bytes[o] = b;
            }
        }
        Mutation::DuplicateLine(at) => {
            let (s, e) = line_at(bytes, at);
            let line = bytes[s..e].to_vec();
            bytes.splice(e..e, line);
        }
        Mutation::DropLine(at) => {
            let (s, e) = line_at(bytes, at);
            bytes.drain(s..e);
        }
        Mutation::DropHeader => {
            let (s, e) = line_at(bytes, 0.0);
            bytes.drain(s..e);
        }
        Mutation::LongLine(at, n, d) => {
            let (s, _) = line_at(bytes, at);
            let mut line: Vec<u8> = Vec::with_capacity(n * 6);
            for k in 0..n {
                if k > 0 {
                    line.push(d);
                }
                line.extend_from_slice(format!("{}.{}", k % 97, k % 7).as_bytes());
            }
            line.push(b'\n');
            bytes.splice(s..s, line);
        }
        Mutation::Repeat(at, k, n) => {
            let o = offset(bytes, at);
            let run: Vec<u8> = SNIPPETS[k].repeat(n);
            bytes.splice(o..o, run);
        }
    }
}

/// Needs of the three stages, and specs that reach the loader's column mapping, unit
/// checks and frame rotation.
fn loads(path: &Path) {
    let dir = path.parent().unwrap();
    let file = path.file_name().unwrap().to_string_lossy();
    let history = Needs {
        required: &[Quantity::Time],
        optional: &[
            Quantity::U,
            Quantity::V,
            Quantity::R,
            Quantity::Yaw,
            Quantity::Roll,
            Quantity::X,
            Quantity::Y,
        ],
        min_rows: 2,
    };
    let polar = Needs {
        required: &[Quantity::Alpha, Quantity::Cd, Quantity::Cl, Quantity::Cm],
        optional: &[Quantity::Speed, Quantity::Time],
        min_rows: 1,
    };
    let specs = [
        (String::new(), history),
        (
            "columns = { alpha = { index = 1, unit = \"deg\" }, cd = { index = 2 }, \
             cl = { index = 3 }, cm = { index = 4 } }"
                .to_string(),
            polar,
        ),
        (
            "velocity_frame = \"earth\"\ncolumns = { time = { index = 1, unit = \"s\" }, \
             u = { index = 2, unit = \"m/s\" }, v = { index = 3, unit = \"m/s\" }, \
             yaw = { index = 4, unit = \"deg\" } }"
                .to_string(),
            history,
        ),
    ];
    for (extra, needs) in specs {
        let text = format!("file = {:?}\n{extra}\n", file.as_ref());
        let spec: InputSpec = toml::from_str(&text).unwrap();
        let _ = record::load(&spec, dir, &needs);
    }
}

/// Every reader on `path`, on a thread that must finish within the time limit.
fn read_every_way(path: PathBuf) {
    let shown = path.display().to_string();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let options = ReadOptions::default();
        let _ = formats::read(&path, FormatChoice::Auto, &options);
        for f in Format::ALL {
            let _ = formats::read(&path, FormatChoice::Fixed(f), &options);
        }
        let _ = formats::detect::detect(&path);
        let _ = hydroid::app::inspect::inspect(&path, FormatChoice::Auto);
        loads(&path);
        let _ = tx.send(());
    });
    match rx.recv_timeout(Duration::from_secs(30)) {
        Ok(()) => {}
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
            panic!("reading {shown} did not finish within 30 s")
        }
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            panic!("a reader panicked on {shown} (its message is above)")
        }
    }
}

proptest! {
    #![proptest_config(config(cases(160)))]

    /// Fixtures with one to four mutations.
    #[test]
    fn mutated_fixtures_never_panic_or_hang(
        pick in 0..1000usize,
        mutations in prop::collection::vec(mutation(), 1..5),
    ) {
        let files = corpus();
        let (name, original) = &files[pick % files.len()];
        let mut bytes = original.clone();
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        read_every_way(path);
    }
}

proptest! {
    #![proptest_config(config(cases(64)))]

    /// Bytes of any value, and bytes drawn from what exports are made of, under names that
    /// steer detection.
    #[test]
    fn random_bytes_never_panic_or_hang(
        raw in prop::collection::vec(any::<u8>(), 0..2048),
        texty in prop::collection::vec(
            prop::sample::select(b"0123456789.,;eE+-() \t\n\r\"#[]:Timecdlxyz".to_vec()),
            0..4096,
        ),
        name in prop::sample::select(vec![
            "run.csv", "forceCoeffs.dat", "coefficient.dat", "force.dat", "moment.dat",
            "report.out", "sixDoFRigidBodyState.dat",
        ]),
    ) {
        let dir = tempfile::tempdir().unwrap();
        for (k, bytes) in [raw, texty].iter().enumerate() {
            let sub = dir.path().join(k.to_string());
            std::fs::create_dir(&sub).unwrap();
            let path = sub.join(name);
            std::fs::write(&path, bytes).unwrap();
            read_every_way(path);
        }
    }
}
