//! `calibrate` and `plan` write into an existing output folder (issue 48): onto what is not
//! an output of `hydroid run`, an output edited since, or one replaced between runs, they
//! refuse naming what is wrong and write nothing; a folder replaced whole by another
//! complete output is an output like any other. (A folder replaced while they run is
//! tests/calibrate.rs's `a_folder_replaced_while_calibrate_runs_is_not_written`.)

use super::{copy_run_output, refused, run_table, Case, Expect};
use std::path::Path;

/// The shared set-up run's output at `dir/out/s`.
fn output(dir: &Path) {
    copy_run_output(dir, "configs/spheroid.toml", &[], "s");
}

/// The output at `dir/out/s`, then changed by `edit`.
fn edited(edit: fn(&Path)) -> impl Fn(&Path) + Send + Sync + Clone {
    move |dir: &Path| {
        output(dir);
        edit(&dir.join("out/s"));
    }
}

/// `calibrate` and `plan` onto `target`, each expecting a refusal with `words` (the verb's
/// own words are added: "refusing to calibrate" ...), set up by `setup`.
fn both(
    what: &str,
    target: &str,
    words: &[&str],
    setup: impl Fn(&Path) + Send + Sync + Clone + 'static,
) -> Vec<Case> {
    ["calibrate", "plan"]
        .iter()
        .map(|verb| {
            let extra = if *verb == "calibrate" {
                " --replicas 2"
            } else {
                ""
            };
            Case::new(
                &format!("{verb} onto {what}"),
                &format!("{verb} {target}{extra}"),
                refused(words),
            )
            .setup(setup.clone())
        })
        .collect()
}

fn nothing(_: &Path) {}

/// What is not an output of `hydroid run`.
fn not_outputs() -> Vec<Case> {
    let mut cases = Vec::new();
    cases.extend(both(
        "a folder of configurations",
        "configs",
        &["configs is not an output folder"],
        nothing,
    ));
    cases.push(Case::new(
        "calibrate onto a missing folder",
        "calibrate out/none",
        refused(&["out/none: no such output folder"]),
    ));
    // a plan's source that is no folder is a configuration
    cases.push(Case::new(
        "plan of a missing folder",
        "plan out/none",
        refused(&["out/none"]),
    ));
    cases.extend(both(
        "an output's sub-folder",
        "out/s/plots",
        &["not an output folder"],
        output,
    ));
    cases.extend(both(
        "a symbolic link to an output",
        "link",
        &["link is not an output folder", "symbolic link"],
        |d: &Path| {
            output(d);
            std::os::unix::fs::symlink(d.join("out/s"), d.join("link")).unwrap();
        },
    ));
    cases
}

/// Outputs changed since hydroid wrote them.
fn edited_outputs() -> Vec<Case> {
    let mut cases = Vec::new();
    cases.extend(both(
        "an output with a note added",
        "out/s",
        &["changed since hydroid wrote it", "added: notes.txt"],
        edited(|o| std::fs::write(o.join("notes.txt"), "mine").unwrap()),
    ));
    cases.extend(both(
        "an output with results.json edited",
        "out/s",
        &["changed: results.json"],
        edited(|o| {
            let t = std::fs::read_to_string(o.join("results.json")).unwrap();
            std::fs::write(o.join("results.json"), t.replace("\"value\"", "\"value\" ")).unwrap();
        }),
    ));
    cases.extend(both(
        "an output with config.toml edited",
        "out/s",
        &["config.toml"],
        edited(|o| {
            let mut t = std::fs::read_to_string(o.join("config.toml")).unwrap();
            t.push_str("\n# edited\n");
            std::fs::write(o.join("config.toml"), t).unwrap();
        }),
    ));
    cases.extend(both(
        "an output with a file removed",
        "out/s",
        &["removed or replaced: coefficients.csv"],
        edited(|o| std::fs::remove_file(o.join("coefficients.csv")).unwrap()),
    ));
    cases.extend(both(
        "an output without its marker",
        "out/s",
        &["not an output folder", ".hydroid-output.json"],
        edited(|o| std::fs::remove_file(o.join(".hydroid-output.json")).unwrap()),
    ));
    cases.extend(both(
        "an output with a marker of another format",
        "out/s",
        &["not an output folder", "format"],
        edited(|o| {
            std::fs::write(
                o.join(".hydroid-output.json"),
                r#"{"format":"x/9","files":{}}"#,
            )
            .unwrap()
        }),
    ));
    cases.extend(both(
        "an output whose marker lists a path outside it",
        "out/s",
        &["not a path inside the folder"],
        edited(|o| {
            let f = o.join(".hydroid-output.json");
            let t = std::fs::read_to_string(&f).unwrap();
            std::fs::write(
                &f,
                t.replacen("\"files\": {", "\"files\": {\"../x\": \"00\",", 1),
            )
            .unwrap()
        }),
    ));
    cases.extend(both(
        "an output with a file made a link",
        "out/s",
        &["symbolic link"],
        edited(|o| {
            std::fs::remove_file(o.join("coefficients.csv")).unwrap();
            std::os::unix::fs::symlink("/etc/hostname", o.join("coefficients.csv")).unwrap();
        }),
    ));
    cases
}

/// Files, devices, pipes, a bad replica count, and a folder replaced between runs.
fn other_places() -> Vec<Case> {
    let mut cases = Vec::new();
    cases.extend([
        Case::new(
            "calibrate onto a file",
            "calibrate configs/spheroid.toml",
            refused(&["not a folder"]),
        ),
        Case::new(
            "calibrate onto a device",
            "calibrate /dev/null",
            refused(&["/dev/null", "not a folder"]),
        ),
        Case::new(
            "calibrate onto a named pipe",
            "calibrate fifo",
            refused(&["named pipe"]),
        )
        .setup(|d: &Path| {
            let made = std::process::Command::new("mkfifo")
                .arg(d.join("fifo"))
                .status();
            assert!(made.unwrap().success());
        }),
        Case::new(
            "calibrate one replica",
            "calibrate out/s --replicas 1",
            refused(&["replicas"]),
        )
        .setup(output),
        // plan of a configuration writes nothing anywhere
        Case::new(
            "plan of a file that is no configuration",
            "plan cfd_exports/surge_run.csv",
            Expect::Any,
        ),
        // replaced between runs by another whole output: an output like any other
        Case::new(
            "calibrate onto a folder replaced between runs",
            "calibrate out/s --replicas 2",
            Expect::Fine,
        )
        .setup(|d: &Path| {
            output(d);
            std::fs::rename(d.join("out/s"), d.join("out/old")).unwrap();
            copy_run_output(d, "configs/spheroid.toml", &[], "s");
        })
        .may_change(&["out/s"]),
    ]);
    cases
}

#[test]
fn calibrate_and_plan_write_only_into_an_unchanged_output() {
    let mut cases = not_outputs();
    cases.extend(edited_outputs());
    cases.extend(other_places());
    run_table("writers", cases);
}
