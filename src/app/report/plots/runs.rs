//! The runs the re-simulation figures show: each HEKF run (fit runs, then validation runs)
//! with the data, the identified model re-simulated on it, the filter's smoothed estimate of
//! a fit run, and where its data come from.

use crate::app::resim::{ResimMetrics, ResimTrace};
use crate::app::results::RunOutput;
use crate::base::quantity::Quantity;
use crate::config::DataSource;
use crate::io::record::Record;
use crate::numerics::signal;

/// One manoeuvre with everything the figures show of it.
#[derive(Debug, Clone, Copy)]
pub struct RunView<'a> {
    /// 1-based number among the runs of its kind.
    pub index: usize,
    /// Used for identification (else validation only).
    pub fit: bool,
    /// The run's data.
    pub record: &'a Record,
    /// The model re-simulated on it.
    pub sim: &'a ResimTrace,
    /// The re-simulation's metrics.
    pub metrics: Option<&'a ResimMetrics>,
    /// Smoothed states (K x nx, in `sim.quantities` order) of a fit run.
    pub smoothed: Option<&'a [f64]>,
    /// Rows of the run per smoothed sample (`hekf.decimate`): smoothed sample j is row
    /// j * stride.
    pub stride: usize,
    /// Where the run's data come from.
    pub source: DataSource,
}

impl RunView<'_> {
    /// "fit" or "validation".
    pub fn kind(&self) -> &'static str {
        if self.fit {
            "fit"
        } else {
            "validation"
        }
    }

    /// The file stem of a figure of this run: `FAMILY_fit_1`.
    pub fn stem(&self, family: &str) -> String {
        format!("{family}_{}_{}", self.kind(), self.index)
    }

    /// "fit run 1: NAME".
    pub fn label(&self) -> String {
        format!("{} run {}: {}", self.kind(), self.index, self.record.name)
    }

    /// What the data are called: "measured" or "CFD".
    pub fn word(&self) -> &'static str {
        self.source.word()
    }

    /// The run's times.
    pub fn time(&self) -> Option<&[f64]> {
        self.record.time()
    }

    /// The measured history of `q`.
    pub fn measured(&self, q: Quantity) -> Option<&[f64]> {
        self.record.channel(q)
    }

    /// The re-simulated state `q` (None when the model has no such state).
    pub fn simulated(&self, q: Quantity) -> Option<Vec<f64>> {
        let i = self.sim.quantities.iter().position(|x| *x == q)?;
        Some(self.sim.states.iter().map(|s| s[i]).collect())
    }

    /// What the re-simulated model's sensors read of `q`: its output `q` when the model
    /// declares a measurement function with one, else its state `q`. This is what is
    /// compared with the run's measurement of `q`.
    pub fn model_reading(&self, q: Quantity) -> Option<Vec<f64>> {
        match self.sim.outputs.iter().position(|x| *x == q) {
            Some(i) => Some(self.sim.output_values.iter().map(|y| y[i]).collect()),
            None => self.simulated(q),
        }
    }

    /// The smoothed history of state `q`, one value every [`RunView::stride`] rows.
    pub fn smoothed(&self, q: Quantity) -> Option<Vec<f64>> {
        let nx = self.sim.quantities.len();
        let i = self.sim.quantities.iter().position(|x| *x == q)?;
        Some(self.smoothed?.chunks_exact(nx).map(|s| s[i]).collect())
    }

    /// Whether the model declares outputs that differ from its states (a compass reading
    /// low-frequency plus wave-induced heading).
    pub fn has_sensor_model(&self) -> bool {
        !self.sim.outputs.is_empty()
    }
}

/// The runs of `out` in report order (fit runs, then validation runs).
pub fn runs(out: &RunOutput) -> Vec<RunView<'_>> {
    let traces = out.result.stages.hekf.as_ref().map(|h| &h.traces);
    let stride = out
        .result
        .stages
        .hekf
        .as_ref()
        .map_or(1, |h| h.settings.decimate.max(1));
    let (mut n_fit, mut n_val) = (0, 0);
    out.resim_traces
        .iter()
        .enumerate()
        .map(|(i, (record, sim))| {
            let metrics = out
                .result
                .resimulation
                .get(i)
                .filter(|m| m.run == record.name);
            let fit = metrics.map_or(i < traces.map_or(0, Vec::len), |m| m.used_for_fit);
            let index = if fit {
                n_fit += 1;
                n_fit
            } else {
                n_val += 1;
                n_val
            };
            let nx = sim.quantities.len();
            let smoothed = fit
                .then(|| traces?.get(index - 1))
                .flatten()
                .and_then(|t| t.smoothed.as_deref())
                .filter(|s| nx > 0 && s.len() == nx * record.rows().div_ceil(stride));
            let source = out
                .result
                .inputs
                .iter()
                .find(|i| i.key.starts_with("hekf.") && i.name == record.name)
                .map_or_else(|| DataSource::of_format(record.format), |i| i.source);
            RunView {
                index,
                fit,
                record,
                sim,
                metrics,
                smoothed,
                stride,
                source,
            }
        })
        .collect()
}

/// A measured series with its gross outliers left out (spike cells are not data; the
/// re-simulation's RMS leaves them out too), as (time, value) points.
pub fn without_outliers(time: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    let spikes = signal::outliers(v);
    let mut skip = spikes.iter().map(|o| o.index).peekable();
    time.iter()
        .zip(v)
        .enumerate()
        .filter_map(|(k, (t, y))| {
            if skip.peek() == Some(&k) {
                skip.next();
                None
            } else {
                Some((*t, *y))
            }
        })
        .collect()
}
