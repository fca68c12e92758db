//! The autopilot's plant (`[autopilot.plant]`): held inputs with units, in the wrong unit or
//! sign, a ship at rest, a rudder that works the other way, a Nomoto plant without yaw
//! damping. A value no plant can have is a configuration problem naming the key; a plant the
//! loop could only spin around stops the autopilot with a warning that names the cause (the
//! identification stands on its own).

use super::autopilot_case;
use crate::hostile::{refused, run_table, warned, Case, Expect};

/// The 150 m ship (ship_linear) at 8 m/s as the plant, with `rest` after its model and vehicle.
fn ship(rest: &str) -> String {
    format!(
        "[autopilot.plant]\nmodel = \"ship_linear\"\nvehicle_file = \
         \"vehicles/ship150_clarke.toml\"\n{rest}\n"
    )
}

/// `ship(rest)` with the 8 m/s approach.
fn ship8(rest: &str) -> String {
    ship(&format!("speed = \"8 m/s\"\n{rest}"))
}

/// A Nomoto plant with these coefficients.
fn nomoto(coefficients: &str, rest: &str) -> String {
    format!(
        "[autopilot.plant]\nmodel = \"nomoto_wave\"\ncoefficients = {{ {coefficients} }}\n{rest}\n"
    )
}

fn case(name: &str, plant: &str, expect: Expect) -> Case {
    autopilot_case(name, plant, expect)
}

/// Refused while the configuration is read.
fn configuration() -> Vec<Case> {
    let rpm = |name: &str, v: &str, words: &[&str]| {
        case(
            name,
            &ship8(&format!("inputs = {{ rpm = {v} }}")),
            refused(words),
        )
    };
    vec![
        rpm("rpm in m/s", "\"1.8 m/s\"", &["autopilot.plant.inputs.rpm", "m/s"]),
        rpm("rpm 1e6 rpm", "\"1e6 rpm\"", &["autopilot.plant.inputs.rpm", "beyond any plausible"]),
        rpm("rpm 1e6 rev/s", "1e6", &["autopilot.plant.inputs.rpm", "rev/s", "beyond any plausible"]),
        rpm("rpm negative", "-1.8", &["autopilot.plant.inputs.rpm", "-1.8 rev/s", "astern"]),
        rpm("rpm negative with unit", "\"-108 rpm\"", &["autopilot.plant.inputs.rpm", "-108 rpm", "astern"]),
        rpm("rpm nan", "nan", &["autopilot.plant.inputs.rpm", "finite"]),
        rpm("rpm unknown unit", "\"108 rpmm\"", &["autopilot.plant.inputs.rpm", "rpmm"]),
        rpm("rpm as words", "\"fast\"", &["autopilot.plant.inputs.rpm"]),
        rpm("rpm as a boolean", "true", &["autopilot.plant.inputs.rpm"]),
        case("input rudder", &ship8("inputs = { rudder = 0.1 }"), refused(&["autopilot.plant.inputs.rudder", "other than the rudder"])),
        case("input thrust", &ship8("inputs = { thrust = 100.0 }"), refused(&["autopilot.plant.inputs.thrust", "rpm"])),
        case("input misspelt", &ship8("inputs = { rpmm = 1.8 }"), refused(&["autopilot.plant.inputs.rpmm"])),
        case("speed zero", &ship("speed = 0.0\ninputs = { rpm = 1.8 }"), refused(&["autopilot.plant.speed", "at rest"])),
        case("speed negative", &ship("speed = \"-8 m/s\"\ninputs = { rpm = 1.8 }"), refused(&["autopilot.plant.speed", "at rest"])),
        case("speed 100 m/s", &ship("speed = \"100 m/s\"\ninputs = { rpm = 1.8 }"), refused(&["autopilot.plant.speed", "100 m/s", "faster"])),
        case("speed 1e6 kn", &ship("speed = \"1e6 kn\""), refused(&["autopilot.plant.speed", "faster"])),
        case("speed in deg", &ship("speed = \"8 deg\""), refused(&["autopilot.plant.speed", "deg"])),
        case("change speed zero", &ship8("inputs = { rpm = 1.8 }\n[autopilot.plant.change]\nat = 100.0\nspeed = 0.0"), refused(&["autopilot.plant.change.speed", "at rest"])),
        case("change at the end", &ship8("inputs = { rpm = 1.8 }\n[autopilot.plant.change]\nat = 200.0\nspeed = 5.0"), refused(&["autopilot.plant.change.at", "before its end", "never happens"])),
        case("change at 0", &ship8("[autopilot.plant.change]\nat = 0.0\nspeed = 5.0"), refused(&["autopilot.plant.change.at", "after 0 s"])),
        case("change at 1e9", &ship8("[autopilot.plant.change]\nat = 1e9\nspeed = 5.0"), refused(&["autopilot.plant.change.at", "1e9 s"])),
        case("change rpm negative", &ship8("inputs = { rpm = 1.8 }\n[autopilot.plant.change]\nat = 100.0\ninputs = { rpm = -1.0 }"), refused(&["autopilot.plant.change.inputs.rpm", "astern"])),
        case("change rpm in m/s", &ship8("[autopilot.plant.change]\nat = 100.0\ninputs = { rpm = \"1 m/s\" }"), refused(&["autopilot.plant.change.inputs.rpm", "m/s"])),
        case("coefficient nan", &ship8("coefficients = { b3 = nan }"), refused(&["autopilot.plant.coefficients.b3", "finite"])),
        case("coefficient misspelt", &ship8("coefficients = { b33 = 0.1 }"), refused(&["autopilot.plant.coefficients.b33", "not a coefficient"])),
        case("model misspelt", "[autopilot.plant]\nmodel = \"shiplinear\"\n", refused(&["autopilot.plant.model", "ship_linear"])),
        case("key misspelt", &ship8("speeed = 8.0"), refused(&["speeed", "did you mean"])),
        case("vehicle file missing", "[autopilot.plant]\nmodel = \"ship_linear\"\nvehicle_file = \"vehicles/nope.toml\"\nspeed = 8.0\n", refused(&["nope.toml"])),
    ]
}

