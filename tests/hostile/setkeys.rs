//! `--set KEY=VALUE` as a hostile or careless user writes it: keys long, deep, with huge or
//! malformed list positions, empty segments, unbalanced quotes, Unicode and control
//! characters; values huge, deeply nested, not TOML. Every one ends as a refusal naming what
//! to fix (or runs, when it is a fine override), never an abort: a key of 20,000 segments
//! overflowed the stack, one of 10,000 took 5 GB (issue 48).

use super::{refused, run_table, Case, Expect};

const CONFIG: &str = "configs/spheroid.toml";

/// `hydroid check CONFIG --set SPEC`.
fn check(name: &str, spec: &str, expect: Expect) -> Case {
    Case::with_args(
        name,
        vec!["check".into(), CONFIG.into(), "--set".into(), spec.into()],
        expect,
    )
}

/// `hydroid run CONFIG --set SPEC --out out/s` (refused before any stage runs).
fn run(name: &str, spec: &str, expect: Expect) -> Case {
    Case::with_args(
        name,
        vec![
            "run".into(),
            CONFIG.into(),
            "--set".into(),
            spec.into(),
            "--out".into(),
            "out/s".into(),
        ],
        expect,
    )
}

/// `n` dotted segments `a.a.a...`.
fn dotted(n: usize) -> String {
    vec!["a"; n].join(".")
}

const STEPS: &str = "more than 32 steps";
const BYTES: &str = "longer than 1024 bytes";
const PAST: &str = "past the highest list position";

fn deep_and_long_keys() -> Vec<Case> {
    vec![
        check(
            "20000 segments",
            &format!("{}=1", dotted(20_000)),
            refused(&[STEPS]),
        ),
        run(
            "20000 segments (run)",
            &format!("{}=1", dotted(20_000)),
            refused(&[STEPS]),
        ),
        check(
            "10000 segments",
            &format!("{}=1", dotted(10_000)),
            refused(&[STEPS]),
        ),
        check(
            "33 segments",
            &format!("{}=1", dotted(33)),
            refused(&[STEPS]),
        ),
        // 32 segments is a key path; `a` is no key of a configuration
        check(
            "32 segments",
            &format!("{}=1", dotted(32)),
            refused(&["unknown key `a`"]),
        ),
        check(
            "33 list positions",
            &format!("hekf.estimate{}=1", "[0]".repeat(33)),
            refused(&[STEPS]),
        ),
        check(
            "alternating keys and positions",
            &format!("{}=1", vec!["a[0]"; 20].join(".")),
            refused(&[STEPS]),
        ),
        check(
            "bare key 1025 bytes",
            &format!("{}=1", "k".repeat(1025)),
            refused(&[BYTES]),
        ),
        check(
            "bare key 100000 bytes",
            &format!("{}=1", "k".repeat(100_000)),
            refused(&[BYTES]),
        ),
        run(
            "bare key 100000 bytes (run)",
            &format!("{}=1", "k".repeat(100_000)),
            refused(&[BYTES]),
        ),
        check(
            "quoted key 5000 bytes",
            &format!("hekf.\"{}\"=1", "q".repeat(5000)),
            refused(&[BYTES]),
        ),
        check(
            "30 quoted keys of 40 bytes",
            &format!(
                "{}=1",
                vec![format!("\"{}\"", "w".repeat(40)); 30].join(".")
            ),
            refused(&[BYTES]),
        ),
        check(
            "10000 quoted segments",
            &format!("{}=1", vec!["\"a b\""; 10_000].join(".")),
            refused(&[STEPS]),
        ),
        check(
            "long key of dots only",
            &format!("{}=1", ".".repeat(50_000)),
            refused(&["no key at"]),
        ),
    ]
}

fn list_positions() -> Vec<Case> {
    vec![
        check(
            "position 99999999999",
            "hekf.runs[99999999999].name=x",
            refused(&[PAST, "[99999]"]),
        ),
        run(
            "position 99999999999 (run)",
            "hekf.runs[99999999999].name=x",
            refused(&[PAST]),
        ),
        check(
            "position 2^64",
            "hekf.runs[18446744073709551616].name=x",
            refused(&[PAST]),
        ),
        check(
            "position 100000",
            "hekf.runs[100000].name=x",
            refused(&[PAST]),
        ),
        check(
            "position 99999 within the bound",
            "hekf.runs[99999].name=x",
            refused(&["hekf.runs has 1 entry", "[99999] does not exist"]),
        ),
        check(
            "position 1 of one run",
            "hekf.runs[1].name=x",
            refused(&["[1] does not exist"]),
        ),
        check(
            "negative position",
            "hekf.runs[-1].name=x",
            refused(&["'[-1]' is not a list position"]),
        ),
        check(
            "empty position",
            "hekf.runs[].name=x",
            refused(&["'[]' is not a list position"]),
        ),
        check(
            "unclosed position",
            "hekf.runs[0.name=x",
            refused(&["ends with ']'"]),
        ),
        check(
            "word as position",
            "hekf.runs[first].name=x",
            refused(&["not a list position"]),
        ),
        check(
            "position on a value",
            "vehicle.mass[0]=1",
            refused(&["vehicle.mass is the value", "not a list"]),
        ),
        check(
            "position on a table",
            "vehicle[0]=1",
            refused(&["vehicle is a table, not a list"]),
        ),
        check(
            "list without a position",
            "hekf.runs.file=x",
            refused(&["give a position"]),
        ),
        check(
            "a table of a list set whole",
            "hekf.runs[0]=1",
            refused(&["set one of its keys"]),
        ),
        check(
            "position into a missing list",
            "polar.nothing[3].x=1",
            refused(&["polar.nothing is not in the configuration"]),
        ),
    ]
}

