//! `hydroid export fmu OUTDIR -o vessel.fmu`: the identified model of an output folder as an
//! FMI 2.0 co-simulation FMU (docs/fmu.md).

use super::CmdResult;
use crate::app::export::fmu;
use crate::base::error::Error;
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
    /// The FMU's shared library, built by `cargo build -p hydroid-fmu` (default:
    /// libhydroid_fmu.so beside the running hydroid executable).
    #[arg(long)]
    library: Option<PathBuf>,
    /// Longest RK4 step inside the FMU, s: a communication step of H takes ceil(H / STEP)
    /// equal steps.
    #[arg(long, default_value_t = crate::numerics::ode::DEFAULT_MAX_STEP)]
    max_step: f64,
    /// Overwrite an FMU hydroid wrote even if it was changed since (a file hydroid did not
    /// write is never overwritten).
    #[arg(long)]
    force: bool,
}

/// The library's file name.
const LIBRARY: &str = "libhydroid_fmu.so";

/// The library given, else the one beside the running executable.
fn library(given: Option<&Path>) -> crate::Result<(PathBuf, Vec<u8>)> {
    let path = match given {
        Some(p) => p.to_path_buf(),
        None => std::env::current_exe()
            .map_err(|e| Error::Usage(format!("cannot find the running hydroid: {e}")))?
            .with_file_name(LIBRARY),
    };
    match std::fs::read(&path) {
        Ok(bytes) => Ok((path, bytes)),
        Err(e) => Err(Error::Usage(format!(
            "cannot read the FMU library {}: {}; build it with `cargo build -p hydroid-fmu` \
             (it lands beside the hydroid executable, in the same profile: add --release for \
             a release hydroid) or give it with --library",
            path.display(),
            crate::base::error::io_reason(&e)
        ))),
    }
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    let What::Fmu(a) = args.what;
    crate::io::output::clean_up_on_signals()?;
    if !(a.max_step.is_finite() && a.max_step > 0.0) {
        return Err(Error::Usage(format!(
            "--max-step {} is not a positive step in s",
            a.max_step
        ))
        .into());
    }
    let spec = fmu::read_folder(&a.outdir, a.max_step)?;
    let (lib_path, lib) = library(a.library.as_deref())?;
    if !lib.starts_with(b"\x7fELF") {
        return Err(Error::Usage(format!(
            "{} is not a Linux shared library (no ELF header)",
            lib_path.display()
        ))
        .into());
    }
    let bytes = fmu::package(&spec, &lib)?;
    let written =
        crate::io::output::exports::write_export(&a.out, &bytes, &[], Replace::forced(a.force))?;
    writeln!(
        out,
        "wrote {} (FMI 2.0 co-simulation, {} model: {} inputs, {} outputs)",
        written.display(),
        spec.model,
        spec.inputs.len(),
        spec.states.len()
    )?;
    Ok(0)
}
