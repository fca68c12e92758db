//! `[autopilot]` configuration: the heading autopilot tuned from the identified Nomoto K and
//! T and closed around the identified model in waves, fed the raw compass and gyro or the
//! wave filter's estimate (docs/models/nomoto.md).

use super::{si, Problems};
use crate::dynamics::autopilot::seas::DisturbanceKind;
use crate::dynamics::autopilot::Feed;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

fn default_omega() -> f64 {
    0.05
}
fn default_zeta() -> f64 {
    0.9
}
fn default_reference_omega() -> f64 {
    0.03
}
fn default_reference_zeta() -> f64 {
    1.0
}
fn default_duration() -> f64 {
    600.0
}
fn default_dt() -> f64 {
    0.1
}
fn default_rudder_limit() -> f64 {
    35f64.to_radians()
}
fn default_rudder_rate() -> f64 {
    2.32f64.to_radians()
}
fn default_change_at() -> f64 {
    50.0
}
fn default_feeds() -> Vec<Feed> {
    vec![Feed::Raw, Feed::Filter]
}

/// The unit of a disturbance file's values when its header states none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleUnit {
    /// Radians (SI).
    #[default]
    Rad,
    /// Degrees, converted to radians on reading.
    Deg,
}

/// `[autopilot.disturbance_columns]`: the disturbance file's columns by header name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisturbanceColumns {
    /// The time column (s, or the unit its header states).
    pub time: String,
    /// The disturbance column.
    pub disturbance: String,
}

/// `[autopilot]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AutopilotConfig {
    /// Closed-loop natural frequency w_n the PID places, rad/s (default 0.05).
    #[serde(
        default = "default_omega",
        deserialize_with = "si::value::<_, si::Rate>"
    )]
    pub omega_n: f64,
    /// Closed-loop relative damping (default 0.9).
    #[serde(default = "default_zeta")]
    pub zeta: f64,
    /// Natural frequency of the heading reference model, rad/s (default 0.03).
    #[serde(
        default = "default_reference_omega",
        deserialize_with = "si::value::<_, si::Rate>"
    )]
    pub reference_omega: f64,
    /// Damping of the reference model (default 1: no overshoot).
    #[serde(default = "default_reference_zeta")]
    pub reference_zeta: f64,
    /// The ordered course change (default 10 deg).
    #[serde(
        default = "default_course_change",
        deserialize_with = "si::value::<_, si::Angle>"
    )]
    pub course_change: f64,
    /// When it is ordered (default 50 s).
    #[serde(
        default = "default_change_at",
        deserialize_with = "si::value::<_, si::Time>"
    )]
    pub change_at: f64,
    /// Duration of each closed-loop run (default 600 s).
    #[serde(
        default = "default_duration",
        deserialize_with = "si::value::<_, si::Time>"
    )]
    pub duration: f64,
    /// Sampling interval of the compass and the autopilot (default 0.1 s).
    #[serde(default = "default_dt", deserialize_with = "si::value::<_, si::Time>")]
    pub dt: f64,
    /// Largest rudder angle (default 35 deg).
    #[serde(
        default = "default_rudder_limit",
        deserialize_with = "si::value::<_, si::Angle>"
    )]
    pub rudder_limit: f64,
    /// Steering gear rate (default 2.32 deg/s, IMO).
    #[serde(
        default = "default_rudder_rate",
        deserialize_with = "si::value::<_, si::Rate>"
    )]
    pub rudder_rate: f64,
    /// Compass noise standard deviation (required: the log's).
    #[serde(deserialize_with = "si::value::<_, si::Angle>")]
    pub compass_noise: f64,
    /// Yaw-rate gyro noise of the raw feed (default 0.01 deg/s).
    #[serde(
        default = "default_gyro_noise",
        deserialize_with = "si::value::<_, si::Rate>"
    )]
    pub gyro_noise: f64,
    /// The wave filter's process noise on the low-frequency yaw rate, rad^2/s^3 (default:
    /// compass_noise^2 (w0 / 10)^4, the filter's bandwidth a decade below the waves).
    #[serde(default)]
    pub rate_noise: Option<f64>,
    /// The ordinary low-pass filter's cut-off (the `lowpass` feed and the figures' comparison),
    /// rad/s (default: a quarter of the identified model's wave frequency w0).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Rate>",
        skip_serializing_if = "Option::is_none"
    )]
    pub lowpass_cutoff: Option<f64>,
    /// Seed of the generated waves and the sensor noise (the same for every feed; default 1).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The feeds to compare (default raw and filter).
    #[serde(default = "default_feeds")]
    pub feeds: Vec<Feed>,
    /// Time constant of the steering gear's first-order lag (default none).
    #[serde(default, deserialize_with = "si::value::<_, si::Time>")]
    pub rudder_lag: f64,
    /// A recorded disturbance replayed instead of the generated waves: a table of time (s)
    /// and the disturbance, relative to the configuration's folder.
    #[serde(default)]
    pub disturbance_file: Option<PathBuf>,
    /// What the recorded disturbance is (default the wave-induced yaw).
    #[serde(default = "default_disturbance")]
    pub disturbance: DisturbanceKind,
    /// The unit of its values when the file's header states none (default rad).
    #[serde(default)]
    pub disturbance_unit: AngleUnit,
    /// Which columns of the disturbance file hold the time and the disturbance, by header
    /// name (default: a file of exactly two columns, time first).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub disturbance_columns: Option<DisturbanceColumns>,
    /// The yaw inertia a recorded yaw moment accelerates, rigid and added (I_z - N_rdot),
    /// kg m^2 (default: the plant's vehicle izz).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Inertia>",
        skip_serializing_if = "Option::is_none"
    )]
    pub yaw_inertia: Option<f64>,
    /// The adaptive feed's settings (default: [`super::autopilot_adaptive::AdaptiveConfig`]'s).
    #[serde(default)]
    pub adaptive: super::autopilot_adaptive::AdaptiveConfig,
    /// Course orders after the course change.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub orders: Vec<super::autopilot_adaptive::CourseOrder>,
    /// The ship the autopilot steers (default: the identified model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plant: Option<super::autopilot_plant::PlantConfig>,
}

