//! Warnings: what a stage noticed and what it means for the numbers.
//!
//! Every warning reaches the user three ways: printed on the console by `hydroid run`, listed
//! in results.json `warnings` and in the report's Warnings section. A warning carries its
//! meaning, so that a reader of any of the three knows which numbers to distrust and why.

use serde::Serialize;
use std::fmt;

/// Something the user should know about a result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warning {
    /// Where it arose: `input`, `polar`, `surge`, `hekf`, `resimulation`, `coefficients`.
    pub stage: String,
    /// The run (or input) it concerns, when it concerns one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    /// What was seen.
    pub message: String,
    /// What it means for the numbers (and, where there is one, what to do).
    pub meaning: String,
    /// The consistency test it reports as failed, when it reports one (`hydroid run
    /// --strict` exits with status 3 on these).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed_test: Option<Test>,
}

/// A consistency test whose failure a warning reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Test {
    /// The filter's innovations against its noise model (NIS; Bar-Shalom et al. 2001, 5.4).
    Innovations,
    /// Two stages' estimates of one coefficient (docs/stages.md, "Stage conflicts").
    StageConflict,
    /// The estimates' dependence on the noise model (docs/hekf.md, "The noise model").
    NoiseModel,
    /// The identified model re-simulated against a run, or steered through its manoeuvre.
    Resimulation,
    /// A captive fit's lack of fit on steady tables (docs/stages.md, "Captive plausibility").
    Misfit,
    /// The spread of a parametric bootstrap's estimates against the reported sigmas
    /// (`hydroid calibrate`, docs/calibrate.md).
    Calibration,
}

impl Test {
    /// The test in words: `innovations`, `stage conflict` ...
    pub fn name(self) -> &'static str {
        match self {
            Test::Innovations => "innovations (NIS)",
            Test::StageConflict => "stage conflict",
            Test::NoiseModel => "noise model",
            Test::Resimulation => "re-simulation",
            Test::Misfit => "captive lack of fit",
            Test::Calibration => "calibration",
        }
    }
}

impl Warning {
    /// A warning of `stage` with its message and meaning.
    pub fn new(stage: &str, message: impl Into<String>, meaning: impl Into<String>) -> Self {
        Warning {
            stage: stage.to_string(),
            run: None,
            message: message.into(),
            meaning: meaning.into(),
            failed_test: None,
        }
    }

    /// The same warning, reporting a failed consistency test.
    pub fn failed(mut self, test: Test) -> Self {
        self.failed_test = Some(test);
        self
    }

    /// The same warning, about run `name`.
    pub fn for_run(mut self, name: &str) -> Self {
        self.run = Some(name.to_string());
        self
    }

    /// Where it arose, for messages: `hekf, run 'turn'`.
    pub fn origin(&self) -> String {
        match &self.run {
            Some(r) => format!("{}, run '{r}'", self.stage),
            None => self.stage.clone(),
        }
    }
}

impl fmt::Display for Warning {
    /// `stage, run 'name': message. Meaning: ...`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.origin(), self.message)?;
        if !self.meaning.is_empty() {
            write!(f, "\n  meaning: {}", self.meaning)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn says_where_what_and_what_it_means() {
        let w = Warning::new("hekf", "mean NIS 12.3", "sigmas are too small").for_run("turn");
        let s = w.to_string();
        assert!(s.starts_with("hekf, run 'turn': mean NIS 12.3"), "{s}");
        assert!(s.contains("meaning: sigmas are too small"), "{s}");
        let j = serde_json::to_value(&w).unwrap();
        assert_eq!(j["run"], "turn");
        let w = Warning::new("surge", "x", "");
        assert_eq!(w.to_string(), "surge: x");
        assert!(serde_json::to_value(&w).unwrap().get("run").is_none());
    }
}
