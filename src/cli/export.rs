//! `hydroid export fmu OUTDIR -o vessel.fmu`: the identified model of an output folder as an
//! FMI 2.0 co-simulation FMU (docs/fmu.md).

use super::CmdResult;
use crate::app::export::fmu;
use crate::base::error::Error;
use crate::io::output::exports::{write_export, Export, ExportKind};
use crate::io::output::Replace;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Package an identified model for other tools.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(Debug, clap::Subcommand)]
enum What {
    Fmu(FmuArgs),
}

/// The model and coefficients of an output folder of `hydroid run` as an FMI 2.0
/// co-simulation FMU for Linux x86-64 (docs/fmu.md): its inputs held over each communication
/// step, its states as outputs in SI, integrated with hydroid's RK4.
#[derive(Debug, clap::Args)]
struct FmuArgs {
    /// An output folder written by `hydroid run` (with an HEKF stage).
    outdir: PathBuf,
    /// The FMU to write (`vessel.fmu`).
    #[arg(short = 'o', long = "out")]
    out: PathBuf,
    /// The FMU's shared library (default: libhydroid_fmu.so beside the running hydroid
    /// executable, which `cargo build --release` at the repository root builds beside it).
    #[arg(long)]
    library: Option<PathBuf>,
    /// Longest RK4 step inside the FMU, s (1e-5 to 1): a communication step of H takes
    /// ceil(H / STEP) equal steps.
    #[arg(long, default_value_t = crate::numerics::ode::DEFAULT_MAX_STEP, allow_hyphen_values = true)]
    max_step: f64,
    /// Overwrite an FMU hydroid exported even if it was changed since (a file hydroid did not
    /// write, an export of `hydroid simulate` or an input of the run are never overwritten).
    #[arg(long)]
    force: bool,
}

/// The library's file name.
const LIBRARY: &str = "libhydroid_fmu.so";

/// The library given, else the one beside the running executable: its bytes, read and
/// checked (`fmu::library`).
fn library(given: Option<&Path>) -> crate::Result<Vec<u8>> {
    let path = match given {
        Some(p) => p.to_path_buf(),
        None => std::env::current_exe()
            .map_err(|e| Error::Usage(format!("cannot find the running hydroid: {e}")))?
            .with_file_name(LIBRARY),
    };
    if given.is_none() && std::fs::symlink_metadata(&path).is_err() {
        return Err(Error::Usage(format!(
            "the FMU library {} is missing: build it with `cargo build --release` at the \
             repository root (the README's first command builds it beside hydroid; `cargo \
             build -p hydroid-fmu` for a debug hydroid), or give it with --library",
            path.display()
        )));
    }
    fmu::library::read(&path)
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let What::Fmu(a) = args.what;
    crate::io::output::clean_up_on_signals()?;
    fmu::spec::check_max_step(a.max_step).map_err(|e| Error::Usage(format!("--max-step {e}")))?;
    let exported = fmu::read_folder(&a.outdir, a.max_step)?;
    let lib = library(a.library.as_deref())?;
    let bytes = fmu::package(&exported.spec, &lib)?;
    let export = Export {
        kind: ExportKind::Fmu,
        source: &a.outdir,
        guarded: &exported.guarded,
    };
    let written = write_export(&a.out, &bytes, &export, Replace::forced(a.force))?;
    let spec = &exported.spec;
    writeln!(
        out,
        "wrote {} (FMI 2.0 co-simulation, {} model: {} inputs, {} outputs); start values: {}",
        written.display(),
        spec.model,
        spec.inputs.len(),
        spec.states.len(),
        exported.starts
    )?;
    Ok(0)
}
