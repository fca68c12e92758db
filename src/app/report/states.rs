//! The state series of each run the HEKF fits, `states/NAME.csv` (docs/results.md, "State
//! series"): streamed from the stage's spool ([`crate::stages::hekf::states`]) into the
//! staging folder row by row, every number as coefficients.csv writes it (Rust's shortest
//! form that reads back to the same double), so that the same run gives the same bytes.

use crate::app::results::RunOutput;
use crate::base::error::Result;
use crate::io::output::Staging;
use crate::stages::hekf::states::Table;
use std::fmt::Write as _;
use std::io::Write;

/// Writes every HEKF run's state series into the staging folder.
pub fn write(staging: &Staging, out: &RunOutput) -> Result<()> {
    let Some(h) = out.result.stages.hekf.as_ref() else {
        return Ok(());
    };
    for t in h.traces.iter().filter_map(|t| t.states.as_ref()) {
        staging.write_stream(&t.path, |w| table(t, w))?;
    }
    Ok(())
}

/// One table: the header, then every spooled row.
fn table(t: &Table, w: &mut dyn Write) -> std::io::Result<()> {
    rows(w, &t.columns, |each| t.spool.for_each_row(each))
}

/// A table of numbers: the header `columns`, then every row `each_row` hands its callback,
/// each number in Rust's shortest form that reads back to the same double (the state series
/// and the autopilot's series alike).
pub(super) fn rows(
    w: &mut dyn Write,
    columns: &[String],
    each_row: impl FnOnce(&mut dyn FnMut(&[f64]) -> std::io::Result<()>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut c = csv::Writer::from_writer(w);
    c.write_record(columns)?;
    let mut field = String::new();
    each_row(&mut |row| {
        for v in row {
            field.clear();
            write!(field, "{v}").expect("writing to a String");
            c.write_field(field.as_bytes())?;
        }
        c.write_record(None::<&[u8]>)?;
        Ok(())
    })?;
    c.flush()
}
