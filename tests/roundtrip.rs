//! Property tests of the generic reader: random tables written in random layouts come back
//! with the same names, numbers and line numbers; random junk never panics.

use hydroid::io::formats::{self, Format, FormatChoice, ReadOptions};
use proptest::prelude::*;
use std::io::Write;

#[derive(Debug, Clone, Copy)]
enum Sep {
    Comma,
    Semicolon,
    Tab,
    Spaces,
}

impl Sep {
    fn join(self, cells: &[String], pad: usize) -> String {
        match self {
            Sep::Comma => cells.join(","),
            Sep::Semicolon => cells.join(";"),
            Sep::Tab => cells.join("\t"),
            Sep::Spaces => {
                let gap = " ".repeat(pad.max(1));
                format!("{gap}{}", cells.join(&gap))
            }
        }
    }
}

/// One random table and how to write it.
#[derive(Debug, Clone)]
struct Layout {
    names: Vec<String>,
    rows: Vec<Vec<f64>>,
    sep: Sep,
    pad: usize,
    header: bool,
    quoted: bool,
    title: bool,
    /// (position among the lines, marker, text) of comment lines.
    comments: Vec<(usize, usize, String)>,
    /// Per value: write with `{:e}` instead of `{}`.
    exp: Vec<bool>,
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1.0e6..1.0e6f64,
        (-1.0..1.0f64, -300..300i32).prop_map(|(m, e)| m * 10f64.powi(e)),
        (-1000i64..1000).prop_map(|i| i as f64),
        Just(0.0),
    ]
}

fn layout() -> impl Strategy<Value = Layout> {
    (1usize..6, 1usize..25).prop_flat_map(|(ncols, nrows)| {
        (
            prop::collection::vec("[a-z][a-z0-9_]{0,6}", ncols),
            prop::collection::vec(prop::collection::vec(value(), ncols), nrows),
            prop_oneof![
                Just(Sep::Comma),
                Just(Sep::Semicolon),
                Just(Sep::Tab),
                Just(Sep::Spaces)
            ],
            1usize..4,
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
            prop::collection::vec((0usize..30, 0usize..3, "[a-z ]{0,20}"), 0..4),
            prop::collection::vec(any::<bool>(), ncols * nrows),
        )
            .prop_map(
                |(names, rows, sep, pad, header, quoted, title, comments, exp)| Layout {
                    // `q` keeps names from reading as numbers or as a time column
                    names: names
                        .iter()
                        .enumerate()
                        .map(|(j, n)| format!("q{j}{n}"))
                        .collect(),
                    rows,
                    sep,
                    pad,
                    header,
                    quoted,
                    title,
                    comments,
                    exp,
                },
            )
    })
}

/// The file text and the 1-based line of every data row.
fn write(l: &Layout) -> (String, Vec<usize>) {
    let mut lines: Vec<String> = Vec::new();
    let mut data_lines = Vec::new();
    let mut comments = l.comments.clone();
    comments.sort_by_key(|c| c.0);
    let mut next_comment = comments.iter().peekable();
    let mut emit_comments = |lines: &mut Vec<String>, pos: usize| {
        while let Some((_, marker, text)) = next_comment.next_if(|c| c.0 <= pos) {
            let m = ["#", "%", "//"][*marker];
            lines.push(format!("{m} {text}"));
        }
    };
    if l.header && l.title {
        lines.push("Run log of the free-running model".into());
    }
    emit_comments(&mut lines, 0);
    if l.header {
        let cells: Vec<String> = l
            .names
            .iter()
            .map(|n| {
                if l.quoted {
                    format!("\"{n}\"")
                } else {
                    n.clone()
                }
            })
            .collect();
        lines.push(l.sep.join(&cells, l.pad));
    }
    for (r, row) in l.rows.iter().enumerate() {
        emit_comments(&mut lines, r + 1);
        let cells: Vec<String> = row
            .iter()
            .enumerate()
            .map(|(j, v)| {
                if l.exp[r * row.len() + j] {
                    format!("{v:e}")
                } else {
                    format!("{v}")
                }
            })
            .collect();
        lines.push(l.sep.join(&cells, l.pad));
        data_lines.push(lines.len());
    }
    emit_comments(&mut lines, usize::MAX);
    (lines.join("\n") + "\n", data_lines)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn generic_tables_round_trip(l in layout()) {
        let (text, data_lines) = write(&l);
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(text.as_bytes()).unwrap();
        let options = ReadOptions {
            names: (!l.header).then(|| l.names.clone()),
            ..Default::default()
        };
        let t = formats::read(file.path(), FormatChoice::Auto, &options)
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(t.format, Format::Delimited, "{}", text);
        prop_assert_eq!(t.names(), l.names.iter().map(String::as_str).collect::<Vec<_>>(), "{}", text);
        prop_assert_eq!(&t.lines, &data_lines, "{}", text);
        for (j, c) in t.columns.iter().enumerate() {
            let want: Vec<f64> = l.rows.iter().map(|r| r[j]).collect();
            prop_assert_eq!(&c.values, &want, "column {} of\n{}", j, text);
        }
        prop_assert!(t.missing.is_empty());
    }

    #[test]
    fn junk_never_panics(text in "[0-9a-z.,;\t \n\r\"#%/()\\[\\]eE+-]{0,300}") {
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(text.as_bytes()).unwrap();
        let _ = formats::read(file.path(), FormatChoice::Auto, &ReadOptions::default());
        for f in Format::ALL {
            let _ = formats::read(file.path(), FormatChoice::Fixed(f), &ReadOptions::default());
        }
    }
}
