//! Surge acceleration stage: the added mass X_udot from a straight-line run (paper eq. 21).

use crate::config::{yes, Config, InputSpec, Problems};
use serde::{Deserialize, Serialize};

/// `[surge]` configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurgeConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// Straight-line acceleration runs.
    pub runs: Vec<InputSpec>,
}

impl SurgeConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, _config: &Config, p: &mut Problems) {
        for (i, r) in self.runs.iter().enumerate() {
            p.existing_file(&format!("surge.runs[{i}].file"), &r.file);
        }
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
