//! `hydroid check CONFIG` refuses what `hydroid run CONFIG` refuses before any stage runs
//! (issue 48): each case is run twice, as `check` and as `run`, and both must refuse naming
//! the same key (or file, or place). `check` said an empty column map and a 5,000-character
//! run name were usable, which `run` then refused.

use super::{refused, run_table, Case};

/// The overrides of a case: one `--set` each.
type Sets<'a> = &'a [&'a str];

/// `check CONFIG --set ...` and `run CONFIG --set ... --out out/x`, both refused with `words`.
fn both(name: &str, config: &str, sets: Sets, out: Option<&str>, words: &[&str]) -> Vec<Case> {
    let mut tail: Vec<String> = sets
        .iter()
        .flat_map(|s| ["--set".to_string(), s.to_string()])
        .collect();
    tail.extend(["--out".to_string(), out.unwrap_or("out/x").to_string()]);
    ["check", "run"]
        .iter()
        .map(|verb| {
            let mut args = vec![verb.to_string(), config.to_string()];
            args.extend(tail.iter().cloned());
            Case::with_args(&format!("{verb}: {name}"), args, refused(words))
        })
        .collect()
}

const SPHEROID: &str = "configs/spheroid.toml";

/// Overrides of the spheroid example both refuse: a name, the override, the words both must
/// print (the key to fix first).
const SPHEROID_CASES: &[(&str, &str, &[&str])] = &[
    (
        "empty column map of the fit run",
        "hekf.runs[0].columns={}",
        &[
            "hekf.runs[0].columns",
            "none of the spheroid3 model's states",
        ],
    ),
    (
        "unknown process noise",
        "hekf.process_noise.bogus=1",
        &["hekf.process_noise.bogus", "not a state"],
    ),
    (
        "a measured quantity the model lacks",
        "hekf.measure=[\"q\"]",
        &["hekf.measure", "not a state of the spheroid3 model"],
    ),
    (
        "empty column map of the polar",
        "polar.runs[0].columns={}",
        &["no column for alpha"],
    ),
    (
        "empty column map of the surge run",
        "surge.runs[0].columns={}",
        &["no column for u"],
    ),
    (
        "empty column map of the validation run",
        "hekf.validation[0].columns={}",
        &["gives no thrust"],
    ),
    (
        "diameter above the length",
        "vehicle.diameter=2",
        &["vehicle.diameter"],
    ),
    ("no passes", "hekf.passes=0", &["hekf.passes"]),
    (
        "unknown coefficient to estimate",
        "hekf.estimate=[\"Nope\"]",
        &["Nope"],
    ),
    (
        "empty file name",
        "hekf.runs[0].file=\"\"",
        &["hekf.runs[0].file"],
    ),
    (
        "missing file",
        "hekf.runs[0].file=nope.csv",
        &["nope.csv", "does not exist"],
    ),
    (
        "unknown time column",
        "hekf.runs[0].columns.time=Nope",
        &["no column for time"],
    ),
    (
        "too many lines skipped",
        "hekf.runs[0].skip_lines=100000",
        &["skip_lines"],
    ),
    (
        "thrust in metres",
        "hekf.runs[0].constants.thrust=22 m",
        &["hekf.runs[0].constants.thrust"],
    ),
    (
        "velocity in kilograms",
        "hekf.runs[0].columns.u={ column = \"Velocity u\", unit = \"kg\" }",
        &["hekf.runs[0].columns.u.unit"],
    ),
    (
        "zero scale",
        "polar.runs[0].columns.alpha.scale=0",
        &["polar.runs[0].columns.alpha.scale"],
    ),
    (
        "prior outside the range",
        "hekf.prior.Yvd={ initial = 1e9 }",
        &["hekf.prior.Yvd.initial"],
    ),
    ("negative mass", "vehicle.mass=-1", &["vehicle.mass"]),
    ("unknown stage key", "surge.nonsense=1", &["surge.nonsense"]),
];

/// Run names that cannot name a file: a name, the key, the length, the words.
fn name_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for (name, key, n, words) in [
        (
            "5000-character run name",
            "hekf.runs[0].name",
            5000,
            &["hekf.runs[0].name", "5000 characters"][..],
        ),
        (
            "201-character run name",
            "hekf.runs[0].name",
            201,
            &["hekf.runs[0].name", "201 characters"],
        ),
        (
            "long validation run name",
            "hekf.validation[0].name",
            300,
            &["hekf.validation[0].name"],
        ),
        (
            "long polar run name",
            "polar.runs[0].name",
            256,
            &["polar.runs[0].name"],
        ),
        (
            "long surge run name",
            "surge.runs[0].name",
            1000,
            &["surge.runs[0].name"],
        ),
    ] {
        let set = format!("{key}={}", "a".repeat(n));
        cases.extend(both(name, SPHEROID, &[&set], None, words));
    }
    cases
}

/// Places `run` refuses to write the output to, before any stage runs.
fn place_cases() -> Vec<Case> {
    let long = format!("out/{}", "n".repeat(300));
    let mut cases = Vec::new();
    for (name, out, words) in [
        (
            "an output name too long for its staging folder",
            long.as_str(),
            vec!["300 bytes long", "at most 235 bytes"],
        ),
        (
            "an output in /proc",
            "/proc/hydroid-out",
            vec!["cannot write in /proc"],
        ),
        (
            "an output in /sys",
            "/sys/kernel/hydroid-out",
            vec!["cannot write in /sys"],
        ),
        (
            "the configurations' folder",
            "configs",
            vec!["refusing", "configs"],
        ),
        (
            "an input file",
            "cfd_exports/surge_run.csv",
            vec!["refusing", "surge_run.csv"],
        ),
        (
            "below an input file",
            "cfd_exports/surge_run.csv/x",
            vec!["surge_run.csv", "not a folder"],
        ),
        (
            "a device",
            "/dev/full",
            vec!["/dev/full", "character device"],
        ),
    ] {
        cases.extend(both(name, SPHEROID, &[], Some(out), &words));
    }
    cases
}

#[test]
fn check_refuses_what_run_refuses() {
    let mut cases = name_cases();
    for (name, set, words) in SPHEROID_CASES {
        cases.extend(both(name, SPHEROID, &[set], None, words));
    }
    cases.extend(both(
        "empty column map of a nomoto run",
        "configs/nomoto.toml",
        &["hekf.runs[0].columns={}"],
        None,
        &["hekf.runs[0].columns", "none of the nomoto"],
    ));
    cases.extend(both(
        "empty column map of a captive run",
        "configs/ship_captive.toml",
        &["captive.runs[0].columns={}"],
        None,
        &["captive", "no rpm"],
    ));
    cases.extend(both(
        "a missing recorded sea",
        "configs/nomoto.toml",
        &["autopilot.disturbance_file=nope.csv"],
        None,
        &["nope.csv", "does not exist"],
    ));
    cases.extend(place_cases());
    run_table("check", cases);
}
