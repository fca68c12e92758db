//! Memory in proportion to the cells, whatever the shape of the file (issue 24, item 1): a
//! 3 MB export of any shape (one long line, a long header, thousands of columns, one column
//! of a million rows, a wide Fluent or OpenFOAM header) is read or refused within 200 MB of
//! peak resident memory. Before, one 5 MB line took 1.8 GB (about 700 bytes per cell).
//!
//! Each file is read in a fresh process (this test run again on one file) that reports its
//! peak resident memory, `VmHWM` of /proc/self/status (Linux; elsewhere the test only checks
//! that every file is read or refused).

use hydroid::io::formats::FormatChoice;
use std::path::Path;
use std::process::Command;

/// 3 MB, the size the bound is stated for.
const SIZE: usize = 3_000_000;
/// The bound on the peak resident memory of a process that reads one file, bytes.
const BOUND: u64 = 200 << 20;
/// Set in the child process: the file it reads.
const CHILD: &str = "HYDROID_MEMORY_BOUND_FILE";
/// This test's name, to run it again in a child process.
const NAME: &str = "a_3_mb_file_of_any_shape_is_read_or_refused_within_200_mb";

/// `VmHWM` (peak resident memory) of this process, bytes; `None` off Linux.
fn peak() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb << 10)
}

/// A file of about [`SIZE`] bytes: `head`, then `row(k)` lines until the size is reached.
fn fill(head: &str, row: impl Fn(usize) -> String) -> String {
    let mut s = String::with_capacity(SIZE + 4096);
    s.push_str(head);
    let mut k = 0;
    while s.len() < SIZE {
        s.push_str(&row(k));
        s.push('\n');
        k += 1;
    }
    s
}

fn shapes() -> Vec<(&'static str, String)> {
    let ones = |n: usize, sep: &str| vec!["1"; n].join(sep);
    let names = |n: usize| (0..n).map(|j| format!("c{j}")).collect::<Vec<_>>();
    vec![
        ("one_line_commas.csv", format!("{}\n", ones(SIZE / 2, ","))),
        ("one_line_spaces.txt", format!("{}\n", ones(SIZE / 2, " "))),
        ("one_line_no_end.csv", ones(SIZE / 2, ";")),
        (
            "long_header.csv",
            format!("{}\n1,2\n", names(SIZE / 8).join(",")),
        ),
        (
            "columns_10000.csv",
            fill(&format!("{}\n", names(10_000).join(",")), |_| {
                ones(10_000, ",")
            }),
        ),
        ("columns_1024.csv", fill("", |_| ones(1024, ","))),
        ("columns_4096_spaces.txt", fill("", |_| ones(4096, " "))),
        ("one_column.csv", fill("t\n", |k| k.to_string())),
        ("one_cell_rows.txt", fill("", |_| "1".into())),
        ("two_columns.csv", fill("t,u\n", |k| format!("{k},1"))),
        (
            "empty_cells.csv",
            fill("t,u\n1,2\n2,3\n3,4\n", |_| ",".into()),
        ),
        (
            "fluent.out",
            format!(
                "\"title\"\n\"a\" \"b\"\n({})\n{}\n",
                names(SIZE / 16)
                    .iter()
                    .map(|n| format!("\"{n}\""))
                    .collect::<Vec<_>>()
                    .join(" "),
                ones(SIZE / 16, " ")
            ),
        ),
        (
            "forces.dat",
            format!(
                "# Time forces(pressure viscous) moment(pressure viscous)\n1 {}\n",
                "((1 2 3) (4 5 6)) ".repeat(SIZE / 20)
            ),
        ),
        (
            "cfx.csv",
            format!(
                "[Data]\n{}\n{}\n",
                names(SIZE / 16)
                    .iter()
                    .map(|n| format!("{n} [ m ]"))
                    .collect::<Vec<_>>()
                    .join(","),
                ones(SIZE / 16, ",")
            ),
        ),
        (
            "title_words.txt",
            format!("{}\n1 2\n3 4\n5 6\n", vec!["word"; SIZE / 5].join(" ")),
        ),
    ]
}

#[test]
fn a_3_mb_file_of_any_shape_is_read_or_refused_within_200_mb() {
    if let Some(file) = std::env::var_os(CHILD) {
        // the child: read one file, say what came of it and the peak
        let outcome = read(Path::new(&file));
        println!("outcome: {outcome}");
        println!("peak: {}", peak().map_or(-1, |p| p as i64));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut report = Vec::new();
    for (name, text) in shapes() {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let out = Command::new(std::env::current_exe().unwrap())
            .args([NAME, "--exact", "--nocapture", "--test-threads=1"])
            .env(CHILD, &p)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let field = |key: &str| {
            // libtest writes "test NAME ... " without a line end before the child's output
            stdout
                .split(key)
                .nth(1)
                .and_then(|rest| rest.lines().next())
                .unwrap_or_else(|| panic!("{name}: no '{key}' from the child: {stdout}"))
                .to_string()
        };
        assert!(out.status.success(), "{name}: {stdout}");
        let (outcome, peak): (String, i64) = (field("outcome: "), field("peak: ").parse().unwrap());
        report.push(format!("{name}: {} MB ({outcome})", peak >> 20));
        assert!(
            peak < BOUND as i64,
            "{name}: {} MB at the peak ({outcome})",
            peak >> 20
        );
    }
    eprintln!("{}", report.join("\n"));
}

/// What `hydroid inspect` does with the file: "read" or the error.
fn read(p: &Path) -> String {
    match hydroid::app::inspect::inspect(p, FormatChoice::Auto) {
        Ok(r) => format!("read, {} columns", r.columns.len()),
        Err(e) => {
            let e = e.to_string();
            assert!(
                e.contains(p.file_name().unwrap().to_str().unwrap()),
                "an error names the file: {e}"
            );
            e.chars().take(100).collect()
        }
    }
}
