//! Long lines, the environment's read limits and last lines cut while being written (issue
//! 48): every limit has a maximum that cannot exhaust memory, and the advice a refusal prints
//! works when followed; a last row cut inside its final number with no line end is warned of
//! (file, line and column) in every layout that reads delimited text, and a whole file that
//! merely lacks its last line end is read without a word.

use super::{refused, run_table, warned, Case, Expect};
use crate::common;
use std::path::Path;

const COLUMNS: &str = "HYDROID_MAX_COLUMNS";
const SIZE: &str = "HYDROID_MAX_INPUT_SIZE";
const LINE: &str = "HYDROID_MAX_LINE_LENGTH";

/// `hydroid inspect FILE` with `var=value`.
fn inspect_with(name: &str, file: &str, var: &str, value: &str, expect: Expect) -> Case {
    Case::new(name, &format!("inspect {file}"), expect).env(var, value)
}

/// A comma-separated file of `columns` columns (a header and two rows) at `dir/rel`.
fn wide(dir: &Path, rel: &str, columns: usize) {
    let header: Vec<String> = (0..columns).map(|i| format!("c{i}")).collect();
    let row = vec!["1"; columns].join(",");
    let text = format!("{}\n{row}\n{row}\n", header.join(","));
    std::fs::write(dir.join(rel), text).unwrap();
}

/// Values no limit takes.
const NOT_SIZES: &[(&str, &str)] = &[
    ("0", "0"),
    ("negative", "-1"),
    ("empty", ""),
    ("garbage", "lots"),
    ("float", "1e5"),
    ("hex", "0x10"),
    ("overflowing", "99999999999999999999"),
];

/// Each variable: not a size, at its maximum, just above it.
fn limits_of_each_variable() -> Vec<Case> {
    let export = "cfd_exports/surge_run.csv";
    let mut cases = Vec::new();
    for (var, max, above) in [
        (COLUMNS, "100000", "100001"),
        (SIZE, "64G", "65G"),
        (LINE, "64G", "65G"),
    ] {
        let name = |what: &str| format!("{var} {what}");
        for (what, value) in NOT_SIZES {
            let words = refused(&[var, "is not a size"]);
            cases.push(inspect_with(&name(what), export, var, value, words));
        }
        let above_words = refused(&[var, "the most it may be", max]);
        cases.extend([
            inspect_with(&name("at the maximum"), export, var, max, Expect::Fine),
            inspect_with(
                &name("just above the maximum"),
                export,
                var,
                above,
                above_words,
            ),
            // a check reads its inputs under the same limits
            Case::new(
                &name("check above"),
                "check configs/spheroid.toml",
                refused(&[var]),
            )
            .env(var, above),
        ]);
    }
    cases
}

/// Particular values: a variable, its value, what hydroid does.
fn particular_limits() -> Vec<Case> {
    let export = "cfd_exports/surge_run.csv";
    let table: [(&str, &str, &str, Expect); 9] = [
        ("columns 99999", COLUMNS, "99999", Expect::Fine),
        ("columns with spaces", COLUMNS, " 100 ", Expect::Fine),
        (
            "columns 100K",
            COLUMNS,
            "100K",
            refused(&["the most it may be"]),
        ),
        (
            "the old advice, 33554432 columns",
            COLUMNS,
            "33554432",
            refused(&["write at most HYDROID_MAX_COLUMNS=100000"]),
        ),
        (
            "columns 1",
            COLUMNS,
            "1",
            refused(&["more than the 1 columns"]),
        ),
        (
            "size 1 TiB",
            SIZE,
            "1T",
            refused(&["at most HYDROID_MAX_INPUT_SIZE=64G"]),
        ),
        (
            "size 1 KiB",
            SIZE,
            "1K",
            refused(&["larger than the 1 KiB", SIZE]),
        ),
        (
            "line 2 bytes",
            LINE,
            "2",
            refused(&["longer than 2 B", LINE]),
        ),
        ("line 1G", LINE, "1G", Expect::Fine),
    ];
    table
        .into_iter()
        .map(|(name, var, value, expect)| inspect_with(name, export, var, value, expect))
        .collect()
}

