//! Independent data generators for hydroid's identification-accuracy tests (issues 22 and 28).
//!
//! hydroid's own accuracy tests are twins: `hydroid simulate` makes the data with the same
//! model code that identifies it, so no model-form, sampling or convention error can show.
//! The generators here are written from the published equations (the papers' text in
//! ../shared/docs and the published coefficient sets in ../shared/data, copied with their
//! sources into tests/fixtures/independent/), NOT from src/model/models and NOT through `hydroid
//! simulate`:
//!
//! * their own integrator: classical RK4 at a fine fixed step, many steps per logged sample;
//! * controls that move continuously: a steering gear (first-order servo with a rate limit)
//!   integrated as a state inside the fine steps, so that the logged rudder angle is a sample
//!   of a moving rudder, not a value held between samples;
//! * a logger: every k-th fine step is written, at 10 to 100 Hz, with additive Gaussian
//!   noise from a fixed seed;
//! * CSV files with a header of names and units (`u (m/s)`, `heading (deg)`) as a basin
//!   logger or a CFD post-processor writes them (docs/formats.md).
//!
//! Each generator returns the sampled series and its truth. `accuracy` runs hydroid as a
//! library on them and tabulates estimate, sigma, truth and z per coefficient.
// Numerical kernels index several arrays with one loop variable (as the crate allows).
#![allow(dead_code, clippy::needless_range_loop, clippy::too_many_arguments)]

pub mod accuracy;
pub mod mmg;
pub mod nomoto;
pub mod npsauv;
pub mod spheroid;

use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::path::{Path, PathBuf};

/// Standard gravity, m/s^2.
pub const G: f64 = 9.80665;

