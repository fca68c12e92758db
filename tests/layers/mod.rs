//! The crate's import layers checked from its source (issue 23): the file -> file import
//! graph of `src/` (graph.rs, reading paths as source.rs does) against the layer table
//! (table.rs, docs/layers.txt). std only; the same check as the project's hand tool
//! `layers.py`, so that the test does not need it.
//!
//! Faults:
//! * an import cycle whose files lie in two or more top-level modules (a cycle inside one
//!   top-level module, a mod.rs and its children, is ordinary Rust);
//! * an import from a file of a lower layer to a file of a higher one;
//! * a file of `src/` in no layer (the crate roots `src/lib.rs` and `src/main.rs` may stay
//!   out of the table; placed in a layer, they are checked like any file);
//! * a table prefix that matches no file.

pub mod graph;
pub mod source;
pub mod table;

use graph::{Graph, Import};
use std::collections::BTreeSet;
use std::fmt;
use std::path::Path;
use table::Table;

/// One layering fault, displayed as a message a developer can act on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Fault {
    /// An import cycle across top-level modules: its files (sorted) and every edge inside it.
    Cycle {
        /// The files of the cycle (a strongly connected component).
        files: Vec<String>,
        /// The top-level modules the files lie in.
        modules: Vec<String>,
        /// Each edge between two files of the cycle, with the paths that make it.
        edges: Vec<(String, String, Vec<Import>)>,
    },
    /// An import from a lower layer to a higher one.
    Up {
        /// The importing file and its layer.
        file: String,
        /// The importing file's layer.
        layer: String,
        /// The imported file.
        target: String,
        /// The imported file's layer.
        target_layer: String,
        /// The paths that make the edge.
        imports: Vec<Import>,
    },
    /// A file of `src/` that no prefix of the table holds.
    Unplaced {
        /// The file.
        file: String,
        /// The table's file name.
        table: String,
    },
    /// A prefix of the table that holds no file.
    Stale {
        /// The table's file name.
        table: String,
        /// The line of the prefix.
        line: usize,
        /// The prefix.
        prefix: String,
    },
}

/// What a check found: the graph (for counts) and the faults.
pub struct Report {
    /// The file -> file import graph of `src/`.
    pub graph: Graph,
    /// Every cycle, across top-level modules or not, largest first.
    pub cycles: Vec<Vec<String>>,
    /// The faults: cross-module cycles first, then up-imports, unplaced files, stale prefixes.
    pub faults: Vec<Fault>,
}

/// Checks the crate at `root` (its `src/`): the cycles across top-level modules always,
/// with a `table` also the imports up its layers and the files it leaves out.
pub fn check(root: &Path, table: Option<&Table>) -> Result<Report, String> {
    let graph = graph::build(root)?;
    let cycles = graph::cycles(&graph);
    let mut faults: Vec<Fault> = cycles
        .iter()
        .filter_map(|c| cycle_fault(&graph, c))
        .collect();
    if let Some(table) = table {
        faults.extend(up_imports(&graph, table));
        faults.extend(placement(&graph, table));
    }
    Ok(Report {
        graph,
        cycles,
        faults,
    })
}

/// The fault of a cycle whose files lie in more than one top-level module, None for a cycle
/// inside one.
fn cycle_fault(graph: &Graph, files: &[String]) -> Option<Fault> {
    let modules: BTreeSet<&str> = files.iter().map(|f| graph::top_level(f)).collect();
    if modules.len() < 2 {
        return None;
    }
    let members: BTreeSet<&String> = files.iter().collect();
    let mut edges = Vec::new();
    for f in files {
        for (g, imports) in &graph[f] {
            if members.contains(g) {
                edges.push((f.clone(), g.clone(), imports.clone()));
            }
        }
    }
    Some(Fault::Cycle {
        files: files.to_vec(),
        modules: modules.into_iter().map(String::from).collect(),
        edges,
    })
}

