//! The crate's import layers (issue 23): no import cycle across top-level modules, no import
//! from a lower layer of docs/layers.txt to a higher one, no file of src/ outside the table.
//! Read from the source (tests/layers/), without the hydroid crate and without the project's
//! hand tool `../shared/tools/layers.py`, which does the same check.
//!
//! `LAYERS_TABLE=/path/to/table cargo test --test suite layers::` checks src/ against
//! another table (a proposed one) instead of docs/layers.txt.
//!
//! The unit tests below check the reading on small crates written to a temporary folder.

#[path = "layers/mod.rs"]
mod reading;

use reading::graph::{self, Import};
use reading::table::Table;
use reading::{check, Fault};
use std::path::Path;

/// The crate's src/ against its layer table: every fault listed in one failure.
#[test]
fn src_keeps_its_layers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let table_path = std::env::var("LAYERS_TABLE")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|_| root.join("docs/layers.txt"));
    let label = table_path
        .strip_prefix(root)
        .unwrap_or(&table_path)
        .display()
        .to_string();
    let text = std::fs::read_to_string(&table_path).unwrap_or_else(|e| {
        panic!("{label}: {e}; the layer table lists each layer's folders and files, lowest first")
    });
    let table = Table::parse(&text, &label).unwrap_or_else(|e| panic!("{}", e.join("\n")));
    let report = check(root, Some(&table)).unwrap_or_else(|e| panic!("{e}"));
    let imports: usize = report.graph.values().map(|t| t.len()).sum();
    println!(
        "{} files, {imports} file -> file imports, {} cycles ({} across top-level modules)",
        report.graph.len(),
        report.cycles.len(),
        report
            .faults
            .iter()
            .filter(|f| matches!(f, Fault::Cycle { .. }))
            .count()
    );
    let messages: Vec<String> = report.faults.iter().map(|f| f.to_string()).collect();
    assert!(
        messages.is_empty(),
        "{} layering faults in src/ (table {label}):\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// A crate in a temporary folder with the given files (paths from the crate root).
fn crate_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("a temporary folder");
    for (path, text) in files {
        let file = dir.path().join(path);
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(file, text).unwrap();
    }
    dir
}

/// The files `file` imports in the crate at `root`, with the lines and paths of each.
fn imports_of(root: &Path, file: &str) -> Vec<(String, Vec<Import>)> {
    let g = graph::build(root).unwrap();
    g[file]
        .iter()
        .map(|(t, i)| (t.clone(), i.clone()))
        .collect()
}

/// The files `file` imports, without the paths.
fn targets_of(root: &Path, file: &str) -> Vec<String> {
    imports_of(root, file).into_iter().map(|(t, _)| t).collect()
}

/// An import (line, path).
fn at(line: usize, path: &str) -> Import {
    Import {
        line,
        path: path.to_string(),
    }
}

#[test]
fn a_cycle_across_top_level_modules_is_a_fault_with_its_files_and_edges() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod a;\npub mod b;\npub mod c;\n"),
        ("src/a.rs", "use crate::b::Thing;\npub struct A;\n"),
        ("src/b/mod.rs", "mod inner;\npub use inner::Thing;\n"),
        ("src/b/inner.rs", "pub struct Thing(crate::a::A);\n"),
        ("src/c.rs", "use crate::a::A;\n"),
    ]);
    let report = check(dir.path(), None).unwrap();
    assert_eq!(
        report.cycles,
        vec![vec!["src/a.rs", "src/b/inner.rs", "src/b/mod.rs"]]
    );
    let [Fault::Cycle { files, modules, .. }] = &report.faults[..] else {
        panic!("one cycle fault expected, got {:?}", report.faults);
    };
    assert_eq!(files.len(), 3);
    assert_eq!(modules, &["a.rs", "b"]);
    let message = report.faults[0].to_string();
    for edge in [
        "src/a.rs:1 => src/b/mod.rs (crate::b::Thing)",
        "src/b/inner.rs:1 => src/a.rs (crate::a::A)",
        "src/b/mod.rs:2 -> src/b/inner.rs (crate::b::inner::Thing)",
    ] {
        assert!(message.contains(edge), "`{edge}` missing from:\n{message}");
    }
    assert!(message.starts_with("import cycle of 3 files across the top-level modules a.rs, b:"));
}

