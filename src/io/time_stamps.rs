//! Repeated time stamps in a sampled history, and what each kind means.
//!
//! Logs repeat a time stamp for three reasons, told apart in this order:
//!
//! 1. **Identical rows** (same time, same values): a logger or an export that wrote a row
//!    twice. The repeats are dropped with one warning that counts them.
//! 2. **Restarts**: a run restarted from an earlier time writes the overlap again (the time
//!    goes back), or writes its last time once more. Each stamp keeps its last row.
//! 3. **Too few digits**: a time column printed with, say, three significant digits
//!    (`1.35E+02`) repeats its stamps while the rows differ. When every stamp is the rounding
//!    of a uniform sampling `t0 + k dt` (k the row number, dt detected or configured) the time
//!    base is rebuilt from it, with a warning.
//!
//! Anything else (repeated stamps with different rows that are not a uniform sampling) is an
//! error naming both lines.

use crate::base::error::InputError;
use crate::io::table::Table;
use std::collections::HashMap;

/// What became of the repeated stamps of a table's time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Repeats {
    /// No stamp repeats (after dropping identical rows).
    None,
    /// The time goes back, or each repeated stamp appears twice: a restart.
    Restart,
    /// Stamps repeat in a non-decreasing column: perhaps printed with too few digits.
    Coarse,
}

/// Tidies the time column `t` of `table` (values in s): drops identical repeated rows, keeps
/// the last row of a restart's overlap, rebuilds a time base printed with too few digits
/// (with the interval `dt` when given), and rejects anything else, or a time that goes back
/// without repeating an earlier stamp.
pub fn tidy(table: &mut Table, t: usize, dt: Option<f64>) -> Result<(), InputError> {
    drop_identical_rows(table, t);
    match classify(&table.columns[t].values) {
        Repeats::None => {}
        Repeats::Coarse => {
            // One repeated stamp is as likely a restart that wrote its last time again: the
            // sampling is only inferred from two or more (or with a configured interval).
            let time = &table.columns[t].values;
            let built = if dt.is_some() || repeated_stamps(time) >= 2 {
                rebuild(time, dt)
            } else {
                Err(None)
            };
            match built {
                Ok(built) => {
                    warn_rebuilt(table, t, &built, dt.is_some());
                    table.columns[t].values = built.times;
                }
                Err(misfit) if dt.is_some() => return Err(not_uniform(table, t, dt, misfit)),
                Err(_) if twice_at_most(&table.columns[t].values) => keep_last(table, t),
                Err(misfit) => return Err(not_uniform(table, t, None, misfit)),
            }
        }
        Repeats::Restart => {
            // A coarse time column with one stamp out of place also goes back: it is read
            // as a uniform sampling (or refused at that row), never thinned as a restart.
            let time = &table.columns[t].values;
            let adjacent = (1..time.len()).filter(|&i| time[i] == time[i - 1]).count();
            match (adjacent >= 2).then(|| rebuild(time, dt)) {
                Some(Ok(built)) => {
                    warn_rebuilt(table, t, &built, dt.is_some());
                    table.columns[t].values = built.times;
                }
                Some(Err(Some(misfit @ Misfit::Row { .. }))) => {
                    return Err(not_uniform(table, t, dt, Some(misfit)))
                }
                _ => keep_last(table, t),
            }
        }
    }
    check_increasing(table, t)
}

/// Drops every row whose time and values equal those of an earlier row with the same stamp,
/// with one warning that counts them.
fn drop_identical_rows(table: &mut Table, t: usize) {
    let rows = table.rows();
    let time = &table.columns[t].values;
    let same = |a: usize, b: usize| {
        table.columns.iter().all(|c| {
            let (x, y) = (c.values[a], c.values[b]);
            x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan())
        })
    };
    let mut seen: HashMap<u64, Vec<usize>> = HashMap::new();
    let mut keep = vec![true; rows];
    let mut first: Option<(usize, usize)> = None;
    for i in 0..rows {
        if !time[i].is_finite() {
            continue;
        }
        let earlier = seen.entry(time[i].to_bits()).or_default();
        if let Some(&j) = earlier.iter().find(|&&j| same(i, j)) {
            keep[i] = false;
            first.get_or_insert((j, i));
        } else {
            earlier.push(i);
        }
    }
    let dropped = keep.iter().filter(|k| !**k).count();
    if let Some((j, i)) = first {
        table.warnings.push(format!(
            "{dropped} row{} repeat{} an earlier row exactly (same time, same values; first \
             line {} repeats line {}); dropped",
            if dropped == 1 { "" } else { "s" },
            if dropped == 1 { "s" } else { "" },
            table.lines[i],
            table.lines[j]
        ));
        table.retain_rows(&keep);
    }
}

