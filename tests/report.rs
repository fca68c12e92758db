//! The report on the bundled example: every figure as well-formed SVG and decodable PNG,
//! report.md and report.html complete and self-contained, results.json valid against
//! docs/results.schema.json, and the whole output byte-identical from run to run.
//!
//! The pipeline runs twice (two output folders, for the determinism check); every other test
//! reuses the first run.

use hydroid::app::report::{self, plots, table};
use hydroid::app::results::RunOutput;
use hydroid::config::LoadedConfig;
use hydroid::io::output::Staging;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

struct Run {
    loaded: LoadedConfig,
    output: RunOutput,
    dir: PathBuf,
}

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/spheroid.toml")
}

fn run_into(name: &str) -> Run {
    let loaded = hydroid::config::load(&example(), &[]).expect("the example loads");
    let output = hydroid::app::pipeline::run(&loaded, &mut hydroid::base::progress::Silent)
        .expect("the example runs");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("report-test")
        .join(name);
    // this test's own scratch folder: an earlier build's copy (perhaps without the
    // output marker of today) must not decide the outcome
    let _ = std::fs::remove_dir_all(&dir);
    let staging = Staging::new(&dir).unwrap();
    report::write(&staging, &loaded, &output).expect("the report is written");
    let dir = staging.commit().unwrap();
    Run {
        loaded,
        output,
        dir,
    }
}

fn first() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| run_into("first"))
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The figure names of the bundled example: polar, surge and HEKF stages, one fit run and
/// one validation run.
const EXPECTED: [&str; 11] = [
    "uncertainty_budget",
    "polar",
    "surge_fit",
    "surge_bins",
    "hekf_convergence",
    "nis_fit_1",
    "hekf_correlation",
    "track_fit_1",
    "states_fit_1",
    "track_validation_1",
    "states_validation_1",
];

fn stems(dir: &Path, ext: &str) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect()
}

/// Width and height attributes of an SVG's root element.
fn svg_size(doc: &roxmltree::Document) -> (u32, u32) {
    let root = doc.root_element();
    let get = |a: &str| root.attribute(a).unwrap().parse::<u32>().unwrap();
    (get("width"), get("height"))
}

#[test]
fn every_figure_is_written_as_svg_and_png() {
    let plots = first().dir.join("plots");
    let want: BTreeSet<String> = EXPECTED.iter().map(|s| s.to_string()).collect();
    assert_eq!(stems(&plots, "svg"), want);
    assert_eq!(stems(&plots, "png"), want);
    for name in EXPECTED {
        let svg = read(&plots.join(format!("{name}.svg")));
        assert!(svg.contains("<svg"), "{name}");
        let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{name}.svg: {e}"));
        assert_eq!(doc.root_element().tag_name().name(), "svg");
        assert!(
            doc.root_element().attribute("viewBox").is_some(),
            "{name}: scalable"
        );
        let texts = doc.descendants().filter(|n| n.has_tag_name("text")).count();
        assert!(texts >= 5, "{name}: {texts} text elements");
        let (w, h) = svg_size(&doc);

        let bytes = std::fs::read(plots.join(format!("{name}.png"))).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder
            .read_info()
            .unwrap_or_else(|e| panic!("{name}.png: {e}"));
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(
            (info.width, info.height),
            (w, h),
            "{name}: PNG and SVG agree"
        );
        assert!(
            (600..=3000).contains(&w) && (500..=3000).contains(&h),
            "{name}: {w}x{h}"
        );
        // something is drawn: many distinct colours, and the corners are the white page
        let px = info.color_type.samples();
        let colours: BTreeSet<&[u8]> = buf[..info.buffer_size()].chunks(px).collect();
        assert!(colours.len() > 20, "{name}: {} colours", colours.len());
        assert_eq!(&buf[..3], &[255, 255, 255], "{name}: white background");
    }
}

#[test]
fn figures_say_what_they_show() {
    let plots = first().dir.join("plots");
    let has = |name: &str, what: &[&str]| {
        let svg = read(&plots.join(format!("{name}.svg")));
        for w in what {
            assert!(svg.contains(w), "{name}.svg lacks '{w}'");
        }
    };
    has(
        "polar",
        &[
            "drift angle α (deg)",
            "C_D (-)",
            "C_L (-)",
            "C_M (-)",
            "pooled fit",
        ],
    );
    has(
        "surge_fit",
        &["time t (s)", "surge speed u (m/s)", "u − û (mm/s)"],
    );
    has(
        "surge_bins",
        &["X_udot (kg)", "Fossen analytic", "Rasekh &amp; Mahdi 2020"],
    );
    has(
        "hekf_convergence",
        &[
            "Yvd (kg)",
            "Nrr (kg m^2)",
            "pass 3",
            "Rasekh &amp; Mahdi 2020",
        ],
    );
    has("nis_fit_1", &["95 % bounds", "running mean of NIS (-)"]);
    has("hekf_correlation", &["Yvd", "Nvv", "\u{2212}1.00"]);
    has(
        "track_validation_1",
        &["east y (m)", "north x (m)", "final position error"],
    );
    has(
        "states_fit_1",
        &["heading ψ (deg)", "yaw rate r (deg/s)", "smoothed estimate"],
    );
    // the thrust the validation run steps is drawn under the surge speed it drives
    has(
        "states_validation_1",
        &["surge u (m/s)", "sway v (m/s)", "thrust T (N)", "CFD"],
    );
    has(
        "uncertainty_budget",
        &["from polar", "from hekf", "Nrd (kg m^2)"],
    );
}

