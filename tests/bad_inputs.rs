//! Inputs that are not plain exports: paths that are not regular files (devices, pipes,
//! folders, broken links), files over the size or line limits, one very wide line, and files
//! that are tricky but valid (tests/fixtures/edge/). Every refusal is an error naming the
//! path and what it is, returned at once; nothing hangs, nothing panics.
//!
//! The broken exports themselves (cut-off lines, decimal commas ...) are in tests/bad_files.rs.

use hydroid::base::quantity::Quantity;
use hydroid::config::InputSpec;
use hydroid::io::formats::input::{self, Limits, MAX_LINE_ENV, MAX_SIZE_ENV};
use hydroid::io::formats::{self, Format, FormatChoice, ReadOptions};
use hydroid::io::record::{self, Needs};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn edge(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/edge")
        .join(name)
}

/// `formats::read` with detection; the error as text.
fn read(path: &Path) -> Result<hydroid::io::table::Table, String> {
    formats::read(path, FormatChoice::Auto, &ReadOptions::default()).map_err(|e| e.to_string())
}

/// Runs `f` on its own thread and fails the test when it has not returned within `secs`
/// (so that a read that hangs is a failure, not a stuck test run).
fn within<T: Send + 'static>(secs: u64, what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(secs))
        .unwrap_or_else(|_| panic!("{what} did not return within {secs} s"))
}

/// Every way hydroid opens a file (reader, detection, configuration, hash) refuses `path`
/// with a message containing `says`, and returns promptly.
fn refused_everywhere(path: &Path, says: &str) {
    let p = path.to_path_buf();
    let shown = path.display().to_string();
    let errors: Vec<String> = within(10, &shown, move || {
        vec![
            read(&p).err().unwrap_or_default(),
            formats::detect::detect(&p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            hydroid::app::inspect::inspect(&p, FormatChoice::Fixed(Format::Delimited))
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            hydroid::config::read(&p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            hydroid::app::pipeline::file_sha256(&p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
        ]
    });
    for (how, e) in ["read", "detect", "inspect", "config::read", "file_sha256"]
        .iter()
        .zip(errors)
    {
        assert!(
            e.contains(&shown) && e.contains(says),
            "{how} on {shown}: '{says}' missing from: {e}"
        );
    }
}

#[test]
fn character_devices_are_refused_without_reading() {
    for dev in ["/dev/zero", "/dev/urandom", "/dev/null"] {
        if Path::new(dev).exists() {
            refused_everywhere(Path::new(dev), "is a character device");
        }
    }
}

#[test]
fn a_fifo_is_refused_without_opening_it() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("export.csv");
    // Skip only where mkfifo does not exist (not a Unix system).
    match Command::new("mkfifo").arg(&fifo).status() {
        Ok(s) if s.success() => {}
        _ => return,
    }
    // Opening a FIFO for reading blocks until a writer appears: the check must come first.
    refused_everywhere(&fifo, "is a named pipe (FIFO)");
}

#[test]
fn a_folder_is_named_as_a_directory() {
    let dir = tempfile::tempdir().unwrap();
    refused_everywhere(dir.path(), "is a directory, not a file");
}

#[test]
fn missing_files_dangling_links_and_link_loops_are_told_apart() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused_everywhere(&d.join("nowhere.csv"), "file does not exist");
    #[cfg(unix)]
    {
        use std::os::unix::fs::symlink;
        symlink(d.join("gone.csv"), d.join("dangling.csv")).unwrap();
        refused_everywhere(
            &d.join("dangling.csv"),
            "which does not exist (a dangling link)",
        );
        let e = read(&d.join("dangling.csv")).unwrap_err();
        assert!(e.contains("gone.csv"), "names the missing target: {e}");

        symlink(d.join("b.csv"), d.join("a.csv")).unwrap();
        symlink(d.join("a.csv"), d.join("b.csv")).unwrap();
        refused_everywhere(&d.join("a.csv"), "is a symbolic link that loops");

        // A link to a regular file is read like the file.
        std::fs::write(d.join("real.csv"), "t,u\n0,1\n1,2\n2,3\n").unwrap();
        symlink(d.join("real.csv"), d.join("link.csv")).unwrap();
        symlink(d.join("link.csv"), d.join("link2.csv")).unwrap();
        assert_eq!(read(&d.join("link2.csv")).unwrap().rows(), 3);
    }
}

#[test]
fn an_unreadable_file_says_permission_denied() {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("locked.csv");
        std::fs::write(&p, "t,u\n0,1\n1,2\n2,3\n").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o000)).unwrap();
        if std::fs::File::open(&p).is_err() {
            refused_everywhere(&p, "permission denied");
        } else {
            // Root reads anything (CI runs as root): the binary is run as the unprivileged
            // user `nobody` instead, through util-linux's setpriv.
            refused_as_nobody(dir.path(), &p);
        }
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o644)).unwrap();
    }
}

