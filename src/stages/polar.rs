//! Static polar stage: C_D, C_L, C_M over angle of attack to X_uu, X_uv, X_vv, Y_vv, Y_uvd,
//! Y_uvl, N_uvl (paper eq. 5-6, after Ridley, Fontan & Corke 2003).

use crate::config::{yes, Config, InputSpec, Problems};
use serde::{Deserialize, Serialize};

/// `[polar]` configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolarConfig {
    /// Run this stage.
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The steady runs: one sweep table with an `alpha` column, or one file per angle.
    pub runs: Vec<InputSpec>,
}

impl PolarConfig {
    /// Adds every problem with this section to `p`.
    pub fn validate(&self, _config: &Config, p: &mut Problems) {
        for (i, r) in self.runs.iter().enumerate() {
            p.existing_file(&format!("polar.runs[{i}].file"), &r.file);
        }
    }

    /// The input files this section names.
    pub fn inputs(&self) -> Vec<(String, &InputSpec)> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("polar.runs[{i}]"), r))
            .collect()
    }
}
