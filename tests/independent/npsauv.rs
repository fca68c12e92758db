//! NPS AUV II, 6-DOF, from the published equations: Healey & Lienard (1993) hydrodynamic
//! terms with their nondimensional coefficient set (Fossen's MSS toolbox, npsauv.m: the
//! fixture npsauv_healey_lienard1993.csv), on Fossen's rigid-body kinetics (Fossen 2011,
//! Handbook of Marine Craft Hydrodynamics and Motion Control, eq. 3.3-3.4 in vector form:
//! Newton-Euler about the body origin CO with the centre of gravity at r_G) and zyx Euler
//! kinematics (eq. 2.18-2.29). Written from ../shared/docs/npsauv-6dof-ekf.md and those
//! sources, not from src/models.
//!
//!     M nu_dot = tau_hydro + tau_control + tau_cf + tau_restoring - c_RB(nu)
//!     M = M_RB + M_A,  M_RB = [[m I, -m S(r_G)], [m S(r_G), I_o]]
//!     c_RB = [m (w x v + w x (w x r_G)); w x (I_o w) + m r_G x (w x v)]   (w: omega)
//!
//! M_A holds the acceleration derivatives (Xudot ... Nrdot) scaled by 0.5 rho L^3 (forces on
//! linear accelerations), L^4 and L^5. There are no added-mass Coriolis terms of their own:
//! Healey & Lienard carry them in their velocity-product derivatives (Yvq, Zvp, Mvr ...).
//!
//! Cross-flow drag (Healey & Lienard 1993, eq. for the integral drag terms): strip theory
//! over the hull from x = -L/2 to L/2, each section of height h and breadth b (the MSS 2024
//! block body: h = b = 0.53 m), its cross-flow velocity (v + x r, w - x q):
//!
//!     Y_cf = -rho/2 Int [C_dy h (v + x r)^2 + C_dz b (w - x q)^2] (v + x r) / U_cf(x) dx
//!     Z_cf = -rho/2 Int [ ... ] (w - x q) / U_cf(x) dx
//!     M_cf = +rho/2 Int [ ... ] (w - x q) / U_cf(x) x dx     (the heave strip force's moment)
//!     N_cf = -rho/2 Int [ ... ] (v + x r) / U_cf(x) x dx     (the sway strip force's moment)
//!
//! integrated accurately (composite 3-point Gauss-Legendre, 40 panels). This is the default
//! ([`CrossFlow::StripTheory`]). MSS npsauv.m (2025) evaluates it as a sum over 11 stations
//! at x = -L/2, -0.4 L, ..., L/2 each weighted L/10 (1.1 L in all) and takes the pitch
//! moment with (w + x q) instead of (w - x q) and the opposite sign:
//! [`CrossFlow::Mss`] reproduces that form, [`CrossFlow::Stations`] the 11-station sum
//! with the strip-theory pitch term, for comparison.
//!
//! Propulsion (Healey & Lienard 1993 as in MSS): eta = k n / u (n in rad/s, k = 0.012 m),
//! X_prop = 0.5 rho L^2 C_d0 (k^2 n |n| - u |u|) (= u^2 C_d0 (eta |eta| - 1) for u > 0), and
//! the propulsion correction eps(n) = -1 + sign(n)/sign(u) (sqrt(C_t + 1) - 1) /
//! (sqrt(C_t1 + 1) - 1) with C_t = 0.008 L^2 eta |eta| / 2, C_t1 = 0.008 L^2 / 2, multiplying
//! the `..n` coefficients.
//!
//! Rigid body: the csv's Ix, Iy, Iz and products are about CO (Healey & Lienard), inertia
//! tensor [[Ix, -Ixy, -Ixz], [-Ixy, Iy, -Iyz], [-Ixz, -Iyz, Iz]]; m = W / g with g = 9.80665.
//! Restoring: weight W at r_G, buoyancy B at CO, force (W - B) R^T e_z and moment
//! r_G x W R^T e_z in the body frame (z down).
//!
//! Conventions: body x forward, y starboard, z down; a positive rudder angle gives a
//! negative yaw moment (N_dr < 0: turns to port), a positive stern-plane angle pitches nose
//! down (M_ds < 0).

