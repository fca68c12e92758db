//! `hydroid simulate` with absurd manoeuvres: a PMM at 100 m/s or oscillating faster than its
//! sampling, an execute after the end, speeds no carriage runs at; each refused with the key
//! and the unit before anything is integrated.

use super::{edited, write};
use crate::hostile::{refused, run_table, Case, Expect};

/// `hydroid simulate` of configs/simulate/`base` with `edits`, written to out/case.csv.
fn sim(name: &str, base: &str, edits: &[(&str, &str)], expect: Expect) -> Case {
    let base = format!("configs/simulate/{base}");
    let edits: Vec<(String, String)> = edits
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    Case::new(
        name,
        "simulate configs/simulate/case.toml --out out/case.csv",
        expect,
    )
    .setup(move |d| {
        let pairs: Vec<(&str, &str)> = edits
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect();
        write(d, "configs/simulate/case.toml", &edited(d, &base, &pairs));
    })
}

const SWAY: &str = "spheroid_pmm_sway.toml";
const YAW: &str = "spheroid_pmm_yaw.toml";
const TURN: &str = "kvlcc2_turn35.toml";

/// A PMM's speed (`speed = "2 m/s"` of the sway run) replaced by `to`.
fn pmm_speed(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("speed = \"2 m/s\"", to)]
}

/// The sway run's amplitude (`amplitude = { v = "0.25 m/s" }`) replaced by `to`.
fn sway_amplitude(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("amplitude = { v = \"0.25 m/s\" }", to)]
}

/// The yaw run's amplitude (`amplitude = { r = "15 deg/s" }`) replaced by `to`.
fn yaw_amplitude(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("amplitude = { r = \"15 deg/s\" }", to)]
}

/// The sway run with frequency `f`, `duration` and `dt` replaced.
fn pmm_timing(name: &str, f: &str, duration: &str, dt: &str, expect: Expect) -> Case {
    let frequency = format!("frequency = \"{f}\"");
    let duration = format!("duration = {duration}");
    let dt = format!("dt = {dt}");
    let edits = [
        ("frequency = \"0.5 Hz\"", frequency.as_str()),
        ("duration = 10.0", duration.as_str()),
        ("dt = 0.01", dt.as_str()),
    ];
    sim(name, SWAY, &edits, expect)
}

/// PMM runs: their speeds.
fn pmm_speeds() -> Vec<Case> {
    vec![
        sim(
            "pmm at 100 m/s",
            SWAY,
            &pmm_speed("speed = \"100 m/s\""),
            refused(&["manoeuvre.speed", "100 m/s", "faster"]),
        ),
        sim(
            "pmm at 1e6 m/s",
            SWAY,
            &pmm_speed("speed = \"1e6 m/s\""),
            refused(&["manoeuvre.speed", "1e6 m/s"]),
        ),
        sim(
            "pmm at 200 km/h",
            SWAY,
            &pmm_speed("speed = \"200 km/h\""),
            refused(&["manoeuvre.speed", "55.56 m/s", "km/h"]),
        ),
        sim(
            "pmm at 100 (bare)",
            SWAY,
            &pmm_speed("speed = 100.0"),
            refused(&["manoeuvre.speed", "100 m/s"]),
        ),
        sim(
            "pmm at -2 m/s",
            SWAY,
            &pmm_speed("speed = \"-2 m/s\""),
            refused(&["manoeuvre.speed", "positive"]),
        ),
        sim(
            "pmm speed in deg",
            SWAY,
            &pmm_speed("speed = \"2 deg\""),
            refused(&["manoeuvre.speed", "deg"]),
        ),
        sim(
            "pmm at 4 kn",
            SWAY,
            &pmm_speed("speed = \"4 kn\""),
            Expect::Fine,
        ),
    ]
}