/// Whether stamps repeat, and how.
fn classify(time: &[f64]) -> Repeats {
    let finite: Vec<f64> = time.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.windows(2).any(|w| w[1] < w[0]) {
        let mut seen = std::collections::HashSet::new();
        let repeats = finite.iter().any(|v| !seen.insert(v.to_bits()));
        return if repeats {
            Repeats::Restart
        } else {
            Repeats::None
        };
    }
    if finite.windows(2).any(|w| w[1] == w[0]) {
        Repeats::Coarse
    } else {
        Repeats::None
    }
}

/// How many distinct stamps appear more than once.
fn repeated_stamps(time: &[f64]) -> usize {
    let mut count: HashMap<u64, usize> = HashMap::new();
    for v in time.iter().filter(|v| v.is_finite()) {
        *count.entry(v.to_bits()).or_default() += 1;
    }
    count.values().filter(|&&c| c > 1).count()
}

/// True when no stamp appears more than twice (a restart that wrote its last time again).
fn twice_at_most(time: &[f64]) -> bool {
    let mut count: HashMap<u64, usize> = HashMap::new();
    time.iter().filter(|v| v.is_finite()).all(|v| {
        let c = count.entry(v.to_bits()).or_default();
        *c += 1;
        *c <= 2
    })
}

/// Keeps the last row of every repeated stamp, with a warning (a restart's overlap).
fn keep_last(table: &mut Table, t: usize) {
    let time = &table.columns[t].values;
    let mut last = HashMap::new();
    for (i, v) in time.iter().enumerate() {
        if v.is_finite() {
            last.insert(v.to_bits(), i);
        }
    }
    let keep: Vec<bool> = time
        .iter()
        .enumerate()
        .map(|(i, v)| !v.is_finite() || last[&v.to_bits()] == i)
        .collect();
    let repeated = keep.iter().filter(|k| !**k).count();
    if repeated == 0 {
        return;
    }
    let first_line = keep.iter().position(|k| !k).map_or(0, |k| table.lines[k]);
    table.warnings.push(format!(
        "{} repeated time stamp{} (first at line {}); kept the last row of each, as written \
         after a restart",
        repeated,
        if repeated == 1 { "" } else { "s" },
        first_line
    ));
    table.retain_rows(&keep);
}

/// A time that goes back (not a repeat of an earlier stamp) is an error at its line.
fn check_increasing(table: &Table, t: usize) -> Result<(), InputError> {
    let time = &table.columns[t].values;
    let mut prev: Option<f64> = None;
    for (i, &v) in time.iter().enumerate() {
        if !v.is_finite() {
            continue;
        }
        if let Some(p) = prev {
            if v < p {
                return Err(InputError::new(
                    table
                        .place(i)
                        .with_column_name(table.columns[t].name.clone()),
                    format!("time goes backwards, from {p} to {v}"),
                )
                .expected(
                    "time increasing down the file (rows that repeat an earlier time \
                     exactly, as after a restart, are allowed)",
                ));
            }
        }
        prev = Some(v);
    }
    Ok(())
}

