//! Warnings on the console, grouped: one entry per kind of warning with the runs it applies
//! to, those that change the answer first (the filter's, the coefficients', the
//! re-simulation's), the notes on how the inputs were read last. results.json and the report
//! keep every warning as it was raised.

use crate::base::warning::{Test, Warning};
use std::collections::BTreeSet;

/// Exit status of `run --strict` when a warning reports a failed consistency test.
pub const STRICT_FAILED: i32 = 3;

/// The exit status of a run that wrote its output: [`STRICT_FAILED`] under `--strict` when
/// a warning reports a failed consistency test (said on the console, naming the tests), else 0.
pub fn exit_status(strict: bool, warnings: &[Warning]) -> i32 {
    let failed: BTreeSet<Test> = warnings.iter().filter_map(|w| w.failed_test).collect();
    if !strict || failed.is_empty() {
        return 0;
    }
    let names: Vec<&str> = failed.iter().map(|t| t.name()).collect();
    super::warning(&format!(
        "--strict: consistency tests failed ({}): exit status {STRICT_FAILED}, the output \
         folder written as without it",
        names.join(", ")
    ));
    STRICT_FAILED
}

/// Stages in the order their warnings are shown: what bears on the estimates first.
const ORDER: [&str; 9] = [
    "hekf",
    "coefficients",
    "captive",
    "polar",
    "surge",
    "resimulation",
    "steering",
    "autopilot",
    "input",
];

/// Words of a message (numbers and quoted names blanked) that tell its kind.
const KIND_WORDS: usize = 7;

/// One kind of warning and the runs it was raised for.
#[derive(Debug)]
struct Group<'a> {
    first: &'a Warning,
    runs: Vec<&'a str>,
    count: usize,
}

/// The console lines for `warnings`, grouped and ordered (see the module documentation).
pub fn render(warnings: &[Warning]) -> Vec<String> {
    let mut groups: Vec<(usize, String, Group)> = Vec::new();
    for w in warnings {
        let key = kind(w);
        match groups.iter_mut().find(|(_, k, _)| *k == key) {
            Some((_, _, g)) => {
                g.count += 1;
                if let Some(r) = w.run.as_deref() {
                    if !g.runs.contains(&r) {
                        g.runs.push(r);
                    }
                }
            }
            None => groups.push((
                rank(&w.stage),
                key,
                Group {
                    first: w,
                    runs: w.run.as_deref().into_iter().collect(),
                    count: 1,
                },
            )),
        }
    }
    // stable: within a stage, the order they arose in
    groups.sort_by_key(|(r, _, _)| *r);
    groups.iter().map(|(_, _, g)| line(g)).collect()
}

/// The kind of a warning: its stage and the first words of its message with every number
/// and quoted name blanked.
fn kind(w: &Warning) -> String {
    let mut blanked = String::new();
    let mut quoted = false;
    for c in w.message.chars() {
        match c {
            '\'' => quoted = !quoted,
            _ if quoted => {}
            '0'..='9' | '.' | '-' | '+' => {
                if !blanked.ends_with('#') {
                    blanked.push('#');
                }
            }
            c => blanked.push(c),
        }
    }
    let words: Vec<&str> = blanked.split_whitespace().take(KIND_WORDS).collect();
    format!("{}|{}", w.stage, words.join(" "))
}

/// Where a stage's warnings go in the order.
fn rank(stage: &str) -> usize {
    ORDER
        .iter()
        .position(|s| *s == stage)
        .unwrap_or(ORDER.len() - 1)
}

/// One group as console text: `warning: hekf, runs 'a', 'b': message` and its meaning; the
/// notes on reading the inputs as `note:`, without their (common) meaning.
fn line(g: &Group) -> String {
    let w = g.first;
    let label = if w.stage == "input" {
        "note"
    } else {
        "warning"
    };
    let runs = match g.runs.len() {
        0 => String::new(),
        1 => format!(", run '{}'", g.runs[0]),
        _ => format!(
            ", runs {}",
            g.runs
                .iter()
                .map(|r| format!("'{r}'"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let more = if g.count > 1 {
        format!(
            " [{} like it; the first shown, all in results.json and the report]",
            g.count
        )
    } else {
        String::new()
    };
    let mut s = format!("{label}: {}{runs}: {}{more}", w.stage, w.message);
    if label == "warning" && !w.meaning.is_empty() {
        s.push_str(&format!("\n  meaning: {}", w.meaning));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_kind_is_one_entry_with_its_runs_and_the_notes_come_last() {
        let ws = vec![
            Warning::new(
                "input",
                "Froude-scaled from full scale with lambda = 45.7",
                "read",
            )
            .for_run("a"),
            Warning::new(
                "input",
                "Froude-scaled from full scale with lambda = 45.7",
                "read",
            )
            .for_run("b"),
            Warning::new(
                "resimulation",
                "poor re-simulation of yaw (RMS error 45 %)",
                "m",
            )
            .for_run("a"),
            Warning::new("hekf", "mean NIS 26.06 for 6 measurements", "sigmas").for_run("a"),
            Warning::new("hekf", "mean NIS 25.05 for 6 measurements", "sigmas").for_run("b"),
        ];
        let lines = render(&ws);
        assert_eq!(lines.len(), 3, "{lines:#?}");
        assert!(
            lines[0].starts_with("warning: hekf, runs 'a', 'b': mean NIS 26.06"),
            "{}",
            lines[0]
        );
        assert!(lines[0].contains("[2 like it"), "{}", lines[0]);
        assert!(lines[0].contains("meaning: sigmas"), "{}", lines[0]);
        assert!(
            lines[1].starts_with("warning: resimulation, run 'a'"),
            "{}",
            lines[1]
        );
        assert!(
            lines[2].starts_with("note: input, runs 'a', 'b': Froude"),
            "{}",
            lines[2]
        );
        assert!(!lines[2].contains("meaning"), "{}", lines[2]);
    }

    #[test]
    fn different_kinds_of_one_stage_stay_apart() {
        let ws = vec![
            Warning::new(
                "hekf",
                "the yaw rate reads 0.03 deg/s above the heading's rate",
                "",
            ),
            Warning::new(
                "hekf",
                "halving or doubling the noise model moves Yv 2 sigma",
                "",
            ),
        ];
        assert_eq!(render(&ws).len(), 2);
    }
}
