//! `hydroid coefficients [MODEL]`: the coefficient catalogue (docs/coefficients.md).

use super::{json, CmdResult};
use crate::app::catalogue::{self, Entry};
use std::io::Write;

/// List every coefficient hydroid knows: name, meaning, SI unit, the stages that can give it
/// and the relations that derive it. With a model name, only that model's coefficients, with
/// its states and inputs (the model names are filled in from the registry: `help`).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A model (`hekf.model`; the registry's names are filled in by `help`).
    model: Option<String>,
    /// Print machine-readable JSON instead of text.
    #[arg(long)]
    pub(super) json: bool,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let entries = catalogue::entries();
    let Some(name) = &args.model else {
        if args.json {
            let models: Vec<_> = crate::model::models::ModelName::ALL
                .iter()
                .map(|m| catalogue::model(*m))
                .collect();
            json::write(
                out,
                &serde_json::json!({ "coefficients": entries, "models": models }),
            )?;
        } else {
            write!(out, "{}", catalogue::text(&entries))?;
        }
        return Ok(0);
    };
    let model = catalogue::model(catalogue::model_named(name)?);
    let of_model: Vec<&Entry> = entries
        .iter()
        .filter(|e| model.coefficients.iter().any(|c| c.name == e.name))
        .collect();
    if args.json {
        json::write(
            out,
            &serde_json::json!({ "model": model, "coefficients": of_model }),
        )?;
    } else {
        writeln!(out, "{}", catalogue::model_text(&model))?;
        let owned: Vec<Entry> = of_model.into_iter().cloned().collect();
        write!(out, "{}", catalogue::text(&owned))?;
    }
    Ok(0)
}