/// The error for repeated stamps with different rows that are no uniform sampling: names the
/// first row beyond one printed digit of the best uniform grid, or else the first two lines
/// that share a stamp.
fn not_uniform(table: &Table, t: usize, dt: Option<f64>, misfit: Option<Misfit>) -> InputError {
    let time = &table.columns[t].values;
    let i = (1..time.len())
        .find(|&i| time[i] == time[i - 1])
        .unwrap_or(0);
    let j = i.saturating_sub(1);
    let grid = match dt {
        Some(dt) => format!("a uniform sampling with the configured dt = {dt} s"),
        None => "a uniform sampling".to_string(),
    };
    let (row, what) = match misfit {
        Some(Misfit::Row { row, at, by }) => (
            row,
            format!(
                "line {} has time {} where {grid} printed with the digits the file has would \
                 give {} ({} s off, more than one printed digit), although lines {} and {} \
                 share the stamp {} as a time column printed with too few digits does",
                table.lines[row],
                time[row],
                crate::base::numfmt::num(at),
                crate::base::numfmt::num(by),
                table.lines[j],
                table.lines[i],
                time[i]
            ),
        ),
        Some(Misfit::TooMany { count }) => (
            i,
            format!(
                "lines {} and {} both have time {} but different values, and {count} stamps \
                 are one printed digit off the rounding of {grid} (at most {} may be)",
                table.lines[j],
                table.lines[i],
                time[i],
                max_off(time.len())
            ),
        ),
        None => (
            i,
            format!(
                "lines {} and {} both have time {} but different values, and they are not the \
                 stamps of {grid} printed with too few digits (nor a restart, which repeats \
                 each stamp once)",
                table.lines[j], table.lines[i], time[i]
            ),
        ),
    };
    InputError::new(
        table
            .place(row)
            .with_column_name(table.columns[t].name.clone()),
        what,
    )
    .expected(
        "one row per time stamp; a log sampled at a fixed interval but printed with too few \
         digits is read when its stamps are the rounding of t0 + k dt (a few one printed digit \
         off); `dt` (its interval in s) fixes the interval",
    )
}

/// A time base rebuilt from a uniform sampling.
struct Rebuilt {
    times: Vec<f64>,
    dt: f64,
    resolution: f64,
    /// Rows whose printed stamp is one printed digit off the rounding of the rebuilt time (a
    /// logger's clock jitter at a rounding boundary), first few.
    off: Vec<usize>,
    /// How many rows are one printed digit off.
    off_count: usize,
}

/// Most stamps that may be one printed digit off the rounding of a uniform sampling: 1 % of
/// the rows (at least 3). More is not a uniform sampling.
fn max_off(rows: usize) -> usize {
    (rows / 100).max(3)
}

/// Why a column of repeated stamps is no uniform sampling: the first row beyond one printed
/// digit of the best uniform grid, or too many rows one digit off.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Misfit {
    /// Row `row` lies `by` s from the grid's time `at`, more than one printed digit.
    Row { row: usize, at: f64, by: f64 },
    /// `count` rows are one printed digit off (more than [`max_off`] allows).
    TooMany { count: usize },
}

/// The uniform sampling `a + k dt` whose rounding gives the stamps, if there is one: `dt`
/// when given, else the interval that fits best. Every stamp must lie within half its print
/// resolution of the rebuilt time, except at most [`max_off`] rows that may be one printed
/// digit off (within one and a half resolutions), which are counted.
fn rebuild(time: &[f64], dt: Option<f64>) -> Result<Rebuilt, Option<Misfit>> {
    let n = time.len();
    if n < 2 || time.iter().any(|v| !v.is_finite()) {
        return Err(None);
    }
    let res = crate::numerics::printed::resolutions(time);
    // tolerance of a stamp printed right (half a resolution) and one printed digit off
    let slack =
        |k: usize, half: f64| half * res[k] * (1.0 + 1e-9) + 4.0 * f64::EPSILON * time[k].abs();
    let (a, h) = consensus_grid(time, &res, dt, max_off(n)).ok_or(None)?;
    let mut off = Vec::new();
    let mut off_count = 0;
    for k in 0..n {
        let by = time[k] - a - k as f64 * h;
        if by.abs() <= slack(k, 0.5) {
            continue;
        }
        if by.abs() > slack(k, 1.5) {
            return Err(Some(Misfit::Row {
                row: k,
                at: a + k as f64 * h,
                by,
            }));
        }
        off_count += 1;
        if off.len() < 5 {
            off.push(k);
        }
    }
    if off_count > max_off(n) {
        return Err(Some(Misfit::TooMany { count: off_count }));
    }
    Ok(Rebuilt {
        times: (0..n).map(|k| a + k as f64 * h).collect(),
        dt: h,
        resolution: res.iter().fold(0.0f64, |m, &r| m.max(r)),
        off,
        off_count,
    })
}