#[test]
fn a_cycle_inside_one_top_level_module_is_not_a_fault() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod m;\n"),
        (
            "src/m/mod.rs",
            "mod child;\nuse child::Leaf;\npub struct Root;\n",
        ),
        ("src/m/child.rs", "use super::Root;\npub struct Leaf;\n"),
    ]);
    let report = check(dir.path(), None).unwrap();
    assert_eq!(report.cycles, vec![vec!["src/m/child.rs", "src/m/mod.rs"]]);
    assert!(report.faults.is_empty(), "{:?}", report.faults);
}

#[test]
fn an_import_up_the_layer_table_is_a_fault_naming_file_line_path_and_layers() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod io;\npub mod stages;\n"),
        ("src/io/mod.rs", "pub mod x;\npub struct Reader;\n"),
        ("src/io/x.rs", "// reads\n\nuse crate::stages::y::Fit;\n"),
        ("src/stages/mod.rs", "pub mod y;\nuse crate::io::Reader;\n"),
        ("src/stages/y.rs", "pub struct Fit;\n"),
    ]);
    let table = Table::parse("# lowest first\nio: src/io\nstages: src/stages/\n", "t.txt");
    let report = check(dir.path(), Some(&table.unwrap())).unwrap();
    let ups: Vec<String> = report.faults.iter().map(|f| f.to_string()).collect();
    assert_eq!(
        ups,
        [
            "src/io/x.rs:3 (layer io) imports crate::stages::y::Fit (src/stages/y.rs, layer \
          stages): a lower layer may not import a higher one"
        ]
    );
    // The same import the other way round is allowed.
    let down = Table::parse("stages: src/stages\nio: src/io\n", "t.txt").unwrap();
    let report = check(dir.path(), Some(&down)).unwrap();
    assert_eq!(report.faults.len(), 1, "{:?}", report.faults);
    assert!(matches!(&report.faults[0], Fault::Up { file, .. } if file == "src/stages/mod.rs"));
}

#[test]
fn an_up_import_written_on_several_lines_names_each_line_and_path_once() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod io;\npub mod stages;\n"),
        (
            "src/io.rs",
            "use crate::stages::{Fit, Plan};\n\nfn f() { crate::stages::go() }\n",
        ),
        (
            "src/stages.rs",
            "pub struct Fit;\npub struct Plan;\npub fn go() {}\n",
        ),
    ]);
    let table = Table::parse("io: src/io.rs\nstages: src/stages.rs\n", "t.txt").unwrap();
    let report = check(dir.path(), Some(&table)).unwrap();
    let messages: Vec<String> = report.faults.iter().map(|f| f.to_string()).collect();
    assert_eq!(
        messages,
        [
            "src/io.rs:1 (also line 3) (layer io) imports crate::stages::Fit, \
          crate::stages::Plan, crate::stages::go (src/stages.rs, layer stages): a lower layer \
          may not import a higher one"
        ]
    );
}

#[test]
fn a_file_belongs_to_the_layer_of_its_longest_prefix() {
    let table = Table::parse("low: src/stages/hekf/system.rs\nhigh: src/stages\n", "t").unwrap();
    assert_eq!(
        table.layer_of("src/stages/hekf/system.rs"),
        Some((0, "low"))
    );
    assert_eq!(table.layer_of("src/stages/hekf/mod.rs"), Some((1, "high")));
    assert_eq!(table.layer_of("src/stagesx.rs"), None);
    assert_eq!(table.layer_of("src/other.rs"), None);
}

#[test]
fn a_file_in_no_layer_a_stale_prefix_and_a_malformed_table_are_faults() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod a;\npub mod b;\n"),
        ("src/a.rs", ""),
        ("src/b.rs", ""),
    ]);
    let table = Table::parse("base: src/a.rs src/gone/\n", "layers.txt").unwrap();
    let report = check(dir.path(), Some(&table)).unwrap();
    let messages: Vec<String> = report.faults.iter().map(|f| f.to_string()).collect();
    assert_eq!(
        messages,
        [
            "src/b.rs is in no layer of layers.txt: add it (or its folder) to the layer it \
             belongs to",
            "layers.txt line 1: `src/gone/` is no file or folder of src/ (misspelt, or moved \
             since the table was written)",
        ]
    );
    let errors = Table::parse("base src/a.rs\nio: src/b.rs\nup: src/b.rs\nx:\n", "l.txt");
    assert_eq!(
        errors.unwrap_err(),
        [
            "l.txt line 1: expected `name: path-prefix path-prefix ...`, found `base src/a.rs`",
            "l.txt line 3: `src/b.rs` is already in layer io (line 2); a file or folder \
             belongs to one layer",
            "l.txt line 4: expected `name: path-prefix path-prefix ...` (a name and at least \
             one prefix), found `x:`",
        ]
    );
}

