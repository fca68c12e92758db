//! The report's figures, each written as SVG and PNG into `plots/`.
//!
//! Every figure family is a type implementing [`Plot`]: it says what it is ([`FigureMeta`]),
//! how large it is, and draws itself on any plotters backend, so the SVG and the PNG come
//! from the same code. Text uses the embedded DejaVu Sans (no system fonts needed), and the
//! output depends on the data only (same input, same bytes). A figure is drawn only when its
//! data exist; non-finite samples are left out of lines (they break the line), and a figure
//! with nothing finite to show is refused with an error naming it.

pub mod autopilot;
pub mod autopilot_paper;
pub mod axes;
pub mod budget;
pub mod convergence;
pub mod correlation;
pub mod manoeuvre;
pub mod nis;
pub mod panels;
pub mod polar;
pub mod runs;
pub mod states;
pub mod style;
pub mod surge;
pub mod sweep;
pub mod tracks;

use crate::app::results::RunOutput;
use crate::base::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use rayon::prelude::*;
use std::fmt;
use std::path::Path;

/// Where in the report a figure belongs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    /// The uncertainty budget, next to the comparison table.
    Budget,
    /// The static polar stage.
    Polar,
    /// The surge stage.
    Surge,
    /// The hybrid EKF stage.
    Hekf,
    /// The re-simulation of each run.
    Resim,
}

/// What a figure is.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureMeta {
    /// File stem in `plots/` (`polar`, `track_fit_1`).
    pub name: String,
    /// Short title (also the alternative text).
    pub title: String,
    /// What the figure shows and how to read it.
    pub caption: String,
    /// Where it goes in the report.
    pub section: Section,
    /// What it shows, as keys: the quantities drawn (`yaw`, `stern_planes`, as
    /// [`Quantity::key`](crate::base::quantity::Quantity::key)) and the manoeuvre measures marked
    /// (`advance`, `first_overshoot`, as in results.json); report.html writes them in the
    /// figure's `data-shows` attribute. Empty for the figures of a stage.
    pub shows: Vec<String>,
}

/// A rendered figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// What it is.
    pub meta: FigureMeta,
    /// The SVG document.
    pub svg: String,
}

impl Figure {
    /// Path of the SVG file relative to the output folder.
    pub fn svg_path(&self) -> String {
        format!("{PLOTS_DIR}/{}.svg", self.meta.name)
    }

    /// Path of the PNG file relative to the output folder.
    pub fn png_path(&self) -> String {
        format!("{PLOTS_DIR}/{}.png", self.meta.name)
    }
}

/// The folder of the figures inside the output folder.
pub const PLOTS_DIR: &str = "plots";

/// A figure that cannot be drawn, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotError(pub String);

impl PlotError {
    /// An error with a message.
    pub fn new(msg: impl Into<String>) -> Self {
        PlotError(msg.into())
    }
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError(format!("drawing failed: {e}"))
    }
}

/// A figure family.
pub trait Plot: Sync {
    /// What it is.
    fn meta(&self) -> FigureMeta;
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Draws `plot` as SVG (returned) and, with `png_dir`, as the PNG file `NAME.png` there.
pub fn render<P: Plot>(plot: &P, png_dir: Option<&Path>) -> Result<Figure> {
    let meta = plot.meta();
    let fail = |e: PlotError| Error::numerical("report", format!("figure '{}': {e}", meta.name));
    style::ensure_font().map_err(fail)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, plot.size()).into_drawing_area();
        plot.draw(&root).map_err(fail)?;
        root.present().map_err(|e| fail(e.into()))?;
    }
    if let Some(dir) = png_dir {
        let (w, h) = plot.size();
        let mut pixels = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut pixels, (w, h)).into_drawing_area();
            plot.draw(&root).map_err(fail)?;
            root.present().map_err(|e| fail(e.into()))?;
        }
        let path = dir.join(format!("{}.png", meta.name));
        let png = encode_png(&pixels, (w, h)).map_err(fail)?;
        // written here, so that a full disk is said in words with the file's name
        std::fs::write(&path, png).map_err(|e| Error::write(&path, e))?;
    }
    Ok(Figure { meta, svg })
}

/// An RGB image (8 bits a channel, rows top down) as a PNG file's bytes.
fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .and_then(|mut writer| writer.write_image_data(rgb))
        .map_err(|e| PlotError(format!("cannot encode the PNG image: {e}")))?;
    Ok(bytes)
}

/// Figures drawn at the same time (each on its own thread).
pub const FIGURES_AT_ONCE: usize = 2;

