//! Telling the layout of a file from its content.
//!
//! The checks run from the most specific layout to the most general:
//!
//! 1. Fluent: the first line is one quoted string and the next a line of quoted names.
//! 2. OpenFOAM: the file opens with `#` lines; the `# Time ...` column line, the metadata
//!    keys and the first row tell forceCoeffs.dat, coefficient.dat, force.dat/moment.dat,
//!    legacy forces.dat and sixDoFRigidBodyState apart. Without a column line the file name
//!    (`forceCoeffs.dat`, `coefficient.dat`, `force.dat`, `moment.dat`) breaks the tie.
//! 3. Delimited tables (the layout pre-scan must find rows of numbers): CFX when the
//!    preamble has `[Data]`/`[Name]` or a header cell ends in `[ unit ]`; STAR-CCM+ when
//!    the file is comma-separated, every header cell is quoted and one ends in ` (unit)` or
//!    names a monitor; otherwise the generic reader.
//!
//! A file that matches nothing is an error naming the file and saying what was looked for.

use super::text::{decode, Source};
use super::{cfx, delimited, fluent, input, openfoam, starccm, Format};
use crate::base::error::InputError;
use std::path::Path;

/// Detects the layout of the file at `path` (a regular file within the environment's
/// [`input::Limits`]).
pub fn detect(path: &Path) -> Result<Format, InputError> {
    let limits = input::Limits::for_file(path)?;
    let bytes = input::read_bytes(path, &limits)?;
    let text = decode(path, bytes)?;
    let src = Source::new(path, &text);
    super::text::check_width(&src, limits.max_columns)?;
    detect_source(&src)
}

/// Detects the layout of decoded text.
pub(crate) fn detect_source(src: &Source) -> Result<Format, InputError> {
    if fluent::looks_like(src) {
        return Ok(Format::Fluent);
    }
    if let Some(f) = openfoam::detect(src) {
        return Ok(f);
    }
    let layout = delimited::scan(src).map_err(|mut e| {
        e.message = format!("cannot tell the format: {}", e.message);
        e.expected = Some(format!(
            "{}; the layouts hydroid reads are {} (docs/formats.md)",
            e.expected.as_deref().unwrap_or("a supported layout"),
            Format::ALL
                .iter()
                .map(|f| f.name())
                .collect::<Vec<_>>()
                .join(", ")
        ));
        e
    })?;
    Ok(if cfx::looks_like(src, &layout) {
        Format::Cfx
    } else if starccm::looks_like(src, &layout) {
        Format::StarCcm
    } else {
        Format::Delimited
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(name: &str, text: &str) -> Format {
        detect_source(&Source::new(Path::new(name), text)).unwrap()
    }

    #[test]
    fn each_family() {
        assert_eq!(
            fmt("a.out", "\"t\"\n\"Iteration\" \"cd\"\n1 2\n"),
            Format::Fluent
        );
        assert_eq!(
            fmt("x.dat", "# Force coefficients\n# Time Cm Cd Cl\n0 1 2 3\n"),
            Format::OpenFoamForceCoeffs
        );
        assert_eq!(
            fmt("x.dat", "# Time Cd Cs Cl CmRoll\n0 1 2 3 4\n"),
            Format::OpenFoamCoefficient
        );
        assert_eq!(
            fmt("x.dat", "# Time total_x total_y total_z\n0 1 2 3\n"),
            Format::OpenFoamForce
        );
        assert_eq!(
            fmt("x.dat", "# Time forces(pressure viscous) moments(pressure viscous)\n0 ((1 2 3) (1 2 3)) ((1 2 3) (1 2 3))\n"),
            Format::OpenFoamForcesLegacy
        );
        assert_eq!(
            fmt("x.dat", "# Motion State\n0 (1 2 3) (1 2 3)\n"),
            Format::OpenFoamSixDof
        );
        assert_eq!(
            fmt("forceCoeffs.dat", "# comment\n0 1 2 3 4 5\n"),
            Format::OpenFoamForceCoeffs
        );
        assert_eq!(fmt("x.csv", "Time [ s ],u [ m s^-1 ]\n0,1\n"), Format::Cfx);
        assert_eq!(
            fmt("x.csv", "\"Time (s)\",\"u (m/s)\"\n0,1\n"),
            Format::StarCcm
        );
        assert_eq!(fmt("x.csv", "# Time u v\n0 1 2\n"), Format::Delimited);
        assert_eq!(fmt("x.csv", "time,u\n0,1\n"), Format::Delimited);
    }

    #[test]
    fn garbage_is_an_error() {
        let src = Source::new(Path::new("g.txt"), "lorem ipsum\ndolor sit\namet\nfoo\n");
        let e = detect_source(&src).unwrap_err().to_string();
        assert!(
            e.contains("cannot tell the format") && e.contains("g.txt:1"),
            "{e}"
        );
    }
}
