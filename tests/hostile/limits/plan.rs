//! `hydroid plan` with a careless or hostile candidates file and settings: each absurd value
//! refused with the candidate's key and unit while the file is read (before the
//! identification), the ones that need the identified run (a manoeuvre's default sampling,
//! r' and omega' at the identified speed, the channels a run measures) right after it.

use super::write;
use crate::hostile::{copy_run_output, refused, run_table, warned, Case, Expect};

/// `hydroid plan` of the spheroid's output folder with one candidate `x` of `body`.
fn spheroid(name: &str, body: &str, expect: Expect) -> Case {
    file(
        name,
        "s",
        &format!("[[candidate]]\nname = \"x\"\n{body}\n"),
        expect,
    )
}

/// The same on the KVLCC2's output folder (a model with a rudder and captive forces).
fn kvlcc2(name: &str, body: &str, expect: Expect) -> Case {
    file(
        name,
        "k",
        &format!("[[candidate]]\nname = \"x\"\n{body}\n"),
        expect,
    )
}

/// `hydroid plan out/OUT --candidates c.toml` with `text` as c.toml.
fn file(name: &str, out: &str, text: &str, expect: Expect) -> Case {
    let text = text.to_string();
    let out = out.to_string();
    Case::new(name, &format!("plan out/{out} --candidates c.toml"), expect)
        .setup(move |d| {
            setup_output(d, &out);
            write(d, "c.toml", &text);
        })
        .may_change(&["out"])
}

/// The shared set-up run of `out`: `s` the spheroid, `k` the KVLCC2.
fn setup_output(d: &std::path::Path, out: &str) {
    let config = match out {
        "s" => "configs/spheroid.toml",
        _ => "configs/ship_kvlcc2.toml",
    };
    copy_run_output(d, config, &[], out);
}

/// `hydroid plan out/s ARGS` (settings, no candidates file).
fn settings(name: &str, args: &str, expect: Expect) -> Case {
    Case::new(name, &format!("plan out/s {args}"), expect)
        .setup(|d| setup_output(d, "s"))
        .may_change(&["out"])
}

/// Speeds and durations: refused while the file is read.
fn speeds_and_durations() -> Vec<Case> {
    let s = spheroid;
    vec![
        s(
            "speed 1e6",
            "kind = \"static\"\nspeed = 1e6",
            refused(&["candidate[0].speed", "1e6 m/s", "faster"]),
        ),
        s(
            "speed 100",
            "kind = \"static\"\nspeed = 100.0",
            refused(&["candidate[0].speed", "100 m/s"]),
        ),
        s(
            "speed negative",
            "kind = \"static\"\nspeed = -2.0",
            refused(&["candidate[0].speed", "positive"]),
        ),
        s(
            "speed zero",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 0.5\nspeed = 0.0",
            refused(&["candidate[0].speed", "positive"]),
        ),
        s(
            "speed nan",
            "kind = \"static\"\nspeed = nan",
            refused(&["candidate[0].speed", "not a finite number"]),
        ),
        s(
            "speed inf",
            "kind = \"free\"\nv0 = 0.5\nspeed = inf",
            refused(&["candidate[0].speed", "not a finite number"]),
        ),
        s(
            "speed as text",
            "kind = \"static\"\nspeed = \"2 m/s\"",
            refused(&["candidate[0].speed"]),
        ),
        s(
            "duration 1e9 captive",
            "kind = \"static\"\ndrift_deg = 5.0\nduration_s = 1e9",
            refused(&["candidate[0].duration_s", "1e9 s"]),
        ),
        s(
            "duration 1e9 manoeuvre",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 1e9",
            refused(&["candidate[0].duration_s", "1e9 s"]),
        ),
        s(
            "duration 1e7",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 1e7",
            refused(&["candidate[0].duration_s", "1e7 s", "86400"]),
        ),
        s(
            "duration negative",
            "kind = \"static\"\nduration_s = -10.0",
            refused(&["candidate[0].duration_s", "positive"]),
        ),
        s(
            "duration zero",
            "kind = \"static\"\nduration_s = 0.0",
            refused(&["candidate[0].duration_s", "positive"]),
        ),
    ]
}

