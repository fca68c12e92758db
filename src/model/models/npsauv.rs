//! NPS AUV II, 6-DOF (Healey & Lienard 1993, IEEE J Ocean Eng 18(3):327-339; Fossen 1994,
//! "Guidance and Control of Ocean Vehicles"; coefficient set as coded in Fossen's MSS toolbox,
//! CRAFT/AUV/models/npsauv.m).
//!
//! States `[u, v, w, p, q, r, x, y, z, phi, theta, psi]` (body frame at the centre of buoyancy
//! CO: x forward, y starboard, z down; zyx Euler angles). Inputs `[delta_r, delta_s, delta_b,
//! n]`: rudder, stern planes, bow planes (both bow planes deflected together, see below) and
//! propeller speed (rev/s inside hydroid, converted to rad/s for the propulsion law as MSS
//! npsauv.m does).
//!
//! Equations: M nu_dot = tau_hydro + tau_control + tau_prop + tau_cf - C_RB(nu) nu - g(eta),
//! eta_dot = J(eta) nu, with
//!
//! * M = M_RB + M_A: rigid-body mass about CO with the centre of gravity r_G = (x_G, y_G, z_G)
//!   and the full inertia tensor (Fossen 2011, eq. 3.44), and the added mass of the
//!   Healey & Lienard set, scaled 0.5 rho L^3..L^5 (the MSS file's M_A);
//! * C_RB(nu) nu from Fossen's rigid-body kinetics (Fossen 2011, eq. 3.60), written here as
//!   vector products, so the two sign errors of the 2024 MSS file (heave rigid-body term and
//!   the (I_z - I_x) p r pitch term, /work/shared/docs/npsauv-6dof-ekf.md) cannot occur: the
//!   energy test of tests/npsauv.rs checks it;
//! * the Healey & Lienard hydrodynamic, control-surface and propulsion terms
//!   (`forces`), and the cross-flow drag integral over hull stations;
//! * weight and buoyancy restoring forces (Fossen 2011, eq. 4.6).
//!
//! Bow planes: every bow-plane term of the set multiplies the sum delta_bp + delta_bs of the
//! port and starboard planes (the coefficients named `..db2`, MSS npsauv.m), so one input
//! `bow_planes` = delta_b, with delta_bp = delta_bs = delta_b, carries all of them. A
//! differential bow-plane deflection would act only through K_db2, which is 0 in the
//! published set.
//!
//! Coefficient names: the CSV's (../shared/data/npsauv_coefficients.csv), except that the
//! paper's names are used for its 17 estimated terms (Mousavian et al. 2015): `Mq` is the
//! Healey & Lienard M_uq (u q term) and `Mw` is M_uw (u w term); the other 15 (Mds, Nr, Ndr,
//! Nv, Np, Zds, Zq, Zw, Ydr, Yr, Yv, Yp, Kp, Kr, Kv) have the same names in both. `Xvv_hl`,
//! `Xvr_hl`, `Xrr_hl`, `Xww_hl` carry an `_hl` suffix because the dimensional SNAME
//! coefficients `Xvv`, `Xvr`, `Xrr`, `Xww` of the other models have those names.

mod coefficients;
mod cross_flow;
mod forces;

pub use cross_flow::CrossFlow;

pub use coefficients::{ADDED_MASS, COEFFICIENTS, PAPER_17, PUBLISHED};
use coefficients::*;

use super::rigid_body::{cross, kinematics, solve};
use super::{
    CoefDef, Example, InputDef, InputRule, Model, Size, StateDef, Unphysical, Vehicle, VehicleProblem,
};
use crate::numerics::ad::Scalar;
use crate::model::coefficients::{CompiledRelations, Relation};
use crate::base::si;
use crate::base::quantity::Quantity;

/// Standard gravity, m/s^2 (as the configuration compares weight and buoyancy).
pub const G: f64 = 9.80665;