#[test]
fn grouped_and_nested_use_paths_are_each_an_import() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod a;\npub mod f;\npub mod top;\n"),
        ("src/a/mod.rs", "pub mod b;\n"),
        ("src/a/b/mod.rs", "pub mod d;\n"),
        ("src/a/b/d.rs", ""),
        ("src/f.rs", ""),
        (
            "src/top.rs",
            "use crate::{\n    a::{self, b::{C, d::{E, G as H}}},\n    f::*,\n};\n",
        ),
    ]);
    let got = imports_of(dir.path(), "src/top.rs");
    let want = vec![
        (
            "src/a/b/d.rs".to_string(),
            vec![at(1, "crate::a::b::d::E"), at(1, "crate::a::b::d::GasH")],
        ),
        ("src/a/b/mod.rs".to_string(), vec![at(1, "crate::a::b::C")]),
        ("src/a/mod.rs".to_string(), vec![at(1, "crate::a")]),
        ("src/f.rs".to_string(), vec![at(1, "crate::f")]),
    ];
    assert_eq!(got, want);
    assert_eq!(
        reading::source::expand("a::{b,c::{d,e},self}"),
        ["a::b", "a::c::d", "a::c::e", "a"]
    );
}

#[test]
fn super_and_self_paths_count_from_the_file_s_module() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod x;\n"),
        ("src/x/mod.rs", "pub mod w;\npub mod y;\n"),
        ("src/x/w.rs", ""),
        (
            "src/x/y/mod.rs",
            "pub mod z;\npub mod sib;\nuse self::sib::S;\n",
        ),
        ("src/x/y/sib.rs", ""),
        (
            "src/x/y/z.rs",
            "use super::super::w::V;\nfn f() { super::sib::g(); }\n",
        ),
    ]);
    assert_eq!(
        imports_of(dir.path(), "src/x/y/z.rs"),
        [
            ("src/x/w.rs".to_string(), vec![at(1, "crate::x::w::V")]),
            (
                "src/x/y/sib.rs".to_string(),
                vec![at(2, "crate::x::y::sib::g")]
            ),
        ]
    );
    assert_eq!(targets_of(dir.path(), "src/x/y/mod.rs"), ["src/x/y/sib.rs"]);
}

#[test]
fn paths_used_inline_in_code_are_imports_but_comments_and_other_crates_are_not() {
    let text = "//! See [crate::docs_only].\n\
                /* crate::in_block\n   comment */\n\
                use std::fmt;\nuse nalgebra::Vector3;\n\
                fn f() -> u8 {\n    let u = crate::units::Unit::Metre; // crate::trailing\n\
                    self::g(u)\n}\n";
    let dir = crate_with(&[
        (
            "src/lib.rs",
            "pub mod units;\npub mod docs_only;\npub mod in_block;\n",
        ),
        (
            "src/main.rs",
            "mod trailing;\nuse trailing::T;\nfn main() { hydroid::units::f(); }\n",
        ),
        ("src/units.rs", "pub enum Unit { Metre }\n"),
        ("src/docs_only.rs", ""),
        ("src/in_block.rs", ""),
        ("src/trailing.rs", ""),
        ("src/code.rs", text),
    ]);
    assert_eq!(
        imports_of(dir.path(), "src/code.rs"),
        [(
            "src/units.rs".to_string(),
            vec![at(7, "crate::units::Unit::Metre")]
        )]
    );
    // A child module named directly is an import of the crate root; `hydroid::` is not.
    assert_eq!(targets_of(dir.path(), "src/main.rs"), ["src/trailing.rs"]);
}

#[test]
fn a_test_module_s_imports_are_ignored() {
    let dir = crate_with(&[
        ("src/lib.rs", "pub mod a;\npub mod b;\n"),
        (
            "src/a.rs",
            "pub fn f() {}\n\n#[cfg(test)]\nmod tests {\n    use crate::b::g;\n}\n",
        ),
        ("src/b.rs", "pub fn g() { crate::a::f() }\n"),
    ]);
    assert!(targets_of(dir.path(), "src/a.rs").is_empty());
    assert_eq!(targets_of(dir.path(), "src/b.rs"), ["src/a.rs"]);
    assert!(check(dir.path(), None).unwrap().cycles.is_empty());
}