fn default_disturbance() -> DisturbanceKind {
    DisturbanceKind::WaveYaw
}

fn default_course_change() -> f64 {
    10f64.to_radians()
}
fn default_gyro_noise() -> f64 {
    0.01f64.to_radians()
}
fn default_seed() -> u64 {
    1
}

impl AutopilotConfig {
    /// Adds every problem to `p` (keys `autopilot.*`): every value within the range a heading
    /// autopilot of a real vessel can have, so that a typing or unit mistake (`omega_n =
    /// 1e9`) is refused rather than tuned into nonsense gains.
    pub fn validate(&self, p: &mut Problems) {
        self.validate_ranges(p);
        self.validate_run(p);
        if let Some(plant) = &self.plant {
            plant.validate(self.duration, p);
        }
        self.adaptive.validate(self.dt, p);
        super::autopilot_adaptive::validate_orders(&self.orders, self.change_at, self.duration, p);
    }

    /// Each tuning, sensor and steering value within a real vessel's range.
    fn validate_ranges(&self, p: &mut Problems) {
        use std::f64::consts::PI;
        let deg = PI / 180.0;
        let bandwidth = "a closed heading loop of a vessel: periods from 3 s to 17 hours";
        for (key, v, range, unit, why) in [
            ("omega_n", self.omega_n, (1e-4, 2.0), "rad/s", bandwidth),
            ("zeta", self.zeta, (0.05, 10.0), "-", "a relative damping"),
            (
                "reference_omega",
                self.reference_omega,
                (1e-4, 2.0),
                "rad/s",
                bandwidth,
            ),
            (
                "reference_zeta",
                self.reference_zeta,
                (0.05, 10.0),
                "-",
                "a relative damping",
            ),
            (
                "dt",
                self.dt,
                (1e-3, 10.0),
                "s",
                "a compass sampling interval",
            ),
            (
                "rudder_limit",
                self.rudder_limit,
                (deg, PI / 2.0),
                "rad",
                "1 to 90 deg",
            ),
            (
                "rudder_rate",
                self.rudder_rate,
                (0.1 * deg, PI / 2.0),
                "rad/s",
                "0.1 to 90 deg/s",
            ),
            (
                "compass_noise",
                self.compass_noise,
                (1e-9, 10.0 * deg),
                "rad",
                "up to 10 deg",
            ),
            (
                "gyro_noise",
                self.gyro_noise,
                (1e-12, 10.0 * deg),
                "rad/s",
                "up to 10 deg/s",
            ),
            (
                "course_change",
                self.course_change.abs(),
                (0.0, PI),
                "rad",
                "at most 180 deg",
            ),
            (
                "rate_noise",
                self.rate_noise.unwrap_or(0.0),
                (0.0, 1.0),
                "rad^2/s^3",
                "a process noise intensity",
            ),
            (
                "rudder_lag",
                self.rudder_lag,
                (0.0, 60.0),
                "s",
                "a steering gear's time constant",
            ),
        ] {
            p.in_range(&format!("autopilot.{key}"), v, range, unit, why);
        }
    }