/// The NPS AUV II vehicle data in SI: L = 5.3 m, W = B = 53400 N, I_x = 2038, I_y = I_z =
/// 13587 kg m^2, z_G = 0.061 m (BG), rho = 1025 kg/m^3 (MSS npsauv.m, Healey & Lienard 1993
/// converted to SI by Fossen). The mass is W / g with standard gravity (5445.3 kg; MSS uses
/// g = 9.81, 5443.4 kg), so that W = B exactly. The particulars are left to their defaults
/// (the published values, see [`NpsParticulars`]).
pub fn nps_auv_vehicle() -> Vehicle {
    Vehicle {
        mass: 53400.0 / G,
        length: 5.3,
        diameter: None,
        ixx: Some(2038.0),
        iyy: Some(13587.0),
        izz: 13587.0,
        reference_area: 5.3 * 5.3,
        buoyancy: Some(53400.0),
        bg: Some(0.061),
        rho: 1025.0,
        particulars: toml::Table::new(),
    }
}

/// What `npsauv` reads from `[vehicle.particulars]`; every key is optional, its default the
/// published NPS AUV II value.
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ParticularsIn {
    #[serde(default, deserialize_with = "si::option::<_, si::Inertia>")]
    ixy: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Inertia>")]
    iyz: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Inertia>")]
    ixz: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Length>")]
    x_g: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Length>")]
    y_g: Option<f64>,
    #[serde(default)]
    cdy: Option<f64>,
    #[serde(default)]
    cdz: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Length>")]
    hull_height: Option<f64>,
    #[serde(default, deserialize_with = "si::option::<_, si::Length>")]
    hull_breadth: Option<f64>,
    #[serde(default)]
    cd0: Option<f64>,
    #[serde(default)]
    propeller_k: Option<f64>,
    #[serde(default)]
    propeller_ct: Option<f64>,
    #[serde(default)]
    cross_flow: Option<CrossFlow>,
}

/// The NPS AUV's own data (SI), from `[vehicle.particulars]` or the published defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NpsParticulars {
    /// Product of inertia I_xy, kg m^2 (inertia tensor entry -I_xy, Healey & Lienard's sign;
    /// default -13.58, MSS npsauv.m).
    pub ixy: f64,
    /// Product of inertia I_yz, kg m^2 (default -13.58, MSS npsauv.m).
    pub iyz: f64,
    /// Product of inertia I_xz, kg m^2 (default -13.58, MSS npsauv.m).
    pub ixz: f64,
    /// Centre of gravity ahead of CO, x_G, m (default 0, MSS npsauv.m).
    pub x_g: f64,
    /// Centre of gravity to starboard of CO, y_G, m (default 0, MSS npsauv.m).
    pub y_g: f64,
    /// Cross-flow drag coefficient in sway, C_dy (default 0.5, MSS npsauv.m).
    pub cdy: f64,
    /// Cross-flow drag coefficient in heave, C_dz (default 0.6, MSS npsauv.m).
    pub cdz: f64,
    /// Height of the hull sections of the cross-flow integral, m (default 0.53 m, the MSS
    /// 2024 file's block-shaped body, "average height of submerged body").
    pub hull_height: f64,
    /// Breadth of the hull sections of the cross-flow integral, m (default 0.53 m, MSS 2024).
    pub hull_breadth: f64,
    /// Hull resistance coefficient C_d0 of the propulsion law (default 0.00385, MSS
    /// npsauv.m, Healey & Lienard 1993).
    pub cd0: f64,
    /// Propeller advance gain k of eta = k n / u, m/rad with n in rad/s (default 0.012, MSS
    /// npsauv.m: `prop = 0.012 n / u` with n converted from rpm to rad/s).
    pub propeller_k: f64,
    /// Thrust coefficient factor of C_t = 0.5 c_t L^2 eta |eta| (default 0.008, MSS npsauv.m).
    pub propeller_ct: f64,
    /// How the cross-flow drag integral is evaluated (default Healey & Lienard's integral;
    /// `"stations"` and `"mss"` are the forms of MSS npsauv.m, [`CrossFlow`]).
    pub cross_flow: CrossFlow,
}