/// Samples and costs: refused while the file is read (a manoeuvre at the run's sampling
/// right after the identification).
fn samples_and_costs() -> Vec<Case> {
    let s = spheroid;
    vec![
        s(
            "dt zero",
            "kind = \"static\"\ndt_s = 0.0",
            refused(&["candidate[0].dt_s", "positive"]),
        ),
        s(
            "dt nan",
            "kind = \"static\"\ndt_s = nan",
            refused(&["candidate[0].dt_s", "not a finite number"]),
        ),
        s(
            "captive at 1 us",
            "kind = \"static\"\ndrift_deg = 5.0\ndt_s = 1e-6",
            refused(&["candidate[0].dt_s", "1e7 samples", "200000"]),
        ),
        s(
            "pmm at 1 us",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = 0.5\ndt_s = 1e-6",
            refused(&["candidate[0].dt_s", "samples", "200000"]),
        ),
        s(
            "manoeuvre at 1 us",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 10.0\ndt_s = 1e-6",
            refused(&["candidate[0].dt_s", "1e7 samples"]),
        ),
        s(
            "manoeuvre long at 1 ms",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 1000.0\ndt_s = 1e-3",
            refused(&["candidate[0].dt_s", "1e6 samples"]),
        ),
        s(
            "dt beyond duration",
            "kind = \"static\"\ndt_s = 20.0",
            refused(&["candidate[0].dt_s", "longer than the run"]),
        ),
        s(
            "manoeuvre dt beyond duration",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 5.0\ndt_s = 6.0",
            refused(&["candidate[0].dt_s", "longer than the run"]),
        ),
        // the manoeuvre's sampling is the identified run's: known after the identification
        s(
            "manoeuvre 5e4 s at the run's sampling",
            "kind = \"free\"\nv0 = 0.5\nduration_s = 5e4",
            refused(&["candidate 'x'", "duration_s", "samples", "200000"]),
        ),
        s(
            "cost zero",
            "kind = \"static\"\ncost = 0.0",
            refused(&["candidate[0].cost", "cost must be positive"]),
        ),
        s(
            "cost negative",
            "kind = \"static\"\ncost = -40.0",
            refused(&["candidate[0].cost", "cost must be positive"]),
        ),
        s(
            "cost nan",
            "kind = \"static\"\ncost = nan",
            refused(&["candidate[0].cost", "not a finite number"]),
        ),
    ]
}