/// The autopilot stopped with the cause named (the run itself goes on).
fn not_run() -> Vec<Case> {
    let stopped = |name: &str, plant: &str, words: &[&str]| {
        let mut all = vec!["the autopilot was not run"];
        all.extend_from_slice(words);
        case(name, plant, warned(&all))
    };
    vec![
        stopped("rpm read as rev/s", &ship8("inputs = { rpm = 108.1 }"), &["127.1 m/s^2", "autopilot.plant.inputs.rpm is in rev/s", "6486 rpm", "\"108.1 rpm\""]),
        stopped("rpm 60 read as rev/s", &ship8("inputs = { rpm = 60.0 }"), &["accelerate it", "3600 rpm"]),
        stopped("reversed rudder", &ship8("inputs = { rpm = 1.80101 }\ncoefficients = { b3 = 6.357587e-2, c3 = -2.954610e-3 }"), &["works the other way", "autopilot.plant.coefficients"]),
        stopped("rudder moves no yaw", &ship8("inputs = { rpm = 1.80101 }\ncoefficients = { b3 = 0.0, c3 = 0.0 }"), &["plant ship_linear", "no rudder moment"]),
        stopped("npsauv rudder the other way", "[autopilot.plant]\nmodel = \"npsauv\"\nvehicle_file = \"vehicles/npsauv.toml\"\nspeed = \"2 m/s\"\ninputs = { rpm = \"1500 rpm\" }\n", &["plant npsauv", "works the other way"]),
        stopped("nomoto K negative", &nomoto("K = -0.18, inv_T = 0.037", ""), &["works the other way"]),
        stopped("nomoto K zero", &nomoto("K = 0.0, inv_T = 0.037", ""), &["moves no yaw"]),
        stopped("nomoto 1/T zero", &nomoto("K = 0.18, inv_T = 0.0", ""), &["1/T = inv_T = 0", "no yaw damping"]),
        stopped("nomoto 1/T negative", &nomoto("K = 0.18, inv_T = -0.03", ""), &["course-unstable"]),
        stopped("nomoto 1/T zero after a change", &nomoto("K = 0.18, inv_T = 0.037", "[autopilot.plant.change]\nat = 100.0\ncoefficients = { inv_T = 0.0 }"), &["after its change", "no yaw damping"]),
        stopped("nomoto reversed after a change", &nomoto("K = 0.18, inv_T = 0.037", "[autopilot.plant.change]\nat = 100.0\ncoefficients = { K = -0.18 }"), &["works the other way", "after its change"]),
        stopped("ship at rest", &ship("inputs = { rpm = 1.80101 }"), &["starts at rest", "autopilot.plant.speed"]),
        stopped("kvlcc2 at rest", "[autopilot.plant]\nmodel = \"mmg3\"\nvehicle_file = \"vehicles/kvlcc2_mmg.toml\"\n", &["starts at rest"]),
        stopped("rpm read as rev/s after a change", &ship8("inputs = { rpm = 1.80101 }\n[autopilot.plant.change]\nat = 100.0\nspeed = \"5 m/s\"\ninputs = { rpm = 80.0 }"), &["after its change", "rev/s"]),
    ]
}

/// What works: units on a held input, and the identified plant.
fn working() -> Vec<Case> {
    vec![
        case(
            "rpm with a unit",
            &ship8("inputs = { rpm = \"108.06 rpm\" }"),
            warned(&["plant ship_linear: K = 0.1227 1/s, T = 80.04 s"]),
        ),
        case(
            "rpm in rps",
            &ship8("inputs = { rpm = \"1.80101 rps\" }"),
            warned(&["plant ship_linear: K = 0.1227 1/s"]),
        ),
        case("identified plant", "", warned(&["plant nomoto_wave"])),
        // a steering gear that cannot hold the frigate's 1 deg rudder bias: the loop runs and
        // says it holds no course
        case(
            "rudder limit below the bias",
            "rudder_limit = \"1.2 deg\"",
            warned(&[
                "the closed loop holds no course",
                "hard over (1.2 deg)",
                "rudder_limit",
            ]),
        ),
    ]
}

#[test]
fn autopilot_plants_are_plausible_or_named() {
    let mut cases = configuration();
    cases.extend(not_run());
    cases.extend(working());
    let n = run_table("limits (plant)", cases);
    assert!(n >= 40, "{n} cases");
}
