//! Hostile cases of the exports (issue 48): `hydroid export fmu` and `hydroid simulate` aimed
//! at the run's own inputs and configuration, its output folder, the record of exports, other
//! exports, earlier FMUs, folders, links, pipes and devices. docs/outputs.md says what is
//! refused and why. The library, `--max-step` and the folders exported are in hostile/fmu.rs,
//! which shares the set-up steps here.

use super::{copy_run_output, refused, run_table, Case, Expect};
use crate::common;
use hydroid::app::export::fmu::library::stand_in_fmi;
use sha2::{Digest, Sha256};
use std::path::Path;

/// The stand-in FMI library every case that needs a valid one gives with `--library`.
pub(super) const LIB: &str = "lib.so";
/// The state series of the spheroid run's first fit run.
pub(super) const STATES: &str = "states/paper_manoeuvre_u0_3_v0_1_m_s_22_N.csv";

fn sha(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Makes the copied output folder `out/NAME` the case's own: its rerun.json's configuration
/// folder becomes the case's configs/ (the shared set-up run was made elsewhere), and its
/// marker records the new rerun.json, so that the run's inputs are this copy's files.
fn rebase(d: &Path, name: &str) {
    let run = d.join("out").join(name);
    let path = run.join("rerun.json");
    let mut rerun: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let configs = std::fs::canonicalize(d.join("configs")).unwrap();
    rerun["base_dir"] = configs.to_string_lossy().into_owned().into();
    let bytes = serde_json::to_vec_pretty(&rerun).unwrap();
    std::fs::write(&path, &bytes).unwrap();
    let marker_path = run.join(".hydroid-output.json");
    let mut marker: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&marker_path).unwrap()).unwrap();
    marker["files"]["rerun.json"] = sha(&bytes).into();
    std::fs::write(&marker_path, serde_json::to_vec_pretty(&marker).unwrap()).unwrap();
}

/// The run of `config` (with `args`) as the case's own `out/NAME`, and the stand-in library.
pub(super) fn run_as(d: &Path, config: &str, args: &[&str], name: &str) {
    copy_run_output(d, config, args, name);
    rebase(d, name);
    std::fs::write(d.join(LIB), stand_in_fmi()).unwrap();
}

/// The spheroid run as out/s.
pub(super) fn spheroid(d: &Path) {
    run_as(d, "configs/spheroid.toml", &[], "s");
}

/// The KVLCC2 run as out/k (the run of the issue's data loss).
fn kvlcc2(d: &Path) {
    run_as(d, "configs/ship_kvlcc2.toml", &[], "k");
}

/// The spheroid run and an FMU exported from it to `to`.
pub(super) fn spheroid_and_fmu(d: &Path, to: &str) {
    spheroid(d);
    let o = common::hydroid_in(d, &["export", "fmu", "out/s", "-o", to, "--library", LIB]);
    assert!(o.status.success(), "{}", common::text(&o.stderr));
}

/// `export fmu RUN -o OUT --library lib.so EXTRA`.
pub(super) fn export(run: &str, out: &str, extra: &str) -> String {
    format!("export fmu out/{run} -o {out} --library {LIB} {extra}")
}

/// The record of `dir` with `name` listed as an FMU of its present contents.
fn list_as_fmu(d: &Path, dir: &str, name: &str) {
    let path = d.join(dir).join(".hydroid-exports.json");
    let mut record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let contents = std::fs::read(d.join(dir).join(name)).unwrap_or_default();
    record["files"][name] = serde_json::json!({"sha256": sha(&contents), "kind": "fmu"});
    std::fs::write(&path, serde_json::to_vec_pretty(&record).unwrap()).unwrap();
}

pub(super) fn mkfifo(p: &Path) {
    let status = std::process::Command::new("mkfifo").arg(p).status();
    assert!(status.is_ok_and(|s| s.success()), "mkfifo {}", p.display());
}

