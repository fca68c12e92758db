//! The seas and sensors of the closed loop: the identified model's own wave states driven by
//! its process noise (the generator, seeded), or a recorded disturbance replayed from a file
//! (a reference closed loop's wave-induced yaw, or a yaw moment as a rudder-equivalent angle),
//! read at any time by linear interpolation between its samples; and the feeds, what the
//! autopilot reads of the ship.

use crate::dynamics::sim::inputs::{Input, InputSeries};
use serde::{Deserialize, Serialize};

/// What the autopilot is fed: the heading and the yaw rate it closes the loop on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Feed {
    /// The raw compass and a raw yaw-rate gyro (the model's compass and gyro outputs, which
    /// see the wave-induced yaw, with their noise).
    Raw,
    /// The raw compass and its backward difference as the yaw rate (no gyro).
    Differentiated,
    /// The wave filter's low-frequency heading psi_L and yaw rate r_L.
    Filter,
    /// An ordinary low-pass filter on the compass (second-order Butterworth below the wave
    /// band) and the backward difference of its output as the yaw rate: the filter the
    /// paper compares its EKF with ([`super::lowpass`]).
    #[serde(rename = "lowpass")]
    LowPass,
    /// The plant's own low-frequency heading and yaw rate, without noise: the ideal a wave
    /// filter aims at, for comparison (when the plant changes mid-run, its gains are
    /// re-placed on the plant's own Nomoto indices at the change).
    True,
    /// The adaptive autopilot: the online filter's psi_L and r_L, with K, 1/T and the rudder
    /// bias estimated as it steers and the gains re-placed from them.
    Adaptive,
}

impl Feed {
    /// Every feed, in the order the results list them.
    pub const ALL: [Feed; 6] = [
        Feed::Raw,
        Feed::Differentiated,
        Feed::Filter,
        Feed::LowPass,
        Feed::True,
        Feed::Adaptive,
    ];

    /// The feed's name in configurations and results (`raw`, `differentiated`, `filter`,
    /// `lowpass`, `true`, `adaptive`).
    pub fn name(self) -> &'static str {
        match self {
            Feed::Raw => "raw",
            Feed::Differentiated => "differentiated",
            Feed::Filter => "filter",
            Feed::LowPass => "lowpass",
            Feed::True => "true",
            Feed::Adaptive => "adaptive",
        }
    }

    /// The feed in words.
    pub fn describe(self) -> &'static str {
        match self {
            Feed::Raw => "raw compass and gyro",
            Feed::Differentiated => "raw compass and its difference",
            Feed::Filter => "wave filter (psi_L, r_L)",
            Feed::LowPass => "ordinary low-pass filter on the compass",
            Feed::True => "true low-frequency heading",
            Feed::Adaptive => "adaptive (online K, T; gains re-placed)",
        }
    }
}

/// What a recorded disturbance is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DisturbanceKind {
    /// Wave-induced yaw psi_H, rad: added to what the compass reads (Fossen 2011, 8.2.1:
    /// compass = psi_L + psi_H), its rate to what the gyro reads.
    WaveYaw,
    /// A yaw moment as the rudder angle that makes it, rad: added to the rudder in the
    /// plant, T r_dot + r = K (delta + delta_w - delta_0) (Fossen 2011, 7.2).
    Rudder,
    /// A yaw moment N, N m: added to the rudder in the plant as the angle that gives the same
    /// yaw acceleration about straight motion, delta_w = N / (I b_r) with I the yaw inertia
    /// (rigid and added; [`Recording::yaw_inertia`]) and b_r = d r_dot / d delta the plant's
    /// (Fossen 2011, 7.1: r_dot = (N + N_delta delta) / (I_z - N_rdot) in the linear model).
    YawMoment,
}

/// A disturbance sampled in time (SI), replayed by linear interpolation.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// What the samples are.
    pub kind: DisturbanceKind,
    /// The yaw inertia a yaw moment accelerates, kg m^2 (rigid and added; only for
    /// [`DisturbanceKind::YawMoment`]).
    pub yaw_inertia: Option<f64>,
    series: InputSeries,
}

