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
}

impl Warning {
    /// A warning of `stage` with its message and meaning.
    pub fn new(stage: &str, message: impl Into<String>, meaning: impl Into<String>) -> Self {
        Warning {
            stage: stage.to_string(),
            run: None,
            message: message.into(),
            meaning: meaning.into(),
        }
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
