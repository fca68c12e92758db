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

use crate::error::InputError;
use crate::table::Table;
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
                None
            };
            if let Some(built) = built {
                warn_rebuilt(table, t, &built, dt.is_some());
                table.columns[t].values = built.times;
            } else if let Some(dt) = dt {
                return Err(not_uniform(table, t, Some(dt)));
            } else if twice_at_most(&table.columns[t].values) {
                keep_last(table, t);
            } else {
                return Err(not_uniform(table, t, None));
            }
        }
        Repeats::Restart => keep_last(table, t),
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
/// first two lines that share a stamp.
fn not_uniform(table: &Table, t: usize, dt: Option<f64>) -> InputError {
    let time = &table.columns[t].values;
    let i = (1..time.len())
        .find(|&i| time[i] == time[i - 1])
        .unwrap_or(0);
    let j = i.saturating_sub(1);
    let why = match dt {
        Some(dt) => format!(
            "and they are not the stamps of a uniform sampling with the configured dt = {dt} s \
             printed with the digits the file has"
        ),
        None => "and they are not the stamps of a uniform sampling printed with too few digits \
                 (nor a restart, which repeats each stamp once)"
            .to_string(),
    };
    InputError::new(
        table
            .place(i)
            .with_column_name(table.columns[t].name.clone()),
        format!(
            "lines {} and {} both have time {} but different values, {why}",
            table.lines[j], table.lines[i], time[i]
        ),
    )
    .expected(
        "one row per time stamp; a log sampled at a fixed interval but printed with too few \
         digits is read with `dt` (its interval in s) when its stamps are the rounding of \
         t0 + k dt",
    )
}

/// A time base rebuilt from a uniform sampling.
struct Rebuilt {
    times: Vec<f64>,
    dt: f64,
    resolution: f64,
}

/// The print resolution of each stamp: the larger of a fixed number of decimals (the most any
/// stamp shows) and a fixed number of significant digits (the most any stamp shows).
fn resolutions(time: &[f64]) -> Vec<f64> {
    let decimals = |v: f64| {
        let s = format!("{}", v.abs());
        s.split('.').nth(1).map_or(0, str::len) as i32
    };
    // `{:e}` writes the shortest mantissa that reads back: 1.35e-1, 1e1.
    let sig_exp = |v: f64| {
        let s = format!("{:e}", v.abs());
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let digits = m.chars().filter(char::is_ascii_digit).count() as i32;
        (digits, e.parse::<i32>().unwrap_or(0))
    };
    let d = time.iter().map(|&v| decimals(v)).max().unwrap_or(0).min(17);
    let s = time
        .iter()
        .filter(|v| **v != 0.0)
        .map(|&v| sig_exp(v).0)
        .max()
        .unwrap_or(1)
        .min(17);
    time.iter()
        .map(|&v| {
            let fixed = 10f64.powi(-d);
            if v == 0.0 {
                fixed
            } else {
                fixed.max(10f64.powi(sig_exp(v).1 - s + 1))
            }
        })
        .collect()
}

/// The uniform sampling `a + k dt` whose rounding gives every stamp, if there is one: `dt`
/// when given, else the interval that fits best. Every stamp must lie within half its print
/// resolution of the rebuilt time.
fn rebuild(time: &[f64], dt: Option<f64>) -> Option<Rebuilt> {
    let n = time.len();
    if n < 2 || time.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let res = resolutions(time);
    let tol: Vec<f64> = time
        .iter()
        .zip(&res)
        .map(|(t, r)| 0.5 * r * (1.0 + 1e-9) + 4.0 * f64::EPSILON * t.abs())
        .collect();
    // The intercepts a that fit with interval h: a + k h within [t_k - tol_k, t_k + tol_k].
    let span = |h: f64| {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (k, (t, e)) in time.iter().zip(&tol).enumerate() {
            lo = lo.max(t - e - k as f64 * h);
            hi = hi.min(t + e - k as f64 * h);
        }
        (lo, hi)
    };
    let gap = |h: f64| {
        let (lo, hi) = span(h);
        lo - hi
    };
    let h = match dt {
        Some(h) => h,
        None => {
            // gap(h) is convex (a maximum of lines minus a minimum of lines): golden section.
            let tol_max = tol.iter().fold(0.0f64, |a, &b| a.max(b));
            let (mut a, mut b) = (
                0.0,
                2.0 * (time[n - 1] - time[0] + 2.0 * tol_max) / (n - 1) as f64,
            );
            let g = (5f64.sqrt() - 1.0) / 2.0;
            for _ in 0..200 {
                let (c, d) = (b - g * (b - a), a + g * (b - a));
                if gap(c) <= gap(d) {
                    b = d;
                } else {
                    a = c;
                }
            }
            0.5 * (a + b)
        }
    };
    let (lo, hi) = span(h);
    if !(h > 0.0 && lo <= hi) {
        return None;
    }
    let a = if (lo..=hi).contains(&time[0]) {
        time[0]
    } else {
        0.5 * (lo + hi)
    };
    Some(Rebuilt {
        times: (0..n).map(|k| a + k as f64 * h).collect(),
        dt: h,
        resolution: res.iter().fold(0.0f64, |m, &r| m.max(r)),
    })
}

/// The warning for a rebuilt time base.
fn warn_rebuilt(table: &mut Table, t: usize, built: &Rebuilt, configured: bool) {
    let time = &table.columns[t].values;
    let shared = (1..time.len()).filter(|&i| time[i] == time[i - 1]).count();
    let i = (1..time.len())
        .find(|&i| time[i] == time[i - 1])
        .unwrap_or(0);
    table.warnings.push(format!(
        "the time column repeats stamps while the rows differ ({shared} rows share the stamp \
         of the row above, first lines {} and {}): it is printed with too few digits \
         (resolution up to {} s); rebuilt the time base as a uniform sampling from {} s every \
         {} s ({}), which rounds to every printed stamp",
        table.lines[i.saturating_sub(1)],
        table.lines[i],
        crate::numfmt::num(built.resolution),
        crate::numfmt::num(built.times[0]),
        crate::numfmt::num(built.dt),
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
    use crate::formats::Format;
    use crate::table::Column;

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