impl Default for NpsParticulars {
    fn default() -> Self {
        NpsParticulars {
            ixy: -13.58,
            iyz: -13.58,
            ixz: -13.58,
            x_g: 0.0,
            y_g: 0.0,
            cdy: 0.5,
            cdz: 0.6,
            hull_height: 0.53,
            hull_breadth: 0.53,
            cd0: 0.00385,
            propeller_k: 0.012,
            propeller_ct: 0.008,
            cross_flow: CrossFlow::Integral,
        }
    }
}

/// The NPS AUV II 6-DOF model.
#[derive(Debug, Clone)]
pub struct NpsAuv {
    /// Mass m, kg.
    pub mass: f64,
    /// Length L, m (the reference length of every coefficient).
    pub length: f64,
    /// Water density rho, kg/m^3.
    pub rho: f64,
    /// Inertia tensor about CO, kg m^2: [[I_x, -I_xy, -I_xz], [-I_xy, I_y, -I_yz],
    /// [-I_xz, -I_yz, I_z]] (Fossen 2011, eq. 3.34).
    pub inertia: [[f64; 3]; 3],
    /// Centre of gravity r_G = (x_G, y_G, z_G) from CO, m.
    pub r_g: [f64; 3],
    /// Weight W = m g, N.
    pub weight: f64,
    /// Buoyancy B, N (acting at CO).
    pub buoyancy: f64,
    /// The particulars.
    pub particulars: NpsParticulars,
    /// Stations and weights (x, dx) of the cross-flow quadrature, from the particulars'
    /// form and the length (computed once: the dynamics use them at every evaluation).
    cross_flow_stations: Vec<(f64, f64)>,
    relations: CompiledRelations,
}


impl NpsAuv {
    /// Reads and checks the particulars of `v`, naming every problem.
    fn read_particulars(v: &Vehicle) -> Result<NpsParticulars, Vec<VehicleProblem>> {
        let p: ParticularsIn = v.particulars(Self::NAME)?;
        let d = NpsParticulars::default();
        let s = NpsParticulars {
            ixy: p.ixy.unwrap_or(d.ixy),
            iyz: p.iyz.unwrap_or(d.iyz),
            ixz: p.ixz.unwrap_or(d.ixz),
            x_g: p.x_g.unwrap_or(d.x_g),
            y_g: p.y_g.unwrap_or(d.y_g),
            cdy: p.cdy.unwrap_or(d.cdy),
            cdz: p.cdz.unwrap_or(d.cdz),
            hull_height: p.hull_height.unwrap_or(d.hull_height),
            hull_breadth: p.hull_breadth.unwrap_or(d.hull_breadth),
            cd0: p.cd0.unwrap_or(d.cd0),
            propeller_k: p.propeller_k.unwrap_or(d.propeller_k),
            propeller_ct: p.propeller_ct.unwrap_or(d.propeller_ct),
            cross_flow: p.cross_flow.unwrap_or(d.cross_flow),
        };
        let mut problems = Vec::new();
        let mut need = |key: &str, value: f64, ok: bool, what: &str| {
            if !(value.is_finite() && ok) {
                problems.push(VehicleProblem {
                    key: format!("vehicle.particulars.{key}"),
                    message: format!("the npsauv model needs {what}, got {value}"),
                });
            }
        };
        for (key, value) in [("ixy", s.ixy), ("iyz", s.iyz), ("ixz", s.ixz)] {
            need(key, value, true, "a finite product of inertia (kg m^2)");
        }
        let l = v.length;
        for (key, value) in [("x_g", s.x_g), ("y_g", s.y_g)] {
            need(key, value, value.abs() < l, "a centre of gravity within the length (m)");
        }
        for (key, value) in [
            ("cdy", s.cdy),
            ("cdz", s.cdz),
            ("hull_height", s.hull_height),
            ("hull_breadth", s.hull_breadth),
            ("cd0", s.cd0),
            ("propeller_ct", s.propeller_ct),
        ] {
            need(key, value, value >= 0.0, "a value that is not negative");
        }
        need(
            "propeller_k",
            s.propeller_k,
            s.propeller_k > 0.0,
            "a positive propeller advance gain (m/rad)",
        );
        if problems.is_empty() {
            Ok(s)
        } else {
            Err(problems)
        }
    }

