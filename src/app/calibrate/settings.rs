//! The estimates under changed settings (issue 22 item 5, the "settings" row): the same
//! data identified again with the inputs read the other way between samples (held instead
//! of linear, and the reverse), and with each run of a stage that has several left out.
//!
//! Reading the inputs the other way changes no data: whatever it moves is a systematic
//! effect of the choice, reported in reported sigmas, and that move is the coefficient's
//! settings sigma. Leaving a run out changes the data, so the estimates also move by chance:
//! for efficient estimators on nested data sets the difference of the two estimates has the
//! variance sigma_out^2 - sigma^2 (Hausman 1978, Econometrica 46(6), lemma 2.1), and the move
//! over that spread is its `z`. A run whose omission moves an estimate by more than its
//! reported sigma and more than [`LEAVE_OUT_WARNED`] times that spread disagrees with the
//! others (both conditions: a joint estimate's sigmas also hold budget rows that are not
//! information, so z alone overstates small moves). The noise model's part is in
//! results.json's budget (row "noise model", the estimates with every noise halved and
//! doubled), not repeated here.

use crate::app::pipeline::InputsByStage;
use crate::app::results::{LoadedInput, RunOutput};
use crate::base::quantity::Quantity;
use crate::base::warning::{Test, Warning};
use crate::config::LoadedConfig;
use crate::io::input_spec::Between;
use crate::model::coefficients::Coefficient;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// A move of the inputs' variant above this many reported sigmas is warned.
pub const BETWEEN_WARNED: f64 = 1.0;
/// A leave-one-out z above this is warned (a run that disagrees with the others).
pub const LEAVE_OUT_WARNED: f64 = 3.0;

/// The settings check of one output folder.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SettingsCheck {
    /// Each variant identified.
    pub variants: Vec<Variant>,
    /// Per identified coefficient.
    pub coefficients: Vec<SettingsRow>,
}

/// One changed setting and what it did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variant {
    /// What was changed, in words.
    pub label: String,
    /// `between` (inputs read the other way) or `leave_out` (a run left out).
    pub kind: VariantKind,
    /// Why the identification failed, if it did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Per coefficient, the move in reported sigmas.
    pub moves: BTreeMap<String, f64>,
    /// Per coefficient (`leave_out`), the move over its expected spread
    /// sqrt(sigma_out^2 - sigma^2).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub z: BTreeMap<String, f64>,
}

/// What kind of setting a [`Variant`] changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VariantKind {
    /// The fitted manoeuvres' sampled inputs read the other way.
    Between,
    /// One run left out.
    LeaveOut,
}

/// One coefficient under the changed settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SettingsRow {
    /// Name.
    pub name: String,
    /// The move with the inputs read the other way, in reported sigmas (None: no sampled
    /// input, or the variant failed).
    pub between_sigmas: Option<f64>,
    /// The largest leave-one-out z (None: no stage with two runs or more).
    pub leave_out_max_z: Option<f64>,
    /// The settings part of the uncertainty, SI: the move with the inputs read the other
    /// way (0 without that variant).
    pub settings_sigma: f64,
    /// `settings_sigma` over the reported sigma.
    pub settings_ratio: f64,
}

/// One variant, before identification: its inputs are made when it is identified, so that
/// only the variants in progress hold a copy of the data.
struct Planned {
    label: String,
    change: Change,
}

/// What a variant changes.
#[derive(Clone, Copy)]
enum Change {
    /// The fitted manoeuvres' sampled inputs read the other way.
    Between,
    /// Run `k` of stage `stage` (an index into [`InputsByStage::fitted`]) left out.
    LeaveOut { stage: usize, k: usize },
}

impl Change {
    /// Its kind in calibration.json.
    fn kind(self) -> VariantKind {
        match self {
            Change::Between => VariantKind::Between,
            Change::LeaveOut { .. } => VariantKind::LeaveOut,
        }
    }
}

/// Identifies every variant of `inputs` (in parallel) and compares with `original`'s
/// identified coefficients.
pub fn check(
    loaded: &LoadedConfig,
    inputs: &InputsByStage<LoadedInput>,
    original: &RunOutput,
    identified: &[&Coefficient],
) -> (SettingsCheck, Vec<Warning>) {
    let variants: Vec<Variant> = planned(inputs, original)
        .into_par_iter()
        .map(|p| {
            let outcome = made(inputs, original, p.change)
                .ok_or_else(|| "no sampled input to read the other way".to_string())
                .and_then(|data| super::identified_on(loaded, &data));
            compare(&p, &outcome, identified)
        })
        .collect();
    let coefficients = identified.iter().map(|c| row(c, &variants)).collect();
    let check = SettingsCheck {
        variants,
        coefficients,
    };
    let warnings = warnings(&check);
    (check, warnings)
}

