//! The state series of each run the HEKF fits, as a table per run (`states/NAME.csv`,
//! docs/results.md, "State series"): at every sample the filter used in the last pass, the
//! filtered states and sigmas, the smoothed ones when the smoother ran, each measurement with
//! its innovation and innovation sigma, the NIS, and the estimated coefficients with their
//! sigmas.
//!
//! The rows are spooled, as the filter produces them, to two anonymous temporary files
//! (binary, 8 bytes a number): the forward pass's in order, the smoother's, which come last
//! sample first, segment by segment at their place. A run of a million samples thus holds no
//! second copy of its samples in memory; the report reads the spool back row by row into
//! the output folder.

use crate::model::models::Model;
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::sync::{Arc, Mutex};

/// The folder of the output the tables go into.
pub const DIR: &str = "states";

/// The numbers of a row: states, measurements and coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Model states.
    pub nx: usize,
    /// Measured channels.
    pub m: usize,
    /// Estimated coefficients.
    pub nb: usize,
    /// Whether smoothed states follow the filtered ones.
    pub smoothed: bool,
}

impl Layout {
    /// Numbers per row of the forward spool: time, nx filtered values and sigmas, m
    /// measurements, innovations and innovation sigmas, the NIS, nb coefficients and sigmas.
    fn forward(&self) -> usize {
        1 + 2 * self.nx + 3 * self.m + 1 + 2 * self.nb
    }

    /// Numbers per row of the smoothed spool: nx smoothed values and sigmas.
    fn backward(&self) -> usize {
        2 * self.nx
    }

    /// Numbers per row of the table.
    pub fn columns(&self) -> usize {
        self.forward() + if self.smoothed { self.backward() } else { 0 }
    }
}

/// What one sample of the forward pass gives a row, after its update.
pub struct Sample<'a> {
    /// Time, s.
    pub t: f64,
    /// The augmented state (states, then scaled coefficients).
    pub x: &'a [f64],
    /// Its covariance (n x n).
    pub p: &'a [f64],
    /// The measurements.
    pub y: &'a [f64],
    /// The innovations y - h(x_prior) (0 where a measurement was missing or rejected).
    pub innovation: &'a [f64],
    /// The innovation variances, the diagonal of S = H P H^T + R.
    pub innovation_variance: &'a [f64],
    /// The normalised innovation squared.
    pub nis: f64,
    /// The coefficients' scale (their state is value / scale).
    pub scale: &'a [f64],
}

/// Spools the rows of one run while the filter and the smoother produce them.
pub struct SpoolWriter {
    layout: Layout,
    forward: Option<BufWriter<File>>,
    backward: Option<File>,
    rows: usize,
    /// The smoother's segment length and the rows of the segment being filled.
    segment: usize,
    pending: Vec<f64>,
    bytes: Vec<u8>,
    failed: Option<String>,
}

impl SpoolWriter {
    /// A spool for `layout` (the smoothed part in segments of `segment` samples) in two
    /// anonymous temporary files; a failure to create them is kept and reported when the
    /// table is written.
    pub fn new(layout: Layout, segment: usize) -> Self {
        let mut w = SpoolWriter {
            layout,
            forward: None,
            backward: None,
            rows: 0,
            segment: segment.max(1),
            pending: Vec::new(),
            bytes: Vec::new(),
            failed: None,
        };
        match tempfile::tempfile() {
            Ok(f) => w.forward = Some(BufWriter::with_capacity(1 << 16, f)),
            Err(e) => w.fail(e),
        }
        if layout.smoothed {
            match tempfile::tempfile() {
                Ok(f) => w.backward = Some(f),
                Err(e) => w.fail(e),
            }
            w.pending = vec![0.0; w.segment * layout.backward()];
        }
        w
    }

    fn fail(&mut self, e: std::io::Error) {
        if self.failed.is_none() {
            self.failed = Some(format!(
                "the state series could not be spooled to a temporary file ({}; TMPDIR names \
                 the folder it goes in)",
                crate::base::error::io_reason(&e)
            ));
        }
    }