/// PMM runs: their sway and yaw amplitudes (and the yaw run's speed).
fn pmm_amplitudes() -> Vec<Case> {
    vec![
        sim(
            "sway amplitude 10 m/s",
            SWAY,
            &sway_amplitude("amplitude = { v = \"10 m/s\" }"),
            refused(&["manoeuvre.amplitude.v", "more than the speed"]),
        ),
        sim(
            "sway amplitude 1e6 m/s",
            SWAY,
            &sway_amplitude("amplitude = { v = \"1e6 m/s\" }"),
            refused(&["manoeuvre.amplitude.v", "beyond any plausible"]),
        ),
        sim(
            "sway amplitude in deg",
            SWAY,
            &sway_amplitude("amplitude = { v = \"0.25 deg\" }"),
            refused(&["manoeuvre.amplitude.v", "deg"]),
        ),
        sim(
            "sway amplitude negative",
            SWAY,
            &sway_amplitude("amplitude = { v = \"-0.25 m/s\" }"),
            refused(&["manoeuvre.amplitude.v", "positive"]),
        ),
        sim(
            "yaw amplitude 900 deg/s",
            YAW,
            &yaw_amplitude("amplitude = { r = \"900 deg/s\" }"),
            refused(&["manoeuvre.amplitude.r", "r' = r L / U"]),
        ),
        sim(
            "yaw amplitude 10 rad/s bare",
            YAW,
            &yaw_amplitude("amplitude = { r = 10.0 }"),
            refused(&["manoeuvre.amplitude.r", "10 rad/s"]),
        ),
        sim(
            "yaw amplitude 1e5 deg/s",
            YAW,
            &yaw_amplitude("amplitude = { r = \"1e5 deg/s\" }"),
            refused(&["manoeuvre.amplitude.r", "beyond any plausible"]),
        ),
        sim(
            "yaw amplitude in m/s",
            YAW,
            &yaw_amplitude("amplitude = { r = \"15 m/s\" }"),
            refused(&["manoeuvre.amplitude.r", "m/s"]),
        ),
        sim(
            "pmm at 100 m/s yaw",
            YAW,
            &pmm_speed("speed = \"100 m/s\""),
            refused(&["manoeuvre.speed", "100 m/s"]),
        ),
    ]
}

/// PMM runs: frequency, duration and sampling.
fn pmm_sampling() -> Vec<Case> {
    vec![
        pmm_timing(
            "50 Hz on a 1.2 m body",
            "50 Hz",
            "1.0",
            "0.0005",
            refused(&["manoeuvre.frequency", "omega'"]),
        ),
        pmm_timing(
            "1000 Hz at 100 Hz",
            "1000 Hz",
            "10.0",
            "0.01",
            refused(&["manoeuvre.dt", "fewer than 20 samples"]),
        ),
        pmm_timing(
            "frequency in rad/s",
            "3 rad/s",
            "10.0",
            "0.01",
            refused(&["manoeuvre.frequency", "rad/s"]),
        ),
        pmm_timing(
            "duration 1e9",
            "0.5 Hz",
            "1e9",
            "0.01",
            refused(&["manoeuvre.duration", "rows"]),
        ),
        pmm_timing(
            "dt 1e-9",
            "0.5 Hz",
            "10.0",
            "1e-9",
            refused(&["manoeuvre.duration", "rows"]),
        ),
        pmm_timing(
            "dt zero",
            "0.5 Hz",
            "10.0",
            "0.0",
            refused(&["manoeuvre.dt", "positive"]),
        ),
    ]
}

/// The turn's execute (`execute = "5 s"`) replaced by `to`.
fn execute(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("execute = \"5 s\"", to)]
}

/// The turn's initial state (`initial = { u = "1.179 m/s" }`) replaced by `to`.
fn initial(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("initial = { u = \"1.179 m/s\" }", to)]
}

/// The turn's inputs (`inputs = { rpm = "710.8 rpm" }`) replaced by `to`.
fn turn_rpm(to: &'static str) -> [(&'static str, &'static str); 1] {
    [("inputs = { rpm = \"710.8 rpm\" }", to)]
}

/// Time histories: the helm's execute, angle and rate.
fn helm() -> Vec<Case> {
    vec![
        sim(
            "execute at 1e6 s",
            TURN,
            &execute("execute = \"1e6 s\""),
            refused(&["manoeuvre.steering.execute", "1e6 s", "never act"]),
        ),
        sim(
            "execute at the end",
            TURN,
            &execute("execute = \"200 s\""),
            refused(&["manoeuvre.steering.execute", "200 s"]),
        ),
        sim(
            "execute in ms read as s",
            TURN,
            &execute("execute = 5000.0"),
            refused(&["manoeuvre.steering.execute", "5000 s"]),
        ),
        sim(
            "execute negative",
            TURN,
            &execute("execute = \"-5 s\""),
            refused(&["manoeuvre.steering.execute"]),
        ),
        sim(
            "execute in deg",
            TURN,
            &execute("execute = \"5 deg\""),
            refused(&["manoeuvre.steering.execute", "deg"]),
        ),
        sim(
            "rudder 95 deg",
            TURN,
            &[("rudder = \"35 deg\"", "rudder = \"95 deg\"")],
            refused(&["manoeuvre.steering.rudder", "57 deg"]),
        ),
        sim(
            "rudder 35 rad",
            TURN,
            &[("rudder = \"35 deg\"", "rudder = 35.0")],
            refused(&["manoeuvre.steering.rudder"]),
        ),
        sim(
            "rudder rate zero",
            TURN,
            &[("rate = \"15.8 deg/s\"", "rate = \"0 deg/s\"")],
            refused(&["manoeuvre.steering.rate"]),
        ),
    ]
}

