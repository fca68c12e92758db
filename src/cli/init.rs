//! `hydroid init [PATH]`: write a commented template run configuration, and nothing else.

use super::{CmdResult, Say};
use crate::app::catalogue;
use crate::stages::hekf::ModelName;
use crate::stages::surge::DragFrom;
use crate::Error;
use std::fmt::Write as _;
use std::io::Write;
use std::path::PathBuf;

/// The file written when PATH is a folder.
const FILE_NAME: &str = "hydroid.toml";

/// A stage the template can set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Stage {
    /// Static polars.
    Polar,
    /// Surge acceleration run.
    Surge,
    /// Hybrid EKF on a free manoeuvre.
    Hekf,
}

/// Write a commented template run configuration (hydroid.toml) that `hydroid check` accepts
/// once its file names are filled in. Never overwrites anything.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A folder (the template is written to FOLDER/hydroid.toml; missing folders are
    /// created) or a file name ending in .toml.
    #[arg(default_value = ".")]
    path: PathBuf,
    /// The stages to set up, in pipeline order (default: polar,surge,hekf for a model whose
    /// coefficients the polar and surge stages give, such as the spheroid's; hekf alone for
    /// the others: ships, Nomoto).
    #[arg(long, value_enum, value_delimiter = ',')]
    stages: Option<Vec<Stage>>,
    /// The HEKF's model (the registry's names are filled in by `help`).
    #[arg(long, default_value = "spheroid3")]
    model: String,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    let model = catalogue::model_named(&args.model)?;
    let stages = args.stages.clone().unwrap_or_else(|| {
        if uses_stage_coefficients(model) {
            vec![Stage::Polar, Stage::Surge, Stage::Hekf]
        } else {
            vec![Stage::Hekf]
        }
    });
    check_stages(model, &stages)?;
    let has = |s: Stage| stages.contains(&s);
    let file = if args.path.extension().is_some_and(|e| e == "toml") {
        args.path.clone()
    } else {
        args.path.join(FILE_NAME)
    };
    let text = template(
        has(Stage::Polar),
        has(Stage::Surge),
        has(Stage::Hekf),
        model,
    );
    crate::io::output::write_new(&file, text.as_bytes())?;
    writeln!(out, "wrote {}", file.display())?;
    say.note(&format!(
        "next: fill in the vehicle and every FILL-IN file name, then `hydroid check {}`",
        file.display()
    ));
    Ok(0)
}

/// The paper's 6:1 spheroid (Rasekh & Mahdi 2020, Table 1), as placeholders a user replaces.
const VEHICLE: &str = r#"[vehicle]                      # REPLACE with your vehicle (here the 6:1 spheroid of the example)
name = "my vehicle"
mass = 50.0                    # kg
length = 1.2                   # m, overall
diameter = 0.2                 # m, maximum: gives Fossen's analytic added mass of a prolate
                               # spheroid for comparison and priors (remove for other shapes)
izz = 3.7                      # kg m^2, yaw inertia about the origin (centre of buoyancy)
reference_area = 0.0314159265  # m^2, A_ref of the force coefficients (here the frontal area)
reference_length = 1.0         # m, L_ref of the moment coefficient C_M = N / (0.5 rho U^2 A_ref L_ref)
"#;