/// PMM runs: the sampling must resolve the motion; amplitude and frequency against the
/// speed and length.
fn pmm() -> Vec<Case> {
    let s = spheroid;
    vec![
        s(
            "1000 Hz at 100 Hz",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = 1000.0\ndt_s = 0.01",
            refused(&["candidate[0].frequency_hz", "Nyquist", "resolve"]),
        ),
        s(
            "1000 Hz at the default 100 Hz",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 1000.0",
            refused(&["candidate[0].frequency_hz", "Nyquist"]),
        ),
        s(
            "30 Hz at 100 Hz",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 30.0",
            refused(&["candidate[0].frequency_hz", "20 samples a period"]),
        ),
        s(
            "50 Hz at 1 kHz",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 60.0\ndt_s = 0.001",
            refused(&["candidate[0].frequency_hz", "samples a period"]),
        ),
        s(
            "less than a period",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = 0.01\nduration_s = 10.0",
            refused(&["candidate[0].duration_s", "whole periods"]),
        ),
        // the captive stage refuses fewer than two whole periods (issue 49, item 4)
        s(
            "1.9 periods",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = 0.19\nduration_s = 10.0",
            refused(&[
                "candidate[0].duration_s",
                "1.9 periods",
                "at least 2 whole periods",
            ]),
        ),
        s(
            "no amplitude",
            "kind = \"pmm_yaw\"\nfrequency_hz = 0.5",
            refused(&["candidate[0].amplitude", "PMM run needs"]),
        ),
        s(
            "negative frequency",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = -0.5",
            refused(&["candidate[0].frequency_hz", "positive frequency_hz"]),
        ),
        s(
            "nan frequency",
            "kind = \"pmm_yaw\"\namplitude = 15.0\nfrequency_hz = nan",
            refused(&["candidate[0].frequency_hz", "finite"]),
        ),
        s(
            "sway amplitude 1e6",
            "kind = \"pmm_sway\"\namplitude = 1e6\nfrequency_hz = 0.5",
            refused(&["candidate[0].amplitude", "1e6 m/s", "beyond any plausible"]),
        ),
        s(
            "yaw amplitude 1e6",
            "kind = \"pmm_yaw\"\namplitude = 1e6\nfrequency_hz = 0.5",
            refused(&["candidate[0].amplitude", "1e6 deg/s"]),
        ),
        s(
            "sway amplitude inf",
            "kind = \"pmm_sway\"\namplitude = inf\nfrequency_hz = 0.5",
            refused(&["candidate[0].amplitude", "finite"]),
        ),
        // against the identified speed (3 m/s) and length: after the identification
        s(
            "sway amplitude above U",
            "kind = \"pmm_sway\"\namplitude = 10.0\nfrequency_hz = 0.5",
            refused(&["candidate 'x'", "amplitude", "more than the speed"]),
        ),
        s(
            "sway amplitude above given U",
            "kind = \"pmm_sway\"\namplitude = 1.5\nfrequency_hz = 0.5\nspeed = 1.0",
            refused(&["candidate 'x'", "amplitude", "U = 1 m/s"]),
        ),
        s(
            "yaw amplitude r' 9",
            "kind = \"pmm_yaw\"\namplitude = 900.0\nfrequency_hz = 0.5",
            refused(&["candidate 'x'", "amplitude", "r' = r L / U"]),
        ),
        s(
            "frequency in rad/s",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 10.0\ndt_s = 0.001",
            refused(&["candidate 'x'", "frequency_hz", "omega'"]),
        ),
        s(
            "pmm drift key",
            "kind = \"pmm_sway\"\namplitude = 0.1\nfrequency_hz = 0.5\ndrift_deg = 5.0",
            refused(&["candidate[0].drift_deg", "not used by a pmm_sway candidate"]),
        ),
    ]
}

/// The helm: rudder angles against the quantity's magnitude and the helm's limit, zig-zag
/// changes, turns.
fn helm() -> Vec<Case> {
    let (s, k) = (spheroid, kvlcc2);
    vec![
        s(
            "rudder 95 deg",
            "kind = \"static\"\nrudder_deg = 95.0",
            refused(&["candidate[0].rudder_deg", "95 deg", "90 deg"]),
        ),
        s(
            "rudder -95 deg",
            "kind = \"static\"\nrudder_deg = -95.0",
            refused(&["candidate[0].rudder_deg", "-95 deg"]),
        ),
        k(
            "static rudder 95 deg",
            "kind = \"static\"\nrudder_deg = 95.0",
            refused(&["candidate[0].rudder_deg", "95 deg"]),
        ),
        k(
            "turn rudder 95 deg",
            "kind = \"turn\"\nrudder_deg = 95.0",
            refused(&["candidate[0].rudder_deg", "95 deg"]),
        ),
        k(
            "turn rudder 70 deg",
            "kind = \"turn\"\nrudder_deg = 70.0",
            refused(&["candidate[0].rudder_deg", "57 deg"]),
        ),
        k(
            "zigzag rudder 1e3 deg",
            "kind = \"zigzag\"\nrudder_deg = 1000.0\nheading_deg = 10.0",
            refused(&["candidate[0].rudder_deg", "1000 deg"]),
        ),
        k(
            "zigzag heading 200 deg",
            "kind = \"zigzag\"\nrudder_deg = 10.0\nheading_deg = 200.0",
            refused(&["candidate[0].heading_deg", "180"]),
        ),
        k(
            "zigzag without heading",
            "kind = \"zigzag\"\nrudder_deg = 10.0",
            refused(&["candidate[0].heading_deg", "zig-zag needs"]),
        ),
        k(
            "turn without rudder",
            "kind = \"turn\"",
            refused(&["candidate[0].rudder_deg", "turn needs rudder_deg"]),
        ),
        k(
            "turn 1e7 s",
            "kind = \"turn\"\nrudder_deg = 35.0\nduration_s = 1e7",
            refused(&["candidate[0].duration_s", "1e7 s"]),
        ),
        k(
            "turn at 1 us",
            "kind = \"turn\"\nrudder_deg = 35.0\nduration_s = 100.0\ndt_s = 1e-6",
            refused(&["candidate[0].dt_s", "1e8 samples"]),
        ),
        k(
            "turn at 1e6 m/s",
            "kind = \"turn\"\nrudder_deg = 35.0\nspeed = 1e6",
            refused(&["candidate[0].speed", "1e6 m/s"]),
        ),
        k(
            "turn with amplitude",
            "kind = \"turn\"\nrudder_deg = 35.0\namplitude = 3.0",
            refused(&["candidate[0].amplitude", "not used by a turn candidate"]),
        ),
    ]
}