/// The advice of each refusal, followed.
fn advice_followed() -> Vec<Case> {
    let surge = common::root().join("cfd_exports/surge_run.csv");
    let size = std::fs::metadata(&surge).unwrap().len();
    // what the refusal advises for this file (`suggested_size`: whole KiB above it)
    let advised = format!("{}K", size.div_ceil(1024));
    vec![
        Case::new(
            "20000 columns",
            "inspect wide.csv",
            refused(&["HYDROID_MAX_COLUMNS=32768"]),
        )
        .setup(|d| wide(d, "wide.csv", 20_000)),
        Case::new(
            "20000 columns, advice followed",
            "inspect wide.csv",
            Expect::Fine,
        )
        .setup(|d| wide(d, "wide.csv", 20_000))
        .env(COLUMNS, "32768"),
        Case::new(
            "70000 columns",
            "inspect wide.csv",
            refused(&["HYDROID_MAX_COLUMNS=100000"]),
        )
        .setup(|d| wide(d, "wide.csv", 70_000)),
        Case::new(
            "70000 columns, advice followed",
            "inspect wide.csv",
            Expect::Fine,
        )
        .setup(|d| wide(d, "wide.csv", 70_000))
        .env(COLUMNS, "100000"),
        Case::new(
            "100000 columns, the maximum",
            "inspect wide.csv",
            Expect::Fine,
        )
        .setup(|d| wide(d, "wide.csv", 100_000))
        .env(COLUMNS, "100000"),
        Case::new(
            "200000 columns: no advice to raise",
            "inspect wide.csv",
            refused(&["no table of more than 100000 columns"]),
        )
        .setup(|d| wide(d, "wide.csv", 200_000))
        .env(COLUMNS, "100000"),
        Case::new(
            "a 64 MiB line of commas",
            "inspect commas.csv",
            refused(&["no table of more than 100000 columns"]),
        )
        .setup(|d| std::fs::write(d.join("commas.csv"), vec![b','; 64 << 20]).unwrap()),
        Case::new(
            "a 64 MiB line of commas, limits at their maxima",
            "inspect commas.csv",
            refused(&["no table of more than 100000 columns"]),
        )
        .setup(|d| std::fs::write(d.join("commas.csv"), vec![b','; 64 << 20]).unwrap())
        .env(COLUMNS, "100000")
        .env(LINE, "64G")
        .env(SIZE, "64G"),
        inspect_with(
            "size too small: the advice names this file's size",
            "cfd_exports/surge_run.csv",
            SIZE,
            "1K",
            refused(&[&format!("{SIZE}={advised} for this file")]),
        ),
        inspect_with(
            "size advice followed",
            "cfd_exports/surge_run.csv",
            SIZE,
            &advised,
            Expect::Fine,
        ),
        Case::new(
            "a line longer than 1 KiB",
            "inspect long.csv",
            refused(&["longer than 1 KiB", LINE]),
        )
        .setup(|d| {
            std::fs::write(d.join("long.csv"), format!("t,u\n0,{}\n", "1".repeat(5000))).unwrap()
        })
        .env(LINE, "1K"),
        Case::new("line advice followed", "inspect long.csv", Expect::Any)
            .setup(|d| {
                std::fs::write(d.join("long.csv"), format!("t,u\n0,{}\n", "1".repeat(5000)))
                    .unwrap()
            })
            .env(LINE, "5K"),
    ]
}

/// The text of `file` (under the repository) without its final line end, with its last
/// `cut` characters removed, written to `dir/rel`.
fn cut_copy(dir: &Path, file: &str, rel: &str, cut: usize) {
    let text = std::fs::read_to_string(common::root().join(file)).unwrap();
    let mut t = text.trim_end_matches(['\n', '\r']).to_string();
    for _ in 0..cut {
        t.pop();
    }
    std::fs::write(dir.join(rel), t).unwrap();
}