/// One classical fourth-order Runge-Kutta step of x_dot = f(x) over `h` (the inputs that f
/// reads are constant over the step or are themselves states).
pub fn rk4<const N: usize>(f: &impl Fn(&[f64; N]) -> [f64; N], x: &[f64; N], h: f64) -> [f64; N] {
    let add = |a: &[f64; N], k: &[f64; N], s: f64| {
        let mut o = *a;
        for i in 0..N {
            o[i] += s * k[i];
        }
        o
    };
    let k1 = f(x);
    let k2 = f(&add(x, &k1, 0.5 * h));
    let k3 = f(&add(x, &k2, 0.5 * h));
    let k4 = f(&add(x, &k3, h));
    let mut o = *x;
    for i in 0..N {
        o[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    o
}

/// A steering gear (rudder, planes): the angle follows its command as a first-order lag of
/// time constant `tau`, its rate limited to `rate` (rad/s). Integrated as a state by RK4, the
/// angle is a continuous, piecewise smooth function of time: ramps at the rate limit that
/// round off into the commanded angle.
#[derive(Debug, Clone, Copy)]
pub struct Servo {
    /// Maximum rate, rad/s.
    pub rate: f64,
    /// Time constant of the lag, s.
    pub tau: f64,
}

impl Servo {
    /// d(angle)/dt for the angle `delta` and the command `cmd`.
    pub fn rate_of(&self, delta: f64, cmd: f64) -> f64 {
        ((cmd - delta) / self.tau).clamp(-self.rate, self.rate)
    }
}

/// A 20/20-style zig-zag helmsman: rudder `+angle` first, reversed whenever the heading has
/// changed by `switch` from the initial heading in the direction the rudder turns it.
/// `turn_sign` is the sign of the yaw rate a positive rudder angle gives (+1 for a ship
/// steered with the MMG convention, -1 for Fossen's AUV convention).
#[derive(Debug, Clone, Copy)]
pub struct ZigZag {
    /// Rudder amplitude, rad.
    pub angle: f64,
    /// Heading change that reverses the rudder, rad.
    pub switch: f64,
    /// Sign of the yaw rate for a positive rudder.
    pub turn_sign: f64,
    /// Time of the first rudder order, s.
    pub execute: f64,
    /// The current rudder order's sign (+1 or -1).
    pub side: f64,
    /// Initial heading, rad.
    pub psi0: f64,
}

impl ZigZag {
    pub fn new(angle: f64, switch: f64, turn_sign: f64, execute: f64, psi0: f64) -> Self {
        ZigZag {
            angle,
            switch,
            turn_sign,
            execute,
            side: 1.0,
            psi0,
        }
    }

    /// The rudder command at time `t` for the heading `psi` (checked once per fine step).
    pub fn command(&mut self, t: f64, psi: f64) -> f64 {
        if t < self.execute {
            return 0.0;
        }
        // heading change in the direction the present rudder order turns the vehicle
        let change = self.turn_sign * self.side * (psi - self.psi0);
        if change >= self.switch {
            self.side = -self.side;
        }
        self.side * self.angle
    }
}

/// Seeded Gaussian measurement noise.
pub struct Noise {
    rng: StdRng,
}

impl Noise {
    pub fn new(seed: u64) -> Self {
        Noise {
            rng: StdRng::seed_from_u64(seed),
        }
    }

    /// `values` plus white noise of standard deviation `sigma` (none when 0).
    pub fn add(&mut self, values: &[f64], sigma: f64) -> Vec<f64> {
        if sigma == 0.0 {
            return values.to_vec();
        }
        let n = Normal::new(0.0, sigma).unwrap();
        values.iter().map(|v| v + n.sample(&mut self.rng)).collect()
    }

    /// One standard normal number.
    pub fn standard(&mut self) -> f64 {
        Normal::new(0.0, 1.0).unwrap().sample(&mut self.rng)
    }
}

/// One logged column: its header name, unit and values (in that unit).
#[derive(Debug, Clone)]
pub struct Column {
    pub name: String,
    pub unit: String,
    pub values: Vec<f64>,
}

/// A sampled log, as a logger or a CFD post-processor writes it.
#[derive(Debug, Clone)]
pub struct Series {
    /// A title line written above the header.
    pub title: String,
    pub columns: Vec<Column>,
}

impl Series {
    pub fn new(title: &str) -> Self {
        Series {
            title: title.to_string(),
            columns: Vec::new(),
        }
    }

    /// Adds a column `name (unit)`.
    pub fn push(&mut self, name: &str, unit: &str, values: Vec<f64>) {
        if let Some(first) = self.columns.first() {
            assert_eq!(first.values.len(), values.len(), "column {name}");
        }
        self.columns.push(Column {
            name: name.to_string(),
            unit: unit.to_string(),
            values,
        });
    }

    /// The values of column `name`.
    pub fn get(&self, name: &str) -> &[f64] {
        &self
            .columns
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no column {name}"))
            .values
    }

    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// Writes `dir/file`: a `# title` comment line, a header `"name (unit)",...` and the rows
    /// with 10 significant digits. Returns the path.
    pub fn write_csv(&self, dir: &Path, file: &str) -> PathBuf {
        let mut s = format!("# {}\n", self.title);
        let header: Vec<String> = self
            .columns
            .iter()
            .map(|c| format!("\"{} ({})\"", c.name, c.unit))
            .collect();
        s.push_str(&header.join(","));
        s.push('\n');
        for k in 0..self.rows() {
            let row: Vec<String> = self
                .columns
                .iter()
                .map(|c| format!("{:.10e}", c.values[k]))
                .collect();
            s.push_str(&row.join(","));
            s.push('\n');
        }
        let path = dir.join(file);
        std::fs::write(&path, s).unwrap();
        path
    }
}

/// The truth a generator used: named coefficient values in the units hydroid reads them.
pub type Truth = Vec<(&'static str, f64)>;

/// The value of `name` in `truth`.
pub fn truth_of(truth: &Truth, name: &str) -> f64 {
    truth
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no truth for {name}"))
        .1
}

/// A fixture of published values (tests/fixtures/independent/FILE): `name,value` lines after
/// `#` comment lines that give the source.
pub fn published(file: &str) -> Vec<(String, f64)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/independent")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1) // header: name,value
        .map(|l| {
            let (n, v) = l.split_once(',').unwrap();
            (n.trim().to_string(), v.trim().parse::<f64>().unwrap())
        })
        .collect()
}

/// The value of `name` in a fixture read by [`published`].
pub fn value(set: &[(String, f64)], name: &str) -> f64 {
    set.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no published value for {name}"))
        .1
}

/// Solves A x = b for a small dense system (Gaussian elimination with partial pivoting).
pub fn solve<const N: usize>(a: &[[f64; N]; N], b: &[f64; N]) -> [f64; N] {
    let mut m = *a;
    let mut x = *b;
    for c in 0..N {
        let p = (c..N)
            .max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))
            .unwrap();
        m.swap(c, p);
        x.swap(c, p);
        let d = m[c][c];
        assert!(d.abs() > 1e-300, "singular matrix");
        for r in c + 1..N {
            let f = m[r][c] / d;
            if f != 0.0 {
                for k in c..N {
                    m[r][k] -= f * m[c][k];
                }
                x[r] -= f * x[c];
            }
        }
    }
    for c in (0..N).rev() {
        let mut s = x[c];
        for k in c + 1..N {
            s -= m[c][k] * x[k];
        }
        x[c] = s / m[c][c];
    }
    x
}