/// Why a recording cannot drive the closed loop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecordingError {
    /// Fewer than two samples, or times not increasing, or a value not finite.
    #[error("{0}")]
    Malformed(String),
    /// The samples end (or begin) inside the closed loop's run.
    #[error(
        "the recording covers {from} to {to} s; the closed loop runs from 0 to {duration} s \
         (autopilot.duration): a disturbance is replayed, never extrapolated"
    )]
    TooShort {
        /// First sample time, s.
        from: f64,
        /// Last sample time, s.
        to: f64,
        /// The closed loop's duration, s.
        duration: f64,
    },
}

impl Recording {
    /// A recording of `kind` from sample times `t` (s, increasing) and values (SI).
    pub fn new(
        kind: DisturbanceKind,
        t: Vec<f64>,
        values: Vec<f64>,
    ) -> Result<Self, RecordingError> {
        let bad = |m: &str| Err(RecordingError::Malformed(m.to_string()));
        if t.len() < 2 || t.len() != values.len() {
            return bad("at least two samples of time and value");
        }
        if t.windows(2)
            .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return bad("times increasing from one sample to the next");
        }
        if t.iter().chain(&values).any(|v| !v.is_finite()) {
            return bad("finite times and values");
        }
        Ok(Recording {
            kind,
            yaw_inertia: None,
            series: InputSeries {
                t,
                inputs: vec![Input::Series(values)],
            },
        })
    }

    /// Refuses a recording that does not cover 0 to `duration` s.
    pub fn covers(&self, duration: f64) -> Result<(), RecordingError> {
        let (from, to) = (self.series.t[0], self.series.t[self.series.t.len() - 1]);
        // a sample time printed with a few digits may miss the end by rounding
        let slack = 1e-9 * duration.abs().max(1.0);
        if from > slack || to < duration - slack {
            return Err(RecordingError::TooShort { from, to, duration });
        }
        Ok(())
    }

    /// The disturbance at `t`, linearly interpolated between the samples.
    pub fn at(&self, t: f64) -> f64 {
        let mut out = [0.0];
        self.series.at(t, &mut out);
        out[0]
    }

    /// The RMS and the largest magnitude of its samples from 0 to `duration` s (SI).
    pub fn rms_and_peak(&self, duration: f64) -> (f64, f64) {
        let Some(Input::Series(v)) = self.series.inputs.first() else {
            return (0.0, 0.0);
        };
        let within: Vec<f64> = self
            .series
            .t
            .iter()
            .zip(v)
            .filter(|(t, _)| **t >= 0.0 && **t <= duration)
            .map(|(_, v)| *v)
            .collect();
        let n = within.len().max(1) as f64;
        let rms = (within.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        (rms, within.iter().fold(0.0, |m: f64, v| m.max(v.abs())))
    }

    /// Its rate at `t`: the central difference over `h` (a gyro's view of a recorded wave
    /// yaw; second-order accurate for a recording sampled every `h`).
    pub fn rate(&self, t: f64, h: f64) -> f64 {
        (self.at(t + h / 2.0) - self.at(t - h / 2.0)) / h
    }
}

/// Where the closed loop's disturbance comes from.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Seas {
    /// The model's own wave states driven by its process noise (seeded).
    #[default]
    Generated,
    /// A recorded disturbance; the plant then has no process noise of its own.
    Recorded(Recording),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recording_is_interpolated_and_refused_when_short() {
        let r = Recording::new(
            DisturbanceKind::WaveYaw,
            vec![0.0, 1.0, 2.0],
            vec![0.0, 2.0, 0.0],
        )
        .unwrap();
        assert!((r.at(0.25) - 0.5).abs() < 1e-12);
        assert!(r.rate(1.0, 1.0).abs() < 1e-12 && (r.rate(0.5, 1.0) - 2.0).abs() < 1e-12);
        assert!(r.covers(2.0).is_ok());
        let e = r.covers(600.0).unwrap_err().to_string();
        assert!(e.contains("covers 0 to 2 s") && e.contains("600"), "{e}");
        assert!(Recording::new(DisturbanceKind::Rudder, vec![0.0, 0.0], vec![1.0, 1.0]).is_err());
    }
}