/// `inspect` of a copy of `file` cut by `cut` characters and without its last line end.
fn cut_case(file: &'static str, cut: usize, expect: Expect) -> Case {
    // the file's own name after `cut_`: its extension says its layout
    let base = Path::new(file).file_name().unwrap().to_string_lossy();
    let rel = format!("cut_{base}");
    let name = format!("{file} cut by {cut}");
    let args = format!("inspect {rel}");
    Case::new(&name, &args, expect).setup(move |d| cut_copy(d, file, &rel, cut))
}

/// Files that lose their last line end, or the end of their last number.
const FIXTURES: &[&str] = &[
    "cfd_exports/kvlcc2_turn35.csv",
    "cfd_exports/kvlcc2_captive.csv",
    "cfd_exports/turn_validation.csv",
    "cfd_exports/polar_sweep.csv",
    "cfd_exports/nomoto_zigzag_waves.csv",
    "cfd_exports/ship150_nomoto_waves.csv",
    "cfd_exports/surge_run.csv",
    "cfd_exports/turn_paper.csv",
    "cfd_exports/npsauv_zigzag_horizontal.csv",
    "cfd_exports/npsauv_zigzag_vertical.csv",
    "cfd_exports/spheroid_pmm_sway.forces.dat",
    "cfd_exports/npsauv_helix.dat",
    "tests/fixtures/formats/cfx_monitor.csv",
    "tests/fixtures/formats/cfx_post_table.csv",
    "tests/fixtures/formats/fluent_history_flowtime",
    "tests/fixtures/formats/fluent_report_flowtime_crlf.out",
    "tests/fixtures/formats/fluent_rfile_iteration.out",
    "tests/fixtures/formats/generic_comma.csv",
    "tests/fixtures/formats/generic_tab.tsv",
    "tests/fixtures/formats/generic_whitespace.dat",
    "tests/fixtures/formats/generic_semicolon_decimal_comma.csv",
    "tests/fixtures/formats/openfoam_esi_coefficient.dat",
    "tests/fixtures/formats/openfoam_legacy_forceCoeffs.dat",
    "tests/fixtures/formats/openfoam_forceCoeffs_restart.dat",
    "tests/fixtures/formats/starccm_monitor.csv",
    "tests/fixtures/formats/starccm_table_export.csv",
];

const CUT: &[&str] = &["cut off while being written"];

/// Cuts of a file's last number: the file, the characters cut, whether the value left still
/// reads as a number (a warning) or not (an error).
const CUTS: &[(&str, usize, bool)] = &[
    ("cfd_exports/kvlcc2_turn35.csv", 2, true),
    ("cfd_exports/kvlcc2_turn35.csv", 3, true),
    ("cfd_exports/kvlcc2_turn35.csv", 1, false),
    ("cfd_exports/kvlcc2_captive.csv", 4, true),
    ("cfd_exports/turn_validation.csv", 1, true),
    ("cfd_exports/polar_sweep.csv", 4, true),
    ("cfd_exports/nomoto_zigzag_waves.csv", 1, true),
    ("cfd_exports/ship150_nomoto_waves.csv", 1, true),
    ("cfd_exports/surge_run.csv", 1, true),
    ("cfd_exports/turn_paper.csv", 4, true),
    ("cfd_exports/npsauv_zigzag_horizontal.csv", 2, true),
    ("cfd_exports/npsauv_zigzag_vertical.csv", 1, true),
    ("cfd_exports/spheroid_pmm_sway.forces.dat", 3, false),
    ("cfd_exports/npsauv_helix.dat", 3, false),
    ("tests/fixtures/formats/cfx_monitor.csv", 1, true),
    ("tests/fixtures/formats/cfx_post_table.csv", 1, true),
    ("tests/fixtures/formats/fluent_history_flowtime", 1, true),
    (
        "tests/fixtures/formats/fluent_report_flowtime_crlf.out",
        1,
        true,
    ),
    ("tests/fixtures/formats/fluent_rfile_iteration.out", 3, true),
    ("tests/fixtures/formats/generic_comma.csv", 1, true),
    ("tests/fixtures/formats/generic_tab.tsv", 1, true),
    ("tests/fixtures/formats/generic_whitespace.dat", 2, false),
    (
        "tests/fixtures/formats/generic_semicolon_decimal_comma.csv",
        1,
        false,
    ),
    (
        "tests/fixtures/formats/openfoam_esi_coefficient.dat",
        1,
        true,
    ),
    (
        "tests/fixtures/formats/openfoam_legacy_forceCoeffs.dat",
        1,
        true,
    ),
    (
        "tests/fixtures/formats/openfoam_forceCoeffs_restart.dat",
        1,
        true,
    ),
    ("tests/fixtures/formats/starccm_monitor.csv", 2, true),
];