/// The grid `a + k h` that rounds to the most stamps: the minimax fit of every stamp within
/// half its resolution, removing the two rows that bind it while it does not fit (Sim &
/// Hartley 2006, "Removing outliers using the L-infinity norm", CVPR: each removal takes at
/// least one row that does not fit), at most `spare + 1` times. Rows removed on the way that
/// do fit are counted back by the caller's classification.
fn consensus_grid(time: &[f64], res: &[f64], dt: Option<f64>, spare: usize) -> Option<(f64, f64)> {
    // every stamp on one grid: stamps exactly at a rounding boundary (a time of 100.5 s
    // printed 1.00E+02, as a grid of 0.1 s gives) fit the exact grid only, which a fit of
    // part of the rows would miss and then count them one printed digit off
    let all: Vec<usize> = (0..time.len()).collect();
    let fit = minimax_grid(time, res, &all, dt);
    if fit.lo <= fit.hi && fit.h > 0.0 {
        return Some(refit(time, res, dt, fit));
    }
    // else start from the rows near the least-squares line, which a few rows off cannot move
    let (a0, h0) = least_squares_grid(time, res, dt);
    let mut rows: Vec<usize> = (0..time.len())
        .filter(|&k| (time[k] - a0 - k as f64 * h0).abs() <= 0.5 * res[k])
        .collect();
    for _ in 0..=spare + 1 {
        if rows.len() < 2 {
            return None;
        }
        let fit = minimax_grid(time, res, &rows, dt);
        if fit.lo <= fit.hi && fit.h > 0.0 {
            return Some(refit(time, res, dt, fit));
        }
        rows.retain(|&k| k != fit.binding.0 && k != fit.binding.1);
    }
    None
}

/// The intercept of a feasible minimax fit: the first stamp when it fits, else the middle of
/// the window.
fn intercept(time: &[f64], fit: &Minimax) -> f64 {
    if (fit.lo..=fit.hi).contains(&time[0]) {
        time[0]
    } else {
        0.5 * (fit.lo + fit.hi)
    }
}

/// Takes back the rows a feasible grid fits (the removal may have taken some that fit) and
/// fits them again, while that takes back more rows (a few rounds).
fn refit(time: &[f64], res: &[f64], dt: Option<f64>, mut fit: Minimax) -> (f64, f64) {
    let mut grid = (intercept(time, &fit), fit.h);
    let mut count = 0;
    for _ in 0..5 {
        let rows: Vec<usize> = (0..time.len())
            .filter(|&k| {
                let tol = 0.5 * res[k] * (1.0 + 1e-9) + 4.0 * f64::EPSILON * time[k].abs();
                (time[k] - grid.0 - k as f64 * grid.1).abs() <= tol
            })
            .collect();
        if rows.len() <= count || rows.len() < 2 {
            break;
        }
        count = rows.len();
        fit = minimax_grid(time, res, &rows, dt);
        if !(fit.lo <= fit.hi && fit.h > 0.0) {
            break;
        }
        grid = (intercept(time, &fit), fit.h);
    }
    grid
}

/// The minimax grid of some rows: its interval, the window of intercepts that fit every row
/// (empty when `lo > hi`) and the two rows that bound the window.
struct Minimax {
    h: f64,
    lo: f64,
    hi: f64,
    binding: (usize, usize),
}

