//! `hydroid analytic SHAPE ...`: analytic added mass of simple shapes.

// CmdResult carries crate::Error, which is large (its InputError variant); boxing it is a
// crate-wide choice.

use super::CmdResult;
use crate::model::analytic::Spheroid;
use crate::model::coefficients::Coefficient;
use std::io::Write;

/// Analytic added mass of simple shapes (Fossen 1994, section 2.4.1).
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    shape: Shape,
}

#[derive(Debug, clap::Subcommand)]
enum Shape {
    /// Prolate spheroid (semi-axes a = length/2 > b = diameter/2): Lamb's k-factors and
    /// Xud, Yvd = Zwd, Nrd = Mqd (Kpd = Yrd = Nvd = 0).
    Spheroid(SpheroidArgs),
}

#[derive(Debug, clap::Args)]
struct SpheroidArgs {
    /// Overall length 2a, m.
    #[arg(long, allow_negative_numbers = true)]
    length: f64,
    /// Maximum diameter 2b, m (smaller than the length).
    #[arg(long, allow_negative_numbers = true)]
    diameter: f64,
    /// Fluid density, kg/m^3.
    #[arg(long, default_value_t = 1025.0, allow_negative_numbers = true)]
    rho: f64,
    /// Print machine-readable JSON instead of a table.
    #[arg(long)]
    json: bool,
}

impl Args {
    /// Whether JSON was asked for (`--json`).
    pub(super) fn json(&self) -> bool {
        match &self.shape {
            Shape::Spheroid(a) => a.json,
        }
    }
}

/// Runs the command.
pub fn run(args: Args, out: &mut impl Write) -> CmdResult {
    match args.shape {
        Shape::Spheroid(a) => spheroid(a, out),
    }
}

fn spheroid(args: SpheroidArgs, out: &mut impl Write) -> CmdResult {
    let s = Spheroid::from_length_diameter(args.length, args.diameter, args.rho)?;
    let coefficients = s.coefficients();
    if args.json {
        let value = serde_json::json!({
            "shape": "prolate_spheroid",
            "length": args.length,
            "diameter": args.diameter,
            "rho": args.rho,
            "factors": &s,
            "coefficients": &coefficients,
            "source": "Fossen (1994), Guidance and Control of Ocean Vehicles, section 2.4.1 \
                       (Lamb's k-factors)",
        });
        let text = serde_json::to_string_pretty(&value)
            .map_err(|e| crate::Error::Usage(format!("cannot format JSON: {e}")))?;
        writeln!(out, "{text}")?;
        return Ok(0);
    }
    writeln!(
        out,
        "Prolate spheroid L = {} m, D = {} m (a = {} m, b = {} m, L/D = {:.4}), rho = {} kg/m^3",
        args.length,
        args.diameter,
        s.a,
        s.b,
        s.a / s.b,
        args.rho
    )?;
    writeln!(
        out,
        "Fossen (1994), Guidance and Control of Ocean Vehicles, section 2.4.1 (Lamb's k-factors)"
    )?;
    writeln!(out)?;
    writeln!(out, "  e        {:>12.6}", s.e)?;
    writeln!(out, "  alpha0   {:>12.6}", s.alpha0)?;
    writeln!(out, "  beta0    {:>12.6}", s.beta0)?;
    writeln!(out, "  k1       {:>12.6}", s.k1)?;
    writeln!(out, "  k2       {:>12.6}", s.k2)?;
    writeln!(out, "  k'       {:>12.6}", s.k_prime)?;
    writeln!(out, "  m_f      {:>12.6} kg", s.displaced_mass)?;
    writeln!(out, "  I_f      {:>12.6} kg m^2", s.displaced_inertia)?;
    writeln!(out)?;
    writeln!(
        out,
        "  {:<6} {:>12}  {:<7} relation",
        "name", "value", "unit"
    )?;
    for c in &coefficients {
        write_row(out, c)?;
    }
    Ok(0)
}

fn write_row(out: &mut impl Write, c: &Coefficient) -> std::io::Result<()> {
    let relation = c
        .note
        .as_deref()
        .and_then(|n| n.rsplit(": ").next())
        .unwrap_or("");
    writeln!(
        out,
        "  {:<6} {:>12.5}  {:<7} {}",
        c.name,
        c.value + 0.0,
        c.unit,
        relation
    )
}