    /// The run's length and sampling, the loop against the sampling, the feeds, the filter
    /// and the disturbance's unit.
    fn validate_run(&self, p: &mut Problems) {
        p.positive("autopilot.duration", self.duration, "s");
        if self.dt > 0.0 && self.duration / self.dt > 1e6 {
            p.add(
                "autopilot.duration",
                "at most a million samples per closed-loop run (duration / dt)",
            );
        }
        // ten samples per period of the closed loop at least, or the sampled PID is not the
        // one placed
        let placed = (1e-4..=2.0).contains(&self.omega_n) && (1e-3..=10.0).contains(&self.dt);
        if placed && self.omega_n * self.dt > 0.6 {
            p.add(
                "autopilot.omega_n",
                format!(
                    "{} rad/s is too fast for the compass sampled every {} s: at most 0.6 / dt \
                     = {} rad/s (ten samples per period of the loop)",
                    self.omega_n,
                    self.dt,
                    crate::base::numfmt::num(0.6 / self.dt)
                ),
            );
        }
        if self.change_at < 0.0 || self.change_at > self.duration {
            p.add("autopilot.change_at", "within the run, 0 to duration");
        }
        let mut seen = Vec::new();
        for f in &self.feeds {
            if seen.contains(f) {
                p.add(
                    "autopilot.feeds",
                    format!("{} twice: each feed once", f.name()),
                );
            }
            seen.push(*f);
        }
        if let Some(w) = self.lowpass_cutoff {
            self.validate_cutoff(w, p);
        }
        if let Some(i) = self.yaw_inertia {
            p.positive("autopilot.yaw_inertia", i, "kg m^2");
        }
        if self.disturbance == DisturbanceKind::YawMoment && self.disturbance_unit != AngleUnit::Rad
        {
            p.add(
                "autopilot.disturbance_unit",
                "a yaw moment is read in N m (or the unit its header states): rad or deg are \
                 for a wave yaw or a rudder angle",
            );
        }
        if self.feeds.is_empty() {
            p.add(
                "autopilot.feeds",
                "at least one of raw, differentiated, filter, lowpass, true, adaptive",
            );
        }
    }

    /// The low-pass filter's cut-off `w`: a heading filter's (1e-4 to 2 rad/s, as `omega_n`)
    /// and below the Nyquist frequency pi / dt of the compass sampling.
    fn validate_cutoff(&self, w: f64, p: &mut Problems) {
        let why = "a heading filter's cut-off, below the waves";
        p.in_range("autopilot.lowpass_cutoff", w, (1e-4, 2.0), "rad/s", why);
        let nyquist = std::f64::consts::PI / self.dt;
        if self.dt > 0.0 && w >= nyquist {
            p.add(
                "autopilot.lowpass_cutoff",
                format!(
                    "{w} rad/s is above the Nyquist frequency pi / dt = {} rad/s of the compass \
                     sampled every {} s",
                    crate::base::numfmt::num(nyquist),
                    self.dt
                ),
            );
        }
    }
}
