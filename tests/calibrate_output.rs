//! `hydroid calibrate` (docs/calibrate.md) as a writer of outputs: a folder that is not an
//! untouched output is refused naming what is wrong, and a folder replaced while calibrate
//! or plan runs is not written (issue 48). The replica studies are in tests/calibrate.rs, a
//! module of the studies target (tests/studies.rs).

use crate::common;

#[test]
fn calibrate_refuses_what_is_not_an_untouched_output() {
    let example = common::example_copy();
    // a folder hydroid did not write
    let configs = example.path().join("configs");
    let o = common::calibrate(&configs, 2, &[]);
    let stderr = common::text(&o.stderr);
    assert_ne!(o.status.code(), Some(0));
    assert!(
        stderr.contains(&format!(
            "{} is not an output folder of `hydroid run`",
            configs.display()
        )),
        "{stderr}"
    );
    assert!(!configs.join("calibration.json").exists());
    // no folder at all
    let o = common::calibrate(&example.path().join("nowhere"), 2, &[]);
    assert!(common::text(&o.stderr).contains("no such output folder"));
    // an output whose recorded configuration was edited
    let out = common::joint_run(example.path(), &[]);
    let config = out.join("config.toml");
    let mut text = std::fs::read_to_string(&config).unwrap();
    text.push_str("\n# edited\n");
    std::fs::write(&config, text).unwrap();
    let o = common::calibrate(&out, 2, &[]);
    let stderr = common::text(&o.stderr);
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr.contains("refusing to calibrate"), "{stderr}");
    assert!(stderr.contains("config.toml"), "{stderr}");
    assert!(!out.join("calibration.json").exists());
}

/// A folder another run replaced while `calibrate` or `plan` ran is not written into (issue
/// 48). Before writing, each waits for the lock on the folder it read (docs/outputs.md,
/// "Adding to an output"), which this test holds as a reader; once the command has read the
/// folder (its first note), the test puts another output in its place and lets go: the
/// command then finds another folder at the name, refuses and writes nothing in either.
/// The order is set by the lock, not by timing.
#[test]
fn a_folder_replaced_while_calibrate_or_plan_runs_is_not_written() {
    use crate::hostile::{copy_run_output, snapshot};
    use std::io::{BufRead, Read};
    use std::process::{Command, Stdio};
    for (verb, extra) in [("calibrate", &["--replicas", "2"][..]), ("plan", &[][..])] {
        let example = common::example_copy();
        let d = example.path();
        copy_run_output(d, "configs/spheroid.toml", &[], "a");
        copy_run_output(d, "configs/spheroid.toml", &[], "b");
        let (a, b, old) = (d.join("out/a"), d.join("out/b"), d.join("out/old"));
        let held = std::fs::File::open(&a).unwrap();
        held.lock_shared().unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_hydroid"))
            .arg(verb)
            .arg("out/a")
            .args(extra)
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
        let mut said = String::new();
        loop {
            let mut line = String::new();
            let n = err.read_line(&mut line).unwrap();
            assert!(n > 0, "{verb} ended before reading the folder: {said}");
            said.push_str(&line);
            if line.starts_with(&format!("{verb}:")) {
                break;
            }
        }
        // another run's output in place of the one read (the same run: the same files)
        std::fs::rename(&a, &old).unwrap();
        std::fs::rename(&b, &a).unwrap();
        let before = (snapshot(&a), snapshot(&old));
        drop(held);
        err.read_to_string(&mut said).unwrap();
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(2), "{verb}: {said}");
        let expected =
            format!("out/a was replaced by another run while {verb} ran; nothing written");
        assert!(said.contains(&expected), "{verb}: {said}");
        assert_eq!(
            (snapshot(&a), snapshot(&old)),
            before,
            "{verb} wrote something"
        );
    }
}