/// Other angles and rates: planes, pitch, drift, yaw rate, initial motion; keys a kind does
/// not read.
fn attitudes_and_rates() -> Vec<Case> {
    let s = spheroid;
    vec![
        s(
            "vertical zig-zag pitch 95 deg",
            "kind = \"zigzag_vertical\"\nplanes_deg = 10.0\npitch_deg = 95.0",
            refused(&["candidate[0].pitch_deg", "90"]),
        ),
        s(
            "helix planes 95 deg",
            "kind = \"helix\"\nrudder_deg = 10.0\nplanes_deg = 95.0",
            refused(&["candidate[0].planes_deg", "95 deg"]),
        ),
        s(
            "drift 500 deg",
            "kind = \"static\"\ndrift_deg = 500.0",
            refused(&["candidate[0].drift_deg", "500 deg"]),
        ),
        s(
            "drift nan",
            "kind = \"static\"\ndrift_deg = nan",
            refused(&["candidate[0].drift_deg", "finite"]),
        ),
        s(
            "yaw rate 1e5 deg/s",
            "kind = \"static\"\nyaw_rate_deg_s = 1e5",
            refused(&["candidate[0].yaw_rate_deg_s", "100000 deg/s", "20 rad/s"]),
        ),
        s(
            "yaw rate r' 6",
            "kind = \"static\"\nyaw_rate_deg_s = 500.0",
            refused(&["candidate 'x'", "yaw_rate_deg_s", "r' = r L / U"]),
        ),
        s(
            "free r0 1e5 deg/s",
            "kind = \"free\"\nr0_deg_s = 1e5",
            refused(&["candidate[0].r0_deg_s", "deg/s"]),
        ),
        s(
            "free r0 r' 10",
            "kind = \"free\"\nr0_deg_s = 900.0",
            refused(&["candidate 'x'", "r0_deg_s", "r'"]),
        ),
        s(
            "free v0 1e4",
            "kind = \"free\"\nv0 = 1e4",
            refused(&["candidate[0].v0", "10000 m/s", "200 m/s"]),
        ),
        s(
            "free with rudder",
            "kind = \"free\"\nv0 = 0.5\nrudder_deg = 10.0",
            refused(&["candidate[0].rudder_deg", "not used by a free candidate"]),
        ),
        s(
            "static with frequency",
            "kind = \"static\"\ndrift_deg = 5.0\nfrequency_hz = 2.0",
            refused(&[
                "candidate[0].frequency_hz",
                "not used by a static candidate",
            ]),
        ),
        s(
            "static with heading",
            "kind = \"static\"\ndrift_deg = 5.0\nheading_deg = 20.0",
            refused(&["candidate[0].heading_deg", "not used"]),
        ),
    ]
}