/// The variants of `inputs`: the fitted manoeuvres' sampled inputs read the other way (when
/// a run has one), and each run of a stage with two or more left out.
fn planned(inputs: &InputsByStage<LoadedInput>, original: &RunOutput) -> Vec<Planned> {
    let mut out = Vec::new();
    let sampled = original
        .result
        .stages
        .hekf
        .as_ref()
        .is_some_and(|h| h.runs.iter().any(|r| !r.between.is_empty()));
    if sampled {
        out.push(Planned {
            label: "the inputs read the other way between samples (held <-> linear)".into(),
            change: Change::Between,
        });
    }
    for (stage, (name, runs)) in inputs.fitted().into_iter().enumerate() {
        if runs.len() < 2 {
            continue;
        }
        for (k, run) in runs.iter().enumerate() {
            out.push(Planned {
                label: format!("{name} run '{}' left out", run.record.name),
                change: Change::LeaveOut { stage, k },
            });
        }
    }
    out
}

/// The inputs of one variant.
fn made(
    inputs: &InputsByStage<LoadedInput>,
    original: &RunOutput,
    change: Change,
) -> Option<InputsByStage<LoadedInput>> {
    match change {
        Change::Between => flipped_inputs(inputs, original),
        Change::LeaveOut { stage, k } => {
            let mut v = inputs.clone();
            v.fitted_mut()[stage].remove(k);
            Some(v)
        }
    }
}

/// The fitted manoeuvres with every sampled input read the other way than the run read it
/// (results.json's `between` per run); None when no run has a sampled input.
fn flipped_inputs(
    inputs: &InputsByStage<LoadedInput>,
    original: &RunOutput,
) -> Option<InputsByStage<LoadedInput>> {
    let runs = &original.result.stages.hekf.as_ref()?.runs;
    let mut v = inputs.clone();
    let mut any = false;
    for input in &mut v.hekf_fit {
        let Some(run) = runs.iter().find(|r| r.name == input.record.name) else {
            continue;
        };
        for (key, rule) in &run.between {
            let Some(q) = Quantity::ALL.iter().find(|q| q.key() == key) else {
                continue;
            };
            let other = if rule == "held" {
                Between::Linear
            } else {
                Between::Hold
            };
            input.record.between.insert(*q, other);
            any = true;
        }
    }
    any.then_some(v)
}

/// One variant's moves against the identified coefficients.
fn compare(
    p: &Planned,
    outcome: &crate::app::calibrate::Outcome,
    identified: &[&Coefficient],
) -> Variant {
    let mut v = Variant {
        label: p.label.clone(),
        kind: p.change.kind(),
        error: None,
        moves: BTreeMap::new(),
        z: BTreeMap::new(),
    };
    let found = match outcome {
        Ok(f) => f,
        Err(e) => {
            v.error = Some(e.clone());
            return v;
        }
    };
    for c in identified {
        let sigma = c.sigma.unwrap_or(f64::NAN);
        let Some((_, value, s_out)) = found.iter().find(|f| f.0 == c.name) else {
            continue;
        };
        if !value.is_finite() || !sigma.is_finite() || sigma <= 0.0 {
            continue;
        }
        let shift = value - c.value;
        v.moves.insert(c.name.clone(), shift / sigma);
        if let Change::LeaveOut { .. } = p.change {
            // the difference of nested efficient estimates (Hausman 1978): its variance is
            // sigma_out^2 - sigma^2, floored at a tenth of sigma^2 against rounding
            let s_out = s_out.unwrap_or(f64::NAN);
            let spread = (s_out * s_out - sigma * sigma)
                .max(0.01 * sigma * sigma)
                .sqrt();
            if spread.is_finite() {
                v.z.insert(c.name.clone(), shift / spread);
            }
        }
    }
    v
}

