//! `hydroid export fmu` on the command line (docs/fmu.md): the archive it writes from an
//! output folder of the bundled KVLCC2 run, the same bytes twice, the files it refuses to
//! overwrite and the message for a missing library. (FMPy runs the FMU in
//! fmu/tests/test_fmu.py.)

use crate::common;

use common::{hydroid, run_config, text};
use std::io::Read;
use std::path::Path;

/// The KVLCC2 run's output folder in `dir`.
fn kvlcc2_run(dir: &Path) -> std::path::PathBuf {
    let out = dir.join("run");
    let o = run_config(&common::root().join("configs/ship_kvlcc2.toml"), &out, &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    out
}

fn export(run: &Path, fmu: &Path, library: &Path) -> std::process::Output {
    hydroid(&[
        "export",
        "fmu",
        run.to_str().unwrap(),
        "-o",
        fmu.to_str().unwrap(),
        "--library",
        library.to_str().unwrap(),
    ])
}

#[test]
fn exports_an_fmu_writes_it_again_identically_and_refuses_foreign_files() {
    let dir = tempfile::tempdir().unwrap();
    let run = kvlcc2_run(dir.path());
    // a stand-in for the library: the archive carries its bytes
    let lib = dir.path().join("libstand_in.so");
    std::fs::write(&lib, b"\x7fELF stand-in").unwrap();
    let fmu = dir.path().join("vessel.fmu");

    let o = export(&run, &fmu, &lib);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("mmg3 model: 2 inputs, 6 outputs"));
    let first = std::fs::read(&fmu).unwrap();
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(first.clone())).unwrap();
    let mut so = Vec::new();
    zip.by_name("binaries/linux64/hydroid_mmg3.so")
        .unwrap()
        .read_to_end(&mut so)
        .unwrap();
    assert_eq!(so, b"\x7fELF stand-in");
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    assert!(xml.contains("fmiVersion=\"2.0\"") && xml.contains("name=\"rudder\""));

    // again: replaces its own unchanged file with the same bytes
    let o = export(&run, &fmu, &lib);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(std::fs::read(&fmu).unwrap(), first, "deterministic");

    // a file hydroid did not write is never overwritten
    let foreign = dir.path().join("mine.fmu");
    std::fs::write(&foreign, b"not hydroid's").unwrap();
    let o = export(&run, &foreign, &lib);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("refusing"), "{}", text(&o.stderr));
    assert_eq!(std::fs::read(&foreign).unwrap(), b"not hydroid's");

    // a missing library says how to build it; a file that is not one is refused
    let o = export(&run, &dir.path().join("b.fmu"), &dir.path().join("none.so"));
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("cargo build -p hydroid-fmu"),
        "{}",
        text(&o.stderr)
    );
    let o = export(&run, &dir.path().join("b.fmu"), &run.join("results.json"));
    assert!(text(&o.stderr).contains("not a Linux shared library"));
    assert!(!dir.path().join("b.fmu").exists());
}

#[test]
fn a_folder_that_is_not_a_run_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let lib = dir.path().join("lib.so");
    std::fs::write(&lib, b"\x7fELF").unwrap();
    let o = export(dir.path(), &dir.path().join("a.fmu"), &lib);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("no results.json"));
}