#[test]
fn report_md_links_every_figure_and_holds_the_comparison_table() {
    let r = first();
    let md = read(&r.dir.join(report::REPORT_MD));
    for name in EXPECTED {
        assert!(
            md.contains(&format!("](plots/{name}.svg)")),
            "{name} not linked"
        );
        assert!(
            md.contains(&format!("(plots/{name}.png)")),
            "{name} PNG not linked"
        );
    }
    assert!(md.contains(&table::markdown(&r.output.result)));
    for heading in [
        "## Vehicle and reference quantities",
        "## What ran",
        "## Coefficients",
        "### Uncertainty budget",
        "## Static polars",
        "## Surge run",
        "## Hybrid extended Kalman filter",
        "### Tuning choices",
        "### Measurement noise",
        "### Innovation consistency (NIS)",
        "## Re-simulation",
        "## Warnings",
        "## Files",
    ] {
        assert!(md.contains(&format!("\n{heading}\n")), "missing {heading}");
    }
    // the reference quantities and the resimulation metrics are there
    assert!(md.contains("| reference area (force coefficients) | A\\_ref | 0.03142 | m^2 |"));
    assert!(md.contains("| validation turn (u0 = 2 m/s, 15 N then 30 N) | validation |"));
    // every warning of the run appears
    let surge = r.output.result.stages.surge.as_ref().unwrap();
    assert!(!surge.warnings.is_empty());
    for w in &surge.warnings {
        assert!(
            md.contains(&markdown_escaped(&w.message)),
            "warning missing: {w}"
        );
    }
}

/// `s` as CommonMark needs it in running text: a backslash before each ASCII punctuation
/// character that is markup (CommonMark 0.31, section 2.4, "Backslash escapes"), line breaks
/// as spaces; written here, not taken from hydroid, so the test checks the report's escaping.
fn markdown_escaped(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '|' | '#' => format!("\\{c}"),
            '\n' | '\r' => " ".to_string(),
            c => c.to_string(),
        })
        .collect()
}

#[test]
fn report_html_is_self_contained_and_complete() {
    let r = first();
    let html = read(&r.dir.join(report::REPORT_HTML));
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert_eq!(html.matches("<svg").count(), EXPECTED.len());
    for name in EXPECTED {
        assert!(
            html.contains(&format!("<figure id=\"fig-{name}\"")),
            "{name}"
        );
    }
    for bad in ["http://", "https://", "<script", "<link", "@import", "url("] {
        assert!(!html.contains(bad), "report.html contains {bad}");
    }
    for row in &r.output.result.comparison {
        assert!(
            html.contains(&format!("<td class=\"t\">{}</td>", row.name)),
            "row {} missing",
            row.name
        );
    }
    assert!(html.contains("<th>Rasekh &amp; Mahdi 2020</th>"));
    // every inline SVG is well-formed XML on its own
    let mut rest = html.as_str();
    while let Some(start) = rest.find("<svg") {
        let end = rest[start..].find("</svg>").unwrap() + start + 6;
        roxmltree::Document::parse(&rest[start..end]).unwrap();
        rest = &rest[end..];
    }
}

#[test]
fn results_json_matches_its_schema() {
    let schema: serde_json::Value = serde_json::from_str(&read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/results.schema.json"),
    ))
    .unwrap();
    let validator = jsonschema::draft202012::new(&schema).expect("the schema is valid");
    let results: serde_json::Value =
        serde_json::from_str(&read(&first().dir.join(report::RESULTS_JSON))).unwrap();
    let errors: Vec<String> = validator
        .iter_errors(&results)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");

    // the schema has teeth: a NaN written as null, a missing field, an unknown field and a
    // wrong version each fail
    let mut broken = results.clone();
    broken["coefficients"][0]["value"] = serde_json::Value::Null;
    assert!(!validator.is_valid(&broken));
    let mut broken = results.clone();
    broken["stages"]["hekf"]
        .as_object_mut()
        .unwrap()
        .remove("settings");
    assert!(!validator.is_valid(&broken));
    let mut broken = results.clone();
    broken["resimulation"][0]["undocumented"] = serde_json::json!(1);
    assert!(!validator.is_valid(&broken));
    let mut broken = results.clone();
    broken["schema"] = serde_json::json!("hydroid-results/3");
    assert!(!validator.is_valid(&broken));
    let mut broken = results;
    broken["inputs"][0]["sha256"] = serde_json::json!("not a hash");
    assert!(!validator.is_valid(&broken));
}

