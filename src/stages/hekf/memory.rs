//! The memory a run with the HEKF stage takes, estimated before the filter starts from the
//! number of samples, and the memory there is for it: a run that would not fit stops with
//! the estimate and the setting that fits (`hekf.decimate`, `hekf.smoother = false`) instead
//! of being killed by the operating system hours later.
//!
//! The figures are a least-squares fit of the peak resident memory of `hydroid run` (release
//! build, the bundled configuration with its fit run 10^5 to 10^6 rows long, decimated by 1
//! to 30; docs/performance.md, "Memory"), which they match within 5 %, with 10 % added: the
//! estimate lies 5 to 17 % above every measured peak. (Until issue 24 they were the first
//! measurements with 25 % added to each, and the program's own 64 MiB: 16 to 44 % above, so
//! that at a 600 MB limit a million rows fitted no decimation, although one sample in 10 ran
//! in 506 MB.)

/// Bytes a run takes besides its samples: the program, the other stages, the report
/// (fitted: 40 MB).
pub const FIXED: u64 = 45_000_000;

/// Bytes per row of every HEKF run file, fit and validation, per state of the model: the
/// record and its copies, its re-simulation, the figures drawn from them, none of which
/// decimation changes (fitted: 77.6).
pub const PER_ROW_STATE: u64 = 85;

/// Bytes per sample the filter uses (after `hekf.decimate`), per state of the model: the
/// run's measurements and the last pass's traces (fitted with the smoother's: 29.5 together;
/// the filter's part measured at 20).
pub const PER_SAMPLE_STATE: u64 = 24;

/// Bytes per sample the smoother adds, per state of the model: the smoothed states and the
/// checkpoints (measured: 7.5).
pub const PER_SAMPLE_STATE_SMOOTHER: u64 = 8;

/// What a run of the stage will hold.
#[derive(Debug, Clone, PartialEq)]
pub struct Demand {
    /// Rows of every HEKF run file (fit and validation).
    pub rows: usize,
    /// Rows of the fit runs, each.
    pub fit_rows: Vec<usize>,
    /// States of the model.
    pub states: usize,
}

impl Demand {
    /// Samples the filter uses with every `decimate`-th sample.
    pub fn samples(&self, decimate: usize) -> usize {
        self.fit_rows
            .iter()
            .map(|r| r.div_ceil(decimate.max(1)))
            .sum()
    }

    /// Estimated peak memory of the run, bytes.
    pub fn bytes(&self, decimate: usize, smoother: bool) -> u64 {
        let nx = self.states as u64;
        let per_sample = nx
            * (PER_SAMPLE_STATE
                + if smoother {
                    PER_SAMPLE_STATE_SMOOTHER
                } else {
                    0
                });
        FIXED + self.rows as u64 * nx * PER_ROW_STATE + self.samples(decimate) as u64 * per_sample
    }
}

/// Memory there is for the run, and where the figure comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Supply {
    /// Bytes.
    pub bytes: u64,
    /// Where the figure comes from, for messages.
    pub source: String,
}

/// The memory the run may take: `limit` (`hekf.memory_limit`) when given (the user knows
/// the machine: swap, other jobs, an estimate on the safe side), else, on Linux, what the
/// system has available (MemAvailable, or the control group's room when smaller) plus what
/// this process already holds. None when nothing is known.
pub fn supply(limit: Option<u64>) -> Option<Supply> {
    if let Some(bytes) = limit {
        return Some(Supply {
            bytes,
            source: "set in hekf.memory_limit".into(),
        });
    }
    let held = resident().unwrap_or(0);
    let system = [
        meminfo_available().map(|b| {
            (
                b,
                "available (MemAvailable in /proc/meminfo, plus what hydroid already holds; \
                 hekf.memory_limit overrides this)",
            )
        }),
        cgroup_room().map(|b| {
            (
                b,
                "left in the control group (memory.max, plus what hydroid already holds; \
                 hekf.memory_limit overrides this)",
            )
        }),
    ];
    system
        .into_iter()
        .flatten()
        .min_by_key(|(free, _)| *free)
        .map(|(free, what)| Supply {
            bytes: free.saturating_add(held),
            source: what.into(),
        })
}

/// Checks that the run fits; the error says how much it needs, how much there is, and the
/// setting that fits.
pub fn check(
    demand: &Demand,
    decimate: usize,
    smoother: bool,
    supply: &Supply,
) -> Result<(), String> {
    let need = demand.bytes(decimate, smoother);
    if need <= supply.bytes {
        return Ok(());
    }
    let mut ways = Vec::new();
    if smoother && demand.bytes(decimate, false) <= supply.bytes {
        ways.push(format!(
            "`hekf.smoother = false` (about {})",
            size(demand.bytes(decimate, false))
        ));
    }
    // the smallest decimation that fits (the bytes fall as the decimation grows)
    let longest = demand.fit_rows.iter().copied().max().unwrap_or(1).max(1);
    let fits = |d: usize| demand.bytes(d, smoother) <= supply.bytes;
    if fits(longest) {
        let (mut lo, mut hi) = (decimate.max(1), longest);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if fits(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        ways.insert(
            0,
            format!(
                "`hekf.decimate = {hi}` (one sample in {hi}, about {})",
                size(demand.bytes(hi, smoother))
            ),
        );
    }
    let advice = if ways.is_empty() {
        "no setting of hekf.decimate or hekf.smoother brings it within that: the program and \
         the run files alone take more; shorten the runs or run on a machine with more memory"
            .to_string()
    } else {
        format!("set {}", ways.join(" or "))
    };
    Err(format!(
        "the run would need about {} of memory ({} filter samples of {} run{}, smoother {}), \
         more than the {} {}: {advice}",
        size(need),
        demand.samples(decimate),
        demand.fit_rows.len(),
        if demand.fit_rows.len() == 1 { "" } else { "s" },
        if smoother { "on" } else { "off" },
        size(supply.bytes),
        supply.source
    ))
}

pub use crate::config::hekf::parse_memory_size as parse_size;

/// Bytes for people: "1.9 GB", "850 MB".
pub fn size(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

/// MemAvailable from /proc/meminfo, bytes (Linux).
fn meminfo_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    kb_field(&text, "MemAvailable:")
}

/// Resident memory of this process, bytes (Linux).
fn resident() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    kb_field(&text, "VmRSS:")
}