use super::{published, rk4, solve, value, Noise, Series, Servo, ZigZag, G};

macro_rules! coefficients {
    ($($name:ident),* $(,)?) => {
        /// The Healey & Lienard nondimensional coefficients (names as in the fixture).
        #[allow(non_snake_case)]
        #[derive(Debug, Clone)]
        pub struct Hl { $(pub $name: f64,)* }
        impl Hl {
            /// The published set from the fixture.
            pub fn published() -> Self {
                let set = published("npsauv_healey_lienard1993.csv");
                Hl { $($name: value(&set, stringify!($name)),)* }
            }
            /// Every coefficient but the added-mass (acceleration) ones set to zero.
            pub fn added_mass_only(&self) -> Self {
                let mut z = Hl { $($name: 0.0,)* };
                z.Xudot = self.Xudot; z.Yvdot = self.Yvdot; z.Ypdot = self.Ypdot;
                z.Yrdot = self.Yrdot; z.Zwdot = self.Zwdot; z.Zqdot = self.Zqdot;
                z.Kvdot = self.Kvdot; z.Kpdot = self.Kpdot; z.Krdot = self.Krdot;
                z.Mwdot = self.Mwdot; z.Mqdot = self.Mqdot; z.Nvdot = self.Nvdot;
                z.Npdot = self.Npdot; z.Nrdot = self.Nrdot;
                z
            }
        }
    };
}

coefficients!(
    Xpp, Xqq, Xrr, Xpr, Xudot, Xwq, Xvp, Xvr, Xqds, Xqdb2, Xrdr, Xvv, Xww, Xvdr, Xwds, Xwdb2,
    Xdsds, Xdrdr, Xqdsn, Xwdsn, Xdsdsn, Ypdot, Yrdot, Ypq, Yqr, Yvdot, Yp, Yr, Yvq, Ywp, Ywr, Yv,
    Yvw, Ydr, Zqdot, Zpp, Zpr, Zrr, Zwdot, Zq, Zvp, Zvr, Zw, Zvv, Zds, Zdb2, Zqn, Zwn, Zdsn, Kpdot,
    Krdot, Kpq, Kqr, Kvdot, Kp, Kr, Kvq, Kwp, Kwr, Kv, Kvw, Kdb2, Kpn, Kprop, Mqdot, Mpp, Mpr, Mrr,
    Mwdot, Muq, Mvp, Mvr, Muw, Mvv, Mds, Mdb2, Mqn, Mwn, Mdsn, Npdot, Nrdot, Npq, Nqr, Nvdot, Np,
    Nr, Nvq, Nwp, Nwr, Nv, Nvw, Ndr, Nprop,
);

/// How the cross-flow drag integral is evaluated (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CrossFlow {
    /// Healey & Lienard's integral over -L/2..L/2, pitch moment of the heave strip force.
    StripTheory,
    /// MSS npsauv.m's 11 stations weighted L/10, with the pitch moment of the heave strip
    /// force (w - x q).
    Stations,
    /// MSS npsauv.m (2025) as written: 11 stations weighted L/10, pitch term with (w + x q).
    Mss,
}

/// The vehicle: particulars, coefficients, and the mass matrix with its inverse.
#[derive(Debug, Clone)]
pub struct NpsAuv {
    pub hl: Hl,
    pub length: f64,
    pub rho: f64,
    pub weight: f64,
    pub buoyancy: f64,
    pub mass: f64,
    /// Centre of gravity relative to CO, m.
    pub r_g: [f64; 3],
    /// Inertia tensor about CO, kg m^2.
    pub inertia: [[f64; 3]; 3],
    pub cdy: f64,
    pub cdz: f64,
    pub hull_height: f64,
    pub hull_breadth: f64,
    pub cd0: f64,
    /// eta = k n / u, n in rad/s.
    pub prop_k: f64,
    pub prop_ct: f64,
    pub cross_flow: CrossFlow,
    /// M = M_RB + M_A.
    pub mass_matrix: [[f64; 6]; 6],
    minv: [[f64; 6]; 6],
    /// Quadrature stations and weights of the cross-flow integral.
    stations: Vec<(f64, f64)>,
}