/// A coefficient's row over the variants.
fn row(c: &Coefficient, variants: &[Variant]) -> SettingsRow {
    let sigma = c.sigma.unwrap_or(f64::NAN);
    let between_sigmas = variants
        .iter()
        .filter(|v| v.kind == VariantKind::Between)
        .find_map(|v| v.moves.get(&c.name).copied());
    let loo: Vec<(f64, f64)> = variants
        .iter()
        .filter(|v| v.kind == VariantKind::LeaveOut)
        .filter_map(|v| Some((*v.moves.get(&c.name)?, *v.z.get(&c.name)?)))
        .collect();
    let leave_out_max_z = loo.iter().map(|(_, z)| z.abs()).max_by(f64::total_cmp);
    let ratio = between_sigmas.unwrap_or(0.0).abs();
    SettingsRow {
        name: c.name.clone(),
        between_sigmas,
        leave_out_max_z,
        settings_sigma: ratio * sigma,
        settings_ratio: ratio,
    }
}

/// Warnings: a coefficient the inputs' reading moves by more than [`BETWEEN_WARNED`]
/// sigmas, or that the inputs cannot be read the other way; a run whose omission moves one by
/// more than its sigma and more than [`LEAVE_OUT_WARNED`] of its expected spread. A run that
/// cannot be left out (the rest do not determine the coefficients) is recorded, not warned.
fn warnings(check: &SettingsCheck) -> Vec<Warning> {
    let mut out = Vec::new();
    for v in &check.variants {
        match (&v.error, v.kind) {
            (Some(e), VariantKind::Between) => out.push(Warning::new(
                "calibration",
                format!("with {}, the identification failed: {e}", v.label),
                "the estimates depend on how the inputs are read between samples more than \
                 the sigmas can say",
            )),
            (Some(_), _) => {}
            (None, VariantKind::Between) => out.extend(between_warning(v)),
            (None, _) => out.extend(leave_out_warning(v)),
        }
    }
    out
}

/// The inputs' variant's warning: estimates moved by more than [`BETWEEN_WARNED`] sigmas (a
/// choice the data do not make: said, not a failed test).
fn between_warning(v: &Variant) -> Option<Warning> {
    let moved: Vec<(&String, f64)> = v
        .moves
        .iter()
        .filter(|(_, m)| m.abs() > BETWEEN_WARNED)
        .map(|(n, m)| (n, *m))
        .collect();
    Some(Warning::new(
        "calibration",
        format!(
            "with {}, estimates move (sigma): {}",
            v.label,
            listed(moved)?
        ),
        "the estimates depend on how the inputs are read between samples: give each input's \
         `between` as the signal is (a sampled moving rudder: linear; a step log: hold) or \
         sample faster; calibration.json's settings sigma holds the move",
    ))
}

/// A left-out run's warning: estimates moved by more than their sigma and by more than
/// [`LEAVE_OUT_WARNED`] times their expected spread (a failed consistency test).
fn leave_out_warning(v: &Variant) -> Option<Warning> {
    let moved: Vec<(&String, f64)> =
        v.z.iter()
            .filter(|(n, z)| {
                z.abs() > LEAVE_OUT_WARNED && v.moves.get(*n).is_some_and(|m| m.abs() > 1.0)
            })
            .map(|(n, z)| (n, *z))
            .collect();
    Some(
        Warning::new(
            "calibration",
            format!(
                "with {}, estimates move (times their expected spread): {}",
                v.label,
                listed(moved)?
            ),
            "this run disagrees with the others more than their noise explains: a run with \
             another condition (speed, loading, a sensor problem) or a model that does not hold \
             over all of them",
        )
        .failed(Test::Calibration),
    )
}

/// "Name +1.23, ..." by size, None when empty.
fn listed(mut moved: Vec<(&String, f64)>) -> Option<String> {
    if moved.is_empty() {
        return None;
    }
    moved.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    let list: Vec<String> = moved.iter().map(|(n, m)| format!("{n} {m:+.2}")).collect();
    Some(list.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// calibration.json names a variant's kind `between` or `leave_out`, as it did before
    /// the kind was an enum.
    #[test]
    fn a_variants_kind_is_written_as_the_docs_name_it() {
        let kinds = [VariantKind::Between, VariantKind::LeaveOut].map(|k| {
            serde_json::to_value(k)
                .unwrap()
                .as_str()
                .unwrap()
                .to_string()
        });
        assert_eq!(kinds, ["between", "leave_out"]);
    }
}
