//! The 6:1 prolate spheroid in the horizontal plane, from the paper's equations: Rasekh &
//! Mahdi (2020), eq. 2-4 as ../shared/docs/spheroid-hekf.md reads them (section 1), written
//! from that text, not from src/model/models:
//!
//!     (m - Xud) u_dot                = F_X
//!     (m - Yvd) v_dot - Yrd r_dot    = F_Y
//!     -Nvd v_dot + (Izz - Nrd) r_dot = F_N
//!     F_X =  m v r + Xuu u|u| + Xuv u v + Xvv v^2 + Xvr v r + Xrr r^2 + X_prop
//!     F_Y = -m u r + Yvv v|v| + Yrr r|r| + Yur u r + Yuv u v
//!     F_N =          Nvv v|v| + Nrr r|r| + Nur u r + Nuv u v
//!
//! with the symmetry relations of eq. 4 (Nvd = Yrd, Xrr = -Yrd, Xvr = -Yvd, Yur = Xud,
//! Nur = Yrd, Nuva = -(Xud - Yvd)), Yuv = Yuvd + Yuvl, Nuv = Nuva + Nuvl, and the planar
//! kinematics. Vehicle (paper Table 1): m = 50 kg, Izz = 3.7 kg m^2. Truth: hydroid's
//! bundled "bounded truth" (src/model/models/spheroid3.rs BOUNDED_TRUTH, values only: the paper's
//! Table 3 polar coefficients, Lamb's added masses, and a restoring Nvv = +10, Nrr = -5,
//! Yrr = +0.5 with which the paper's manoeuvre stays bounded, as the shared document says).

use super::{rk4, Noise, Series};

/// The coefficients (SI), by the paper's names.
#[derive(Debug, Clone, Copy)]
pub struct Spheroid {
    pub mass: f64,
    pub izz: f64,
    pub xud: f64,
    pub yvd: f64,
    pub yrd: f64,
    pub nrd: f64,
    pub xuu: f64,
    pub xuv: f64,
    pub xvv: f64,
    pub yvv: f64,
    pub yrr: f64,
    pub yuvd: f64,
    pub yuvl: f64,
    pub nvv: f64,
    pub nrr: f64,
    pub nuvl: f64,
}

/// State: u, v, r, x, y, psi.
pub type State = [f64; 6];

impl Spheroid {
    /// The paper's vehicle with the bounded truth.
    pub fn bounded_truth() -> Self {
        Spheroid {
            mass: 50.0,
            izz: 3.7,
            xud: -1.1640,
            yvd: -23.626,
            yrd: 0.0,
            nrd: -1.4532,
            xuu: -1.33,
            xuv: 0.44,
            xvv: -5.38,
            yvv: -0.44,
            yrr: 0.5,
            yuvd: 1.33,
            yuvl: -16.31,
            nvv: 10.0,
            nrr: -5.0,
            nuvl: 13.43,
        }
    }

    /// Only the inertial terms: every damping and lift coefficient zero (the added masses
    /// and their relations kept), for the energy check.
    pub fn inertial_only(&self) -> Self {
        Spheroid {
            xuu: 0.0,
            xuv: 0.0,
            xvv: 0.0,
            yvv: 0.0,
            yrr: 0.0,
            yuvd: 0.0,
            yuvl: 0.0,
            nvv: 0.0,
            nrr: 0.0,
            nuvl: 0.0,
            ..*self
        }
    }

    /// [F_X, F_Y, F_N] with the thrust `thrust` N.
    pub fn forces(&self, u: f64, v: f64, r: f64, thrust: f64) -> [f64; 3] {
        let m = self.mass;
        let xvr = -self.yvd;
        let xrr = -self.yrd;
        let yur = self.xud;
        let nur = self.yrd;
        let nuva = -(self.xud - self.yvd);
        let yuv = self.yuvd + self.yuvl;
        let nuv = nuva + self.nuvl;
        [
            m * v * r
                + self.xuu * u * u.abs()
                + self.xuv * u * v
                + self.xvv * v * v
                + xvr * v * r
                + xrr * r * r
                + thrust,
            -m * u * r
                + self.yvv * v * v.abs()
                + self.yrr * r * r.abs()
                + yur * u * r
                + yuv * u * v,
            self.nvv * v * v.abs() + self.nrr * r * r.abs() + nur * u * r + nuv * u * v,
        ]
    }

