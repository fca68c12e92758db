//! The harness's own cases: what every earlier round already fixed, so that the properties
//! are exercised on every kind of outcome (refused, warned, fine).

use super::{refused, run_table, Case, Expect};

#[test]
fn earlier_rounds_stay_fixed() {
    let cases = vec![
        Case::new(
            "device as input",
            "inspect /dev/zero",
            refused(&["/dev/zero", "character device"]),
        ),
        Case::new(
            "device as config",
            "run /dev/zero",
            refused(&["cannot read the configuration"]),
        ),
        Case::new(
            "missing config",
            "run configs/nope.toml",
            refused(&["configs/nope.toml"]),
        ),
        Case::new(
            "out onto an input",
            "run configs/spheroid.toml --out cfd_exports",
            refused(&["refusing", "cfd_exports"]),
        ),
        Case::new(
            "out onto the config",
            "run configs/spheroid.toml --out configs/spheroid.toml",
            refused(&["refusing", "configuration"]),
        ),
        Case::new(
            "check the example",
            "check configs/spheroid.toml",
            Expect::Fine,
        ),
        Case::new(
            "inspect an export",
            "inspect cfd_exports/surge_run.csv",
            Expect::Any,
        ),
    ];
    run_table("basics", cases);
}

#[test]
fn a_run_replaces_its_own_output_but_not_a_foreign_folder() {
    let cases = vec![
        Case::new(
            "rerun into own output",
            "run configs/spheroid.toml --out out/s",
            Expect::Fine,
        )
        .setup(|d| super::copy_run_output(d, "configs/spheroid.toml", &[], "s"))
        .may_change(&["out/s"]),
        Case::new(
            "run into a foreign folder",
            "run configs/spheroid.toml --out notes",
            refused(&["refusing", "notes"]),
        )
        .setup(|d| {
            std::fs::create_dir_all(d.join("notes")).unwrap();
            std::fs::write(d.join("notes/mine.txt"), "mine").unwrap();
        }),
    ];
    run_table("basics (outputs)", cases);
}
