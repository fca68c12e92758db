//! The end of the report: every warning, and the files of the output folder.

use crate::app::report::doc::{code, strong, text, Document};
use crate::app::report::plots::Figure;
use crate::app::results::RunResult;

pub fn write(d: &mut Document, r: &RunResult, figures: Option<&[Figure]>) {
    d.heading(2, "Warnings");
    let items: Vec<_> = r
        .warnings
        .iter()
        .map(|w| {
            vec![
                strong(w.origin()),
                text(format!(": {}. ", w.message.trim_end_matches('.'))),
                text(w.meaning.clone()),
            ]
        })
        .collect();
    if items.is_empty() {
        d.text("None.");
    } else {
        d.list(items);
    }
    d.heading(2, "Files");
    let mut files = vec![
        vec![
            code("results.json"),
            text(": everything above, versioned (docs/results.md)."),
        ],
        vec![
            code("coefficients.csv"),
            text(": the comparison table, full precision."),
        ],
    ];
    let tables: Vec<&str> = r
        .stages
        .hekf
        .iter()
        .flat_map(|h| h.runs.iter())
        .filter_map(|run| run.states.as_deref())
        .collect();
    if !tables.is_empty() {
        files.push(vec![
            code("states/"),
            text(format!(
                ": each HEKF fit run's filtered and smoothed states, innovations and \
                 coefficients at every sample, as CSV ({}; docs/results.md, \"State series\").",
                tables.join(", ")
            )),
        ]);
    }
    files.extend([
        vec![
            code("inputs.json"),
            text(": every input file with its SHA-256."),
        ],
        vec![
            code("config.toml"),
            text(": the effective configuration (defaults and overrides applied)."),
        ],
        vec![
            code("rerun.json"),
            text(": where the configuration and inputs live, for "),
            code("hydroid rerun"),
            text("."),
        ],
        vec![code("report.md"), text(": this report in Markdown.")],
    ]);
    match figures {
        Some(f) => {
            files.push(vec![
                code("report.html"),
                text(": this report as one self-contained page."),
            ]);
            files.push(vec![
                code("plots/"),
                text(format!(
                    ": the {} figures, each as SVG and PNG ({}).",
                    f.len(),
                    f.iter()
                        .map(|x| x.meta.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            ]);
        }
        None => files.push(vec![text("No figures and no report.html: plots are off.")]),
    }
    d.list(files);
}