#[test]
fn an_fmu_never_lands_on_the_run_it_exports() {
    let input = |name: &str, file: &str, key: &str| {
        Case::new(
            name,
            &export("k", &format!("cfd_exports/{file}"), ""),
            refused(&["refusing", file, "an input of the run", key]),
        )
        .setup(kvlcc2)
    };
    let cases = vec![
        // the issue's data loss
        input("fit input", "kvlcc2_turn35.csv", "hekf.runs[0]"),
        input("second fit input", "kvlcc2_turn35_port.csv", "hekf.runs[1]"),
        input(
            "validation input",
            "kvlcc2_zigzag20.csv",
            "hekf.validation[0]",
        ),
        Case::new(
            "fit input, forced",
            &export("k", "cfd_exports/kvlcc2_turn35.csv", "--force"),
            refused(&["refusing", "an input of the run", "even with --force"]),
        )
        .setup(kvlcc2),
        Case::new(
            "fit input, spelt with ..",
            &export("k", "./cfd_exports/../cfd_exports/kvlcc2_turn35.csv", ""),
            refused(&["refusing", "an input of the run"]),
        )
        .setup(kvlcc2),
        Case::new(
            "fit input through a linked folder",
            &export("k", "exports/kvlcc2_turn35.csv", "--force"),
            refused(&["refusing", "an input of the run"]),
        )
        .setup(|d| {
            kvlcc2(d);
            std::os::unix::fs::symlink(d.join("cfd_exports"), d.join("exports")).unwrap();
        }),
        Case::new(
            "the run's configuration",
            &export("k", "configs/ship_kvlcc2.toml", "--force"),
            refused(&[
                "refusing",
                "ship_kvlcc2.toml",
                "the configuration of the run",
            ]),
        )
        .setup(kvlcc2),
        Case::new(
            "the run's configuration, spelt with ..",
            &export("k", "configs/vehicles/../ship_kvlcc2.toml", ""),
            refused(&["refusing", "the configuration of the run"]),
        )
        .setup(kvlcc2),
    ];
    run_table("exports (the KVLCC2 run's inputs)", cases);
}

/// Only the run's inputs stop these: the record lists them as FMUs, one is gone, or its
/// stage was disabled; and every input of the spheroid run.
#[test]
fn an_input_listed_as_an_fmu_removed_or_of_a_disabled_stage_is_refused() {
    let mut cases = vec![
        // the record says FMU (a file hydroid may replace): only the run's inputs stop it
        Case::new(
            "input listed as an FMU",
            &export("k", "cfd_exports/kvlcc2_turn35.csv", ""),
            refused(&["refusing", "an input of the run", "hekf.runs[0]"]),
        )
        .setup(|d| {
            kvlcc2(d);
            list_as_fmu(d, "cfd_exports", "kvlcc2_turn35.csv");
        }),
        Case::new(
            "input listed as an FMU, forced",
            &export("k", "cfd_exports/kvlcc2_zigzag20.csv", "--force"),
            refused(&["refusing", "an input of the run"]),
        )
        .setup(|d| {
            kvlcc2(d);
            list_as_fmu(d, "cfd_exports", "kvlcc2_zigzag20.csv");
        }),
        Case::new(
            "configuration listed as an FMU",
            &export("k", "configs/ship_kvlcc2.toml", "--force"),
            refused(&["refusing", "the configuration of the run"]),
        )
        .setup(|d| {
            kvlcc2(d);
            std::fs::write(
                d.join("configs/.hydroid-exports.json"),
                r#"{"format": "hydroid-exports/2", "files": {}}"#,
            )
            .unwrap();
            list_as_fmu(d, "configs", "ship_kvlcc2.toml");
        }),
        Case::new(
            "input removed since the run",
            &export("k", "cfd_exports/kvlcc2_turn35_port.csv", "--force"),
            refused(&["refusing", "an input of the run", "hekf.runs[1]"]),
        )
        .setup(|d| {
            kvlcc2(d);
            std::fs::remove_file(d.join("cfd_exports/kvlcc2_turn35_port.csv")).unwrap();
        }),
        // an input of a stage the run had disabled (config.toml still names it)
        Case::new(
            "input of a disabled stage",
            &export("d", "cfd_exports/surge_run.csv", "--force"),
            refused(&["refusing", "an input of the run", "surge"]),
        )
        .setup(|d| {
            // Xud, which the surge stage gives, fixed instead
            let set = [
                "--set",
                "surge.enabled=false",
                "--set",
                "coefficients.Xud=-0.3",
            ];
            run_as(d, "configs/spheroid.toml", &set, "d");
            list_as_fmu(d, "cfd_exports", "surge_run.csv");
        }),
        Case::new(
            "the spheroid's configuration",
            &export("s", "configs/spheroid.toml", ""),
            refused(&["refusing", "the configuration of the run"]),
        )
        .setup(spheroid),
    ];
    for (file, key) in [
        ("polar_sweep.csv", "polar"),
        ("surge_run.csv", "surge"),
        ("turn_paper.csv", "hekf.runs[0]"),
        ("turn_validation.csv", "hekf.validation[0]"),
    ] {
        cases.push(
            Case::new(
                &format!("spheroid input {file}"),
                &export("s", &format!("cfd_exports/{file}"), "--force"),
                refused(&["refusing", file, "an input of the run", key]),
            )
            .setup(spheroid),
        );
    }
    run_table("exports (the run's inputs)", cases);
}