/// The straight line `a + k h` through the stamps by weighted least squares (weights
/// 1/res^2; `h` fixed when given).
fn least_squares_grid(time: &[f64], res: &[f64], dt: Option<f64>) -> (f64, f64) {
    let (mut sw, mut sk, mut st, mut skk, mut skt) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, (t, r)) in time.iter().zip(res).enumerate() {
        let w = 1.0 / (r * r);
        let kf = k as f64;
        sw += w;
        sk += w * kf;
        st += w * t;
        skk += w * kf * kf;
        skt += w * kf * t;
    }
    let h = dt.unwrap_or((sw * skt - sk * st) / (sw * skk - sk * sk));
    ((st - h * sk) / sw, h)
}

/// The interval `h` (given, or of smallest misfit: the misfit is convex in h, golden
/// section) and the window of intercepts `a` with `a + k h` within half a resolution of
/// every stamp of `rows`.
fn minimax_grid(time: &[f64], res: &[f64], rows: &[usize], dt: Option<f64>) -> Minimax {
    let tol = |k: usize| 0.5 * res[k] * (1.0 + 1e-9) + 4.0 * f64::EPSILON * time[k].abs();
    let window = |h: f64| {
        let mut m = Minimax {
            h,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            binding: (rows[0], rows[0]),
        };
        for &k in rows {
            let (lo, hi) = (
                time[k] - tol(k) - k as f64 * h,
                time[k] + tol(k) - k as f64 * h,
            );
            if lo > m.lo {
                (m.lo, m.binding.0) = (lo, k);
            }
            if hi < m.hi {
                (m.hi, m.binding.1) = (hi, k);
            }
        }
        m
    };
    let h = dt.unwrap_or_else(|| {
        let gap = |h: f64| {
            let w = window(h);
            w.lo - w.hi
        };
        let (first, last) = (rows[0], rows[rows.len() - 1]);
        let tol_max = rows.iter().fold(0.0f64, |m, &k| m.max(tol(k)));
        let (mut a, mut b) = (
            0.0,
            2.0 * (time[last] - time[first] + 2.0 * tol_max) / (last - first).max(1) as f64,
        );
        let g = (5f64.sqrt() - 1.0) / 2.0;
        for _ in 0..120 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if gap(c) <= gap(d) {
                b = d;
            } else {
                a = c;
            }
        }
        0.5 * (a + b)
    });
    window(h)
}