/// The template for the chosen stages and model.
fn template(polar: bool, surge: bool, hekf: bool, model: ModelName) -> String {
    let mut s = format!(
        "# hydroid run configuration, written by `hydroid init` (hydroid {version}).\n\
         #\n\
         # 1. Replace the vehicle below with yours.\n\
         # 2. Give every `file = \"FILL-IN...\"` the path of a CFD export, relative to this file,\n\
         #    and map its columns (`hydroid inspect FILE` shows what hydroid reads in it).\n\
         # 3. hydroid check THIS_FILE   # lists every problem with its line\n\
         #    hydroid run THIS_FILE     # writes the output folder\n\
         #\n\
         # Every key: docs/config.md. Coefficient names and units: `hydroid coefficients`.\n\
         # Numbers are SI (kg, m, s, N, rad); a string carries its unit: \"4 deg\", \"22 N\".\n\n\
         title = \"my vehicle\"\n\n{VEHICLE}",
        version = env!("CARGO_PKG_VERSION"),
    );
    let needs = catalogue::model(model).vehicle_needs;
    if needs.iter().any(|k| k == "ixx" || k == "iyy") {
        s.push_str(&format!(
            "ixx = 0.2                      # kg m^2, roll inertia (the {model} model needs it)\n\
             iyy = 3.7                      # kg m^2, pitch inertia\n\
             bg = 0.0                       # m, centre of buoyancy above the centre of gravity\n",
        ));
    }
    s.push_str(&particulars(model));
    s.push_str(
        "\n[fluid]\n\
         rho = 1025.0                   # kg/m^3\n\
         mu = 0.0009                    # Pa s\n\n\
         [output]\n\
         dir = \"out\"                    # relative to this file; hydroid replaces only an\n\
         \x20                              # earlier output of its own, nothing else\n\n",
    );
    s.push_str(&coefficients(polar, surge, hekf, model));
    s.push_str(
        "# Published values to compare with, shown as a column of the results table:\n\
         # [reference]\n\
         # name = \"Rasekh & Mahdi 2020\"\n\
         # values = { Yvd = -23.99, Nrd = -1.44 }\n",
    );
    if polar {
        s.push_str(
            "\n# Static polars: C_D, C_L, C_M over the drift angle (docs/stages.md, section 1).\n\
             [polar]\n\
             moment.part = \"total\"            # C_M includes the Munk moment (CFD); \"lift-only\": the paper's reading\n\
             [[polar.runs]]\n\
             name = \"drift sweep\"\n\
             file = \"FILL-IN-polar-sweep.csv\"\n\
             [polar.runs.columns]           # quantity = \"column name in the file\"\n\
             alpha = \"alpha\"                # the unit comes from the header, or write\n\
             \x20                              # alpha = { column = \"AoA\", unit = \"deg\" }\n\
             speed = \"speed\"\n\
             cd = \"cd\"\n\
             cl = \"cl\"\n\
             cm = \"cm\"\n",
        );
    }
    if surge {
        s.push_str(
            "\n# Surge acceleration run: u under a known thrust (docs/stages.md, section 2).\n\
             [surge]\n\
             [[surge.runs]]\n\
             name = \"surge run\"\n\
             file = \"FILL-IN-surge-run.csv\"\n\
             [surge.runs.columns]\n\
             time = \"time\"\n\
             u = \"u\"\n\
             thrust = \"thrust\"              # a constant thrust instead: remove this line and \
             write\n\
             \x20                              # constants = { thrust = \"22 N\" } under `file`\n",
        );
    }
    if hekf {
        s.push_str(&hekf_section(model));
    }
    s
}

/// Refuses stages a template for `model` could never run usefully: the polar and surge stages
/// give coefficients only some models use, and a template of those stages alone for another
/// model would leave its particulars read by no stage (a configuration `check` never
/// accepts). The error names the stages the model supports and the models that use the
/// polar and surge stages.
fn check_stages(model: ModelName, stages: &[Stage]) -> Result<(), Error> {
    if uses_stage_coefficients(model) {
        return Ok(());
    }
    let unused: Vec<&str> = stages
        .iter()
        .filter_map(|s| match s {
            Stage::Polar => Some("polar"),
            Stage::Surge => Some("surge"),
            Stage::Hekf => None,
        })
        .collect();
    if unused.is_empty() {
        return Ok(());
    }
    let with_them: Vec<&str> = ModelName::ALL
        .iter()
        .filter(|m| uses_stage_coefficients(**m))
        .map(|m| m.as_str())
        .collect();
    Err(Error::Usage(format!(
        "--stages {}: the {model} model uses no coefficient the polar or surge stage gives, so \
         its template has the hekf stage only (--stages hekf, the default for it); the polar \
         and surge stages are for the models that use their coefficients: {}",
        unused.join(","),
        with_them.join(", ")
    )))
}

/// Whether the model uses a coefficient that the polar or the surge stage gives (then those
/// stages belong in its template).
fn uses_stage_coefficients(model: ModelName) -> bool {
    let entries = catalogue::entries();
    catalogue::model(model).coefficients.iter().any(|c| {
        entries.iter().any(|e| {
            e.name == c.name
                && e.given_by.iter().any(|p| {
                    matches!(
                        p.source,
                        crate::model::coefficients::Source::Polar
                            | crate::model::coefficients::Source::Surge
                    )
                })
        })
    })
}

/// The `[vehicle.particulars]` a model needs, as values to replace.
fn particulars(model: ModelName) -> String {
    let keys: Vec<String> = catalogue::model(model)
        .vehicle_needs
        .iter()
        .filter_map(|k| k.strip_prefix("particulars.").map(str::to_string))
        .collect();
    if keys.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n[vehicle.particulars]          # REPLACE: what the {model} model reads besides the \
         above\n                               # (meanings and units: docs/models/, \
         `hydroid coefficients {model}`)\n"
    );
    for k in keys {
        let _ = writeln!(s, "{k} = 0.0");
    }
    s
}