#[test]
fn an_fmu_never_lands_in_an_output_folder_or_on_a_record() {
    let inside = |name: &str, out: &str| {
        Case::new(
            name,
            &export("s", out, "--force"),
            refused(&["refusing", "output folder of a run"]),
        )
        .setup(spheroid)
    };
    let cases = vec![
        inside("results.json", "out/s/results.json"),
        inside("config.toml", "out/s/config.toml"),
        inside("inputs.json", "out/s/inputs.json"),
        inside("rerun.json", "out/s/rerun.json"),
        inside("the marker", "out/s/.hydroid-output.json"),
        inside("a state series", &format!("out/s/{STATES}")),
        inside("a new file in the output", "out/s/vessel.fmu"),
        inside("a new file in a plots folder", "out/s/plots/vessel.fmu"),
        inside("a new folder in the output", "out/s/fmu/vessel.fmu"),
        Case::new(
            "the output folder itself",
            &export("s", "out/s", "--force"),
            refused(&["refusing", "folder"]),
        )
        .setup(spheroid),
        Case::new(
            "the folder of outputs",
            &export("s", "out", ""),
            refused(&["refusing", "folder"]),
        )
        .setup(spheroid),
        Case::new(
            "the record of exports",
            &export("s", "cfd_exports/.hydroid-exports.json", "--force"),
            refused(&["refusing", "record of exports"]),
        )
        .setup(spheroid),
        Case::new(
            "a record's name where there is none",
            &export("s", ".hydroid-exports.json", ""),
            refused(&["refusing", "record of exports"]),
        )
        .setup(spheroid),
    ];
    run_table("exports (output folders and records)", cases);
}

#[test]
fn an_fmu_never_replaces_a_simulations_export() {
    let cases = vec![
        Case::new(
            "a simulation's export the run does not read",
            &export("k", "cfd_exports/surge_run.csv", ""),
            refused(&["refusing", "hydroid simulate", "an FMU never replaces it"]),
        )
        .setup(kvlcc2),
        Case::new(
            "a simulation's export, forced",
            &export("k", "cfd_exports/npsauv_helix.dat", "--force"),
            refused(&["refusing", "an FMU never replaces it"]),
        )
        .setup(kvlcc2),
        Case::new(
            "another run's input",
            &export("s", "cfd_exports/kvlcc2_captive.csv", "--force"),
            refused(&["refusing", "an FMU never replaces it"]),
        )
        .setup(spheroid),
        Case::new(
            "a simulation's export elsewhere",
            &export("s", "sims/surge.csv", "--force"),
            refused(&["refusing", "an FMU never replaces it"]),
        )
        .setup(|d| {
            spheroid(d);
            let sim = "configs/simulate/polar_sweep.toml";
            let o = common::hydroid_in(d, &["simulate", sim, "--out", "sims/surge.csv"]);
            assert!(o.status.success(), "{}", common::text(&o.stderr));
        }),
    ];
    run_table("exports (an FMU onto simulations' exports)", cases);
}

