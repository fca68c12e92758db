//! The crate's file -> file import graph: every `.rs` file under `src/` is a node, every
//! module path it names (source.rs) is mapped to the file that defines the module, and the
//! import cycles are the graph's strongly connected components.
//!
//! A file defines the module of its path (`src/a/b.rs` and `src/a/b/mod.rs` are `a::b`;
//! `src/lib.rs` and `src/main.rs` are the crate root). A path is resolved by its longest
//! prefix that is a module (`crate::a::b::Thing::f` -> `a::b`); `super::` and `self::` count
//! from the module of the file, and a path starting with the name of a child module (Rust
//! 2018 `use child::X;`) from the file's module too. Paths into other crates (`std::`,
//! `nalgebra::`) are not edges; a file naming itself is not an edge.

use super::source;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// One path in a file that makes an edge: where it is written and the module path it
/// resolves to, absolute (`crate::stages::hekf::Thing`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Import {
    /// 1-based line in the importing file.
    pub line: usize,
    /// The path made absolute from the crate root, `crate::...`.
    pub path: String,
}

/// The import graph: for each file (`src/...`, `/`-separated), the files it imports and,
/// for each, the paths that make the edge (sorted by line).
pub type Graph = BTreeMap<String, BTreeMap<String, Vec<Import>>>;

/// Every `.rs` file under `root/src` with the module it defines, sorted by path.
pub fn module_files(root: &Path) -> Result<Vec<(Vec<String>, String)>, String> {
    let mut out = Vec::new();
    walk(&root.join("src"), "src", &mut out)?;
    out.sort_by(|a, b| a.1.cmp(&b.1));
    Ok(out)
}

/// Adds the `.rs` files of folder `dir` (written `rel` from the crate root) to `out`.
fn walk(dir: &Path, rel: &str, out: &mut Vec<(Vec<String>, String)>) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: {e}", dir.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let file = format!("{rel}/{name}");
        let kind = entry.file_type().map_err(|e| format!("{file}: {e}"))?;
        if kind.is_dir() {
            walk(&entry.path(), &file, out)?;
        } else if let Some(stem) = name.strip_suffix(".rs") {
            let mut module: Vec<String> = rel.split('/').skip(1).map(String::from).collect();
            if !matches!(stem, "mod" | "lib" | "main") {
                module.push(stem.to_string());
            }
            out.push((module, file));
        }
    }
    Ok(())
}

/// The import graph of the crate at `root`: every file under `src/` a node, every path it
/// names that resolves to another file of the crate an edge.
pub fn build(root: &Path) -> Result<Graph, String> {
    let files = module_files(root)?;
    // The crate root (lib.rs, main.rs) is a node but never a target: a path names a module.
    let modules: BTreeMap<Vec<String>, String> = files
        .iter()
        .filter(|(m, _)| !m.is_empty())
        .cloned()
        .collect();
    let mut graph = Graph::new();
    for (module, file) in &files {
        let bytes = std::fs::read(root.join(file)).map_err(|e| format!("{file}: {e}"))?;
        let text = String::from_utf8_lossy(&bytes);
        let edges = graph.entry(file.clone()).or_default();
        for mention in source::mentions(&text) {
            let Some(segs) = absolute(&mention.path, module, &modules) else {
                continue;
            };
            if let Some(target) = resolve(&segs, &modules).filter(|t| *t != file) {
                edges.entry(target.clone()).or_default().push(Import {
                    line: mention.line,
                    path: format!("crate::{}", segs.join("::")),
                });
            }
        }
    }
    for edges in graph.values_mut() {
        edges.values_mut().for_each(|v| {
            v.sort();
            v.dedup();
        });
    }
    Ok(graph)
}

/// The module path a mention names, from the crate root (`crate::`, `super::`, `self::`, or
/// a child module of `module` named directly); None for a path into another crate.
fn absolute(
    path: &str,
    module: &[String],
    modules: &BTreeMap<Vec<String>, String>,
) -> Option<Vec<String>> {
    let mut segs: Vec<String> = path
        .split("::")
        .filter(|s| !s.is_empty() && *s != "*")
        .map(String::from)
        .collect();
    let first = segs.first()?.clone();
    if first == "crate" {
        segs.remove(0);
        return Some(segs);
    }
    let mut base = module.to_vec();
    if first == "super" || first == "self" {
        while segs.first().map(String::as_str) == Some("super") {
            segs.remove(0);
            base.pop();
        }
        if segs.first().map(String::as_str) == Some("self") {
            segs.remove(0);
        }
    } else {
        let mut child = base.clone();
        child.push(first);
        if !modules.contains_key(&child) {
            return None;
        }
    }
    base.extend(segs);
    Some(base)
}

/// The file defining the longest prefix of `segs` that is a module of the crate.
fn resolve<'a>(segs: &[String], modules: &'a BTreeMap<Vec<String>, String>) -> Option<&'a String> {
    (1..=segs.len()).rev().find_map(|k| modules.get(&segs[..k]))
}

/// The top-level module a file belongs to: its first folder under `src/`, or its own name
/// for a file directly in `src/` (`src/config/si.rs` -> `config`, `src/units.rs` ->
/// `units.rs`).
pub fn top_level(file: &str) -> &str {
    let rel = file.strip_prefix("src/").unwrap_or(file);
    rel.split('/').next().unwrap_or(rel)
}

/// The import cycles: strongly connected components of more than one file (Tarjan), each
/// sorted, the largest first (ties by their first file).
pub fn cycles(graph: &Graph) -> Vec<Vec<String>> {
    let mut t = Tarjan {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    let mut out = t.out;
    out.iter_mut().for_each(|c| c.sort());
    out.sort_by(|a, b| b.len().cmp(&a.len()).then_with(|| a.cmp(b)));
    out
}

/// Tarjan's strongly connected components: the state of one search.
struct Tarjan<'g> {
    graph: &'g Graph,
    index: BTreeMap<&'g str, usize>,
    low: BTreeMap<&'g str, usize>,
    stack: Vec<&'g str>,
    on_stack: BTreeSet<&'g str>,
    out: Vec<Vec<String>>,
}

impl<'g> Tarjan<'g> {
    /// Visits `v` and everything reachable from it not yet visited; a component closes at
    /// the file whose lowest reachable index is its own.
    fn visit(&mut self, v: &'g str) {
        let n = self.index.len();
        self.index.insert(v, n);
        self.low.insert(v, n);
        self.stack.push(v);
        self.on_stack.insert(v);
        let graph = self.graph;
        for w in graph.get(v).into_iter().flat_map(|e| e.keys()) {
            let w = w.as_str();
            if !self.index.contains_key(w) {
                self.visit(w);
                let low = self.low[v].min(self.low[w]);
                self.low.insert(v, low);
            } else if self.on_stack.contains(w) {
                let low = self.low[v].min(self.index[w]);
                self.low.insert(v, low);
            }
        }
        if self.low[v] == self.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = self.stack.pop() {
                self.on_stack.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                self.out.push(comp);
            }
        }
    }
}