fn cut_last_lines() -> Vec<Case> {
    let mut cases: Vec<Case> = CUTS
        .iter()
        .map(|&(file, cut, reads)| {
            let expect = if reads {
                warned(&[
                    "cut off while being written",
                    "(the last) has no line end",
                    "column '",
                ])
            } else {
                refused(CUT)
            };
            cut_case(file, cut, expect)
        })
        .collect();
    cases.extend([
        // two rows: one above the last says nothing of the column's usual form
        cut_case(
            "tests/fixtures/formats/starccm_table_export.csv",
            5,
            Expect::Fine,
        ),
        // through a configuration: check says it too (console; run puts it in the report)
        Case::with_args(
            "check of a cut surge run",
            vec![
                "check".into(),
                "configs/spheroid.toml".into(),
                "--set".into(),
                "surge.runs[0].file=../cfd_exports/cut_surge_run.csv".into(),
            ],
            warned(&[
                "cut_surge_run.csv",
                "(the last) has no line end",
                "column 'Thrust'",
            ]),
        )
        .setup(|d| {
            cut_copy(
                d,
                "cfd_exports/surge_run.csv",
                "cfd_exports/cut_surge_run.csv",
                1,
            )
        }),
    ]);
    cases
}

fn whole_files_without_a_line_end() -> Vec<Case> {
    FIXTURES
        .iter()
        .map(|&f| {
            let mut c = cut_case(f, 0, Expect::Fine);
            c.name = format!("{f} without its last line end");
            c
        })
        .collect()
}

#[test]
fn limits_and_cut_lines() {
    let mut cases = limits_of_each_variable();
    cases.extend(particular_limits());
    cases.extend(advice_followed());
    cases.extend(cut_last_lines());
    cases.extend(whole_files_without_a_line_end());
    run_table("lines", cases);
}

/// The files above, whole but without their last line end: no warning of a cut (the table's
/// `Fine` only sees the exit code).
#[test]
fn a_whole_last_line_without_its_end_is_not_warned_of() {
    use hydroid::io::formats::{self, FormatChoice, ReadOptions};
    let dir = tempfile::tempdir().unwrap();
    for f in FIXTURES {
        let rel = format!(
            "whole_{}",
            Path::new(f).file_name().unwrap().to_string_lossy()
        );
        cut_copy(dir.path(), f, &rel, 0);
        let t = formats::read(
            &dir.path().join(&rel),
            FormatChoice::Auto,
            &ReadOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(
            !t.warnings.iter().any(|w| w.contains("cut off")),
            "{f}: {:?}",
            t.warnings
        );
    }
}

/// The warning of a cut last line reaches the console and the report (results.json's
/// warnings) of a run, naming the file, the line and the column.
#[test]
fn a_cut_last_line_is_in_the_run_s_warnings() {
    let example = common::example_copy();
    let d = example.path();
    cut_copy(
        d,
        "cfd_exports/surge_run.csv",
        "cfd_exports/cut_surge_run.csv",
        1,
    );
    let o = common::hydroid_in(
        d,
        &[
            "run",
            "configs/spheroid.toml",
            "--set",
            "surge.runs[0].file=../cfd_exports/cut_surge_run.csv",
            "--out",
            "out/c",
        ],
    );
    let stderr = common::text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    let said = |text: &str| {
        text.contains("cut_surge_run.csv: line 2006 (the last) has no line end")
            && text.contains("(column 'Thrust')")
    };
    assert!(said(&stderr), "{stderr}");
    let results = std::fs::read_to_string(d.join("out/c/results.json")).unwrap();
    assert!(said(&results), "no cut warning in results.json");
}