#[test]
fn a_simulation_replaces_neither_an_fmu_nor_another_simulations_export() {
    let cases = vec![
        Case::new(
            "a simulation onto an FMU",
            "simulate configs/simulate/surge_run.toml --out v.fmu",
            refused(&["refusing", "a simulation never replaces it"]),
        )
        .setup(|d| spheroid_and_fmu(d, "v.fmu")),
        Case::new(
            "a simulation onto an FMU, forced",
            "simulate configs/simulate/surge_run.toml --out v.fmu --force",
            refused(&["refusing", "a simulation never replaces it"]),
        )
        .setup(|d| spheroid_and_fmu(d, "v.fmu")),
        Case::new(
            "a simulation onto another simulation's export (a run's input)",
            "simulate configs/simulate/turn_validation.toml --out cfd_exports/turn_paper.csv",
            refused(&[
                "refusing",
                "another simulation",
                "turn_paper.toml",
                "--force",
            ]),
        ),
        Case::new(
            "a simulation onto another simulation's export, forced",
            "simulate configs/simulate/turn_validation.toml --out cfd_exports/turn_paper.csv \
             --force",
            Expect::Fine,
        )
        .may_change(&[
            "cfd_exports/turn_paper.csv",
            "cfd_exports/.hydroid-exports.json",
        ]),
        Case::new(
            "a simulation regenerates its own export",
            "simulate configs/simulate/surge_run.toml",
            Expect::Fine,
        )
        .may_change(&["cfd_exports/.hydroid-exports.json"]),
        Case::new(
            "a simulation onto its configuration",
            "simulate configs/simulate/surge_run.toml --out configs/simulate/surge_run.toml \
             --force",
            refused(&["refusing", "the simulation's configuration"]),
        ),
        Case::new(
            "a simulation into a run's output",
            "simulate configs/simulate/surge_run.toml --out out/s/surge.csv",
            refused(&["refusing", "output folder of a run"]),
        )
        .setup(spheroid),
        // a record of the first format does not say which simulation wrote an export: any
        // simulation replaces it (docs/outputs.md, what is not protected)
        Case::new(
            "a first-format record",
            "simulate configs/simulate/turn_validation.toml --out cfd_exports/turn_paper.csv",
            Expect::Fine,
        )
        .setup(|d| {
            let p = d.join("cfd_exports/turn_paper.csv");
            let first = format!(
                r#"{{"format": "hydroid-exports/1", "files": {{"turn_paper.csv": "{}"}}}}"#,
                sha(&std::fs::read(&p).unwrap())
            );
            std::fs::write(d.join("cfd_exports/.hydroid-exports.json"), first).unwrap();
        })
        .may_change(&[
            "cfd_exports/turn_paper.csv",
            "cfd_exports/.hydroid-exports.json",
        ]),
    ];
    run_table("exports (simulations onto exports)", cases);
}

#[test]
fn an_fmu_replaces_only_its_own_earlier_fmu() {
    let fmu_at = |to: &'static str| move |d: &Path| spheroid_and_fmu(d, to);
    let cases = vec![
        Case::new("again", &export("s", "v.fmu", ""), Expect::Fine)
            .setup(fmu_at("v.fmu"))
            .may_change(&["v.fmu", ".hydroid-exports.json"]),
        Case::new(
            "another run onto it",
            &export("k", "v.fmu", ""),
            Expect::Fine,
        )
        .setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            kvlcc2(d);
        })
        .may_change(&["v.fmu", ".hydroid-exports.json"]),
        Case::new(
            "again, in the exports folder",
            &export("s", "cfd_exports/v.fmu", ""),
            Expect::Fine,
        )
        .setup(fmu_at("cfd_exports/v.fmu"))
        .may_change(&["cfd_exports/v.fmu", "cfd_exports/.hydroid-exports.json"]),
        Case::new(
            "edited since",
            &export("s", "v.fmu", ""),
            refused(&["refusing", "changed since", "--force"]),
        )
        .setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            std::fs::write(d.join("v.fmu"), "my notes").unwrap();
        }),
        Case::new(
            "edited since, forced",
            &export("s", "v.fmu", "--force"),
            Expect::Fine,
        )
        .setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            std::fs::write(d.join("v.fmu"), "my notes").unwrap();
        })
        .may_change(&["v.fmu", ".hydroid-exports.json"]),
        Case::new("removed since", &export("s", "v.fmu", ""), Expect::Fine).setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            std::fs::remove_file(d.join("v.fmu")).unwrap();
        }),
    ];
    run_table("exports (earlier FMUs)", cases);
}

