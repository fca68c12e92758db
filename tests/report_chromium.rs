//! report.html rendered by headless Chromium: the comparison table and every figure are in
//! the rendered DOM, and a screenshot is a real picture.
//!
//! Without Chromium the test prints why it is skipped and passes, unless
//! HYDROID_REQUIRE_CHROMIUM=1 is set (CI sets it after installing Chromium): then it fails.

use hydroid::output::Staging;
use hydroid::report;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CANDIDATES: [&str; 4] = [
    "/usr/bin/chromium",
    "/usr/bin/chromium-browser",
    "/usr/bin/google-chrome",
    "/usr/bin/google-chrome-stable",
];

fn chromium() -> Option<PathBuf> {
    CANDIDATES.iter().map(PathBuf::from).find(|p| p.exists())
}

/// Runs Chromium headless with a fresh profile and no network activity of its own; returns
/// its standard output. Fails the test after two minutes.
fn headless(bin: &Path, args: &[String]) -> String {
    let profile = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(bin);
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
    ])
    .arg(format!("--user-data-dir={}", profile.path().display()))
    .args(args)
    .stdin(Stdio::null())
    .stdout(Stdio::piped())
    .stderr(Stdio::null());
    let mut child = cmd.spawn().expect("chromium starts");
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut s).map(|_| s)
    });
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            assert!(status.success(), "chromium failed: {status}");
            break;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("chromium did not finish in two minutes");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    reader.join().unwrap().expect("chromium's output is text")
}

#[test]
fn chromium_renders_the_report() {
    let Some(bin) = chromium() else {
        let required = std::env::var("HYDROID_REQUIRE_CHROMIUM").is_ok_and(|v| v == "1");
        assert!(
            !required,
            "HYDROID_REQUIRE_CHROMIUM=1 but no Chromium found at any of {CANDIDATES:?}"
        );
        eprintln!(
            "SKIPPED chromium_renders_the_report: no Chromium at any of {CANDIDATES:?} \
             (install it, e.g. `apt-get install chromium`, to run this test; set \
             HYDROID_REQUIRE_CHROMIUM=1 to make its absence a failure)"
        );
        return;
    };

    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/spheroid.toml");
    let loaded = hydroid::config::load(&config, &[]).unwrap();
    let output = hydroid::pipeline::run(&loaded, &mut hydroid::progress::Silent).unwrap();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("report-test")
        .join("chromium");
    // this test's own scratch folder: an earlier build's copy (perhaps without the
    // output marker of today) must not decide the outcome
    let _ = std::fs::remove_dir_all(&out);
    let staging = Staging::new(&out).unwrap();
    report::write(&staging, &loaded, &output).unwrap();
    let out = staging.commit().unwrap();
    let html = std::fs::canonicalize(out.join(report::REPORT_HTML)).unwrap();
    let url = format!("file://{}", html.display());

    // the DOM after parsing and layout
    let dom = headless(&bin, &["--dump-dom".into(), url.clone()]);
    assert!(dom.contains("<table"), "no table in the rendered DOM");
    for row in &output.result.comparison {
        assert!(
            dom.contains(&format!("<td class=\"t\">{}</td>", row.name)),
            "comparison row {} missing from the rendered DOM",
            row.name
        );
    }
    let figures: Vec<String> = std::fs::read_dir(out.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(figures.len() >= 10, "{figures:?}");
    for f in &figures {
        assert!(
            dom.contains(&format!("<figure id=\"fig-{f}\">")),
            "figure {f} missing from the rendered DOM"
        );
    }
    assert_eq!(dom.matches("<svg").count(), figures.len());

    // a screenshot of the top of the page
    let shot_dir = tempfile::tempdir().unwrap();
    let shot = shot_dir.path().join("report.png");
    headless(
        &bin,
        &[
            "--window-size=1280,2400".into(),
            format!("--screenshot={}", shot.display()),
            url,
        ],
    );
    let bytes = std::fs::read(&shot).expect("a screenshot was written");
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("the screenshot is a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (1280, 2400));
    let px = info.color_type.samples();
    let colours: BTreeSet<&[u8]> = buf[..info.buffer_size()].chunks(px).collect();
    assert!(
        colours.len() > 50,
        "a blank page? {} colours",
        colours.len()
    );
}
