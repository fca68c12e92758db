//! `hydroid manoeuvre CONFIG`: the measures of every HEKF run of a configuration, read as the
//! run reads it, with the reason for each measure a run cannot give.

mod common;

use common::{hydroid, text};

const LOGS: &str = "tests/fixtures/freerunning/manoeuvres.toml";

#[test]
fn measures_every_run_and_says_what_a_short_log_cannot_give() {
    let o = hydroid(&["manoeuvre", LOGS, "--scale", "45.7"]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(out.contains("turning circle 35 deg ("), "{out}");
    assert!(out.contains("zig-zag ("), "{out}");
    // these logs are short: every measure they cannot give says why, none is a number made up
    assert!(
        out.contains("advance (measured): the heading changes by"),
        "{out}"
    );
    assert!(out.contains("this needs 90 deg"), "{out}");
    assert!(!out.contains("NaN"), "{out}");
    // the IMO limits at full scale: 4.5 L and 5 L with L = 45.7 x 7 m
    assert!(out.contains("<= 1440 (MSC.137(76) 5.3.1)"), "{out}");
    assert!(out.contains("<= 1600 (MSC.137(76) 5.3.1)"), "{out}");
    let o = hydroid(&["manoeuvre", LOGS, "--json"]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    let runs = v.as_array().unwrap();
    assert_eq!(runs.len(), 2);
    assert!(
        runs[0]["turning_circle"]["advance"]["missing"].is_string(),
        "{v}"
    );
    assert!(
        runs[0]["checks"].as_array().unwrap().is_empty(),
        "no --scale: no IMO check"
    );
}

#[test]
fn a_run_without_rudder_or_a_bad_scale_is_refused_with_the_reason() {
    let o = hydroid(&["manoeuvre", "configs/spheroid.toml"]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(err.contains("cfd_exports/turn_paper.csv"), "{err}");
    assert!(
        err.contains("needs the rudder angle (or an execute time)"),
        "{err}"
    );
    let o = hydroid(&["manoeuvre", LOGS, "--scale", "0.5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("--scale must be a scale ratio of at least 1"));
}