    /// Adds the forward pass's row of one sample.
    pub fn push(&mut self, s: &Sample) {
        let Layout { nx, nb, .. } = self.layout;
        let n = nx + nb;
        let sd = |i: usize| s.p[i * n + i].max(0.0).sqrt();
        self.bytes.clear();
        let mut put = |v: f64| self.bytes.extend_from_slice(&v.to_le_bytes());
        put(s.t);
        for i in 0..nx {
            put(s.x[i]);
            put(sd(i));
        }
        for a in 0..self.layout.m {
            put(s.y[a]);
            put(s.innovation[a]);
            put(s.innovation_variance[a].max(0.0).sqrt());
        }
        put(s.nis);
        // the coefficients in SI, as the pass's estimate is reported (identify::pass_summary)
        for j in 0..nb {
            put(s.x[nx + j] * s.scale[j]);
            put(sd(nx + j) * s.scale[j]);
        }
        self.rows += 1;
        if let Some(f) = self.forward.as_mut() {
            if let Err(e) = f.write_all(&self.bytes) {
                self.forward = None;
                self.fail(e);
            }
        }
    }

    /// Adds the smoothed state `x` and covariance `p` (n x n of the augmented state) of
    /// sample `k`; the smoother gives them last sample first, segment by segment, and a
    /// segment is written at its place once its first sample has come.
    pub fn push_smoothed(&mut self, k: usize, x: &[f64], p: &[f64]) {
        let w = self.layout.backward();
        if w == 0 || self.backward.is_none() {
            return;
        }
        let n = x.len();
        let row = &mut self.pending[(k % self.segment) * w..(k % self.segment + 1) * w];
        for i in 0..self.layout.nx {
            row[2 * i] = x[i];
            row[2 * i + 1] = p[i * n + i].max(0.0).sqrt();
        }
        if k.is_multiple_of(self.segment) {
            let count = self.segment.min(self.rows.saturating_sub(k));
            self.bytes.clear();
            for v in &self.pending[..count * w] {
                self.bytes.extend_from_slice(&v.to_le_bytes());
            }
            let at = (k * w * 8) as u64;
            let file = self.backward.as_mut().expect("checked above");
            let written = file
                .seek(SeekFrom::Start(at))
                .and_then(|_| file.write_all(&self.bytes));
            if let Err(e) = written {
                self.backward = None;
                self.fail(e);
            }
        }
    }

    /// The spool, complete.
    pub fn finish(mut self) -> Spool {
        let forward = match self.forward.take().map(BufWriter::into_inner) {
            Some(Ok(f)) => Some(f),
            Some(Err(e)) => {
                self.fail(e.into_error());
                None
            }
            None => None,
        };
        Spool {
            layout: self.layout,
            rows: self.rows,
            files: Arc::new(Mutex::new(Files {
                forward,
                backward: self.backward,
            })),
            failed: self.failed,
        }
    }
}

struct Files {
    forward: Option<File>,
    backward: Option<File>,
}

/// The spooled rows of one run, read back by [`Spool::for_each_row`].
#[derive(Clone)]
pub struct Spool {
    layout: Layout,
    rows: usize,
    files: Arc<Mutex<Files>>,
    failed: Option<String>,
}

impl std::fmt::Debug for Spool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Spool")
            .field("layout", &self.layout)
            .field("rows", &self.rows)
            .field("failed", &self.failed)
            .finish()
    }
}

impl PartialEq for Spool {
    /// The same spool (its files are not compared).
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.files, &other.files)
    }
}