/// Time histories: the initial state, the inputs, the sampling.
fn turn_state_and_sampling() -> Vec<Case> {
    vec![
        sim(
            "initial u 100 m/s",
            TURN,
            &initial("initial = { u = \"100 m/s\" }"),
            refused(&["manoeuvre.initial.u", "100 m/s", "faster"]),
        ),
        sim(
            "initial u 1e6 m/s",
            TURN,
            &initial("initial = { u = \"1e6 m/s\" }"),
            refused(&["manoeuvre.initial.u", "beyond any plausible"]),
        ),
        sim(
            "initial u in deg",
            TURN,
            &initial("initial = { u = \"1.179 deg\" }"),
            refused(&["manoeuvre.initial.u", "deg"]),
        ),
        sim(
            "initial r 1e3 rad/s",
            TURN,
            &initial("initial = { u = \"1.179 m/s\", r = 1000.0 }"),
            refused(&["manoeuvre.initial.r", "beyond any plausible"]),
        ),
        sim(
            "rpm 1e9 rpm",
            TURN,
            &turn_rpm("inputs = { rpm = \"1e9 rpm\" }"),
            refused(&["manoeuvre.inputs.rpm", "beyond any plausible"]),
        ),
        sim(
            "rpm in m/s",
            TURN,
            &turn_rpm("inputs = { rpm = \"710.8 m/s\" }"),
            refused(&["manoeuvre.inputs.rpm", "m/s"]),
        ),
        sim(
            "duration 1e9",
            TURN,
            &[("duration = 200", "duration = 1e9")],
            refused(&["manoeuvre.dt", "samples"]),
        ),
        sim(
            "dt 1e-9",
            TURN,
            &[("dt = 0.1", "dt = 1e-9")],
            refused(&["manoeuvre.dt", "samples"]),
        ),
        sim(
            "substeps 1e6",
            TURN,
            &[("substeps = 10", "substeps = 1000000")],
            refused(&["manoeuvre.substeps"]),
        ),
    ]
}

/// Captive programmes, polar and turning-circle sweeps: their speeds.
fn sweeps() -> Vec<Case> {
    let captive = "kvlcc2_captive.toml";
    vec![
        sim(
            "captive at 100 m/s",
            captive,
            &[("speeds = [1.179]", "speeds = [100.0]")],
            refused(&["manoeuvre.speeds[0]", "100 m/s"]),
        ),
        sim(
            "captive at 1e6 m/s",
            captive,
            &[("speeds = [1.179]", "speeds = [1.179, 1e6]")],
            refused(&["manoeuvre.speeds[1]", "1e6 m/s"]),
        ),
        sim(
            "captive drift 95 deg",
            captive,
            &[("drift_deg = [-16,", "drift_deg = [-95,")],
            refused(&["manoeuvre.drift_deg[0]"]),
        ),
        sim(
            "captive r' 5",
            captive,
            &[("yaw_rate_prime = [0,", "yaw_rate_prime = [5,")],
            refused(&["manoeuvre.yaw_rate_prime[0]"]),
        ),
        sim(
            "captive rudder 95 deg",
            captive,
            &[("rudder_deg = [-20,", "rudder_deg = [-95,")],
            refused(&["manoeuvre.rudder_deg[0]"]),
        ),
        sim(
            "polar at 1e6 m/s",
            "polar_sweep.toml",
            &[("speeds = [2.0, 3.0]", "speeds = [2.0, 1e6]")],
            refused(&["manoeuvre.speeds[1]", "1e6 m/s"]),
        ),
        sim(
            "polar alpha 1e3 deg",
            "polar_sweep.toml",
            &[("alpha_deg = [-12.0,", "alpha_deg = [-1000.0,")],
            refused(&["manoeuvre.alpha_deg[0]"]),
        ),
        sim(
            "sweep at 100 m/s",
            "kvlcc2_sweep.toml",
            &[("speed = [\"1.0 m/s\",", "speed = [\"100 m/s\",")],
            refused(&["sweep.speed[0]", "100 m/s"]),
        ),
        sim(
            "sweep rudder 95 deg",
            "kvlcc2_sweep.toml",
            &[("rudder = [\"10 deg\",", "rudder = [\"95 deg\",")],
            refused(&["sweep.rudder[0]"]),
        ),
    ]
}

#[test]
fn simulate_manoeuvres_are_bounded() {
    let mut cases = pmm_speeds();
    cases.extend(pmm_amplitudes());
    cases.extend(pmm_sampling());
    cases.extend(helm());
    cases.extend(turn_state_and_sampling());
    cases.extend(sweeps());
    let n = run_table("limits (simulate)", cases);
    assert!(n >= 40, "{n} cases");
}
