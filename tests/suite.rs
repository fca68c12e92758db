//! hydroid's integration tests as one test binary: each file of tests/ (but the two memory
//! tests, which read their own process's peak memory) is a module here, so the tests link
//! once and `cargo test` spreads all of them over the machine's threads instead of running
//! some sixty binaries one after another. One file's tests: `cargo test --test suite polar::`.
//! The seed, coverage and replica studies and the longest identifications are the modules of
//! tests/studies.rs instead, a target `cargo test` leaves out (`cargo test --test studies`),
//! so that this one runs in a few minutes on a built tree (issue 53, item 6).

#[path = "common/mod.rs"]
mod common;
#[path = "hostile/mod.rs"]
mod hostile;
#[path = "independent/mod.rs"]
mod independent;

#[path = "analytic.rs"]
mod analytic;
#[path = "attitude_quaternion.rs"]
mod attitude_quaternion;
#[path = "autopilot_adaptive.rs"]
mod autopilot_adaptive;
#[path = "autopilot_figures.rs"]
mod autopilot_figures;
#[path = "autopilot_plant.rs"]
mod autopilot_plant;
#[path = "autopilot_seas.rs"]
mod autopilot_seas;
#[path = "auv_manoeuvres.rs"]
mod auv_manoeuvres;
#[path = "bad_files.rs"]
mod bad_files;
#[path = "bad_inputs.rs"]
mod bad_inputs;
#[path = "calibrate_output.rs"]
mod calibrate_output;
#[path = "captive.rs"]
mod captive;
#[path = "captive_plausibility.rs"]
mod captive_plausibility;
#[path = "cli.rs"]
mod cli;
#[path = "cli_console.rs"]
mod cli_console;
#[path = "cli_export.rs"]
mod cli_export;
#[path = "cli_inspect.rs"]
mod cli_inspect;
#[path = "cli_manoeuvre.rs"]
mod cli_manoeuvre;
#[path = "config_errors.rs"]
mod config_errors;
#[path = "conformance.rs"]
mod conformance;
#[path = "diagnostics.rs"]
mod diagnostics;
#[path = "filter_variants.rs"]
mod filter_variants;
#[path = "formats.rs"]
mod formats;
#[path = "freerunning.rs"]
mod freerunning;
#[path = "fuzz_config.rs"]
mod fuzz_config;
#[path = "fuzz_readers.rs"]
mod fuzz_readers;
#[path = "hekf_twin.rs"]
mod hekf_twin;
#[path = "independent_generators.rs"]
mod independent_generators;
#[path = "independent_spheroid.rs"]
mod independent_spheroid;
#[path = "layers.rs"]
mod layers;
#[path = "manoeuvres.rs"]
mod manoeuvres;
#[path = "munk_moment.rs"]
mod munk_moment;
#[path = "nomoto.rs"]
mod nomoto;
#[path = "npsauv.rs"]
mod npsauv;
#[path = "output_safety.rs"]
mod output_safety;
#[path = "planner.rs"]
mod planner;
#[path = "plausibility.rs"]
mod plausibility;
#[path = "pmm.rs"]
mod pmm;
#[path = "polar.rs"]
mod polar;
#[path = "readme.rs"]
mod readme;
#[path = "real_captive.rs"]
mod real_captive;
#[path = "real_logs.rs"]
mod real_logs;
#[path = "real_manoeuvres.rs"]
mod real_manoeuvres;
#[path = "real_plausibility.rs"]
mod real_plausibility;
#[path = "report.rs"]
mod report;
#[path = "roundtrip.rs"]
mod roundtrip;
#[path = "ship_linear.rs"]
mod ship_linear;
#[path = "ships.rs"]
mod ships;
#[path = "states.rs"]
mod states;
#[path = "surge.rs"]
mod surge;
#[path = "sweep.rs"]
mod sweep;
