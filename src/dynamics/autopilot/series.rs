//! The time series of one closed-loop run that the paper's figures show (Dinh, Hoang & Pham
//! 2016, fig. 6-8: the heading error of the filtered against the true heading with an
//! ordinary filter and with the EKF, the heading's response to the set course, the rudder),
//! beside those the statistics use: the course ordered, the reference model's heading, the
//! true heading with and without the wave yaw, and what the EKF wave filter and the ordinary
//! low-pass filter make of the same compass, whatever the feed in the loop (observers: they
//! read the compass and the rudder and steer nothing).

use super::closed_loop::Scenario;
use super::lowpass::{default_cutoff, LowPass};
use super::sight::Indices;
use super::wave_filter::WaveFilter;
use super::Feed;
use crate::model::models::Model;

/// The folder of the output the series go into, one table per feed (`autopilot/FEED.csv`).
pub const DIR: &str = "autopilot";

/// Per-sample series of a run, every angle in rad, at the run's times.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// The course ordered (the set course: 0 before the course change, then each order).
    pub ordered: Vec<f64>,
    /// The reference model's heading psi_d, the one the heading error is taken from.
    pub reference: Vec<f64>,
    /// The plant's true heading, the wave yaw included (the compass without its noise).
    pub heading: Vec<f64>,
    /// The plant's true low-frequency heading psi_L.
    pub heading_lf: Vec<f64>,
    /// The EKF wave filter's psi_L (the feed's own for the `filter` feed; None when it could
    /// not run beside the loop).
    pub ekf: Option<Vec<f64>>,
    /// The ordinary low-pass filter's heading (the feed's own for the `lowpass` feed; None
    /// without a cut-off: no wave frequency and no `lowpass_cutoff`).
    pub lowpass: Option<Vec<f64>>,
    /// The rudder the autopilot commanded (before the steering gear), held over the same
    /// interval as the rudder angle recorded at the sample.
    pub command: Vec<f64>,
}

impl Series {
    /// The RMS of a filtered heading's error against the true low-frequency heading,
    /// sqrt(mean((psi_f - psi_L)^2)) over every sample, rad.
    pub fn error_rms(&self, filtered: &[f64]) -> f64 {
        let n = filtered.len().min(self.heading_lf.len()).max(1);
        let sum: f64 = filtered
            .iter()
            .zip(&self.heading_lf)
            .map(|(f, t)| (f - t).powi(2))
            .sum();
        (sum / n as f64).sqrt()
    }
}

/// The low-pass filter's cut-off for `s` on the identified `model` with `c`: the scenario's,
/// else a quarter of the model's wave frequency; None without either, or when it is not
/// positive and below the Nyquist frequency pi / dt (the bilinear transform maps only those
/// frequencies; Oppenheim & Schafer 7.2).
pub(super) fn cutoff<M: Model>(model: &M, c: &[f64], s: &Scenario) -> Option<f64> {
    s.lowpass_cutoff
        .or_else(|| model.wave_frequency(c).map(default_cutoff))
        .filter(|w| *w > 0.0 && *w * s.dt < std::f64::consts::PI)
}

/// The filters that run beside the loop without steering it.
pub(super) struct Observers {
    feed: Feed,
    ekf: Option<Box<WaveFilter>>,
    lowpass: Option<LowPass>,
}

impl Observers {
    /// The observers of a loop fed `feed`: the EKF wave filter unless the feed is it, the
    /// low-pass filter unless the feed is it or it has no cut-off.
    pub(super) fn new<M: Model>(
        feed: Feed,
        model: &M,
        c: &[f64],
        at: Indices,
        s: &Scenario,
    ) -> Self {
        let ekf = (feed != Feed::Filter)
            .then(|| WaveFilter::new(model, c, at, s).ok().map(Box::new))
            .flatten();
        let lowpass = (feed != Feed::LowPass)
            .then(|| cutoff(model, c, s).map(|w| LowPass::new(w, s.dt)))
            .flatten();
        Observers { feed, ekf, lowpass }
    }

    /// The series to fill for a run of `n` samples.
    pub(super) fn series(&self, n: usize) -> Series {
        let column = |on: bool| on.then(|| Vec::with_capacity(n));
        Series {
            ordered: Vec::with_capacity(n),
            reference: Vec::with_capacity(n),
            heading: Vec::with_capacity(n),
            heading_lf: Vec::with_capacity(n),
            ekf: column(self.feed == Feed::Filter || self.ekf.is_some()),
            lowpass: column(self.feed == Feed::LowPass || self.lowpass.is_some()),
            command: Vec::with_capacity(n),
        }
    }

    /// Reads sample `k` (time `t`): the `compass` with the rudder `delta` held over the
    /// interval ending at `t`; `seen` is the heading the feed gave the autopilot. Appends
    /// the EKF's and the low-pass filter's headings to `series`. An EKF that diverges beside
    /// the loop is dropped with its column (the loop goes on).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn see<M: Model>(
        &mut self,
        at: (usize, f64, f64),
        model: &M,
        c: &[f64],
        delta: f64,
        compass: f64,
        seen: f64,
        series: &mut Series,
    ) {
        let ekf = match (self.feed, self.ekf.as_mut()) {
            (Feed::Filter, _) => Some(seen),
            (_, Some(f)) => f
                .read(at, model, c, delta, compass)
                .ok()
                .map(|(psi, _)| psi),
            _ => None,
        };
        match (ekf, series.ekf.as_mut()) {
            (Some(v), Some(col)) => col.push(v),
            _ => {
                self.ekf = None;
                series.ekf = None;
            }
        }
        let low = match (self.feed, self.lowpass.as_mut()) {
            (Feed::LowPass, _) => Some(seen),
            (_, Some(f)) => Some(f.step(compass).0),
            _ => None,
        };
        if let (Some(v), Some(col)) = (low, series.lowpass.as_mut()) {
            col.push(v);
        }
    }
}