/// The `[coefficients]` section: what the HEKF's model needs that no chosen stage and no
/// analytic formula gives, as values to replace; commented out when nothing is missing.
fn coefficients(polar: bool, surge: bool, hekf: bool, model: ModelName) -> String {
    let entries = catalogue::entries();
    let given = |name: &str| {
        let e = entries.iter().find(|e| e.name == name);
        e.is_some_and(|e| {
            e.given_by.iter().any(|p| match p.source {
                // the template gives the diameter: Lamb's added mass is known
                crate::model::coefficients::Source::Analytic => true,
                crate::model::coefficients::Source::Polar => polar,
                _ => false,
            })
        }) || (surge && crate::stages::surge::provides_with(DragFrom::Coefficients).contains(&name))
    };
    let mut needed: Vec<(&str, &str)> = Vec::new();
    if surge && !polar {
        needed.push(("Xuu", "kg/m"));
    }
    if hekf {
        for c in catalogue::model(model).coefficients {
            if c.derived_by.is_none()
                && !catalogue::model(model).estimated.contains(&c.name)
                && !given(c.name)
                && !needed.iter().any(|(n, _)| *n == c.name)
            {
                needed.push((c.name, c.unit));
            }
        }
    }
    let mut s = String::new();
    if needed.is_empty() {
        s.push_str(
            "# Coefficients known beforehand (SI), held fixed unless a stage estimates them:\n\
             # [coefficients]\n\
             # Kpp = -0.05    # kg m^2\n\n",
        );
        return s;
    }
    s.push_str(
        "# Coefficients known beforehand (SI), held fixed unless a stage estimates them. The\n\
         # chosen stages do not give these: REPLACE the zeros with your values.\n\
         [coefficients]\n",
    );
    for (name, unit) in needed {
        let _ = writeln!(s, "{name:<4} = 0.0    # {unit}");
    }
    s.push('\n');
    s
}

/// The `[hekf]` section with a run mapping every state and input of the model.
fn hekf_section(model: ModelName) -> String {
    let m = catalogue::model(model);
    let mut s = format!(
        "\n# Hybrid EKF on a free manoeuvre (docs/hekf.md); the model's states, inputs and\n\
         # coefficients: `hydroid coefficients {model}`.\n\
         [hekf]\n\
         model = \"{model}\"\n\
         preset = \"hydroid\"             # or \"paper\" (the paper's tuning, for comparison)\n\
         estimate = [{}]\n\n\
         [[hekf.runs]]\n\
         name = \"manoeuvre\"\n\
         file = \"FILL-IN-manoeuvre.csv\"\n\
         [hekf.runs.columns]            # every state the file has is a measurement\n\
         time = \"time\"\n",
        m.estimated
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for v in m.states.iter().chain(&m.inputs) {
        let _ = writeln!(s, "{q} = \"{q}\"", q = v.quantity);
    }
    s.push_str(
        "\n# Runs kept for validation: re-simulated with the identified model, not fitted.\n\
         # [[hekf.validation]]\n\
         # file = \"another-manoeuvre.csv\"\n\
         # [hekf.validation.columns]\n\
         # time = \"time\"\n",
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_template_without_polar_asks_for_what_the_polar_would_give() {
        let t = template(false, false, true, ModelName::Spheroid3);
        assert!(t.contains("[coefficients]\nXuu  = 0.0    # kg/m\n"), "{t}");
        assert!(t.contains("\nNuvl = 0.0    # kg\n"), "{t}");
        // added masses come from Lamb's formulas, estimated ones from the filter
        assert!(
            !t.contains("Xud  = 0.0") && !t.contains("Yvd  = 0.0"),
            "{t}"
        );
        let t = template(true, true, true, ModelName::Spheroid6);
        assert!(
            t.contains("[coefficients]\nKpp  = 0.0    # kg m^2\n"),
            "{t}"
        );
        assert!(t.contains("pitch = \"pitch\""), "{t}");
    }

    #[test]
    fn a_ship_template_asks_for_its_particulars_and_no_polar() {
        assert!(uses_stage_coefficients(ModelName::Spheroid3));
        assert!(!uses_stage_coefficients(ModelName::Mmg3));
        let t = template(false, false, true, ModelName::Mmg3);
        assert!(t.contains("[vehicle.particulars]"), "{t}");
        assert!(
            t.contains("\ndraught = 0.0\n") && t.contains("\nwake_c2_neg = 0.0\n"),
            "{t}"
        );
        assert!(
            !t.contains("[polar]") && t.contains("model = \"mmg3\""),
            "{t}"
        );
        let t = template(true, true, true, ModelName::Spheroid3);
        assert!(!t.contains("[vehicle.particulars]"), "{t}");
    }
}