/// Index of each state in the generator's state vector.
pub mod ix {
    pub const U: usize = 0;
    pub const V: usize = 1;
    pub const W: usize = 2;
    pub const P: usize = 3;
    pub const Q: usize = 4;
    pub const R: usize = 5;
    pub const X: usize = 6;
    pub const Y: usize = 7;
    pub const Z: usize = 8;
    pub const PHI: usize = 9;
    pub const THETA: usize = 10;
    pub const PSI: usize = 11;
    /// Rudder angle (servo state), rad.
    pub const DR: usize = 12;
    /// Stern-plane angle (servo state), rad.
    pub const DS: usize = 13;
}

/// nu, eta and the two control-surface angles.
pub type State = [f64; 14];

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// Rotation body -> earth, zyx Euler angles (Fossen 2011, eq. 2.18).
pub fn rotation(phi: f64, theta: f64, psi: f64) -> [[f64; 3]; 3] {
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    [
        [cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st],
        [sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf],
        [-st, ct * sf, ct * cf],
    ]
}

impl NpsAuv {
    /// The published vehicle and coefficient set.
    pub fn published() -> Self {
        Self::build(Hl::published(), CrossFlow::StripTheory)
    }

    /// The vehicle with the coefficients `hl` and the cross-flow form `cross_flow`.
    pub fn build(hl: Hl, cross_flow: CrossFlow) -> Self {
        let length: f64 = 5.3;
        let rho = 1025.0;
        let weight = 53400.0;
        let mass = weight / G;
        let (ixy, iyz, ixz) = (-13.58, -13.58, -13.58);
        let inertia = [
            [2038.0, -ixy, -ixz],
            [-ixy, 13587.0, -iyz],
            [-ixz, -iyz, 13587.0],
        ];
        let r_g = [0.0, 0.0, 0.061];
        let mut m = [[0.0; 6]; 6];
        // M_RB
        for i in 0..3 {
            m[i][i] = mass;
        }
        // -m S(r_G) in the upper right, m S(r_G) in the lower left; S(a) b = a x b
        let s = |a: [f64; 3]| [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
        let sg = s(r_g);
        for i in 0..3 {
            for j in 0..3 {
                m[i][3 + j] = -mass * sg[i][j];
                m[3 + i][j] = mass * sg[i][j];
                m[3 + i][3 + j] = inertia[i][j];
            }
        }
        // M_A: -(0.5 rho L^k) times the acceleration derivatives
        let r3 = 0.5 * rho * length.powi(3);
        let r4 = r3 * length;
        let r5 = r4 * length;
        let h = &hl;
        m[0][0] -= r3 * h.Xudot;
        m[1][1] -= r3 * h.Yvdot;
        m[1][3] -= r4 * h.Ypdot;
        m[1][5] -= r4 * h.Yrdot;
        m[2][2] -= r3 * h.Zwdot;
        m[2][4] -= r4 * h.Zqdot;
        m[3][1] -= r4 * h.Kvdot;
        m[3][3] -= r5 * h.Kpdot;
        m[3][5] -= r5 * h.Krdot;
        m[4][2] -= r4 * h.Mwdot;
        m[4][4] -= r5 * h.Mqdot;
        m[5][1] -= r4 * h.Nvdot;
        m[5][3] -= r5 * h.Npdot;
        m[5][5] -= r5 * h.Nrdot;
        let mut minv = [[0.0; 6]; 6];
        for j in 0..6 {
            let mut e = [0.0; 6];
            e[j] = 1.0;
            let col = solve(&m, &e);
            for i in 0..6 {
                minv[i][j] = col[i];
            }
        }
        // 3-point Gauss-Legendre on 40 panels over -L/2..L/2
        let panels = 40;
        let gl = [
            (-(0.6f64).sqrt(), 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            ((0.6f64).sqrt(), 5.0 / 9.0),
        ];
        let width = length / panels as f64;
        let mut stations = Vec::new();
        for k in 0..panels {
            let mid = -0.5 * length + (k as f64 + 0.5) * width;
            for (xi, w) in gl {
                stations.push((mid + 0.5 * width * xi, 0.5 * width * w));
            }
        }
        NpsAuv {
            hl,
            length,
            rho,
            weight,
            buoyancy: 53400.0,
            mass,
            r_g,
            inertia,
            cdy: 0.5,
            cdz: 0.6,
            hull_height: 0.53,
            hull_breadth: 0.53,
            cd0: 0.00385,
            prop_k: 0.012,
            prop_ct: 0.008,
            cross_flow,
            mass_matrix: m,
            minv,
            stations,
        }
    }

    /// No damping, lift, control or propulsion: only the added mass (and no cross-flow drag,
    /// no hull resistance), for the energy check.
    pub fn inertial_only(&self) -> Self {
        let mut a = Self::build(self.hl.added_mass_only(), self.cross_flow);
        a.cdy = 0.0;
        a.cdz = 0.0;
        a.cd0 = 0.0;
        a
    }

    /// Cross-flow drag [Y, Z, M, N].
    fn cross_flow(&self, v: f64, w: f64, q: f64, r: f64) -> [f64; 4] {
        let (ch, cb) = (self.cdy * self.hull_height, self.cdz * self.hull_breadth);
        let half_rho = 0.5 * self.rho;
        match self.cross_flow {
            CrossFlow::StripTheory => {
                let (mut y, mut z, mut m, mut n) = (0.0, 0.0, 0.0, 0.0);
                for &(x, wt) in &self.stations {
                    let vc = v + x * r;
                    let wc = w - x * q;
                    let ucf = (vc * vc + wc * wc).sqrt();
                    if ucf == 0.0 {
                        continue;
                    }
                    let d = wt * (ch * vc * vc + cb * wc * wc) / ucf;
                    y += d * vc;
                    z += d * wc;
                    m += d * wc * x;
                    n += d * vc * x;
                }
                [-half_rho * y, -half_rho * z, half_rho * m, -half_rho * n]
            }
            CrossFlow::Stations | CrossFlow::Mss => {
                let mss = self.cross_flow == CrossFlow::Mss;
                let dx = self.length / 10.0;
                let (mut y, mut z, mut m, mut n) = (0.0, 0.0, 0.0, 0.0);
                for k in 0..=10 {
                    let x = -0.5 * self.length + k as f64 * dx;
                    let vc = v + x * r;
                    let wc = w - x * q;
                    let ucf = (vc * vc + wc * wc).sqrt() + 1e-6;
                    let d = dx * (ch * vc * vc + cb * wc * wc) / ucf;
                    y += d * vc;
                    z += d * wc;
                    if mss {
                        m -= d * (w + x * q) * x;
                    } else {
                        m += d * wc * x;
                    }
                    n += d * vc * x;
                }
                [-half_rho * y, -half_rho * z, half_rho * m, -half_rho * n]
            }
        }
    }

    /// The propulsion correction eps(n) for n in rad/s at surge speed u.
    pub fn epsilon(&self, u: f64, n: f64) -> f64 {
        let l2 = self.length * self.length;
        let eta = self.prop_k * n / u;
        let ct = 0.5 * self.prop_ct * l2 * eta * eta.abs();
        let ct1 = 0.5 * self.prop_ct * l2;
        -1.0 + n.signum() / u.signum() * ((ct + 1.0).sqrt() - 1.0) / ((ct1 + 1.0).sqrt() - 1.0)
    }

    /// The generalised hydrodynamic, control, propulsion, cross-flow and restoring forces on
    /// the vehicle at state `x` (control angles from the state) with the propeller at `n`
    /// rad/s.
    pub fn forces(&self, x: &State, n: f64) -> [f64; 6] {
        let h = &self.hl;
        let [u, v, w, p, q, r] = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let (phi, theta) = (x[ix::PHI], x[ix::THETA]);
        let (dr, ds) = (x[ix::DR], x[ix::DS]);
        let l = self.length;
        let r2 = 0.5 * self.rho * l * l;
        let r3 = r2 * l;
        let r4 = r3 * l;
        let r5 = r4 * l;
        let eps = self.epsilon(u, n);
        // Healey & Lienard's hydrodynamic terms
        let xh = r2 * (h.Xvv * v * v + h.Xww * w * w)
            + r3 * (h.Xvr * v * r + h.Xwq * w * q + h.Xvp * v * p)
            + r4 * (h.Xqq * q * q + h.Xrr * r * r + h.Xpr * p * r + h.Xpp * p * p);
        let yh = r2 * (h.Yv * u * v + h.Yvw * v * w)
            + r3 * (h.Yp * u * p + h.Yr * u * r + h.Yvq * v * q + h.Ywp * w * p + h.Ywr * w * r)
            + r4 * (h.Ypq * p * q + h.Yqr * q * r);
        let zh = r2 * (h.Zw * u * w + h.Zvv * v * v)
            + r3 * (h.Zq * u * q + h.Zvp * v * p + h.Zvr * v * r)
            + r4 * (h.Zpp * p * p + h.Zpr * p * r + h.Zrr * r * r);
        let kh = r3 * (h.Kv * u * v + h.Kvw * v * w)
            + r4 * (h.Kp * u * p + h.Kr * u * r + h.Kvq * v * q + h.Kwp * w * p + h.Kwr * w * r)
            + r5 * (h.Kpq * p * q + h.Kqr * q * r);
        let mh = r3 * (h.Muw * u * w + h.Mvv * v * v)
            + r4 * (h.Muq * u * q + h.Mvp * v * p + h.Mvr * v * r)
            + r5 * (h.Mpp * p * p + h.Mpr * p * r + h.Mrr * r * r);
        let nh = r3 * (h.Nv * u * v + h.Nvw * v * w)
            + r4 * (h.Np * u * p + h.Nr * u * r + h.Nvq * v * q + h.Nwp * w * p + h.Nwr * w * r)
            + r5 * (h.Npq * p * q + h.Nqr * q * r);
        // control surfaces (bow planes at zero) and propulsion
        let xprop = r2 * self.cd0 * (self.prop_k * self.prop_k * n * n.abs() - u * u.abs());
        let xc = r3 * (h.Xrdr * u * r * dr + h.Xqds * u * q * ds)
            + r2 * (h.Xvdr * u * v * dr
                + h.Xwds * u * w * ds
                + (h.Xdsds * ds * ds + h.Xdrdr * dr * dr) * u * u)
            + eps
                * (r3 * h.Xqdsn * u * q * ds
                    + r2 * (h.Xwdsn * u * w * ds + h.Xdsdsn * u * u * ds * ds))
            + xprop;
        let yc = r2 * h.Ydr * u * u * dr;
        let zc = r2 * h.Zds * u * u * ds
            + eps * (r3 * h.Zqn * u * q + r2 * (h.Zwn * u * w + h.Zdsn * u * u * ds));
        let kc = eps * r4 * h.Kpn * u * p + r3 * u * u * u * h.Kprop;
        let mc = r3 * h.Mds * u * u * ds
            + eps * (r4 * h.Mqn * u * q + r3 * (h.Mwn * u * w + h.Mdsn * u * u * ds));
        let nc = r3 * u * u * (h.Ndr * dr + h.Nprop);
        let [ycf, zcf, mcf, ncf] = self.cross_flow(v, w, q, r);
        // restoring: weight at r_G, buoyancy at CO
        let e_z = [
            -theta.sin(),
            theta.cos() * phi.sin(),
            theta.cos() * phi.cos(),
        ];
        let f_g: [f64; 3] = [
            (self.weight - self.buoyancy) * e_z[0],
            (self.weight - self.buoyancy) * e_z[1],
            (self.weight - self.buoyancy) * e_z[2],
        ];
        let m_g = cross(
            self.r_g,
            [
                self.weight * e_z[0],
                self.weight * e_z[1],
                self.weight * e_z[2],
            ],
        );
        [
            xh + xc + f_g[0],
            yh + yc + ycf + f_g[1],
            zh + zc + zcf + f_g[2],
            kh + kc + m_g[0],
            mh + mc + mcf + m_g[1],
            nh + nc + ncf + m_g[2],
        ]
    }

    /// The rigid-body Coriolis and centripetal forces c_RB(nu) (left-hand side).
    pub fn rigid_body_coriolis(&self, nu: &[f64]) -> [f64; 6] {
        let v = [nu[0], nu[1], nu[2]];
        let om = [nu[3], nu[4], nu[5]];
        let wv = cross(om, v);
        let wwr = cross(om, cross(om, self.r_g));
        let iw = mat_vec(&self.inertia, om);
        let t = cross(om, iw);
        let g = cross(self.r_g, wv);
        let m = self.mass;
        [
            m * (wv[0] + wwr[0]),
            m * (wv[1] + wwr[1]),
            m * (wv[2] + wwr[2]),
            t[0] + m * g[0],
            t[1] + m * g[1],
            t[2] + m * g[2],
        ]
    }

    /// d/dt of the state with the control-surface commands `cmd` = [rudder, stern planes]
    /// (rad), their servo, and the propeller at `n` rad/s.
    pub fn derivatives(&self, x: &State, cmd: [f64; 2], servo: &Servo, n: f64) -> State {
        let tau = self.forces(x, n);
        let c = self.rigid_body_coriolis(&x[..6]);
        let mut rhs = [0.0; 6];
        for i in 0..6 {
            rhs[i] = tau[i] - c[i];
        }
        let mut dx = [0.0; 14];
        for i in 0..6 {
            dx[i] = (0..6).map(|j| self.minv[i][j] * rhs[j]).sum();
        }
        let (phi, theta, psi) = (x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        let rot = rotation(phi, theta, psi);
        let vel = mat_vec(&rot, [x[0], x[1], x[2]]);
        dx[6..9].copy_from_slice(&vel);
        let (p, q, r) = (x[3], x[4], x[5]);
        let (sf, cf) = phi.sin_cos();
        let (tt, ct) = (theta.tan(), theta.cos());
        dx[ix::PHI] = p + sf * tt * q + cf * tt * r;
        dx[ix::THETA] = cf * q - sf * r;
        dx[ix::PSI] = (sf * q + cf * r) / ct;
        dx[ix::DR] = servo.rate_of(x[ix::DR], cmd[0]);
        dx[ix::DS] = servo.rate_of(x[ix::DS], cmd[1]);
        dx
    }

    /// Kinetic energy 0.5 nu^T M nu (added mass included).
    pub fn kinetic_energy(&self, x: &State) -> f64 {
        let mut e = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                e += 0.5 * x[i] * self.mass_matrix[i][j] * x[j];
            }
        }
        e
    }

    /// Potential energy of weight and buoyancy (z down): -W z_G,earth + B z_CO.
    pub fn potential_energy(&self, x: &State) -> f64 {
        let rot = rotation(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        let zg = x[ix::Z] + mat_vec(&rot, self.r_g)[2];
        -self.weight * zg + self.buoyancy * x[ix::Z]
    }

    /// The straight-ahead speed where thrust balances resistance: eta = 1, u = k n.
    pub fn balance_speed(&self, n: f64) -> f64 {
        self.prop_k * n
    }
}

/// The manoeuvre: what the steering does.
#[derive(Debug, Clone, Copy)]
pub enum Steering {
    /// Rudder and stern planes ordered to these angles (rad) at `at` s.
    Helix {
        rudder: f64,
        stern_planes: f64,
        at: f64,
    },
    /// A horizontal zig-zag on the rudder (stern planes at 0).
    ZigZag(ZigZag),
    /// Nothing moves.
    Straight,
}

/// A run of the generator: the sampled log and the fine-step truth at the samples.
pub struct Run {
    /// Time, position, velocities, rates, attitude, control angles and rpm as logged.
    pub log: Series,
    /// The noise-free states at the samples.
    pub states: Vec<State>,
    pub times: Vec<f64>,
}

/// Sensor noise of the log (standard deviations, SI).
#[derive(Debug, Clone, Copy)]
pub struct Sensors {
    pub position: f64,
    pub velocity: f64,
    pub rate: f64,
    pub angle: f64,
    pub control: f64,
}

impl Sensors {
    /// The bundled examples' figures: 0.01 m, 0.01 m/s, 0.1 deg/s, 0.05 deg; control angles
    /// logged without noise.
    pub fn typical() -> Self {
        Sensors {
            position: 0.01,
            velocity: 0.01,
            rate: 0.1f64.to_radians(),
            angle: 0.05f64.to_radians(),
            control: 0.0,
        }
    }

    pub fn none() -> Self {
        Sensors {
            position: 0.0,
            velocity: 0.0,
            rate: 0.0,
            angle: 0.0,
            control: 0.0,
        }
    }
}

/// Runs `vehicle` from `x0` for `duration` s with the propeller at `rpm`, `steering` through
/// `servo`, RK4 at `fine` s, logged every `sample` s (a whole number of fine steps) with
/// `sensors` noise from `seed`. With [`HOLD_FINS`] set for the thread, the hull feels the
/// fin angles of the last logged sample (a diagnostic: the fins then act exactly as
/// hydroid's npsauv assumes between samples) while the logged angles still move.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    vehicle: &NpsAuv,
    x0: State,
    rpm: f64,
    mut steering: Steering,
    servo: Servo,
    duration: f64,
    fine: f64,
    sample: f64,
    sensors: Sensors,
    seed: u64,
    title: &str,
) -> Run {
    let per = (sample / fine).round() as usize;
    assert!(
        (per as f64 * fine - sample).abs() < 1e-9,
        "sample / fine must be whole"
    );
    let steps = (duration / fine).round() as usize;
    let n = rpm * 2.0 * std::f64::consts::PI / 60.0;
    let mut x = x0;
    let mut states = Vec::new();
    let mut times = Vec::new();
    let held = HOLD_FINS.with(|h| h.get());
    let mut seen = [x[ix::DR], x[ix::DS]];
    for k in 0..=steps {
        let t = k as f64 * fine;
        if k % per == 0 {
            states.push(x);
            times.push(t);
            seen = [x[ix::DR], x[ix::DS]];
        }
        if k == steps {
            break;
        }
        let cmd = match &mut steering {
            Steering::Helix {
                rudder,
                stern_planes,
                at,
            } => {
                if t >= *at {
                    [*rudder, *stern_planes]
                } else {
                    [0.0, 0.0]
                }
            }
            Steering::ZigZag(z) => [z.command(t, x[ix::PSI]), 0.0],
            Steering::Straight => [0.0, 0.0],
        };
        let f = |s: &State| {
            if held {
                let mut h = *s;
                h[ix::DR] = seen[0];
                h[ix::DS] = seen[1];
                let mut d = vehicle.derivatives(&h, cmd, &servo, n);
                d[ix::DR] = servo.rate_of(s[ix::DR], cmd[0]);
                d[ix::DS] = servo.rate_of(s[ix::DS], cmd[1]);
                d
            } else {
                vehicle.derivatives(s, cmd, &servo, n)
            }
        };
        x = rk4(&f, &x, fine);
    }
    let mut noise = Noise::new(seed);
    let col = |i: usize| states.iter().map(|s| s[i]).collect::<Vec<f64>>();
    let deg = |v: Vec<f64>| v.into_iter().map(f64::to_degrees).collect::<Vec<f64>>();
    let mut log = Series::new(title);
    log.push("Time", "s", times.clone());
    for (name, i) in [("X", ix::X), ("Y", ix::Y), ("Z", ix::Z)] {
        log.push(name, "m", noise.add(&col(i), sensors.position));
    }
    for (name, i) in [("u", ix::U), ("v", ix::V), ("w", ix::W)] {
        log.push(name, "m/s", noise.add(&col(i), sensors.velocity));
    }
    for (name, i) in [("p", ix::P), ("q", ix::Q), ("r", ix::R)] {
        log.push(name, "deg/s", deg(noise.add(&col(i), sensors.rate)));
    }
    for (name, i) in [
        ("Roll", ix::PHI),
        ("Pitch", ix::THETA),
        ("Heading", ix::PSI),
    ] {
        log.push(name, "deg", deg(noise.add(&col(i), sensors.angle)));
    }
    log.push(
        "Rudder",
        "deg",
        deg(noise.add(&col(ix::DR), sensors.control)),
    );
    log.push(
        "Stern Planes",
        "deg",
        deg(noise.add(&col(ix::DS), sensors.control)),
    );
    log.push("Bow Planes", "deg", vec![0.0; times.len()]);
    log.push("Propeller Speed", "rpm", vec![rpm; times.len()]);
    Run { log, states, times }
}

thread_local! {
    /// Diagnostic switch of [`simulate`]: the hull feels the fins held at their last logged
    /// angles.
    pub static HOLD_FINS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Straight ahead at `u` m/s.
pub fn ahead(u: f64) -> State {
    let mut x = [0.0; 14];
    x[ix::U] = u;
    x
}

/// The fin servo of these runs: 10 deg/s rate limit, 0.1 s lag (MSS's actuator time
/// constant; the rate limit is this generator's assumption).
pub fn fin_servo() -> Servo {
    Servo {
        rate: 10f64.to_radians(),
        tau: 0.1,
    }
}

/// The paper's helix (Mousavian et al. 2015): rudder and stern planes to 10 deg, propeller
/// at 500 rpm, from the balance speed; ordered at 5 s, `duration` s logged at 50 Hz (RK4 at
/// 2.5 ms), sensor noise [`Sensors::typical`].
pub fn helix(vehicle: &NpsAuv, duration: f64, seed: u64) -> Run {
    let n = 500.0 * 2.0 * std::f64::consts::PI / 60.0;
    simulate(
        vehicle,
        ahead(vehicle.balance_speed(n)),
        500.0,
        Steering::Helix {
            rudder: 10f64.to_radians(),
            stern_planes: 10f64.to_radians(),
            at: 5.0,
        },
        fin_servo(),
        duration,
        0.0025,
        0.02,
        Sensors::typical(),
        seed,
        "NPS AUV II helix: rudder and stern planes 10 deg, 500 rpm (independent generator)",
    )
}

/// A horizontal 20/20 zig-zag on the rudder at 1500 rpm from the balance speed (1.885 m/s),
/// first order at 5 s, `duration` s logged at 50 Hz (RK4 at 2.5 ms).
pub fn zigzag(vehicle: &NpsAuv, duration: f64, seed: u64) -> Run {
    let n = 1500.0 * 2.0 * std::f64::consts::PI / 60.0;
    simulate(
        vehicle,
        ahead(vehicle.balance_speed(n)),
        1500.0,
        Steering::ZigZag(ZigZag::new(
            20f64.to_radians(),
            20f64.to_radians(),
            -1.0,
            5.0,
            0.0,
        )),
        fin_servo(),
        duration,
        0.0025,
        0.02,
        Sensors::typical(),
        seed,
        "NPS AUV II horizontal zig-zag 20/20, 1500 rpm (independent generator)",
    )
}

/// The 17 coefficients of Mousavian et al. (2015) under hydroid's names (Mq = M_uq,
/// Mw = M_uw) with their published values.
pub fn paper_17_truth(hl: &Hl) -> super::Truth {
    vec![
        ("Mq", hl.Muq),
        ("Mds", hl.Mds),
        ("Mw", hl.Muw),
        ("Nr", hl.Nr),
        ("Ndr", hl.Ndr),
        ("Nv", hl.Nv),
        ("Np", hl.Np),
        ("Zds", hl.Zds),
        ("Zq", hl.Zq),
        ("Zw", hl.Zw),
        ("Ydr", hl.Ydr),
        ("Yr", hl.Yr),
        ("Yv", hl.Yv),
        ("Yp", hl.Yp),
        ("Kp", hl.Kp),
        ("Kr", hl.Kr),
        ("Kv", hl.Kv),
    ]
}
