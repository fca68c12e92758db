//! hydroid's long integration tests as one test binary that `cargo test` leaves out
//! (Cargo.toml: `test = false`), so that the contributor's loop, `cargo test`, runs in a
//! few minutes on a built tree (issue 53, item 6): the seed studies on independent
//! generators, the coverage and calibration-replica studies, the long identifications
//! and the Chromium rendering of every bundled report. `.ci/run` runs them as its own
//! step, and the README names it: `cargo test --test studies` (one module's tests:
//! `cargo test --test studies coverage::`).

#[path = "common/mod.rs"]
mod common;
#[path = "independent/mod.rs"]
mod independent;

#[path = "calibrate.rs"]
mod calibrate;
#[path = "coverage.rs"]
mod coverage;
#[path = "hekf_twin_tables.rs"]
mod hekf_twin_tables;
#[path = "independent_mmg.rs"]
mod independent_mmg;
#[path = "independent_nomoto.rs"]
mod independent_nomoto;
#[path = "independent_npsauv.rs"]
mod independent_npsauv;
#[path = "nomoto_crosscheck.rs"]
mod nomoto_crosscheck;
#[path = "npsauv_example.rs"]
mod npsauv_example;
#[path = "planner_kvlcc2.rs"]
mod planner_kvlcc2;
#[path = "report_chromium.rs"]
mod report_chromium;
#[path = "ship_identification.rs"]
mod ship_identification;