/// `hydroid inspect FILE` and `hydroid check` of a configuration naming it, run as the user
/// `nobody`, refuse the unreadable `file` saying "permission denied" (root reads any file).
#[cfg(unix)]
fn refused_as_nobody(dir: &Path, file: &Path) {
    use std::os::unix::fs::PermissionsExt;
    let setpriv = Path::new("/usr/bin/setpriv");
    assert!(
        setpriv.exists(),
        "running as root without util-linux's setpriv: the permission test cannot run"
    );
    let as_nobody = || {
        let mut c = Command::new(setpriv);
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups", "--"]);
        c
    };
    // a root without the capability to change its user (some containers) cannot drop it:
    // said loudly, as nothing can be checked there
    if !as_nobody()
        .arg("/bin/true")
        .status()
        .is_ok_and(|s| s.success())
    {
        eprintln!("NOTE: root here cannot become nobody (setpriv failed): permission test not run");
        return;
    }
    std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        "[vehicle]\nname = \"x\"\n[surge]\nruns = [{ file = \"locked.csv\" }]\n",
    )
    .unwrap();
    std::fs::set_permissions(&config, std::fs::Permissions::from_mode(0o644)).unwrap();
    // A copy of the binary in the (world-readable) test folder: the clone's own may sit under
    // a home folder `nobody` cannot enter.
    let binary = dir.join("hydroid");
    std::fs::copy(env!("CARGO_BIN_EXE_hydroid"), &binary).unwrap();
    std::fs::set_permissions(&binary, std::fs::Permissions::from_mode(0o755)).unwrap();
    for args in [
        vec!["inspect", file.to_str().unwrap()],
        vec!["check", config.to_str().unwrap()],
    ] {
        let o = as_nobody()
            .arg(&binary)
            .args(&args)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let printed =
            String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} as nobody: {printed}");
        assert!(
            printed.contains("locked.csv") && printed.contains("permission denied"),
            "{args:?} as nobody: {printed}"
        );
    }
}

#[test]
fn a_file_over_the_size_limit_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("big.csv");
    let mut text = String::from("t,u\n");
    for k in 0..200 {
        text.push_str(&format!("{k},{}\n", k * 2));
    }
    std::fs::write(&p, &text).unwrap();
    let limits = Limits {
        max_bytes: 1024,
        ..Limits::default()
    };
    let e = formats::read_within(&p, FormatChoice::Auto, &ReadOptions::default(), &limits)
        .unwrap_err()
        .to_string();
    let size = input::format_size(text.len() as u64);
    assert!(
        e.contains("big.csv")
            && e.contains(&format!("the file is {size}, larger than the 1 KiB"))
            && e.contains(MAX_SIZE_ENV),
        "{e}"
    );
    // At the limit it reads.
    let limits = Limits {
        max_bytes: text.len() as u64,
        ..Limits::default()
    };
    let t = formats::read_within(&p, FormatChoice::Auto, &ReadOptions::default(), &limits);
    assert_eq!(t.unwrap().rows(), 200);
}