fn malformed_keys() -> Vec<Case> {
    vec![
        check("empty segment", "hekf..passes=1", refused(&["no key at"])),
        check("leading dot", ".hekf.passes=1", refused(&["no key at"])),
        check("trailing dot", "hekf.passes.=1", refused(&["no key at"])),
        check("no key", "=1", refused(&["no key at"])),
        check("only an equals sign", "=", refused(&["no key at"])),
        check(
            "no equals sign",
            "hekf.passes",
            refused(&["expected KEY=VALUE"]),
        ),
        check(
            "unclosed double quote",
            "hekf.\"passes=1",
            refused(&["unclosed quote"]),
        ),
        check(
            "unclosed single quote",
            "hekf.'passes=1",
            refused(&["unclosed quote"]),
        ),
        check(
            "bad escape in a quoted key",
            "hekf.\"pa\\qsses\"=1",
            refused(&["bad escape"]),
        ),
        check(
            "unicode bare key",
            "h\u{e9}kf.passes=1",
            refused(&["the key stops at", "quote"]),
        ),
        check(
            "unicode quoted key",
            "\"h\u{e9}kf\".passes=1",
            refused(&["h\u{e9}kf"]),
        ),
        check(
            "emoji quoted key",
            "\"\u{1f6a2}\"=1",
            refused(&["\u{1f6a2}"]),
        ),
        check(
            "control character in a key",
            "hekf.pa\u{1}sses=1",
            refused(&["the key stops at '\\u{1}sses"]),
        ),
        check("escaped NUL in a quoted key", "\"\\u0000\"=1", Expect::Any),
        check(
            "escaped NUL inside a section",
            "hekf.\"\\u0000\"=1",
            refused(&["hekf"]),
        ),
        check("tab in a key", "hekf.pa\tsses=1", refused(&["hekf"])),
        check(
            "key with spaces around dots",
            "hekf . passes = 3",
            Expect::Fine,
        ),
        check("quoted known key", "\"hekf\".\"passes\"=3", Expect::Fine),
        check("unknown section", "hekff.passes=3", refused(&["hekff"])),
        check(
            "unknown key in a section",
            "hekf.pases=3",
            refused(&["pases"]),
        ),
    ]
}

/// Values the key refuses: a name, the override, a word the refusal holds (the key).
const REFUSED_VALUES: &[(&str, &str, &str)] = &[
    ("no value", "hekf.passes=", "no value after '='"),
    (
        "integer overflow",
        "hekf.passes=99999999999999999999",
        "hekf.passes",
    ),
    ("float overflow", "vehicle.mass=1e400", "vehicle.mass"),
    ("not a number", "vehicle.mass=nan", "vehicle.mass"),
    ("infinite mass", "vehicle.mass=inf", "vehicle.mass"),
    (
        "negative mass with a unit",
        "vehicle.mass=-50 kg",
        "vehicle.mass",
    ),
    ("mass in metres", "vehicle.mass=50 m", "vehicle.mass"),
    ("unclosed string", "title=\"abc", "not a TOML value"),
    ("lone brace", "vehicle.mass={", "not a TOML value"),
    (
        "sub-key of a value",
        "vehicle.mass.x=1",
        "vehicle.mass is the value",
    ),
    (
        "table for a number",
        "vehicle.mass={ a = 1 }",
        "vehicle.mass",
    ),
    ("list for a number", "hekf.passes=[1, 2]", "hekf.passes"),
];

fn values() -> Vec<Case> {
    let nested_lists = format!("hekf.passes={}1{}", "[".repeat(50_000), "]".repeat(50_000));
    let nested_tables = format!(
        "hekf.passes={}1{}",
        "{a=".repeat(30_000),
        "}".repeat(30_000)
    );
    let long_text = format!("title={}", "t".repeat(100_000));
    let many: Vec<String> = (0..10_000).map(|i| format!("\"C{i}\"")).collect();
    let mut cases: Vec<Case> = REFUSED_VALUES
        .iter()
        .map(|(name, spec, word)| check(name, spec, refused(&[word])))
        .collect();
    let deep = refused(&["hekf.passes"]);
    cases.extend([
        check("value 50000 lists deep", &nested_lists, deep.clone()),
        run("value 50000 lists deep (run)", &nested_lists, deep.clone()),
        check("value 30000 tables deep", &nested_tables, deep),
        check("title of 100000 characters", &long_text, Expect::Fine),
        check(
            "10000 coefficients to estimate",
            &format!("hekf.estimate=[{}]", many.join(",")),
            refused(&["hekf.estimate"]),
        ),
        check("mass with a unit", "vehicle.mass=50 kg", Expect::Fine),
        check(
            "escaped NUL in a text value",
            "title=\"a\\u0000b\"",
            Expect::Any,
        ),
    ]);
    let mut many_sets = vec!["check".to_string(), CONFIG.to_string()];
    for i in 0..1000 {
        many_sets.extend(["--set".to_string(), format!("hekf.passes={}", 1 + i % 3)]);
    }
    cases.push(Case::with_args("1000 overrides", many_sets, Expect::Fine));
    cases
}

#[test]
fn set_keys_and_values() {
    let mut cases = deep_and_long_keys();
    cases.extend(list_positions());
    cases.extend(malformed_keys());
    cases.extend(values());
    run_table("setkeys", cases);
}
