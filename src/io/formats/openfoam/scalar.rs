//! OpenFOAM files with one number per column: forceCoeffs.dat (OpenFOAM.org and older),
//! ESI coefficient.dat, and ESI force.dat / moment.dat.

use super::header;
use crate::base::error::InputError;
use crate::io::formats::columns::{apply_names, assemble, Head};
use crate::io::formats::text::{whitespace_rows, Source};
use crate::io::formats::{Format, ReadOptions};
use crate::io::table::Table;

/// Columns of forceCoeffs.dat when the file has no `# Time` line (OpenFOAM 2.x to 12).
const FORCE_COEFFS: &[&str] = &["Time", "Cm", "Cd", "Cl", "Cl(f)", "Cl(r)"];
/// Columns of ESI coefficient.dat (v1906+).
const COEFFICIENT: &[&str] = &[
    "Time", "Cd", "Cs", "Cl", "CmRoll", "CmPitch", "CmYaw", "Cd(f)", "Cd(r)", "Cs(f)", "Cs(r)",
    "Cl(f)", "Cl(r)",
];
/// Columns of ESI force.dat and moment.dat.
const FORCE: &[&str] = &[
    "Time",
    "total_x",
    "total_y",
    "total_z",
    "pressure_x",
    "pressure_y",
    "pressure_z",
    "viscous_x",
    "viscous_y",
    "viscous_z",
];

/// Reads forceCoeffs.dat, coefficient.dat, force.dat or moment.dat.
pub(crate) fn read(
    src: &Source,
    options: &ReadOptions,
    format: Format,
) -> Result<Table, InputError> {
    let h = header(src);
    let mut warnings = Vec::new();
    let names: Vec<String> = match &h.columns {
        Some((_, tokens)) => tokens.clone(),
        None => {
            let usual = match format {
                Format::OpenFoamCoefficient => COEFFICIENT,
                Format::OpenFoamForce => FORCE,
                _ => FORCE_COEFFS,
            };
            let found = h
                .data
                .first()
                .map_or(0, |&i| src.lines[i].split_ascii_whitespace().count());
            if found != usual.len() {
                let at = h.data.first().map_or(src.file(), |&i| src.at(i));
                return Err(InputError::new(
                    at,
                    format!(
                        "no '# Time ...' column line, and the {found} values per row do not \
                         match the usual {} layout",
                        format
                    ),
                )
                .expected(format!("a column line '# {}'", usual.join(" "))));
            }
            warnings.push(format!(
                "no '# Time ...' column line; columns named as OpenFOAM writes them: {}",
                usual.join(" ")
            ));
            usual.iter().map(|s| s.to_string()).collect()
        }
    };
    let moment_or_force = match format {
        Format::OpenFoamForce => force_unit(src, &h, &mut warnings),
        _ => Some("1"),
    };
    let mut heads: Vec<Head> = names
        .iter()
        .enumerate()
        .map(|(j, n)| match (j, moment_or_force) {
            (0, _) => Head::si(n.clone(), "s"),
            (_, Some(u)) => Head::si(n.clone(), u),
            (_, None) => Head::plain(n.clone()),
        })
        .collect();
    let at = h.columns.as_ref().map_or(src.file(), |(i, _)| src.at(*i));
    apply_names(&mut heads, options, at)?;
    let names: Vec<String> = heads.iter().map(|h| h.name.clone()).collect();
    let rows = whitespace_rows(src, h.data.iter().copied(), &names)?;
    Ok(assemble(src.path, format, heads, rows, h.meta, warnings))
}

/// N for force.dat, N m for moment.dat: from the title line, else the file name.
fn force_unit(src: &Source, h: &super::Header, warnings: &mut Vec<String>) -> Option<&'static str> {
    let title = h.get("title").map(|(t, _)| t.to_ascii_lowercase());
    let file = src
        .path
        .file_name()
        .and_then(|f| f.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let says = |word: &str| title.as_deref().is_some_and(|t| t.starts_with(word));
    if says("moment") || (title.is_none() && file.starts_with("moment")) {
        Some("N m")
    } else if says("force") || (title.is_none() && file.starts_with("force")) {
        Some("N")
    } else {
        warnings.push(
            "neither the title line nor the file name says whether this holds forces or \
             moments; the columns have no unit"
                .into(),
        );
        None
    }
}