/// A "Name:   1234 kB" line of a /proc file, in bytes.
fn kb_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kb: u64 = line[name.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// What the control group (cgroup v2) still allows, bytes, when it sets a limit.
fn cgroup_room() -> Option<u64> {
    let read = |f: &str| std::fs::read_to_string(format!("/sys/fs/cgroup/{f}")).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?; // "max": no limit
    let current: u64 = read("memory.current")?.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_their_units() {
        assert_eq!(parse_size("4 GB"), Ok(4_000_000_000));
        assert_eq!(parse_size("512MiB"), Ok(512 << 20));
        assert_eq!(parse_size(" 1.5 gib "), Ok(3 << 29));
        assert!(parse_size("4").unwrap_err().contains("e.g. \"4 GB\""));
        assert!(parse_size("lots GB").is_err());
        assert!(parse_size("0 GB").is_err());
        assert_eq!(size(1_930_000_000), "1.9 GB");
        assert_eq!(size(85_000_000), "85 MB");
    }

    #[test]
    fn the_estimate_grows_with_the_samples_and_falls_with_decimation() {
        let d = Demand {
            rows: 1_000_001,
            fit_rows: vec![1_000_001],
            states: 6,
        };
        assert_eq!(d.samples(1), 1_000_001);
        assert_eq!(d.samples(4), 250_001);
        assert!(d.bytes(1, true) > d.bytes(1, false));
        assert!(d.bytes(4, true) < d.bytes(1, true));
        // the target: a million rows in under 2 GB
        assert!(d.bytes(1, true) < 2_000_000_000, "{}", d.bytes(1, true));
    }

    #[test]
    fn a_run_that_does_not_fit_is_told_the_setting_that_does() {
        let d = Demand {
            rows: 10_000_001,
            fit_rows: vec![10_000_001],
            states: 6,
        };
        // between what the files alone take and the whole run
        let room = Supply {
            bytes: (d.bytes(1, true) + d.bytes(10_000_001, true)) / 2,
            source: "set in hekf.memory_limit".into(),
        };
        let e = check(&d, 1, true, &room).unwrap_err();
        assert!(e.contains("more than the"), "{e}");
        assert!(e.contains("hekf.memory_limit"), "{e}");
        // the decimation offered is the smallest that fits
        let n: usize = e
            .split("`hekf.decimate = ")
            .nth(1)
            .and_then(|s| s.split('`').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{e}"));
        assert!(d.bytes(n, true) <= room.bytes && d.bytes(n - 1, true) > room.bytes);
        assert!(check(&d, n, true, &room).is_ok());
        // nothing fits when the files alone exceed the room
        let tiny = Supply {
            bytes: FIXED / 2,
            source: "set in hekf.memory_limit".into(),
        };
        assert!(check(&d, 1, true, &tiny)
            .unwrap_err()
            .contains("no setting of hekf.decimate"));
    }

    /// Issue 24, item 8: the peaks of a million-row run measured in release builds
    /// (docs/performance.md, "Memory": `/usr/bin/time -f %M`, KiB) lie under the estimate,
    /// by less than 20 %; at a 600 MB limit the run is offered a decimation, where the old
    /// figures said none fits although one sample in 10 ran in 506 MB.
    #[test]
    fn the_estimate_matches_measured_peaks_and_a_600_mb_limit_gets_a_decimation() {
        let d = |rows: usize| Demand {
            rows: rows + 501,
            fit_rows: vec![rows],
            states: 6,
        };
        for (rows, decimate, peak_kib) in [
            (100_001, 1, 96_540u64),
            (100_001, 10, 86_976),
            (300_001, 1, 226_164),
            (300_001, 10, 189_876),
            (1_000_001, 1, 663_272),
            (1_000_001, 3, 570_640),
            (1_000_001, 10, 494_152),
            (1_000_001, 30, 500_448),
        ] {
            let ratio = d(rows).bytes(decimate, true) as f64 / (peak_kib * 1024) as f64;
            assert!(
                (1.0..1.2).contains(&ratio),
                "{rows} rows, decimate {decimate}: estimate / peak {ratio}"
            );
        }
        let room = Supply {
            bytes: 600_000_000,
            source: "set in hekf.memory_limit".into(),
        };
        let e = check(&d(1_000_001), 1, true, &room).unwrap_err();
        let n: usize = e
            .split("`hekf.decimate = ")
            .nth(1)
            .and_then(|s| s.split('`').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no decimation offered: {e}"));
        assert!(n <= 10, "{e}");
    }

    #[test]
    fn the_system_figures_are_read_on_linux() {
        if cfg!(target_os = "linux") {
            assert!(meminfo_available().is_some());
            assert!(resident().is_some_and(|b| b > 0));
        }
        // a configured limit replaces the system's figure, above or below it
        for limit in [1 << 20, u64::MAX / 2] {
            let s = supply(Some(limit)).unwrap();
            assert_eq!(s.bytes, limit);
            assert_eq!(s.source, "set in hekf.memory_limit");
        }
    }
}
