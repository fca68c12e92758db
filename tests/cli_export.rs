//! `hydroid export fmu` on the command line (docs/fmu.md): the archive it writes from an
//! output folder of the bundled KVLCC2 run, the same bytes twice, the files it refuses to
//! overwrite and the message for a missing library. (FMPy runs the FMU in
//! fmu/tests/test_fmu.py.)

use crate::common;

use common::{hydroid, run_config, text};
use hydroid::app::export::fmu::library::stand_in_fmi;
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
    // a stand-in for the library (an ELF shared object defining the FMI functions, not
    // loadable): the archive carries its bytes
    let lib = dir.path().join("libstand_in.so");
    std::fs::write(&lib, stand_in_fmi()).unwrap();
    let fmu = dir.path().join("vessel.fmu");

    let o = export(&run, &fmu, &lib);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("mmg3 model: 2 inputs, 6 outputs"));
    // the start values: the smoothed states at the first sample of the first fit run
    let states = run.join("states/35_deg_starboard_turn.csv");
    assert!(text(&o.stdout).contains("start values: the smoothed states"));
    assert_eq!(starts(&fmu), first_row(&states, "_smoothed"));
    let first = std::fs::read(&fmu).unwrap();
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(first.clone())).unwrap();
    let mut so = Vec::new();
    zip.by_name("binaries/linux64/hydroid_mmg3.so")
        .unwrap()
        .read_to_end(&mut so)
        .unwrap();
    assert_eq!(so, stand_in_fmi());
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
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("b.fmu").exists());
}

#[test]
fn a_folder_that_is_not_a_run_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let lib = dir.path().join("lib.so");
    std::fs::write(&lib, stand_in_fmi()).unwrap();
    let o = export(dir.path(), &dir.path().join("a.fmu"), &lib);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("no results.json"));
}

/// The start values of the FMU's states (resources/model.json), by name.
fn starts(fmu: &Path) -> Vec<(String, f64)> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut json = String::new();
    zip.by_name("resources/model.json")
        .unwrap()
        .read_to_string(&mut json)
        .unwrap();
    let model: serde_json::Value = serde_json::from_str(&json).unwrap();
    model["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["name"].as_str().unwrap().to_string(),
                s["start"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// The first row of a state series' columns `STATE{suffix} [unit]`, by state name, read
/// here with the csv crate (docs/results.md, "states/").
fn first_row(path: &Path, suffix: &str) -> Vec<(String, f64)> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().clone();
    let row = r.records().next().unwrap().unwrap();
    header
        .iter()
        .zip(row.iter())
        .filter_map(|(h, v)| {
            let name = h.split(' ').next().unwrap().strip_suffix(suffix)?;
            Some((name.to_string(), v.parse().unwrap()))
        })
        .collect()
}

#[test]
fn with_the_smoother_off_the_start_values_are_the_filtered_states() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    let config = common::root().join("configs/spheroid.toml");
    let o = run_config(&config, &run, &["hekf.smoother=false"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let states = run.join("states/paper_manoeuvre_u0_3_v0_1_m_s_22_N.csv");
    assert!(
        first_row(&states, "_smoothed").is_empty(),
        "the smoother was off"
    );
    let lib = dir.path().join("lib.so");
    std::fs::write(&lib, stand_in_fmi()).unwrap();
    let fmu = dir.path().join("s.fmu");
    let o = export(&run, &fmu, &lib);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("start values: the filtered states at the first sample of"),
        "{}",
        text(&o.stdout)
    );
    let want = first_row(&states, "_filtered");
    assert_eq!(want.len(), 6, "{want:?}");
    assert!(want.iter().any(|(_, v)| *v != 0.0));
    assert_eq!(starts(&fmu), want);
}