impl Spool {
    /// Its layout.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Calls `f` with every row in table order: time, the filtered states (value and sigma
    /// of each), the smoothed ones when spooled, then measurements, NIS and coefficients as
    /// [`header`] names them.
    pub fn for_each_row(
        &self,
        mut f: impl FnMut(&[f64]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        if let Some(why) = &self.failed {
            return Err(std::io::Error::other(why.clone()));
        }
        let mut files = self.files.lock().unwrap_or_else(|e| e.into_inner());
        let (fw, bw) = (self.layout.forward(), self.layout.backward());
        let reader = |file: &mut Option<File>| -> std::io::Result<Option<BufReader<File>>> {
            match file.as_mut() {
                Some(f) => {
                    f.seek(SeekFrom::Start(0))?;
                    Ok(Some(BufReader::with_capacity(1 << 16, f.try_clone()?)))
                }
                None => Ok(None),
            }
        };
        let mut forward = reader(&mut files.forward)?
            .ok_or_else(|| std::io::Error::other("the state series was not spooled"))?;
        let mut backward = if self.layout.smoothed {
            reader(&mut files.backward)?
        } else {
            None
        };
        let mut bytes = vec![0u8; 8 * fw.max(bw)];
        let mut a = vec![0.0; fw];
        let mut b = vec![0.0; bw];
        let mut row = Vec::with_capacity(self.layout.columns());
        for _ in 0..self.rows {
            read_into(&mut forward, &mut bytes, &mut a)?;
            row.clear();
            let head = 1 + 2 * self.layout.nx;
            row.extend_from_slice(&a[..head]);
            if let Some(r) = backward.as_mut() {
                read_into(r, &mut bytes, &mut b)?;
                row.extend_from_slice(&b);
            }
            row.extend_from_slice(&a[head..]);
            f(&row)?;
        }
        Ok(())
    }
}

/// One run's table: where it goes in the output, its columns and its rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Path in the output folder (`states/NAME.csv`, [`file_names`]).
    pub path: String,
    /// Column names with units ([`header`]).
    pub columns: Vec<String>,
    /// The rows.
    pub spool: Spool,
}

/// Reads `out.len()` little-endian numbers.
fn read_into(r: &mut impl Read, bytes: &mut [u8], out: &mut [f64]) -> std::io::Result<()> {
    let bytes = &mut bytes[..8 * out.len()];
    r.read_exact(bytes)?;
    for (v, b) in out.iter_mut().zip(bytes.chunks_exact(8)) {
        *v = f64::from_le_bytes(b.try_into().expect("8 bytes"));
    }
    Ok(())
}

/// The table's column names with their SI units, in the order of [`Spool::for_each_row`]:
/// `time [s]`; per state `u_filtered [m/s]`, `u_filtered_sigma [m/s]` (and `u_smoothed`,
/// `u_smoothed_sigma` when `smoothed`); per measured channel (`measured`: indices into the
/// model's outputs) `u_measured`, `u_innovation`, `u_innovation_sigma`; `nis [-]`; per
/// estimated coefficient (`estimated`: indices into the model's coefficients) `Yvd [kg]`,
/// `Yvd_sigma [kg]`.
pub fn header<M: Model>(
    model: &M,
    measured: &[usize],
    estimated: &[usize],
    smoothed: bool,
) -> Vec<String> {
    let mut h = vec!["time [s]".to_string()];
    let states = model.states();
    let pair = |h: &mut Vec<String>, name: &str, what: &str, unit: &str| {
        h.push(format!("{name}_{what} [{unit}]"));
        h.push(format!("{name}_{what}_sigma [{unit}]"));
    };
    for s in states {
        pair(&mut h, s.name, "filtered", s.quantity.si_symbol());
    }
    if smoothed {
        for s in states {
            pair(&mut h, s.name, "smoothed", s.quantity.si_symbol());
        }
    }
    let outputs = model.outputs();
    for &j in measured {
        let (name, q) = match outputs.get(j) {
            Some(o) => (o.name, o.quantity),
            None => (states[j].name, states[j].quantity),
        };
        let unit = q.si_symbol();
        h.push(format!("{name}_measured [{unit}]"));
        h.push(format!("{name}_innovation [{unit}]"));
        h.push(format!("{name}_innovation_sigma [{unit}]"));
    }
    h.push("nis [-]".to_string());
    for &i in estimated {
        let c = &model.coefficients()[i];
        h.push(format!("{} [{}]", c.name, c.unit));
        h.push(format!("{}_sigma [{}]", c.name, c.unit));
    }
    h
}

/// The longest name (before `_2`, `_3` ... and `.csv`) of a state series' file: with them it
/// stays within the 255 bytes of a file name.
const LONGEST_STEM: usize = 240;

