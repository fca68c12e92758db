//! The command line's texts that name the models, read from the model registry: `hydroid
//! --help` (what hydroid does for each kind of vehicle and every model), `hydroid
//! coefficients --help` and `hydroid init --help` (the model names). A model added to the
//! registry appears in them without a change here; the kinds below must name it too (a test
//! checks it).

use crate::app::catalogue;
use crate::model::models::ModelName;
use clap::Command;

/// Each kind of vehicle: what it is, its models, and what hydroid does for it.
const KINDS: &[(&str, &[&str], &str)] = &[
    (
        "Bodies of revolution such as AUV hulls and the spheroid",
        &["spheroid3", "spheroid6", "surge1"],
        "static polars at several drift angles and a surge acceleration run give the \
         damping and the surge added mass; the hybrid EKF identifies the other coefficients \
         from free manoeuvres; compared with Fossen's analytic added mass and the source paper",
    ),
    (
        "Surface ships",
        &["mmg3", "ship_linear"],
        "turning circles and zig-zags from free-running basin logs or sea trials, and captive \
         tests, give the hull derivatives; the identified model sails every manoeuvre again \
         and is measured beside the run: advance, transfer, tactical and steady diameter, \
         overshoots, with the IMO MSC.137(76) criteria",
    ),
    (
        "Course keeping in waves",
        &["nomoto_wave"],
        "a compass and rudder log gives Nomoto's K, T and the rudder bias, a wave filter \
         separating the wave-induced yaw; the PID autopilot tuned from them is closed around \
         the model in the same waves",
    ),
    (
        "Underwater vehicles in six degrees of freedom",
        &["npsauv"],
        "helices and horizontal and vertical zig-zags (rudder, stern and bow planes, \
         propeller) give the sway, heave, roll, pitch and yaw coefficients, with the ones each \
         run leaves undetermined and the manoeuvre that would determine them",
    ),
];

/// Every registered model's configuration name, comma-separated.
pub fn model_names() -> String {
    ModelName::NAMES.join(", ")
}

/// Every registered model with its description, one item per line.
fn model_lines() -> String {
    ModelName::ALL
        .iter()
        .map(|m| {
            let e = catalogue::model(*m);
            format!("- {}: {}", e.name, e.description)
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// What hydroid does for each kind of vehicle, a paragraph each.
fn kind_lines() -> String {
    KINDS
        .iter()
        .map(|(kind, models, what)| format!("- {kind} ({}): {what}.", models.join(", ")))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `hydroid --help`'s description.
fn long_about() -> String {
    format!(
        "hydroid: CFD exports and model-test logs of marine vehicles to manoeuvring models.\n\n\
         Reads CFD exports (ANSYS CFX and Fluent, STAR-CCM+, OpenFOAM) and measured logs \
         (basin and sea trials, captive tests: plain or headerless tables), identifies a \
         model's hydrodynamic coefficients with their uncertainties (static polars, surge \
         run, captive fit, hybrid extended Kalman filter), re-simulates every run with the \
         identified model and writes results.json and the reports (Markdown and HTML with \
         figures).\n\n\
         What hydroid does for each kind of vehicle:\n\n{}\n\n\
         Models (`hekf.model`; `hydroid coefficients MODEL` lists a model's states, inputs \
         and coefficients):\n\n{}",
        kind_lines(),
        model_lines()
    )
}

/// The command line with the texts that name the models filled in from the registry.
pub fn with_models(cmd: Command) -> Command {
    let names = model_names();
    cmd.about("CFD exports and model-test logs of marine vehicles to manoeuvring models")
        .long_about(long_about())
        .mut_subcommand("coefficients", |c| {
            c.about(format!(
                "List every coefficient hydroid knows: name, meaning, SI unit, the stages that \
                 can give it and the relations that derive it. With a model name ({names}), \
                 only that model's coefficients, with its states and inputs"
            ))
            .mut_arg("model", |a| {
                a.help(format!("A model (`hekf.model`): one of {names}"))
                    .long_help(format!(
                        "A model (`hekf.model`), one of:\n{}",
                        model_lines()
                    ))
            })
        })
        .mut_subcommand("init", |c| {
            c.mut_arg("model", |a| {
                a.help(format!("The HEKF's model: one of {names}"))
                    .long_help(format!(
                        "The HEKF's model (`hekf.model`), one of:\n{}\n\nWhat hydroid does \
                         for each kind of vehicle:\n{}",
                        model_lines(),
                        kind_lines()
                    ))
            })
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_model_has_a_kind() {
        for name in ModelName::NAMES {
            assert!(
                KINDS.iter().any(|(_, models, _)| models.contains(name)),
                "model {name} is in no vehicle kind of src/cli/help.rs"
            );
        }
        for (kind, models, _) in KINDS {
            for m in *models {
                assert!(ModelName::from_name(m).is_some(), "{kind}: {m} is no model");
            }
        }
    }
}
