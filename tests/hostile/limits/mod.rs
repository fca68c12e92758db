//! The configuration's magnitude limits where a user gives a quantity outside a run
//! configuration (issue 48, item 3): planner candidates and their settings (`plan.rs`), the
//! autopilot's plants (`plant.rs`) and recorded seas (`seas.rs`), `hydroid simulate`'s
//! manoeuvres (`simulate.rs`). Every absurd value is refused or warned with the key or column
//! and the unit named, never accepted silently.

use std::path::Path;

mod plan;
mod plant;
mod seas;
mod simulate;

/// Writes `text` at `rel` (relative to the case's folder), making its folder.
pub fn write(dir: &Path, rel: &str, text: &str) {
    let path = dir.join(rel);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(path, text).unwrap();
}

/// The text of `rel` in the case's folder with each `(from, to)` replaced; panics when a
/// `from` is not in it (a case that would test nothing).
pub fn edited(dir: &Path, rel: &str, edits: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(dir.join(rel)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{rel} has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    text
}

/// configs/ap.toml: the frigate of configs/nomoto.toml identified from the first 150 s of its
/// log (cfd_exports/short.csv: a second of a debug build), its autopilot fed the true heading
/// for 200 s, with `extra` appended to its `[autopilot]` section (the file's last).
pub fn autopilot(dir: &Path, extra: &str) {
    let log = std::fs::read_to_string(dir.join("cfd_exports/nomoto_zigzag_waves.csv")).unwrap();
    let short: String = log.lines().take(1501).map(|l| format!("{l}\n")).collect();
    write(dir, "cfd_exports/short.csv", &short);
    let cfg = edited(
        dir,
        "configs/nomoto.toml",
        &[
            ("nomoto_zigzag_waves.csv", "short.csv"),
            (
                "feeds = [\"raw\", \"filter\", \"lowpass\", \"true\"]",
                "feeds = [\"true\"]\nduration = 200.0",
            ),
        ],
    );
    write(dir, "configs/ap.toml", &format!("{cfg}\n{extra}\n"));
}

/// `hydroid run configs/ap.toml` with `extra` in its `[autopilot]` section
/// ([`autopilot`]).
pub fn autopilot_case(
    name: &str,
    extra: &str,
    expect: crate::hostile::Expect,
) -> crate::hostile::Case {
    let extra = extra.to_string();
    crate::hostile::Case::new(name, "run configs/ap.toml --out out/ap", expect)
        .setup(move |d| autopilot(d, &extra))
}