#[test]
fn an_over_long_line_is_refused_with_its_number() {
    let dir = tempfile::tempdir().unwrap();
    let limits = Limits {
        max_line_bytes: 1024,
        ..Limits::default()
    };
    for (name, end) in [("lf.csv", "\n"), ("crlf.csv", "\r\n"), ("cr.csv", "\r")] {
        let p = dir.path().join(name);
        let long = vec!["1"; 1000].join(",");
        std::fs::write(&p, ["t,u", "0,1", &long, "2,3"].join(end)).unwrap();
        let e = formats::read_within(&p, FormatChoice::Auto, &ReadOptions::default(), &limits)
            .unwrap_err();
        assert_eq!(e.place.line, Some(3), "{name}: {e}");
        let e = e.to_string();
        assert!(
            e.contains("line 3 is longer than 1 KiB") && e.contains(MAX_LINE_ENV),
            "{name}: {e}"
        );
    }
    // A file without any line end is one long line.
    let p = dir.path().join("stream.bin");
    std::fs::write(&p, vec![b'7'; 5000]).unwrap();
    let e =
        formats::read_within(&p, FormatChoice::Auto, &ReadOptions::default(), &limits).unwrap_err();
    assert_eq!(e.place.line, Some(1), "{e}");
}

/// A table wider than the column limit (10,000 by default) is refused before any line is
/// split into cells, at its line, whatever the delimiter or the layout: the structures kept
/// per column would take far more memory than the numbers (one 5 MB line took 1.8 GB).
#[test]
fn a_table_wider_than_the_column_limit_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let cells = |n: usize, sep: &str| vec!["1.5"; n].join(sep);
    let names = |n: usize| {
        (0..n)
            .map(|j| format!("c{j}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let cases: Vec<(&str, String, usize, &str)> = vec![
        ("line.csv", format!("{}\n", cells(20_000, ",")), 1, "commas"),
        (
            "semi.csv",
            format!("t;u\n1;2\n{}\n", cells(20_000, ";")),
            3,
            "semicolons",
        ),
        ("tabs.txt", format!("{}\n", cells(20_000, "\t")), 1, "tabs"),
        (
            "spaces.txt",
            format!("title\n{}\n", cells(20_000, "   ")),
            2,
            "spaces",
        ),
        (
            "header.csv",
            format!("{}\n1,2\n3,4\n", names(20_000)),
            1,
            "commas",
        ),
        (
            "forces.dat",
            format!(
                "# Time forces(pressure viscous) moment(pressure viscous)\n1 {}\n",
                "((1 2 3) (4 5 6)) ".repeat(5000)
            ),
            2,
            "spaces",
        ),
        (
            "report.out",
            format!(
                "\"title\"\n\"a\" \"b\"\n({})\n1 2\n",
                (0..20_000)
                    .map(|j| format!("\"n{j}\""))
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
            3,
            "spaces",
        ),
    ];
    for (name, text, line, delim) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let start = Instant::now();
        let e = formats::read(&p, FormatChoice::Auto, &ReadOptions::default()).unwrap_err();
        assert_eq!(e.place.line, Some(line), "{name}: {e}");
        let e = e.to_string();
        assert!(
            e.contains(&format!("separated by {delim}"))
                && e.contains("more than the 10000 columns")
                && e.contains(input::MAX_COLUMNS_ENV),
            "{name}: {e}"
        );
        assert!(start.elapsed() < Duration::from_secs(20), "{name}: slow");
    }
}

/// One line of 300,000 cells (2.6 MB), with the column limit raised to read it. Reading it
/// was quadratic in the number of columns (a duplicate-name check compared every column with
/// every earlier one: minutes for this line); now it takes about as long as 300,000 rows.
#[test]
fn one_line_of_300000_cells_reads_in_linear_time_when_the_limit_allows() {
    const N: usize = 300_000;
    let limits = Limits {
        max_columns: N as u64,
        ..Limits::default()
    };
    let read = move |p: &Path| {
        formats::read_within(p, FormatChoice::Auto, &ReadOptions::default(), &limits)
            .map_err(|e| e.to_string())
    };
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("wide.csv");
    let names: Vec<String> = (0..N).map(|j| format!("c{j}")).collect();
    let row: Vec<String> = (0..N).map(|j| format!("{}.5", j % 1000)).collect();
    std::fs::write(&p, format!("{}\n{}\n", names.join(","), row.join(","))).unwrap();
    let start = Instant::now();
    let t = within(300, "the 300,000-cell line", move || read(&p)).unwrap();
    let took = start.elapsed();
    assert_eq!(t.columns.len(), N);
    assert_eq!(t.rows(), 1);
    assert_eq!(t.columns[N - 1].name, format!("c{}", N - 1));
    assert_eq!(t.columns[1234].values, [234.5]);
    eprintln!("300,000 cells in one line: {took:?}");

    // The same number of repeated names: a count, not 300,000 warnings.
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("same.csv");
    let names = vec!["x"; N].join(",");
    let row = vec!["1"; N].join(",");
    std::fs::write(&p, format!("{names}\n{row}\n")).unwrap();
    let t = within(300, "300,000 repeated names", move || read(&p)).unwrap();
    assert!(t.warnings.len() <= 12, "{} warnings", t.warnings.len());
    assert!(
        t.warnings
            .iter()
            .any(|w| w.contains("299989 more columns repeat")),
        "{:?}",
        t.warnings
    );
}

#[test]
fn a_hash_title_above_a_csv_does_not_make_it_openfoam() {
    for name in ["hash_title.csv", "hash_units_line.csv"] {
        let p = edge(name);
        assert_eq!(
            formats::detect::detect(&p).unwrap(),
            Format::Delimited,
            "{name}"
        );
        let t = read(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(t.names(), ["time", "u", "heading"], "{name}");
        assert_eq!(t.rows(), 3);
        assert_eq!(t.time, Some(0));
    }
    let t = read(&edge("hash_title.csv")).unwrap();
    assert_eq!(t.meta("comment"), Some("Towing tank run 12, KCS 1/75"));
}

#[test]
fn a_windows_1252_header_decodes_as_windows_1252() {
    let t = read(&edge("cp1252_header.csv")).unwrap();
    // 0x96 is an en dash in Windows-1252 (a control code in Latin-1), 0xB0 a degree sign.
    assert_eq!(t.columns[1].name, "Drift \u{2013} angle");
    assert_eq!(t.columns[1].header, "Drift \u{2013} angle (°)");
    let u = t.columns[1].unit.as_ref().expect("(°) is a unit");
    assert!(u.is_degrees(), "{u:?}");
    assert!((t.columns[1].values[0] + 10f64.to_radians()).abs() < 1e-12);
    // °C is a real unit hydroid does not convert: kept, with a warning.
    assert_eq!(t.columns[3].header, "Temperature (°C)");
    assert!(
        t.warnings
            .iter()
            .any(|w| w.contains("'°C' is not converted")),
        "{:?}",
        t.warnings
    );
}

/// One name over rows of two integers: `speed` over `0,5` (decimal commas) or a title over
/// a table without header. Read as two columns, with the decimal-comma hint as a warning.
#[test]
fn one_name_over_two_integers_warns_of_decimal_commas() {
    let t = read(&edge("decimal_comma_single_column.csv")).unwrap();
    assert_eq!(t.names(), ["speed", "col2"]);
    assert!(
        t.warnings.iter().any(|w| w.contains(
            "if they are numbers such as 0,5, this file seems to use decimal commas with a \
             comma separator; export with a semicolon or point decimals"
        )),
        "{:?}",
        t.warnings
    );
}

#[test]
fn a_complete_last_line_without_a_line_end_is_fine() {
    let t = read(&edge("unterminated_complete_line.csv")).unwrap();
    assert_eq!(t.rows(), 3);
    assert_eq!(t.columns[2].values, [0.1, 0.2, 0.3]);
}

/// A polar sweep from -120 to 120 deg at two speeds: each row's angle as written. Unwrapping
/// it as if it were a heading history put the second speed at 240 to 480 deg.
#[test]
fn a_polar_sweep_keeps_its_angles_at_every_speed() {
    let p = edge("alpha_sweep_two_speeds.csv");
    let want: Vec<f64> = (0..2)
        .flat_map(|_| (-120..=120).step_by(20))
        .map(|d| f64::from(d).to_radians())
        .collect();
    let t = read(&p).unwrap();
    assert_eq!(t.columns[0].values.len(), want.len());
    for (got, w) in t.columns[0].values.iter().zip(&want) {
        assert!((got - w).abs() < 1e-12, "{:?}", t.columns[0].values);
    }
    // Through the record loader, as the polar stage asks for it.
    let spec: InputSpec = toml::from_str(
        r#"
        file = "alpha_sweep_two_speeds.csv"
        columns = { alpha = "alpha", speed = "speed", cd = "Cd", cl = "Cl", cm = "Cm" }
        "#,
    )
    .unwrap();
    let needs = Needs {
        required: &[Quantity::Alpha, Quantity::Cd, Quantity::Cl, Quantity::Cm],
        optional: &[Quantity::Speed, Quantity::Time],
        min_rows: 1,
    };
    let r = record::load(&spec, p.parent().unwrap(), &needs).unwrap();
    let alpha = r.channel(Quantity::Alpha).unwrap();
    for (got, w) in alpha.iter().zip(&want) {
        assert!((got - w).abs() < 1e-12, "{alpha:?}");
    }
    assert_eq!(r.channel(Quantity::Speed).unwrap()[13], 2.0);
}

/// Runs the binary with `args` and returns (exit code, stderr, seconds), killing it after
/// `secs` so that a hang fails the test.
fn run_binary(args: &[&str], env: &[(&str, &str)], secs: u64) -> (Option<i32>, String, f64) {
    let start = Instant::now();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hydroid"));
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd.spawn().unwrap();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            if let Some(mut s) = child.stderr.take() {
                std::io::Read::read_to_string(&mut s, &mut err).unwrap();
            }
            return (status.code(), err, start.elapsed().as_secs_f64());
        }
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("hydroid {args:?} still running after {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn the_binary_refuses_devices_at_once() {
    // `/dev/stdin` is the test's null input here: a character device too.
    for (args, says) in [
        (
            &["inspect", "/dev/zero"][..],
            "/dev/zero: is a character device",
        ),
        (
            &["inspect", "/dev/urandom"][..],
            "/dev/urandom: is a character device",
        ),
        (&["inspect", "/dev/stdin"][..], "is a character device"),
        (
            &["check", "/dev/urandom"][..],
            "/dev/urandom: cannot read the configuration",
        ),
        (
            &["run", "/dev/zero"][..],
            "/dev/zero: cannot read the configuration",
        ),
    ] {
        if !Path::new(args[1]).exists() {
            continue;
        }
        // Generous for a loaded machine; measured well under a second.
        let (code, err, secs) = run_binary(args, &[], 20);
        assert!(code.is_some_and(|c| c != 0), "{args:?}: exit {code:?}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        eprintln!("hydroid {args:?}: {secs:.2} s");
    }
}

#[test]
fn the_size_limits_are_set_from_the_environment() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("log.csv");
    std::fs::write(&p, "t,u\n".to_string() + &"0,1\n".repeat(1000)).unwrap();
    let file = p.to_str().unwrap();
    let (code, err, _) = run_binary(&["inspect", file], &[(MAX_SIZE_ENV, "1K")], 20);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("larger than the 1 KiB") && err.contains(MAX_SIZE_ENV),
        "{err}"
    );
    let (code, err, _) = run_binary(&["inspect", file], &[(MAX_LINE_ENV, "2")], 20);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("log.csv:1: line 1 is longer than 2 B"),
        "{err}"
    );
    let (code, err, _) = run_binary(&["inspect", file], &[(MAX_SIZE_ENV, "lots")], 20);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("HYDROID_MAX_INPUT_SIZE='lots' is not a size"),
        "{err}"
    );
    let (code, err, _) = run_binary(&["inspect", file], &[(MAX_SIZE_ENV, "8G")], 20);
    assert_eq!(code, Some(0), "{err}");
}
