//! Broken files under tests/fixtures/bad/: each is an error (never a panic) naming the file,
//! the line and, where it applies, the column, with what was expected.

use hydroid::io::formats::{self, Format, FormatChoice, ReadOptions};
use std::path::PathBuf;
use std::process::Command;

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/bad")
        .join(name)
}

/// One broken file and what its error must say.
struct Case {
    file: &'static str,
    /// Read as this format instead of detecting.
    format: Option<Format>,
    line: Option<usize>,
    column: Option<usize>,
    column_name: Option<&'static str>,
    /// Fragments the message must contain.
    says: &'static [&'static str],
    /// A fragment of what was expected.
    expected: &'static str,
}

const fn case(file: &'static str, line: Option<usize>, says: &'static [&'static str]) -> Case {
    Case {
        file,
        format: None,
        line,
        column: None,
        column_name: None,
        says,
        expected: "",
    }
}

const fn at(mut c: Case, column: usize, name: Option<&'static str>) -> Case {
    c.column = Some(column);
    c.column_name = name;
    c
}

const fn expecting(mut c: Case, expected: &'static str) -> Case {
    c.expected = expected;
    c
}

const CASES: &[Case] = &[
    expecting(
        case("empty.csv", None, &["the file is empty"]),
        "a header line and rows of numbers",
    ),
    expecting(
        case("blank_lines_only.csv", None, &["the file is empty"]),
        "rows of numbers",
    ),
    expecting(
        case(
            "header_only.csv",
            Some(1),
            &["no rows of numbers", "'time,u,v'", "header without data"],
        ),
        "rows of numbers",
    ),
    expecting(
        case("binary.bin", Some(1), &["not a text file", "zero byte"]),
        "a text export",
    ),
    expecting(
        case("utf16.csv", None, &["UTF-16"]),
        "save it again as UTF-8",
    ),
    expecting(
        case(
            "garbage.txt",
            Some(1),
            &["cannot tell the format", "'Lorem ipsum dolor sit amet'"],
        ),
        "openfoam-forcecoeffs",
    ),
    expecting(
        at(
            case(
                "non_numeric_cell.csv",
                Some(4),
                &["'1.2.3' is not a number"],
            ),
            3,
            Some("v"),
        ),
        "a finite number",
    ),
    expecting(
        at(
            case(
                "ragged_row.csv",
                Some(4),
                &["2 values on this line", "3 columns"],
            ),
            3,
            None,
        ),
        "3 values separated by commas (time, u, v)",
    ),
    expecting(
        at(
            case("nan_literal.csv", Some(3), &["'nan' is not a number (NaN)"]),
            2,
            Some("u"),
        ),
        "a finite number",
    ),
    expecting(
        at(
            case(
                "inf_literal_forceCoeffs.dat",
                Some(4),
                &["'inf' is infinite"],
            ),
            3,
            Some("Cd"),
        ),
        "a finite number",
    ),
    expecting(
        Case {
            column_name: Some("time"),
            ..case(
                "time_decreasing.csv",
                Some(5),
                &["time goes backwards", "from 0.2 to 0.15"],
            )
        },
        "time increasing",
    ),
    expecting(
        at(
            case("unknown_unit_cfx.csv", Some(1), &["unknown unit 'furlong'"]),
            2,
            Some("Drift"),
        ),
        "a unit such as",
    ),
    expecting(
        at(
            case(
                "unknown_unit_starccm.csv",
                Some(1),
                &["unknown unit 'furlongs/fortnight'"],
            ),
            2,
            Some("Speed Monitor: Speed"),
        ),
        "a unit such as",
    ),
    expecting(
        case(
            "unbalanced_bracket_forces.dat",
            Some(4),
            &["unbalanced brackets", "'(' at character 3 is never closed"],
        ),
        "((x y z) (x y z))",
    ),
    expecting(
        at(
            case(
                "truncated_last_line.csv",
                Some(5),
                &["2 values on this line", "cut off"],
            ),
            3,
            None,
        ),
        "3 values",
    ),
    expecting(
        at(
            case(
                "wrong_vector_components_forces.dat",
                Some(4),
                &["force viscous", "2 components instead of 3", "character 12"],
            ),
            5,
            Some("force_viscous_x"),
        ),
        "(x y z)",
    ),
    expecting(
        at(
            case("forces_non_number.dat", Some(3), &["'abc' is not a number"]),
            3,
            Some("force_pressure_y"),
        ),
        "a finite number",
    ),
    expecting(
        case(
            "sixdof_bad_angle_units.dat",
            Some(2),
            &["unknown angle unit 'gradians'"],
        ),
        "'# Angle Units : radians'",
    ),
    expecting(
        at(
            case(
                "sixdof_missing_vector.dat",
                Some(5),
                &["4 bracketed groups after the time, expected 5"],
            ),
            14,
            Some("omega_x"),
        ),
        "time (x y z)",
    ),
    expecting(
        at(
            case("fluent_ragged.out", Some(5), &["1 value on this line"]),
            2,
            None,
        ),
        "2 values separated by spaces or tabs (Iteration, drag)",
    ),
    expecting(
        at(
            case(
                "openfoam_coeffs_wrong_count.dat",
                Some(4),
                &["5 values on this line", "6 columns"],
            ),
            6,
            None,
        ),
        "Time, Cm, Cd, Cl, Cl(f), Cl(r)",
    ),
    expecting(
        at(
            case(
                "stray_quote.csv",
                Some(3),
                &["opens a quote that never closes"],
            ),
            3,
            None,
        ),
        "3 values",
    ),
    expecting(
        Case {
            format: Some(Format::Fluent),
            ..case(
                "fluent_no_names.out",
                Some(2),
                &["no line of quoted column names"],
            )
        },
        "a quoted title",
    ),
    expecting(
        case(
            "decimal_comma_header.csv",
            Some(1),
            &[
                "the header has 2 names but the rows below have 4 values",
                "decimal commas with a comma separator",
                "export with a semicolon or point decimals",
            ],
        ),
        "2 values per row separated by commas",
    ),
    expecting(
        at(
            case(
                "decimal_comma_ragged.csv",
                Some(5),
                &[
                    "5 values on this line",
                    "decimal commas with a comma separator",
                ],
            ),
            3,
            None,
        ),
        "3 values separated by commas",
    ),
    expecting(
        case(
            "decimal_comma_no_rows.csv",
            Some(2),
            &[
                "no rows of numbers",
                "decimal commas with a comma separator",
            ],
        ),
        "rows of numbers",
    ),
    expecting(
        case(
            "cut_number_point.csv",
            Some(4),
            &["ends in '0.'", "cut off while being written"],
        ),
        "a complete last line",
    ),
    expecting(
        at(
            case(
                "cut_exponent.csv",
                Some(6),
                &["'1.2e' is not a number", "cut off while being written"],
            ),
            3,
            Some("v"),
        ),
        "a finite number",
    ),
    expecting(
        at(
            case(
                "cut_row_whitespace.dat",
                Some(5),
                &["2 values on this line", "cut off while being written"],
            ),
            3,
            None,
        ),
        "3 values separated by spaces or tabs",
    ),
    expecting(
        case(
            "cut_forcecoeffs.dat",
            Some(5),
            &["ends in '5.'", "cut off while being written"],
        ),
        "a complete last line",
    ),
    expecting(
        case(
            "cut_forces_bracket.dat",
            Some(4),
            &[
                "unbalanced brackets",
                "never closed",
                "cut off while being written",
            ],
        ),
        "((x y z) (x y z))",
    ),
    expecting(
        case(
            "cut_after_delimiter.csv",
            Some(4),
            &[
                "ends in ',' with no value after it",
                "cut off while being written",
            ],
        ),
        "a complete last line",
    ),
    expecting(
        case(
            "deeply_nested_brackets.dat",
            Some(4),
            &["nests brackets more than 16 deep"],
        ),
        "((x y z) (x y z))",
    ),
];

#[test]
fn every_bad_file_is_a_precise_error() {
    for c in CASES {
        let p = path(c.file);
        let choice = c.format.map_or(FormatChoice::Auto, FormatChoice::Fixed);
        let e = match formats::read(&p, choice, &ReadOptions::default()) {
            Ok(t) => panic!("{}: read without error: {:?}", c.file, t.names()),
            Err(e) => e,
        };
        let text = e.to_string();
        assert_eq!(e.place.file, p, "{text}");
        assert!(text.contains(c.file), "names the file: {text}");
        assert_eq!(e.place.line, c.line, "line: {text}");
        if let Some(l) = c.line {
            assert!(text.contains(&format!("{}:{l}", c.file)), "{text}");
        }
        assert_eq!(e.place.column, c.column, "column: {text}");
        assert_eq!(e.place.column_name.as_deref(), c.column_name, "{text}");
        for s in c.says {
            assert!(e.message.contains(s), "'{s}' missing from: {text}");
        }
        let expected = e.expected.as_deref().unwrap_or_default();
        assert!(
            !expected.is_empty() && expected.contains(c.expected),
            "expected '{}' in: {text}",
            c.expected
        );
    }
}

#[test]
fn the_corpus_is_complete() {
    let mut files: Vec<String> = std::fs::read_dir(path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert!(files.len() >= 15);
    for f in files {
        assert!(CASES.iter().any(|c| c.file == f), "{f} has no case");
    }
}

#[test]
fn a_missing_file_and_a_directory_are_errors() {
    let e = formats::read(
        &path("no_such_file.csv"),
        FormatChoice::Auto,
        &ReadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("no_such_file.csv") && e.contains("does not exist"),
        "{e}"
    );
    let e = formats::read(&path(""), FormatChoice::Auto, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("directory"), "{e}");
}

#[test]
fn every_format_forced_on_every_bad_file_fails_cleanly() {
    // Whatever the user forces with --format, a broken file is an error, not a panic.
    for c in CASES {
        for f in Format::ALL {
            let r = formats::read(
                &path(c.file),
                FormatChoice::Fixed(f),
                &ReadOptions::default(),
            );
            if let Err(e) = r {
                assert!(e.to_string().contains(c.file), "{f} on {}: {e}", c.file);
            }
        }
    }
}

#[test]
fn the_binary_reports_bad_files_on_stderr_with_exit_code_1() {
    for (file, says) in [
        (
            "non_numeric_cell.csv",
            "non_numeric_cell.csv:4, column 3 'v'",
        ),
        ("garbage.txt", "garbage.txt:1: cannot tell the format"),
        ("empty.csv", "empty.csv: the file is empty"),
        (
            "unbalanced_bracket_forces.dat",
            "unbalanced_bracket_forces.dat:4: unbalanced brackets",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_hydroid"))
            .arg("inspect")
            .arg(path(file))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{file}: {stderr}");
        assert!(out.stdout.is_empty(), "{file}: stdout not empty");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(stderr.contains(says), "{file}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// A last row cut inside its last value still parses (`1.2` of `1.2345e+01`): read with a
/// warning naming the line when the value is written with other digits than the rows above,
/// in every layout; a complete file, with or without a last line end, has no such warning.
#[test]
fn a_last_row_cut_inside_its_last_value_is_read_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let cut = [
        (
            "cut.csv",
            "t,u\n0.00,1.2345e+01\n0.10,1.2350e+01\n0.20,1.2",
            4,
        ),
        ("cut_semi.csv", "t;u\n0,00;1,250\n0,10;1,275\n0,20;1,2", 4),
        (
            "cut.dat",
            "# t u v\n0.000 1.000 2.000\n0.100 1.100 2.100\n0.200 1.200 2.1",
            4,
        ),
        (
            "forceCoeffs.dat",
            "# Time Cm Cd Cl\n0.1 1.000e-02 2.000e-01 3.000e-01\n0.2 1.000e-02 2.000e-01 3.0\
             00e-01\n0.3 1.000e-02 2.000e-01 3.000e-0",
            4,
        ),
        (
            "cut_exponent_digits.csv",
            "t,u\n0,1.5e+01\n1,1.6e+01\n2,1.7e+0",
            4,
        ),
    ];
    for (name, text, line) in cut {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let w = t.warnings.join("\n");
        assert!(
            w.contains(&format!("line {line} (the last) has no line end"))
                && w.contains("cut off while being written"),
            "{name}: {w}"
        );
    }
    let complete = [
        ("no_end.csv", "t,u\n0.00,1.25\n0.10,1.50\n0.20,1.75"),
        ("with_end.csv", "t,u\n0.00,1.25\n0.10,1.50\n0.20,1.7\n"),
        ("general.csv", "t,u\n0,1.25\n0.1,1.5\n0.2,2"),
        ("integers.dat", "1 2\n3 4\n5 10"),
    ];
    for (name, text) in complete {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            !t.warnings.iter().any(|w| w.contains("cut off")),
            "{name}: {:?}",
            t.warnings
        );
    }
}
