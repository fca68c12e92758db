//! The autopilot's series, `autopilot/FEED.csv` (docs/results.md, "Autopilot series"): one
//! table per closed-loop run, the data of the paper's figures (Dinh, Hoang & Pham 2016, fig.
//! 6-8), written with the state series' writer (the same number format, streamed into the
//! staging folder).

use crate::base::error::Result;
use crate::dynamics::autopilot::{AutopilotResult, ClosedLoop};
use crate::io::output::Staging;

/// Writes every run's series to the path results.json names (`series`).
pub fn write(staging: &Staging, a: &AutopilotResult) -> Result<()> {
    for l in &a.feeds {
        if let Some(path) = &l.series_file {
            staging.write_stream(path, |w| {
                let (names, columns) = columns(l);
                super::states::rows(w, &names, |each| {
                    let mut row = vec![0.0; columns.len()];
                    for i in 0..l.times.len() {
                        for (cell, col) in row.iter_mut().zip(&columns) {
                            *cell = col(i);
                        }
                        each(&row)?;
                    }
                    Ok(())
                })
            })?;
        }
    }
    Ok(())
}

/// A column: its value at sample i.
type Column<'a> = Box<dyn Fn(usize) -> f64 + 'a>;

/// The column of a series.
fn at(v: &[f64]) -> Column<'_> {
    Box::new(move |i| v[i])
}

/// The table's header (every name with its SI unit) and its columns, in order: the EKF's and
/// the low-pass filter's columns only when the run has them.
fn columns(l: &ClosedLoop) -> (Vec<String>, Vec<Column<'_>>) {
    let s = &l.series;
    let mut out: Vec<(&str, Column<'_>)> = vec![
        ("time [s]", at(&l.times)),
        ("course_ordered [rad]", at(&s.ordered)),
        ("heading_reference [rad]", at(&s.reference)),
        ("heading_true [rad]", at(&s.heading)),
        ("heading_lf_true [rad]", at(&s.heading_lf)),
        ("compass [rad]", at(&l.compass)),
        ("heading_seen [rad]", at(&l.seen)),
    ];
    let lf = &s.heading_lf;
    if let Some(e) = &s.ekf {
        out.push(("heading_ekf [rad]", at(e)));
        out.push(("error_ekf [rad]", Box::new(move |i| e[i] - lf[i])));
    }
    if let Some(p) = &s.lowpass {
        out.push(("heading_lowpass [rad]", at(p)));
        out.push(("error_lowpass [rad]", Box::new(move |i| p[i] - lf[i])));
    }
    out.push(("heading_error [rad]", at(&l.heading_error)));
    out.push(("rudder_command [rad]", at(&s.command)));
    out.push(("rudder [rad]", at(&l.rudder)));
    out.into_iter().map(|(n, c)| (n.to_string(), c)).unzip()
}