type Job<'a> = Box<dyn Fn(Option<&Path>) -> Result<Figure> + Send + Sync + 'a>;

fn job<'a, P: Plot + Send + 'a>(plot: P) -> Job<'a> {
    Box::new(move |png| render(&plot, png))
}

/// Every figure the run's data support, in report order. With `png_dir`, each figure's PNG
/// is written there as `NAME.png`.
pub fn render_all(out: &RunOutput, png_dir: Option<&Path>) -> Result<Vec<Figure>> {
    let r = &out.result;
    let mut jobs: Vec<Job> = Vec::new();
    if let Some(b) = budget::Budget::new(&r.comparison) {
        jobs.push(job(b));
    }
    if let Some(p) = &r.stages.polar {
        let word = crate::app::results::data_word(&r.inputs, "polar.").unwrap_or("CFD");
        jobs.push(job(polar::PolarFits::new(p, word)?));
    }
    if let Some(s) = &r.stages.surge {
        let word = crate::app::results::data_word(&r.inputs, "surge.").unwrap_or("CFD");
        if let Some(f) = surge::SurgeFit::new(s, word) {
            jobs.push(job(f));
        }
        if let Some(b) = surge::SurgeBins::new(s, r) {
            jobs.push(job(b));
        }
    }
    if let Some(h) = &r.stages.hekf {
        if let Some(c) = convergence::Convergence::new(h, r) {
            jobs.push(job(c));
        }
        for (i, (run, tr)) in h.runs.iter().zip(&h.traces).enumerate() {
            if let Some(n) = nis::NisPlot::new(i + 1, run, tr) {
                jobs.push(job(n));
            }
        }
        if let Some(c) = correlation::CorrelationMap::new(&h.correlation) {
            jobs.push(job(c));
        }
    }
    for run in runs::runs(out) {
        if let Some(t) = tracks::Track::new(run) {
            jobs.push(job(t));
        }
        for s in states::States::of(run) {
            jobs.push(job(s));
        }
        if let Some(m) = manoeuvre::figure(run, r.vehicle.length) {
            jobs.push(job(m));
        }
    }
    if let Some(a) = &r.autopilot {
        jobs.push(job(autopilot::Histories(a)));
        jobs.push(job(autopilot::Spectrum(a)));
        if let Some(f) = autopilot_paper::FilterError::new(a) {
            jobs.push(job(f));
        }
        jobs.push(job(autopilot_paper::CourseChange(a)));
        jobs.push(job(autopilot_paper::Rudder(a)));
    }
    let draw = || {
        jobs.par_iter()
            .map(|j| j(png_dir))
            .collect::<Result<Vec<_>>>()
    };
    // a figure holds scaled copies of its series while it is drawn: at most FIGURES_AT_ONCE
    // at a time, whatever the number of cores, so that the peak memory is what the estimate
    // says (stages::hekf::memory)
    let mut figures = match rayon::ThreadPoolBuilder::new()
        .num_threads(FIGURES_AT_ONCE)
        .build()
    {
        Ok(pool) => pool.install(draw)?,
        Err(_) => jobs
            .iter()
            .map(|j| j(png_dir))
            .collect::<Result<Vec<_>>>()?,
    };
    figures.sort_by_key(|f| f.meta.section);
    Ok(figures)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A white square.
    struct Blank;

    impl Plot for Blank {
        fn meta(&self) -> FigureMeta {
            FigureMeta {
                name: "blank".into(),
                title: "blank".into(),
                caption: String::new(),
                section: Section::Budget,
                shows: Vec::new(),
            }
        }
        fn size(&self) -> (u32, u32) {
            (20, 10)
        }
        fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
            root.fill(&WHITE)?;
            Ok(())
        }
    }

    #[test]
    fn the_png_is_written_and_a_full_disk_is_said_in_words() {
        let dir = tempfile::tempdir().unwrap();
        render(&Blank, Some(dir.path())).unwrap();
        let bytes = std::fs::read(dir.path().join("blank.png")).unwrap();
        let info = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap()
            .info()
            .clone();
        assert_eq!((info.width, info.height), (20, 10));
        // a full disk: the file is /dev/full, where every write fails with ENOSPC
        #[cfg(target_os = "linux")]
        {
            let full = tempfile::tempdir().unwrap();
            std::os::unix::fs::symlink("/dev/full", full.path().join("blank.png")).unwrap();
            let e = render(&Blank, Some(full.path())).unwrap_err().to_string();
            let path = full.path().join("blank.png");
            assert_eq!(
                e,
                format!("cannot write {}: No space left on device", path.display())
            );
        }
    }
}