#[test]
fn foreign_files_links_and_damaged_records_stop_an_fmu() {
    let cases = vec![
        Case::new(
            "a foreign file",
            &export("s", "notes.txt", "--force"),
            refused(&["refusing", "hydroid did not write it"]),
        )
        .setup(|d| {
            spheroid(d);
            std::fs::write(d.join("notes.txt"), "mine").unwrap();
        }),
        Case::new(
            "a foreign FMU beside hydroid's",
            &export("s", "mine.fmu", "--force"),
            refused(&["refusing", "hydroid did not write it"]),
        )
        .setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            std::fs::write(d.join("mine.fmu"), "PK").unwrap();
        }),
        Case::new(
            "a foreign file in the exports folder",
            &export("s", "cfd_exports/mine.fmu", "--force"),
            refused(&["refusing", "hydroid did not write it"]),
        )
        .setup(|d| {
            spheroid(d);
            std::fs::write(d.join("cfd_exports/mine.fmu"), "PK").unwrap();
        }),
        Case::new(
            "a link to an earlier FMU",
            &export("s", "link.fmu", "--force"),
            refused(&["refusing", "symbolic link"]),
        )
        .setup(|d| {
            spheroid_and_fmu(d, "v.fmu");
            std::os::unix::fs::symlink(d.join("v.fmu"), d.join("link.fmu")).unwrap();
        }),
        Case::new(
            "a garbled record",
            &export("s", "v.fmu", ""),
            refused(&[".hydroid-exports.json", "not a hydroid record of exports"]),
        )
        .setup(|d| {
            spheroid(d);
            std::fs::write(d.join(".hydroid-exports.json"), "{ not json").unwrap();
        }),
        Case::new(
            "a record of another format",
            &export("s", "v.fmu", ""),
            refused(&[".hydroid-exports.json", "format 'hydroid-exports/9'"]),
        )
        .setup(|d| {
            spheroid(d);
            let r = r#"{"format": "hydroid-exports/9", "files": {}}"#;
            std::fs::write(d.join(".hydroid-exports.json"), r).unwrap();
        }),
        Case::new(
            "a record that is a folder",
            &export("s", "v.fmu", ""),
            refused(&[".hydroid-exports.json", "not a file"]),
        )
        .setup(|d| {
            spheroid(d);
            std::fs::create_dir(d.join(".hydroid-exports.json")).unwrap();
        }),
        Case::new(
            "a huge record",
            &export("s", "v.fmu", ""),
            refused(&[".hydroid-exports.json", "larger than"]),
        )
        .setup(|d| {
            spheroid(d);
            let f = std::fs::File::create(d.join(".hydroid-exports.json")).unwrap();
            f.set_len(1 << 30).unwrap();
        }),
    ];
    run_table("exports (foreign files and records)", cases);
}

#[test]
fn an_fmu_is_written_only_as_a_file() {
    let place = |name: &str, out: &str, words: &[&str]| {
        Case::new(name, &export("s", out, "--force"), refused(words)).setup(spheroid)
    };
    let cases = vec![
        place("the exports folder", "cfd_exports", &["refusing", "folder"]),
        place("the configs folder", "configs", &["refusing", "folder"]),
        place("the working folder", ".", &["refusing", "folder"]),
        place("the root", "/", &["refusing"]),
        place("/dev/null", "/dev/null", &["refusing", "character device"]),
        place("/dev/full", "/dev/full", &["refusing", "character device"]),
        place("/dev/zero", "/dev/zero", &["refusing", "character device"]),
        place(
            "below a device",
            "/dev/null/v.fmu",
            &["/dev/null", "not a folder"],
        ),
        place(
            "a file of /proc",
            "/proc/version",
            &["refusing", "hydroid did not write it"],
        ),
        place(
            "below a file",
            "cfd_exports/surge_run.csv/v.fmu",
            &["surge_run.csv", "not a folder"],
        ),
        place("a tilde", "~/v.fmu", &["does not expand"]),
        Case::new(
            "a dangling link",
            &export("s", "link.fmu", "--force"),
            refused(&["refusing", "symbolic link"]),
        )
        .setup(|d| {
            spheroid(d);
            std::os::unix::fs::symlink(d.join("nowhere.fmu"), d.join("link.fmu")).unwrap();
        }),
        Case::new(
            "a link to an input",
            &export("k", "link.csv", "--force"),
            refused(&["refusing", "symbolic link"]),
        )
        .setup(|d| {
            kvlcc2(d);
            let input = d.join("cfd_exports/kvlcc2_turn35.csv");
            std::os::unix::fs::symlink(input, d.join("link.csv")).unwrap();
        }),
        Case::new(
            "a named pipe",
            &export("s", "pipe.fmu", "--force"),
            refused(&["refusing", "named pipe"]),
        )
        .setup(|d| {
            spheroid(d);
            mkfifo(&d.join("pipe.fmu"));
        }),
        Case::new(
            "a new folder",
            &export("s", "new/deep/v.fmu", ""),
            Expect::Fine,
        )
        .setup(spheroid),
    ];
    // `-o ""` cannot be written in a space-separated line
    let mut cases = cases;
    cases.push(
        Case::with_args(
            "an empty name",
            ["export", "fmu", "out/s", "-o", "", "--library", LIB]
                .map(String::from)
                .to_vec(),
            refused(&["--out", "a value is required"]),
        )
        .setup(spheroid),
    );
    run_table("exports (places)", cases);
}