/// The warning for a rebuilt time base.
fn warn_rebuilt(table: &mut Table, t: usize, built: &Rebuilt, configured: bool) {
    let time = &table.columns[t].values;
    let shared = (1..time.len()).filter(|&i| time[i] == time[i - 1]).count();
    let i = (1..time.len())
        .find(|&i| time[i] == time[i - 1])
        .unwrap_or(0);
    let off =
        if built.off_count == 0 {
            String::new()
        } else {
            let lines: Vec<String> = built
                .off
                .iter()
                .map(|&k| table.lines[k].to_string())
                .collect();
            format!(
            "; {} stamp{} one printed digit off that rounding (line{} {}{}), as a logger's clock \
             jitter at a rounding boundary prints them",
            built.off_count,
            if built.off_count == 1 { " is" } else { "s are" },
            if lines.len() == 1 { "" } else { "s" },
            lines.join(", "),
            if built.off_count > lines.len() { " ..." } else { "" }
        )
        };
    table.warnings.push(format!(
        "the time column repeats stamps while the rows differ ({shared} rows share the stamp \
         of the row above, first lines {} and {}): it is printed with too few digits \
         (resolution up to {} s); rebuilt the time base as a uniform sampling from {} s every \
         {} s ({}), which rounds to the printed stamps{off}",
        table.lines[i.saturating_sub(1)],
        table.lines[i],
        crate::base::numfmt::num(built.resolution),
        crate::base::numfmt::num(built.times[0]),
        crate::base::numfmt::num(built.dt),
        if configured {
            "the configured dt"
        } else {
            "detected"
        }
    ));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::formats::Format;
    use crate::io::table::Column;

    fn table(times: &[f64], u: &[f64]) -> Table {
        let mut t = Table::new("log.dat", Format::Delimited);
        t.columns.push(Column::new("time", times.to_vec()));
        t.columns.push(Column::new("u", u.to_vec()));
        t.lines = (0..times.len()).map(|i| i + 4).collect();
        t.time = Some(0);
        t
    }

    /// Three significant digits, as `%.2E` prints them.
    fn three_digits(v: f64) -> f64 {
        format!("{v:.2e}").parse().unwrap()
    }

    #[test]
    fn identical_rows_are_dropped_with_one_warning() {
        let mut t = table(
            &[0.0, 0.1, 0.1, 0.2, 0.2, 0.3],
            &[1.0, 2.0, 2.0, 3.0, 3.0, 4.0],
        );
        tidy(&mut t, 0, None).unwrap();
        assert_eq!(t.columns[0].values, [0.0, 0.1, 0.2, 0.3]);
        assert_eq!(t.lines, [4, 5, 7, 9]);
        assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
        assert!(
            t.warnings[0].starts_with("2 rows repeat"),
            "{}",
            t.warnings[0]
        );
        assert!(
            t.warnings[0].contains("line 6 repeats line 5"),
            "{}",
            t.warnings[0]
        );
    }

    #[test]
    fn three_significant_digits_are_rebuilt() {
        let dt = 0.1353;
        let truth: Vec<f64> = (0..1000).map(|k| k as f64 * dt).collect();
        let printed: Vec<f64> = truth.iter().map(|&v| three_digits(v)).collect();
        assert!(printed.windows(2).any(|w| w[0] == w[1]));
        let u: Vec<f64> = (0..1000).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, None).unwrap();
        let rebuilt = &t.columns[0].values;
        assert_eq!(rebuilt.len(), 1000);
        let worst = rebuilt
            .iter()
            .zip(&truth)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(worst < 0.05, "{worst}");
        assert!(t.warnings[0].contains("too few digits"), "{:?}", t.warnings);
        // with the interval given
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, Some(dt)).unwrap();
        assert!((t.columns[0].values[999] - 999.0 * dt).abs() < 1e-9);
        assert!(t.warnings[0].contains("configured"), "{:?}", t.warnings);
    }

    /// A uniform grid printed with 3 significant digits, with `jitter` (s) added to the rows
    /// in `jittered` before printing (a logger clock near a rounding boundary).
    fn jittered_log(n: usize, dt: f64, jittered: &[usize], jitter: f64) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let t = k as f64 * dt + if jittered.contains(&k) { jitter } else { 0.0 };
                three_digits(t)
            })
            .collect()
    }

    #[test]
    fn stamps_one_printed_digit_off_are_counted_and_the_grid_kept() {
        let dt = 0.135264;
        let n = 15000;
        // rows whose stamp lies near a rounding boundary, nudged across it
        let near: Vec<usize> = (1..n)
            .filter(|&k| {
                let t = k as f64 * dt;
                let r = 10f64.powi(t.log10().floor() as i32 - 2);
                let frac = (t / r).fract();
                (0.44..0.5).contains(&frac)
            })
            .take(20)
            .collect();
        assert_eq!(near.len(), 20);
        // each nudged by just enough to print one digit up: the independent statement of the
        // trap (MARIN's logs have 4-34 such rows per file)
        let printed: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 * dt;
                if near.contains(&k) {
                    let r = 10f64.powi(t.log10().floor() as i32 - 2);
                    three_digits(three_digits(t) + r)
                } else {
                    three_digits(t)
                }
            })
            .collect();
        let u: Vec<f64> = (0..n).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, None).unwrap();
        let worst = t.columns[0]
            .values
            .iter()
            .enumerate()
            .fold(0.0f64, |m, (k, v)| m.max((v - k as f64 * dt).abs()));
        assert!(worst < 1e-3, "rebuilt grid off by {worst} s");
        let w = &t.warnings[0];
        assert!(w.contains("20 stamps are one printed digit off"), "{w}");
        assert!(w.contains(&format!("lines {},", near[0] + 4)), "{w}");
        // the same with the interval configured
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, Some(dt)).unwrap();
        assert!((t.columns[0].values[n - 1] - (n - 1) as f64 * dt).abs() < 1e-6);
    }

    #[test]
    fn stamps_at_a_rounding_boundary_fit_the_exact_grid() {
        // 0.1 s printed with 3 significant digits: 100.5 s is printed 1.00E+02 or 1.01E+02
        // as the binary value falls, exactly half a resolution from the grid
        let dt = 0.1;
        let printed: Vec<f64> = (0..2001).map(|k| three_digits(k as f64 * dt)).collect();
        let u: Vec<f64> = (0..2001).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, None).unwrap();
        let worst = t.columns[0]
            .values
            .iter()
            .enumerate()
            .fold(0.0f64, |m, (k, v)| m.max((v - k as f64 * dt).abs()));
        assert!(worst < 1e-6, "rebuilt grid off by {worst} s");
        assert!(!t.warnings[0].contains("off"), "{}", t.warnings[0]);
    }

    #[test]
    fn a_stamp_two_digits_off_is_named() {
        let dt = 0.135264;
        let mut printed = jittered_log(3000, dt, &[], 0.0);
        // line 34 (row 30, t = 4.058 s printed 4.06) is written 0.03 s late (three printed
        // digits); and a stamp out of place where the column repeats (it goes back)
        printed[30] += 0.03;
        let u: Vec<f64> = (0..3000).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        let e = tidy(&mut t, 0, None).unwrap_err();
        let m = e.to_string();
        assert_eq!(e.place.line, Some(34), "{m}");
        assert!(m.contains("more than one printed digit"), "{m}");
        let mut printed = jittered_log(3000, dt, &[], 0.0);
        printed[2000] += 3.0;
        let mut t = table(&printed, &u);
        let e = tidy(&mut t, 0, None).unwrap_err();
        assert_eq!(e.place.line, Some(2004), "{e}");
    }

    #[test]
    fn many_stamps_one_digit_off_are_no_uniform_sampling() {
        let dt = 0.135264;
        let every: Vec<usize> = (0..2000).step_by(7).collect();
        let printed = jittered_log(2000, dt, &every, 0.006);
        let u: Vec<f64> = (0..2000).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        let m = tidy(&mut t, 0, None).unwrap_err().to_string();
        assert!(
            m.contains("one printed digit off") || m.contains("not the stamps"),
            "{m}"
        );
    }

    #[test]
    fn fixed_decimals_are_rebuilt() {
        let printed: Vec<f64> = (0..40)
            .map(|k| format!("{:.1}", k as f64 * 0.04).parse().unwrap())
            .collect();
        let u: Vec<f64> = (0..40).map(|k| k as f64).collect();
        let mut t = table(&printed, &u);
        tidy(&mut t, 0, None).unwrap();
        assert!((t.columns[0].values[39] - 39.0 * 0.04).abs() < 0.01);
    }

    #[test]
    fn repeats_that_are_no_sampling_name_both_lines() {
        let mut t = table(
            &[0.0, 0.1, 0.1, 0.1, 0.1, 0.5],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        );
        let e = tidy(&mut t, 0, None).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("lines 5 and 6"), "{m}");
        assert_eq!(e.place.line, Some(6));
        // a configured interval that does not fit is the same error, naming it
        let mut t = table(&[0.0, 0.1, 0.1, 0.2], &[1.0, 2.0, 3.0, 4.0]);
        let m = tidy(&mut t, 0, Some(0.5)).unwrap_err().to_string();
        assert!(m.contains("dt = 0.5 s"), "{m}");
    }

    #[test]
    fn a_restart_keeps_its_last_rows() {
        let mut t = table(&[0.0, 0.1, 0.2, 0.2, 0.3], &[0.0, 1.0, 2.0, 3.0, 4.0]);
        tidy(&mut t, 0, None).unwrap();
        assert_eq!(t.columns[1].values, [0.0, 1.0, 3.0, 4.0]);
        let mut t = table(
            &[0.8, 0.9, 1.0, 0.9, 1.0, 1.1],
            &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
        );
        tidy(&mut t, 0, None).unwrap();
        assert_eq!(t.columns[1].values, [0.0, 3.0, 4.0, 5.0]);
    }
}
