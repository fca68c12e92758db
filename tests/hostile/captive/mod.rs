//! Captive tables as a careless user gives them (issue 48, item 4): each classic mistake
//! applied to the bundled KVLCC2 table (cfd_exports/kvlcc2_captive.csv with
//! configs/ship_captive.toml: [`kvlcc2`]), to the prime-system table of tests/fixtures/captive
//! and to the spheroid's PMM force files (configs/spheroid_joint.toml: [`forms`]), in several
//! strengths and combinations. Each ends as a refusal or a warning naming the mistake and the
//! key to fix (`hydroid check`: the same checks `run` makes before any stage); the sound
//! variations (columns shuffled, units written in the header, a unit converted correctly)
//! stay quiet. A few 3-point polars close [`forms`] (item 3: sigmas undetermined, never
//! hidden). This file holds what the cases share: the table's editing and the command lines.

mod forms;
mod kvlcc2;

use super::{refused, run_table, warned, Case, Expect};
use std::path::Path;

const CONFIG: &str = "configs/ship_captive.toml";
const TABLE: &str = "cfd_exports/kvlcc2_captive.csv";

/// Columns of the captive table: u, v, yaw rate, rudder, propeller, Fx, Fy, Mz.
const U: usize = 0;
const V: usize = 1;
const R: usize = 2;
const RUDDER: usize = 3;
const PROPELLER: usize = 4;
const FX: usize = 5;
const FY: usize = 6;
const MZ: usize = 7;
const FORCES: [usize; 3] = [FX, FY, MZ];
const DEG: f64 = 180.0 / std::f64::consts::PI;

/// A CSV table as cells: the header's and each row's.
pub(super) struct Table {
    pub head: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let split = |l: &str| l.split(',').map(|c| c.trim().to_string()).collect();
        let head = split(lines.next().unwrap());
        Table {
            head,
            rows: lines.map(split).collect(),
        }
    }

    pub fn write(&self, path: &Path) {
        let mut out = self.head.join(",") + "\n";
        for r in &self.rows {
            out.push_str(&r.join(","));
            out.push('\n');
        }
        std::fs::write(path, out).unwrap();
    }

    pub fn value(&self, row: usize, col: usize) -> f64 {
        self.rows[row][col].parse().unwrap()
    }

    /// Each value of column `col` replaced by `f(value, row)`.
    pub fn map(&mut self, col: usize, f: impl Fn(f64, usize) -> f64) {
        for k in 0..self.rows.len() {
            let v = f(self.value(k, col), k);
            self.rows[k][col] = format!("{v:e}");
        }
    }

    /// Columns `cols` multiplied by `f`.
    pub fn scale(&mut self, cols: &[usize], f: f64) {
        for &c in cols {
            self.map(c, |v, _| v * f);
        }
    }

    /// The columns in the order `order` (old indices).
    pub fn reorder(&mut self, order: &[usize]) {
        self.head = order.iter().map(|&i| self.head[i].clone()).collect();
        for r in &mut self.rows {
            *r = order.iter().map(|&i| r[i].clone()).collect();
        }
    }

    /// Sets a header cell's text (its name and unit), quoted as the exports quote them.
    pub fn rename(&mut self, col: usize, header: &str) {
        self.head[col] = format!("\"{header}\"");
    }
}

/// A set-up step editing the file `rel` of the case's folder.
pub(super) fn edit(
    rel: &'static str,
    f: impl Fn(&mut Table) + Send + Sync + 'static,
) -> impl Fn(&Path) + Send + Sync + 'static {
    move |dir: &Path| {
        let path = dir.join(rel);
        let mut t = Table::read(&path);
        f(&mut t);
        t.write(&path);
    }
}

/// `hydroid check` of the captive example with its table edited by `f` and `--set` values
/// (each `key=value`).
fn table(
    name: &str,
    sets: &[&str],
    f: impl Fn(&mut Table) + Send + Sync + 'static,
    expect: Expect,
) -> Case {
    set(name, sets, expect).setup(edit(TABLE, f))
}

/// `hydroid check` of the captive example with `--set` values (each `key=value`).
fn set(name: &str, sets: &[&str], expect: Expect) -> Case {
    check_with(name, CONFIG, sets, expect)
}

/// `hydroid check CONFIG` with `--set` values (each `key=value`).
pub(super) fn check_with(
    name: &str,
    config: &str,
    sets: &[impl AsRef<str>],
    expect: Expect,
) -> Case {
    let mut args = vec!["check".to_string(), config.to_string()];
    for s in sets {
        args.push("--set".into());
        args.push(s.as_ref().to_string());
    }
    Case::with_args(name, args, expect)
}

/// Every force and moment replaced by noise of its own RMS (a fixed seed).
fn noise(cols: &'static [usize]) -> impl Fn(&mut Table) + Send + Sync + 'static {
    move |t: &mut Table| {
        let mut noise = crate::independent::Noise::new(48);
        for &c in cols {
            let n = t.rows.len() as f64;
            let rms = (t
                .rows
                .iter()
                .map(|r| r[c].parse::<f64>().unwrap().powi(2))
                .sum::<f64>()
                / n)
                .sqrt();
            let fresh = noise.add(&vec![0.0; t.rows.len()], rms);
            t.map(c, |_, k| fresh[k]);
        }
    }
}

/// The moment about the point x (m) instead of midship: N - x F_y.
fn about(x: f64) -> impl Fn(&mut Table) + Send + Sync + 'static {
    move |t: &mut Table| {
        let fy: Vec<f64> = (0..t.rows.len()).map(|k| t.value(k, FY)).collect();
        t.map(MZ, |v, k| v - x * fy[k]);
    }
}