/// Noise channels: quantities, positive, plausible, and measured by the candidate.
fn noise() -> Vec<Case> {
    let s = spheroid;
    vec![
        s(
            "typo'd channel",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fy = 0.2, mzz = 0.05 }",
            refused(&["candidate[0].noise.mzz", "did you mean 'mz'"]),
        ),
        s(
            "capital channel",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { Fy = 0.2 }",
            refused(&["candidate[0].noise.Fy", "did you mean 'fy'"]),
        ),
        s(
            "made-up channel",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { force = 0.2 }",
            refused(&["candidate[0].noise.force", "not a measured channel"]),
        ),
        s(
            "negative noise",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fx = -0.02 }",
            refused(&["candidate[0].noise.fx", "positive"]),
        ),
        s(
            "zero noise",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fx = 0.0 }",
            refused(&["candidate[0].noise.fx", "positive"]),
        ),
        s(
            "noise 1e12 N",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fx = 1e12 }",
            refused(&["candidate[0].noise.fx", "1e12 N", "beyond any plausible"]),
        ),
        s(
            "noise 1e5 rad",
            "kind = \"free\"\nv0 = 0.5\nnoise = { yaw = 1e5 }",
            refused(&["candidate[0].noise.yaw", "rad"]),
        ),
        s(
            "noise with units",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fx = \"0.02 N\", mz = \"0.05 N m\" }",
            Expect::Fine,
        ),
        s(
            "noise in another quantity's unit",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { fx = \"0.02 m/s\" }",
            refused(&["candidate[0].noise.fx", "0.02 m/s", "expected a force"]),
        ),
        // measured or not: after the identification
        s(
            "captive noise on yaw",
            "kind = \"static\"\ndrift_deg = 5.0\nnoise = { yaw = 0.01 }",
            refused(&["candidate 'x'", "noise.yaw", "does not measure yaw", "fx"]),
        ),
        s(
            "manoeuvre noise on fx",
            "kind = \"free\"\nv0 = 0.5\nnoise = { fx = 0.1 }",
            refused(&["candidate 'x'", "noise.fx", "does not measure fx"]),
        ),
    ]
}

/// The file itself: unknown keys and tables, names, counts, what it is.
fn files() -> Vec<Case> {
    let s = spheroid;
    let many: String = (0..1001)
        .map(|i| format!("[[candidate]]\nname = \"c{i}\"\nkind = \"static\"\n"))
        .collect();
    let long = "n".repeat(500);
    vec![
        s("unknown key", "kind = \"static\"\nspeeed = 2.0", refused(&["speeed", "did you mean `speed`"])),
        s("unknown key drift", "kind = \"static\"\ndrift = 5.0", refused(&["drift", "did you mean"])),
        s("unknown kind", "kind = \"pmm_yaww\"", refused(&["candidate[0].kind", "pmm_yaw"])),
        s("no kind", "drift_deg = 5.0", refused(&["candidate[0].kind", "missing"])),
        file("no name", "s", "[[candidate]]\nkind = \"static\"\n", refused(&["candidate[0].name", "missing"])),
        file("empty name", "s", "[[candidate]]\nname = \"\"\nkind = \"static\"\n", refused(&["candidate[0].name", "characters"])),
        file("long name", "s", &format!("[[candidate]]\nname = \"{long}\"\nkind = \"static\"\n"), refused(&["candidate[0].name", "200 characters"])),
        file("duplicate names", "s", "[[candidate]]\nname = \"a\"\nkind = \"static\"\n[[candidate]]\nname = \"a\"\nkind = \"static\"\ndrift_deg = 5.0\n", refused(&["candidate[1].name", "candidates 1 and 2"])),
        file("wrong table name", "s", "[[candidates]]\nname = \"a\"\nkind = \"static\"\n", refused(&["candidates", "did you mean"])),
        file("no tables", "s", "candidate = []\n", refused(&["no [[candidate]] tables"])),
        file("empty file", "s", "", refused(&["candidate", "missing"])),
        file("not TOML", "s", "\u{0}\u{1}binary\u{ff}", refused(&["c.toml"])),
        file("1001 candidates", "s", &many, refused(&["1001 candidates", "at most 1000"])),
        file("second candidate bad", "s", "[[candidate]]\nname = \"a\"\nkind = \"static\"\n[[candidate]]\nname = \"b\"\nkind = \"static\"\nspeed = 1e6\n", refused(&["candidate[1].speed", "'b'"])),
        Case::new("candidates a folder", "plan out/s --candidates configs", refused(&["configs"]))
            .setup(|d| setup_output(d, "s")),
        Case::new("candidates missing", "plan out/s --candidates nope.toml", refused(&["nope.toml"]))
            .setup(|d| setup_output(d, "s")),
        Case::new("candidates on a config", "plan configs/spheroid.toml --candidates c.toml", refused(&["candidate[0].speed"]))
            .setup(|d| write(d, "c.toml", "[[candidate]]\nname = \"x\"\nkind = \"static\"\nspeed = 1e6\n")),
        // the model cannot run it: evaluated and skipped with the reason
        s("turn on a rudderless model", "kind = \"turn\"\nrudder_deg = 10.0", warned(&["candidate 'x' not evaluated", "rudder"])),
    ]
}

