//! Reading a 200,000-row, 8-column export: the generic CSV reader (layout pre-scan, polars
//! parse, SI conversion, restart check) and, for comparison, the same table separated by
//! spaces (the hand tokenizer used for whitespace, Fluent and OpenFOAM files). Then other
//! shapes, to show that the time grows with the number of cells whatever the shape: one line
//! of 100,000 and of 300,000 cells, and 1,000 rows of 1,000 columns.
//!
//! `cargo bench --bench ingest`; numbers are recorded in docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hydroid::io::formats::input::Limits;
use hydroid::io::formats::{read, read_within, FormatChoice, ReadOptions};
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;

const ROWS: usize = 200_000;

/// A free-running manoeuvre log: time, then seven channels written to 9 significant digits.
/// Comma-separated with quoted headers carrying units, or space-separated with bare names.
fn table(sep: &str) -> String {
    let mut s = String::with_capacity(ROWS * 8 * 17);
    let names = [
        "time (s)",
        "x [m]",
        "y [m]",
        "heading (deg)",
        "u (m/s)",
        "v (m/s)",
        "r (deg/s)",
        "rudder (deg)",
    ];
    let header: Vec<String> = if sep == "," {
        names.iter().map(|n| format!("\"{n}\"")).collect()
    } else {
        names
            .iter()
            .map(|n| n.split(' ').next().unwrap_or(n).to_string())
            .collect()
    };
    s.push_str(&header.join(sep));
    s.push('\n');
    for k in 0..ROWS {
        let t = k as f64 * 0.01;
        let row = [
            2.0 * t,
            10.0 * (0.05 * t).sin(),
            (0.3 * t).sin() * 180.0,
            2.0 - 0.1 * (0.2 * t).cos(),
            0.3 * (0.2 * t).sin(),
            5.0 * (0.1 * t).cos(),
            if (k / 1000) % 2 == 0 { 20.0 } else { -20.0 },
        ];
        let _ = write!(s, "{t:.2}");
        for v in row {
            let _ = write!(s, "{sep}{v:.8e}");
        }
        s.push('\n');
    }
    s
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let csv = dir.path().join("log.csv");
    let ws = dir.path().join("log.dat");
    std::fs::write(&csv, table(",")).expect("write the CSV");
    std::fs::write(&ws, table("  ")).expect("write the whitespace table");
    let load = |p: &Path| {
        let t = read(p, FormatChoice::Auto, &ReadOptions::default()).expect("readable");
        assert_eq!(t.rows(), ROWS);
        assert_eq!(t.columns.len(), 8);
        t
    };
    let mut g = c.benchmark_group("ingest");
    g.sample_size(10);
    g.throughput(Throughput::Elements(ROWS as u64));
    g.bench_function("csv_200k_rows_8_cols", |b| b.iter(|| black_box(load(&csv))));
    g.bench_function("whitespace_200k_rows_8_cols", |b| {
        b.iter(|| black_box(load(&ws)))
    });
    g.finish();

    let mut g = c.benchmark_group("ingest_shapes");
    g.sample_size(10);
    // wider than the default column limit (HYDROID_MAX_COLUMNS), raised here
    let limits = Limits {
        max_columns: 300_000,
        ..Limits::default()
    };
    for (name, rows, cols) in [
        ("one_line_100k_cells", 1, 100_000),
        ("one_line_300k_cells", 1, 300_000),
        ("1000_rows_1000_cols", 1000, 1000),
    ] {
        let p = dir.path().join(format!("{name}.csv"));
        std::fs::write(&p, grid(rows, cols)).expect("write the table");
        g.throughput(Throughput::Elements((rows * cols) as u64));
        g.bench_function(name, |b| {
            b.iter(|| {
                let t = read_within(&p, FormatChoice::Auto, &ReadOptions::default(), &limits)
                    .expect("readable");
                assert_eq!((t.rows(), t.columns.len()), (rows, cols));
                black_box(t)
            })
        });
    }
    g.finish();
}

/// `rows` rows of `cols` comma-separated numbers under a header `c0,c1,...`.
fn grid(rows: usize, cols: usize) -> String {
    let mut s = String::with_capacity((rows + 1) * cols * 8);
    for j in 0..cols {
        let _ = write!(s, "{}c{j}", if j > 0 { "," } else { "" });
    }
    s.push('\n');
    for i in 0..rows {
        for j in 0..cols {
            let _ = write!(s, "{}{}.{}", if j > 0 { "," } else { "" }, j % 1000, i % 10);
        }
        s.push('\n');
    }
    s
}

criterion_group!(benches, bench);
criterion_main!(benches);
