//! The files a configuration's run must never overwrite: the configuration, its folder and
//! every input it names ([`Protected`] is the output layer's list; what to put in it is the
//! configuration's knowledge).

use super::LoadedConfig;
use crate::io::output::Protected;

impl Protected {
    /// Everything a run configuration reads: the configuration file, its folder, and every
    /// input file it names (those of disabled stages too).
    pub fn for_config(loaded: &LoadedConfig) -> Self {
        let mut p = Self::for_inputs(loaded);
        p.config(&loaded.path);
        p
    }

    /// Every input file a configuration names (those of disabled stages too), but not the
    /// configuration itself (a rerun reads it from the output folder it replaces).
    pub fn for_inputs(loaded: &LoadedConfig) -> Self {
        let mut p = Self::new();
        for (key, spec) in loaded.config.inputs() {
            p.input(&loaded.resolve(&spec.file), &key);
        }
        p
    }
}