/// Every import from a file of a lower layer to a file of a higher one (files in no layer
/// are reported by `placement`, not here).
fn up_imports(graph: &Graph, table: &Table) -> Vec<Fault> {
    let mut out = Vec::new();
    for (f, targets) in graph {
        let Some((rank, layer)) = table.layer_of(f) else {
            continue;
        };
        for (g, imports) in targets {
            match table.layer_of(g) {
                Some((up, target_layer)) if up > rank => out.push(Fault::Up {
                    file: f.clone(),
                    layer: layer.to_string(),
                    target: g.clone(),
                    target_layer: target_layer.to_string(),
                    imports: imports.clone(),
                }),
                _ => {}
            }
        }
    }
    out
}

/// The files in no layer (but the crate roots) and the prefixes that hold no file.
fn placement(graph: &Graph, table: &Table) -> Vec<Fault> {
    let roots = ["src/lib.rs", "src/main.rs"];
    let mut out: Vec<Fault> = graph
        .keys()
        .filter(|f| !roots.contains(&f.as_str()) && table.layer_of(f).is_none())
        .map(|f| Fault::Unplaced {
            file: f.clone(),
            table: table.file.clone(),
        })
        .collect();
    let files: Vec<&str> = graph.keys().map(String::as_str).collect();
    out.extend(
        table
            .unmatched(&files)
            .into_iter()
            .map(|(line, p)| Fault::Stale {
                table: table.file.clone(),
                line,
                prefix: p.to_string(),
            }),
    );
    out
}

/// `file:line` of the first import and the lines of the others, e.g. `src/a.rs:12` or
/// `src/a.rs:12 (also lines 30, 41)`.
fn located(file: &str, imports: &[Import]) -> String {
    let mut lines: Vec<usize> = imports.iter().map(|i| i.line).collect();
    lines.dedup();
    match lines.split_first() {
        None => file.to_string(),
        Some((first, [])) => format!("{file}:{first}"),
        Some((first, [second])) => format!("{file}:{first} (also line {second})"),
        Some((first, rest)) => {
            let rest: Vec<String> = rest.iter().map(|l| l.to_string()).collect();
            format!("{file}:{first} (also lines {})", rest.join(", "))
        }
    }
}

/// The distinct paths of an edge, without those that only lead to a longer one (the
/// `crate::a` of `use crate::a::{B, C}`): `crate::a::B, crate::a::C`.
fn paths(imports: &[Import]) -> String {
    let set: BTreeSet<&str> = imports.iter().map(|i| i.path.as_str()).collect();
    let longest: Vec<&str> = set
        .iter()
        .filter(|p| {
            let below = format!("{p}::");
            !set.iter().any(|q| q.starts_with(&below))
        })
        .copied()
        .collect();
    longest.join(", ")
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Fault::Cycle {
                files,
                modules,
                edges,
            } => {
                writeln!(
                    f,
                    "import cycle of {} files across the top-level modules {}: {}",
                    files.len(),
                    modules.join(", "),
                    files.join(", ")
                )?;
                write!(
                    f,
                    "  its edges (=> between top-level modules, -> inside one):"
                )?;
                for (a, b, imports) in edges {
                    let arrow = if graph::top_level(a) == graph::top_level(b) {
                        "->"
                    } else {
                        "=>"
                    };
                    let at = located(a, imports);
                    write!(f, "\n    {at} {arrow} {b} ({})", paths(imports))?;
                }
                Ok(())
            }
            Fault::Up {
                file,
                layer,
                target,
                target_layer,
                imports,
            } => write!(
                f,
                "{} (layer {layer}) imports {} ({target}, layer {target_layer}): a lower layer \
                 may not import a higher one",
                located(file, imports),
                paths(imports)
            ),
            Fault::Unplaced { file, table } => write!(
                f,
                "{file} is in no layer of {table}: add it (or its folder) to the layer it \
                 belongs to"
            ),
            Fault::Stale {
                table,
                line,
                prefix,
            } => write!(
                f,
                "{table} line {line}: `{prefix}` is no file or folder of src/ (misspelt, or \
                 moved since the table was written)"
            ),
        }
    }
}