#[test]
fn a_second_run_gives_the_same_bytes() {
    let a = first();
    let b = run_into("second");
    let mut files: Vec<PathBuf> = [
        report::RESULTS_JSON,
        report::COEFFICIENTS_CSV,
        report::REPORT_MD,
        report::REPORT_HTML,
    ]
    .iter()
    .map(PathBuf::from)
    .collect();
    for name in EXPECTED {
        files.push(Path::new("plots").join(format!("{name}.svg")));
        files.push(Path::new("plots").join(format!("{name}.png")));
    }
    for f in files {
        let (x, y) = (
            std::fs::read(a.dir.join(&f)).unwrap(),
            std::fs::read(b.dir.join(&f)).unwrap(),
        );
        assert!(x == y, "{} differs between two runs", f.display());
    }
}

#[test]
fn without_plots_only_report_md_is_written() {
    let r = first();
    let mut loaded = r.loaded.clone();
    loaded.config.output.plots = false;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("report-test")
        .join("no-plots");
    // this test's own scratch folder: an earlier build's copy (perhaps without the
    // output marker of today) must not decide the outcome
    let _ = std::fs::remove_dir_all(&dir);
    let staging = Staging::new(&dir).unwrap();
    report::write(&staging, &loaded, &r.output).unwrap();
    let dir = staging.commit().unwrap();
    assert!(!dir.join("plots").exists());
    assert!(!dir.join(report::REPORT_HTML).exists());
    for f in [
        report::RESULTS_JSON,
        report::COEFFICIENTS_CSV,
        report::REPORT_MD,
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let md = read(&dir.join(report::REPORT_MD));
    assert!(!md.contains("!["), "no figure in report.md");
    assert!(md.contains("output.plots = false"));
    assert!(md.contains(&table::markdown(&r.output.result)));
}

#[test]
fn figures_follow_the_data() {
    let mut out = first().output.clone();
    out.result.stages.polar = None;
    out.result.stages.surge = None;
    let names: Vec<String> = plots::render_all(&out, None)
        .unwrap()
        .into_iter()
        .map(|f| f.meta.name)
        .collect();
    assert!(
        !names.iter().any(|n| n == "polar" || n.starts_with("surge")),
        "{names:?}"
    );
    assert!(names.iter().any(|n| n == "hekf_convergence"));

    out.result.stages.hekf = None;
    out.resim_traces.clear();
    out.result.resimulation.clear();
    let names: Vec<String> = plots::render_all(&out, None)
        .unwrap()
        .into_iter()
        .map(|f| f.meta.name)
        .collect();
    assert_eq!(names, vec!["uncertainty_budget"]);
}

#[test]
fn non_finite_samples_are_skipped_and_empty_data_refused() {
    let mut out = first().output.clone();
    // a few NaN samples: drawn around, never as NaN
    let surge = out.result.stages.surge.as_mut().unwrap();
    surge.residuals[0].u[10] = f64::NAN;
    surge.residuals[0].residual[11] = f64::INFINITY;
    out.result.stages.hekf.as_mut().unwrap().traces[0].nis[5] = f64::NAN;
    let figs = plots::render_all(&out, None).unwrap();
    for f in &figs {
        assert!(!f.svg.contains("NaN"), "{}", f.meta.name);
        roxmltree::Document::parse(&f.svg).unwrap();
    }
    // nothing finite at all: a clear error naming the figure
    let polar = out.result.stages.polar.as_mut().unwrap();
    for p in &mut polar.points {
        p.alpha = f64::NAN;
    }
    let e = plots::render_all(&out, None).unwrap_err().to_string();
    assert!(
        e.contains("figure 'polar'") && e.contains("no finite value"),
        "{e}"
    );
}

#[test]
fn polar_curves_are_the_stage_fits() {
    let polar = first().output.result.stages.polar.as_ref().unwrap();
    for fit in [&polar.pooled.drag, &polar.pooled.lift, &polar.pooled.moment] {
        assert!(!fit.residuals.is_empty());
        for r in &fit.residuals {
            let f = plots::polar::eval(fit, r.alpha).unwrap();
            assert!(
                (f - r.fitted).abs() <= 1e-12 * (1.0 + r.fitted.abs()),
                "{f} vs {}",
                r.fitted
            );
        }
    }
}