/// Targets and verification.
fn settings_cases() -> Vec<Case> {
    vec![
        settings(
            "target twice",
            "--target Nrd,Nrd",
            refused(&["Nrd is named twice"]),
        ),
        settings(
            "target empty",
            "--target Nrd,",
            refused(&["--target", "empty name"]),
        ),
        settings(
            "target unknown",
            "--target Nope",
            refused(&["--target Nope", "not a coefficient of the spheroid3 model"]),
        ),
        settings(
            "target misspelt",
            "--target Nrdd",
            refused(&["--target Nrdd", "did you mean 'Nrd'"]),
        ),
        settings(
            "target of another model",
            "--target Yvvr_p",
            refused(&["--target Yvvr_p", "not a coefficient"]),
        ),
        settings(
            "target not identified",
            "--target Nur",
            refused(&["--target Nur", "not an identified coefficient"]),
        ),
        settings(
            "verify 25",
            "--verify 25",
            refused(&["--verify 25", "at most 20"]),
        ),
        settings(
            "verify 25 replicas 10000",
            "--verify 25 --replicas 10000",
            refused(&["--verify 25"]),
        ),
        settings(
            "verify 20 replicas 10000",
            "--verify 20 --replicas 10000",
            refused(&["200000 replicas", "10000 in all"]),
        ),
        settings(
            "verify 3 replicas 5000",
            "--verify 3 --replicas 5000",
            refused(&["15000 replicas"]),
        ),
        settings(
            "replicas 1",
            "--verify 1 --replicas 1",
            refused(&["replicas"]),
        ),
        settings(
            "replicas 1e5",
            "--verify --replicas 100000",
            refused(&["replicas"]),
        ),
        settings("verify negative", "--verify -1", refused(&["-1"])),
        Case::new(
            "verify says its progress",
            "plan out/s --target Nrd --candidates c.toml --verify 1 --replicas 20",
            warned(&["verifying candidate 1 of 1", "20 of 20 replicas identified"]),
        )
        .setup(|d| {
            setup_output(d, "s");
            write(
                d,
                "c.toml",
                "[[candidate]]\nname = \"drift\"\nkind = \"static\"\ndrift_deg = 8.0\n",
            );
        })
        .may_change(&["out"]),
    ]
}

#[test]
fn planner_candidates_and_settings_are_bounded() {
    let mut cases = speeds_and_durations();
    cases.extend(samples_and_costs());
    cases.extend(pmm());
    cases.extend(helm());
    cases.extend(attitudes_and_rates());
    cases.extend(noise());
    cases.extend(files());
    cases.extend(settings_cases());
    let n = run_table("limits (plan)", cases);
    assert!(n >= 100, "{n} cases");
}