    /// 0.5 rho L^k, the scale of a coefficient on reference `0.5 rho L^k`.
    fn r(&self, k: i32) -> f64 {
        0.5 * self.rho * self.length.powi(k)
    }

    /// The mass matrix M = M_RB + M_A (6x6).
    ///
    /// M_RB = [[m I, -m S(r_G)], [m S(r_G), I_o]] (Fossen 2011, eq. 3.44); M_A = -[X_udot ...]
    /// with the Healey & Lienard added masses scaled 0.5 rho L^3 (translation-translation),
    /// L^4 (coupling) and L^5 (rotation-rotation), the entries of MSS npsauv.m's M_A.
    pub fn mass_matrix<T: Scalar>(&self, c: &[T]) -> [[T; 6]; 6] {
        let z = T::from(0.0);
        let mut m = [[z; 6]; 6];
        let mass = self.mass;
        let [xg, yg, zg] = self.r_g;
        // S(r_G) a = r_G x a
        let s = [[0.0, -zg, yg], [zg, 0.0, -xg], [-yg, xg, 0.0]];
        for i in 0..3 {
            m[i][i] = T::from(mass);
            for j in 0..3 {
                m[i][3 + j] = T::from(-mass * s[i][j]);
                m[3 + i][j] = T::from(mass * s[i][j]);
                m[3 + i][3 + j] = T::from(self.inertia[i][j]);
            }
        }
        let (r3, r4, r5) = (self.r(3), self.r(4), self.r(5));
        let added = [
            (0, 0, XUDOT, r3),
            (1, 1, YVDOT, r3),
            (1, 3, YPDOT, r4),
            (1, 5, YRDOT, r4),
            (2, 2, ZWDOT, r3),
            (2, 4, ZQDOT, r4),
            (3, 1, KVDOT, r4),
            (3, 3, KPDOT, r5),
            (3, 5, KRDOT, r5),
            (4, 2, MWDOT, r4),
            (4, 4, MQDOT, r5),
            (5, 1, NVDOT, r4),
            (5, 3, NPDOT, r5),
            (5, 5, NRDOT, r5),
        ];
        for (i, j, k, scale) in added {
            m[i][j] -= c[k] * scale;
        }
        m
    }

    /// Rigid-body Coriolis and centripetal forces -C_RB(nu) nu about CO (Fossen 2011,
    /// eq. 3.60 in vector form): top = -m [nu2 x nu1 + nu2 x (nu2 x r_G)],
    /// bottom = -[nu2 x (I_o nu2) + m r_G x (nu2 x nu1)].
    pub fn rigid_body_coriolis<T: Scalar>(&self, nu: &[T; 6]) -> [T; 6] {
        let v1 = [nu[0], nu[1], nu[2]];
        let v2 = [nu[3], nu[4], nu[5]];
        let rg = [T::from(self.r_g[0]), T::from(self.r_g[1]), T::from(self.r_g[2])];
        let i = &self.inertia;
        let iv2: [T; 3] = std::array::from_fn(|k| v2[0] * i[k][0] + v2[1] * i[k][1] + v2[2] * i[k][2]);
        let w1 = cross(v2, v1);
        let w2 = cross(v2, cross(v2, rg));
        let b1 = cross(v2, iv2);
        let b2 = cross(rg, w1);
        let m = self.mass;
        [
            -(w1[0] + w2[0]) * m,
            -(w1[1] + w2[1]) * m,
            -(w1[2] + w2[2]) * m,
            -(b1[0] + b2[0] * m),
            -(b1[1] + b2[1] * m),
            -(b1[2] + b2[2] * m),
        ]
    }

    /// Restoring forces -g(eta) for the weight at r_G and the buoyancy at CO (Fossen 2011,
    /// eq. 4.6 with r_B = 0).
    pub fn restoring<T: Scalar>(&self, phi: T, theta: T) -> [T; 6] {
        let (sf, cf) = phi.sin_cos();
        let (st, ct) = theta.sin_cos();
        let (w, b) = (self.weight, self.buoyancy);
        let [xg, yg, zg] = self.r_g;
        [
            -(st * (w - b)),
            ct * sf * (w - b),
            ct * cf * (w - b),
            ct * cf * (yg * w) - ct * sf * (zg * w),
            -(st * (zg * w)) - ct * cf * (xg * w),
            ct * sf * (xg * w) + st * (yg * w),
        ]
    }

