//! `hydroid plan OUTDIR|CONFIG`: which run to do next (docs/planner.md): candidate runs ranked
//! by the reduction of the target coefficients' uncertainty they are predicted to bring.

use super::{CmdResult, Say};
use crate::app::pipeline::{self, Scope};
use crate::app::plan::{self, limits, write, Settings};
use crate::base::error::Error;
use crate::base::progress::Silent;
use crate::config;
use crate::io::output::Claim;
use std::io::Write;
use std::path::PathBuf;

/// Rank candidate runs (CFD or basin) by how much they are predicted to reduce the target
/// coefficients' uncertainty: each candidate simulated with the identified model, its
/// information in the linearisation at the current estimate added to the current covariance
/// (D- and A-optimal scores, each target's predicted sigma, per unit cost). With an output
/// folder, plan.json, plan.md and plots/plan.svg are written into it.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// An output folder written by `hydroid run` (unchanged since), or a configuration,
    /// which is run first (nothing is written then).
    source: PathBuf,
    /// The coefficients that matter, comma-separated (default: every identified one).
    #[arg(long, value_delimiter = ',')]
    target: Vec<String>,
    /// A TOML file of `[[candidate]]` tables (docs/planner.md) instead of the model's
    /// default candidates.
    #[arg(long)]
    candidates: Option<PathBuf>,
    /// Print plan.json on stdout instead of the table.
    #[arg(long)]
    pub(super) json: bool,
    /// Verify the top K candidates (3 without a number; at most 20): replicas simulated
    /// with the current model and the candidate's noise, identified again; predicted against
    /// achieved sigma.
    #[arg(long, num_args = 0..=1, default_missing_value = "3", value_name = "K")]
    verify: Option<usize>,
    /// Replicas per verified candidate (at most 10,000 replicas in all, K times N).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(2..=10_000))]
    replicas: u32,
    /// Seed of the verification's noise (the same seed gives the same output).
    #[arg(long, default_value_t = 2026)]
    seed: u64,
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write, say: Say) -> CmdResult {
    let claim = if args.source.is_dir() {
        Some(Claim::open(&args.source, "plan", super::rerun::READ)?)
    } else {
        None
    };
    let loaded = match &claim {
        Some(c) => super::rerun::load_recorded(c.dir(), false, false)?.0,
        None => config::load(&args.source, &[])?,
    };
    let candidates = match &args.candidates {
        Some(p) => limits::read(p)?,
        None => Vec::new(),
    };
    let verify = args.verify.unwrap_or(0);
    limits::check_settings(&args.target, verify, args.replicas as usize)?;
    check_targets(&loaded, &args.target)?;
    say.note(&format!(
        "plan: identifying {} first",
        args.source.display()
    ));
    let inputs = pipeline::load_inputs(&loaded, pipeline::stage_inputs(&loaded.config))?;
    let output = pipeline::run_on(&loaded, &inputs, &mut Silent, Scope::Full)?;
    let settings = Settings {
        targets: args.target.clone(),
        candidates,
        verify,
        replicas: args.replicas as usize,
        seed: args.seed,
    };
    // a line at every tenth of each candidate's replicas (the count, not the order, is
    // certain), as calibrate says them
    let step = (settings.replicas / 10).max(1);
    let progress = |k: usize, of: usize, n: usize, replicas: usize| {
        if n.is_multiple_of(step) || n == replicas {
            say.note(&format!(
                "plan: verifying candidate {k} of {of}: {n} of {replicas} replicas identified"
            ));
        }
    };
    let plan = plan::plan_with(&loaded, &output, &settings, &progress)?;
    say.note(&format!(
        "plan: {} candidates ranked for {}",
        plan.ranked.len(),
        plan.targets.join(", ")
    ));
    for s in &plan.skipped {
        super::warning(&format!(
            "candidate '{}' not evaluated: {}",
            s.name, s.reason
        ));
    }
    if let Some(c) = &claim {
        write::write(c, &plan)?;
        let d = c.dir();
        say.note(&format!(
            "plan: {}, {} and {} written in {}",
            write::PLAN_JSON,
            write::PLAN_MD,
            write::PLAN_SVG,
            d.display()
        ));
    }
    if args.json {
        out.write_all(&crate::io::output::to_json(&plan)?)?;
        writeln!(out)?;
    } else {
        write!(out, "{}", write::table(&plan))?;
    }
    Ok(0)
}

/// Refuses a target that is no coefficient of the run's model, before the identification
/// (whether the run identifies it is known after it).
fn check_targets(loaded: &crate::config::LoadedConfig, targets: &[String]) -> Result<(), Error> {
    let Some(hekf) = &loaded.config.hekf else {
        return Ok(());
    };
    let names: Vec<&str> = hekf.model.coefficients().iter().map(|c| c.name).collect();
    for t in targets {
        if !names.contains(&t.as_str()) {
            return Err(Error::Usage(format!(
                "--target {t}: not a coefficient of the {} model{} (`hydroid coefficients {}` \
                 lists them)",
                hekf.model,
                crate::base::suggest::did_you_mean(t, names.iter().copied()),
                hekf.model
            )));
        }
    }
    Ok(())
}
