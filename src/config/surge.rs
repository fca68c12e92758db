//! `[surge]` configuration.

use super::{si, yes, Config, InputSpec, Problems};
use serde::{Deserialize, Serialize};

/// `[surge]` configuration (see docs/stages.md for every key with an example).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurgeConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// Straight-line runs (1 DOF, surge only): `time`, `u`, and `thrust` (column or constant)
    /// or `fx`, depending on `drag_from`.
    pub runs: Vec<InputSpec>,
    /// Where the axial drag comes from: `coefficients` (X_uu u|u| with X_uu known from the
    /// polar stage or `[coefficients]`, plus the thrust) or `force` (the exported axial fluid
    /// force `fx`, from which X_uu and X_udot are fitted together).
    #[serde(default)]
    pub drag_from: DragFrom,
    /// Ignore samples before this time, s (e.g. a start-up transient).
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Time>",
        skip_serializing_if = "Option::is_none"
    )]
    pub t_start: Option<f64>,
    /// Ignore samples after this time, s.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Time>",
        skip_serializing_if = "Option::is_none"
    )]
    pub t_end: Option<f64>,
    /// Number of equal-width speed bins between the lowest and highest speed of the runs
    /// (default 4; ignored when `speed_bin_edges` is given), -.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_bins: Option<usize>,
    /// Explicit speed bin edges, m/s, increasing.
    #[serde(
        default,
        deserialize_with = "si::list::<_, si::Speed>",
        skip_serializing_if = "Option::is_none"
    )]
    pub speed_bin_edges: Option<Vec<f64>>,
    /// Fit differences over non-overlapping windows of this length, s, instead of the whole
    /// integral: needed when an integrated column is noisy (the `fx` force, or a fluctuating
    /// `thrust` column), whose noise the running integral accumulates into a random walk.
    /// Default: the whole integral for `coefficients`, 0.5 s for `force`.
    #[serde(
        default,
        deserialize_with = "si::option::<_, si::Time>",
        skip_serializing_if = "Option::is_none"
    )]
    pub window: Option<f64>,
    /// Fewest consecutive samples for a stretch of a run to count in a speed bin (default 20), -.
    #[serde(default = "default_min_bin_samples")]
    pub min_bin_samples: usize,
}

fn default_min_bin_samples() -> usize {
    20
}

/// Default window of the `force` fit, s.
pub const DEFAULT_FORCE_WINDOW: f64 = 0.5;

/// Default number of speed bins.
pub const DEFAULT_SPEED_BINS: usize = 4;

/// Where the surge stage's drag term comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DragFrom {
    /// X_uu from the coefficients known so far; the run needs `thrust`.
    #[default]
    Coefficients,
    /// The exported axial fluid force `fx` (N, body x, pressure + viscous: it includes the
    /// fluid's inertial reaction X_udot u_dot); X_uu is fitted with X_udot.
    Force,
}

impl SurgeConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, _config: &Config, p: &mut Problems) {
        if self.runs.is_empty() {
            p.add("surge.runs", "no run to fit");
        }
        p.inputs(&self.inputs());
        if let Some(t) = self.t_start {
            p.finite("surge.t_start", t);
        }
        if let Some(t) = self.t_end {
            p.finite("surge.t_end", t);
        }
        if let (Some(a), Some(b)) = (self.t_start, self.t_end) {
            if a >= b {
                p.add(
                    "surge.t_end",
                    format!("t_end ({b} s) must be later than t_start ({a} s)"),
                );
            }
        }
        if let Some(w) = self.window {
            p.positive("surge.window", w, "s");
        }
        if let Some(n) = self.speed_bins {
            p.count_within("surge.speed_bins", n as u64, 1, 100, "");
            if self.speed_bin_edges.is_some() {
                p.add(
                    "surge.speed_bins",
                    "give either speed_bins or speed_bin_edges, not both",
                );
            }
        }
        if let Some(edges) = &self.speed_bin_edges {
            if edges.len() < 2 {
                p.add(
                    "surge.speed_bin_edges",
                    "needs at least two edges (m/s) to make one bin",
                );
            }
            for (i, e) in edges.iter().enumerate() {
                p.finite(&format!("surge.speed_bin_edges[{i}]"), *e);
            }
            if let Some(i) = edges
                .windows(2)
                .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            {
                p.add(
                    "surge.speed_bin_edges",
                    format!(
                        "edges must increase, but edge {} ({} m/s) is not above edge {} ({} m/s)",
                        i + 2,
                        edges[i + 1],
                        i + 1,
                        edges[i]
                    ),
                );
            }
        }
        p.count_within(
            "surge.min_bin_samples",
            self.min_bin_samples as u64,
            3,
            u64::MAX,
            "a stretch needs samples to integrate over",
        );
    }

    /// The input files this section names.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("surge.runs[{i}]"), r))
            .collect()
    }
}