    /// Potential energy of the restoring forces, J (z down): V = -(W - B) z -
    /// W (R(Theta) r_G)_z, whose gradient gives [`NpsAuv::restoring`].
    pub fn potential_energy(&self, x: &[f64]) -> f64 {
        let (z, phi, theta) = (x[8], x[9], x[10]);
        let [xg, yg, zg] = self.r_g;
        let rz = -theta.sin() * xg + theta.cos() * phi.sin() * yg + theta.cos() * phi.cos() * zg;
        -(self.weight - self.buoyancy) * z - self.weight * rz
    }

    /// Kinetic energy 0.5 nu^T M nu with the added mass, J.
    pub fn kinetic_energy(&self, x: &[f64], c: &[f64]) -> f64 {
        let m = self.mass_matrix(c);
        let mut e = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                e += 0.5 * x[i] * m[i][j] * x[j];
            }
        }
        e
    }

    /// The forces of the Healey & Lienard model (hydrodynamic, control, propulsion and
    /// cross-flow drag) at state `x` and inputs `u` (SI), N and N m: for tests.
    pub fn forces(&self, x: &[f64], u: &[f64], c: &[f64]) -> [f64; 6] {
        let nu = [x[0], x[1], x[2], x[3], x[4], x[5]];
        forces::total(self, &nu, u, c)
    }
}