/// The file of each run's table, `states/NAME.csv`: the run's name with every stretch of
/// characters but ASCII letters, digits, `-` and `.` made one `_` (none at the end, no leading
/// `.`), cut at [`LONGEST_STEM`] bytes, and `_2`, `_3` ... after a name an earlier run took
/// (compared without case, for file systems that ignore it).
pub fn file_names(names: &[String]) -> Vec<String> {
    let mut taken: Vec<String> = Vec::new();
    names
        .iter()
        .map(|name| {
            let mut safe = String::new();
            for c in name.chars() {
                if c.is_ascii_alphanumeric() || matches!(c, '-' | '.') {
                    safe.push(c);
                } else if !safe.ends_with('_') {
                    safe.push('_');
                }
            }
            // only ASCII is left: any byte is a character boundary
            safe.truncate(LONGEST_STEM);
            if safe.len() > 1 && safe.ends_with('_') {
                safe.pop();
            }
            if safe.starts_with('.') || safe.is_empty() {
                safe.insert(0, '_');
            }
            let mut unique = safe.clone();
            let mut i = 1;
            while taken.contains(&unique.to_lowercase()) {
                i += 1;
                unique = format!("{safe}_{i}");
            }
            taken.push(unique.to_lowercase());
            format!("{DIR}/{unique}.csv")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_file_safe_and_unique() {
        let names: Vec<String> = [
            "turn 1",
            "Turn_1",
            "turn/1",
            "..",
            "",
            "a.b-c",
            "paper manoeuvre (u0 = 3, 22 N)",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        assert_eq!(
            file_names(&names),
            [
                "states/turn_1.csv",
                "states/Turn_1_2.csv",
                "states/turn_1_3.csv",
                "states/_...csv",
                "states/_.csv",
                "states/a.b-c.csv",
                "states/paper_manoeuvre_u0_3_22_N.csv"
            ]
        );
        // a name of any length, or a default name from a long file name, fits a file name
        let long = vec!["a".repeat(5000), "a".repeat(300), "é".repeat(300)];
        let files = file_names(&long);
        assert_eq!(files[0], format!("states/{}.csv", "a".repeat(LONGEST_STEM)));
        assert_eq!(
            files[1],
            format!("states/{}_2.csv", "a".repeat(LONGEST_STEM))
        );
        assert_eq!(files[2], "states/_.csv");
        assert!(files.iter().all(|f| f.len() - "states/".len() <= 255));
    }

    #[test]
    fn a_spheroid_sample_spools_448_bytes() {
        // docs/performance.md: 6 states, 6 measurements, 6 coefficients, smoother on
        let l = Layout {
            nx: 6,
            m: 6,
            nb: 6,
            smoothed: true,
        };
        assert_eq!(8 * l.columns(), 448);
    }

    #[test]
    fn the_spool_gives_back_its_rows_with_the_smoothed_part_in_place() {
        let layout = Layout {
            nx: 1,
            m: 1,
            nb: 1,
            smoothed: true,
        };
        // 7 samples in segments of 3: the smoother comes last first
        let mut w = SpoolWriter::new(layout, 3);
        for k in 0..7 {
            let kf = k as f64;
            w.push(&Sample {
                t: kf,
                x: &[kf, 2.0],
                p: &[4.0, 0.0, 0.0, 9.0],
                y: &[kf + 0.5],
                innovation: &[0.5],
                innovation_variance: &[16.0],
                nis: 0.25,
                scale: &[10.0],
            });
        }
        for k in (0..7).rev() {
            w.push_smoothed(k, &[-(k as f64), 0.0], &[1.0, 0.0, 0.0, 1.0]);
        }
        let spool = w.finish();
        let mut rows = Vec::new();
        spool
            .for_each_row(|r| {
                rows.push(r.to_vec());
                Ok(())
            })
            .unwrap();
        assert_eq!(rows.len(), 7);
        assert_eq!(rows[0].len(), layout.columns());
        let k = 5.0;
        assert_eq!(
            rows[5],
            [k, k, 2.0, -k, 1.0, k + 0.5, 0.5, 4.0, 0.25, 20.0, 30.0]
        );
        // a second reading gives the same
        let mut again = 0;
        spool
            .for_each_row(|r| {
                assert_eq!(r, rows[again].as_slice());
                again += 1;
                Ok(())
            })
            .unwrap();
        assert_eq!(again, 7);
    }
}