    pub fn derivatives(&self, x: &State, thrust: f64) -> State {
        let (u, v, r, psi) = (x[0], x[1], x[2], x[5]);
        let [fx, fy, fn_] = self.forces(u, v, r, thrust);
        let nvd = self.yrd;
        // [[m - Yvd, -Yrd], [-Nvd, Izz - Nrd]] [v_dot, r_dot] = [F_Y, F_N]
        let (a11, a12, a21, a22) = (self.mass - self.yvd, -self.yrd, -nvd, self.izz - self.nrd);
        let det = a11 * a22 - a12 * a21;
        [
            fx / (self.mass - self.xud),
            (a22 * fy - a12 * fn_) / det,
            (a11 * fn_ - a21 * fy) / det,
            u * psi.cos() - v * psi.sin(),
            u * psi.sin() + v * psi.cos(),
            r,
        ]
    }

    /// Kinetic energy with the added masses: 0.5 nu^T M nu.
    pub fn kinetic_energy(&self, x: &State) -> f64 {
        let (u, v, r) = (x[0], x[1], x[2]);
        0.5 * (self.mass - self.xud) * u * u
            + 0.5 * (self.mass - self.yvd) * v * v
            + 0.5 * (self.izz - self.nrd) * r * r
            - self.yrd * v * r
    }
}

/// A run: the log and the noise-free states at the samples.
pub struct Run {
    pub log: Series,
    pub states: Vec<State>,
    pub times: Vec<f64>,
}

/// Sensor noise of a CFD export: velocities 1e-3 m/s, yaw rate 0.05 deg/s, positions 1 mm,
/// heading 0.05 deg (numerical noise of the solver's monitors).
pub fn simulate(
    body: &Spheroid,
    x0: State,
    thrust: f64,
    duration: f64,
    fine: f64,
    sample: f64,
    seed: u64,
    noisy: bool,
) -> Run {
    let per = (sample / fine).round() as usize;
    assert!((per as f64 * fine - sample).abs() < 1e-9);
    let steps = (duration / fine).round() as usize;
    let mut x = x0;
    let mut states = Vec::new();
    let mut times = Vec::new();
    for k in 0..=steps {
        if k % per == 0 {
            states.push(x);
            times.push(k as f64 * fine);
        }
        if k == steps {
            break;
        }
        x = rk4(&|s: &State| body.derivatives(s, thrust), &x, fine);
    }
    let mut noise = Noise::new(seed);
    let f = if noisy { 1.0 } else { 0.0 };
    let col = |i: usize| states.iter().map(|s| s[i]).collect::<Vec<f64>>();
    let mut log = Series::new("spheroid drift release at 3 m/s (independent generator)");
    log.push("Time", "s", times.clone());
    log.push("Position X", "m", noise.add(&col(3), 1e-3 * f));
    log.push("Position Y", "m", noise.add(&col(4), 1e-3 * f));
    // the heading as a CFD post-processor writes it: in degrees, wrapped to (-180, 180]
    let heading: Vec<f64> = noise
        .add(&col(5), 0.05f64.to_radians() * f)
        .into_iter()
        .map(|p| {
            let mut d = p.to_degrees() % 360.0;
            if d > 180.0 {
                d -= 360.0;
            } else if d <= -180.0 {
                d += 360.0;
            }
            d
        })
        .collect();
    log.push("Heading", "deg", heading);
    log.push("Velocity u", "m/s", noise.add(&col(0), 1e-3 * f));
    log.push("Velocity v", "m/s", noise.add(&col(1), 1e-3 * f));
    log.push(
        "Yaw Rate",
        "deg/s",
        noise
            .add(&col(2), 0.05f64.to_radians() * f)
            .into_iter()
            .map(f64::to_degrees)
            .collect(),
    );
    Run { log, states, times }
}

/// The paper's manoeuvre (section 4): u0 = 3 m/s, v0 = 1 m/s, r0 = 0, thrust 22 N, 20 s,
/// exported every 0.01 s (the CFD step), RK4 at 1 ms.
pub fn paper_manoeuvre(body: &Spheroid, seed: u64) -> Run {
    simulate(
        body,
        [3.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        22.0,
        20.0,
        0.001,
        0.01,
        seed,
        true,
    )
}

/// The six coefficients the paper's HEKF estimates, with the truth.
pub fn paper_six_truth(b: &Spheroid) -> super::Truth {
    vec![
        ("Yvd", b.yvd),
        ("Yrd", b.yrd),
        ("Nrd", b.nrd),
        ("Nvv", b.nvv),
        ("Nrr", b.nrr),
        ("Yrr", b.yrr),
    ]
}