/// Cholesky factorisation of the symmetric part of `m`; the first pivot that is not
/// positive (index, value) if it is not positive definite.
fn not_positive_definite(m: &[[f64; 6]; 6]) -> Option<(usize, f64)> {
    let mut l = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..=i {
            let mut s = 0.5 * (m[i][j] + m[j][i]);
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                if !(s.is_finite() && s > 0.0) {
                    return Some((i, s));
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    None
}

impl Model for NpsAuv {
    const NAME: &'static str = "npsauv";
    const DESCRIPTION: &'static str = "NPS AUV II, 6-DOF: Healey & Lienard (1993) hydrodynamic, \
        control-surface and propulsion terms with cross-flow drag, Fossen's rigid-body kinetics \
        with products of inertia and restoring forces (coefficients as in MSS npsauv.m)";
    const COEFFICIENTS: &'static [CoefDef] = COEFFICIENTS;
    const INPUTS: &'static [InputDef] = &[
        InputDef {
            quantity: Quantity::Rudder,
            rule: InputRule::Hold,
        },
        InputDef {
            quantity: Quantity::SternPlanes,
            rule: InputRule::Hold,
        },
        InputDef {
            quantity: Quantity::BowPlanes,
            rule: InputRule::Hold,
        },
        InputDef {
            quantity: Quantity::Rpm,
            rule: InputRule::Interpolate,
        },
    ];
    const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[];

    fn build(v: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
        let mut problems = Vec::new();
        for (key, value) in [("ixx", v.ixx), ("iyy", v.iyy)] {
            if value.is_none() {
                problems.push(VehicleProblem::missing(
                    Self::NAME,
                    key,
                    &format!("the moment of inertia {key} about CO (kg m^2)"),
                ));
            }
        }
        let particulars = match Self::read_particulars(v) {
            Ok(p) => Some(p),
            Err(e) => {
                problems.extend(e);
                None
            }
        };
        // mass, length, inertias and density are checked positive where the configuration
        // is validated (config::VehicleConfig::validate, FluidConfig::validate)
        let (Some(ixx), Some(iyy), Some(p), true) = (v.ixx, v.iyy, particulars, problems.is_empty())
        else {
            return Err(problems);
        };
        let weight = v.mass * G;
        let inertia = [
            [ixx, -p.ixy, -p.ixz],
            [-p.ixy, iyy, -p.iyz],
            [-p.ixz, -p.iyz, v.izz],
        ];
        Ok(NpsAuv {
            mass: v.mass,
            length: v.length,
            rho: v.rho,
            inertia,
            r_g: [p.x_g, p.y_g, v.bg.unwrap_or(0.0)],
            weight,
            buoyancy: v.buoyancy.unwrap_or(weight),
            particulars: p,
            cross_flow_stations: p.cross_flow.stations(v.length),
            relations: CompiledRelations::compile(&[], &[]),
        })
    }

    fn states(&self) -> &'static [StateDef] {
        super::SIX_DOF_STATES
    }

    fn relations(&self) -> &CompiledRelations {
        &self.relations
    }

    fn compared(&self) -> &'static [Quantity] {
        &[
            Quantity::U,
            Quantity::V,
            Quantity::W,
            Quantity::P,
            Quantity::Q,
            Quantity::R,
            Quantity::Roll,
            Quantity::Pitch,
            Quantity::Yaw,
        ]
    }

    fn typical_magnitude(&self, name: &str) -> f64 {
        COEFFICIENTS
            .iter()
            .find(|d| d.name == name)
            .and_then(|d| match d.size {
                Size::Fixed(v) if v != 0.0 => Some(v.abs()),
                _ => None,
            })
            .unwrap_or(1e-2)
    }

    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]) {
        let nu = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let (phi, theta, psi) = (x[9], x[10], x[11]);
        // M nu_dot = tau_hydro + tau_control + tau_prop + tau_cf - C_RB(nu) nu - g(eta)
        let tau = forces::total(self, &nu, u, c);
        let crb = self.rigid_body_coriolis(&nu);
        let g = self.restoring(phi, theta);
        let mut rhs: [T; 6] = std::array::from_fn(|i| tau[i] + crb[i] + g[i]);
        let m = self.mass_matrix(c);
        let mut mm = [T::from(0.0); 36];
        for i in 0..6 {
            mm[i * 6..i * 6 + 6].copy_from_slice(&m[i]);
        }
        if !solve(&mut mm, &mut rhs, 6) {
            // a singular mass matrix: non-finite rates; `check` names the cause
            rhs = [T::from(f64::NAN); 6];
        }
        dx[..6].copy_from_slice(&rhs);
        // eta_dot = J(eta) nu, zyx Euler angles (Fossen 2011, eq. 2.40)
        dx[6..12].copy_from_slice(&kinematics(&nu, phi, theta, psi));
    }

    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical> {
        if let Some((i, pivot)) = not_positive_definite(&self.mass_matrix(c)) {
            return Err(Unphysical::IndefiniteMassMatrix {
                pivot,
                direction: ["surge", "sway", "heave", "roll", "pitch", "yaw"][i],
            });
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Unphysical::NotFinite("state"));
        }
        if x[10].abs() > 85f64.to_radians() {
            return Err(Unphysical::PitchNearVertical {
                degrees: x[10].to_degrees(),
            });
        }
        Ok(())
    }

    fn example_vehicle() -> Vehicle {
        nps_auv_vehicle()
    }

    fn example(&self) -> Example {
        Example {
            coefficients: PUBLISHED,
            // forward motion at 2 m/s entering the paper's helix
            state: vec![2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            // the paper's helix: rudder and stern planes at 0.175 rad (10 deg), 500 rpm
            inputs: vec![0.175, 0.175, 0.0, 500.0 / 60.0],
            // the paper's 17 (Mousavian et al. 2015): the conformance twin identifies every
            // one within 1 % from this 30 s noise-free helix
            estimated: PAPER_17,
            duration: 30.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> (NpsAuv, Vec<f64>) {
        let m = NpsAuv::build(&nps_auv_vehicle()).expect("the published vehicle");
        let c = m.coefficient_vector(PUBLISHED);
        (m, c)
    }

    #[test]
    fn the_table_sizes_are_the_published_values() {
        assert_eq!(PUBLISHED.len(), COEFFICIENTS.len());
        for ((name, value), def) in PUBLISHED.iter().zip(COEFFICIENTS) {
            assert_eq!(*name, def.name);
            let want = if *value == 0.0 { 1e-2 } else { *value };
            assert_eq!(def.size, Size::Fixed(want), "{name}");
        }
        // the paper's 17 are there by their names
        for n in PAPER_17 {
            assert!(COEFFICIENTS.iter().any(|d| d.name == *n), "{n}");
        }
    }

    #[test]
    fn the_published_mass_matrix_is_symmetric_and_positive_definite() {
        let (m, c) = model();
        let mm = m.mass_matrix(&c);
        for i in 0..6 {
            for j in 0..6 {
                assert!((mm[i][j] - mm[j][i]).abs() < 1e-9, "{i} {j}");
            }
        }
        assert!(not_positive_definite(&mm).is_none());
        // surge: m - 0.5 rho L^3 X_udot
        let want = m.mass + 0.5 * 1025.0 * 5.3f64.powi(3) * 7.6e-3;
        assert!((mm[0][0] - want).abs() < 1e-9);
    }

    #[test]
    fn check_refuses_an_indefinite_mass_matrix() {
        let (m, mut c) = model();
        c[ZWDOT] = 1.0; // a "negative added mass" far above the rigid body
        let e = m.check(&[0.0; 12], &c).unwrap_err().to_string();
        assert!(e.contains("not positive definite") && e.contains("heave"), "{e}");
    }

    #[test]
    fn bad_particulars_are_named() {
        let mut v = nps_auv_vehicle();
        v.particulars.insert("cdy".into(), toml::Value::Float(-1.0));
        v.particulars.insert("propeller_k".into(), toml::Value::Float(0.0));
        let e = NpsAuv::build(&v).unwrap_err();
        let keys: Vec<&str> = e.iter().map(|p| p.key.as_str()).collect();
        assert_eq!(keys, ["vehicle.particulars.cdy", "vehicle.particulars.propeller_k"]);
        let mut v = nps_auv_vehicle();
        v.ixx = None;
        v.particulars.insert("hull_heigth".into(), toml::Value::Float(0.5));
        let e = NpsAuv::build(&v).unwrap_err();
        let keys: Vec<&str> = e.iter().map(|p| p.key.as_str()).collect();
        assert_eq!(keys, ["vehicle.ixx", "vehicle.particulars.hull_heigth"], "{e:?}");
        let mut v = nps_auv_vehicle();
        v.particulars.insert("cross_flow".into(), toml::Value::String("trapezoid".into()));
        let e = NpsAuv::build(&v).unwrap_err();
        assert_eq!(e[0].key, "vehicle.particulars.cross_flow", "{e:?}");
        assert!(e[0].message.contains("integral"), "{e:?}");
        let mut v = nps_auv_vehicle();
        v.particulars.insert("cross_flow".into(), toml::Value::String("mss".into()));
        assert_eq!(NpsAuv::build(&v).unwrap().particulars.cross_flow, CrossFlow::Mss);
    }

    #[test]
    fn at_rest_the_dynamics_stay_finite_and_differentiable() {
        let (m, c) = model();
        let x = [0.0; 12];
        let mut val = [0.0; 12];
        let mut ja = [0.0; 144];
        crate::numerics::ad::jacobian(
            &x,
            12,
            |xd, out| {
                let cd: Vec<crate::numerics::ad::Dual> = c.iter().map(|&v| crate::numerics::ad::constant(v)).collect();
                m.derivatives(xd, &[0.1, 0.1, 0.1, 500.0 / 60.0], &cd, out)
            },
            &mut val,
            &mut ja,
        );
        assert!(val.iter().chain(&ja).all(|v| v.is_finite()), "{val:?}");
    }

    #[test]
    fn straight_ahead_without_control_there_is_no_sway_heave_or_moment() {
        let (m, c) = model();
        let f = m.forces(&[1.5, 0.0, 0.0, 0.0, 0.0, 0.0], &[0.0; 4], &c);
        for (i, fi) in f.iter().enumerate().skip(1) {
            assert!(fi.abs() < 1e-9, "{i}: {fi}");
        }
    }
}
