//! The paper's horizontal-plane spheroid model (Rasekh & Mahdi 2020, eq. 2-4).
//!
//! States `[u, v, r, x, y, psi]`; input `[thrust]`. Origin at the centre of buoyancy, which is
//! also the centre of gravity (x_G = 0).

use super::{
    names, positive_inertia, sname, CoefDef, Example, InputDef, InputRule, Model, Scales, StateDef, Unphysical,
    Vehicle, VehicleProblem,
};
use crate::numerics::ad::Scalar;
use crate::model::coefficients::{CompiledRelations, Relation, YawMoment, SYMMETRY};
use crate::base::quantity::Quantity;

/// The 3-DOF spheroid: surge, sway, yaw with nonlinear damping and added mass.
#[derive(Debug, Clone)]
pub struct Spheroid3 {
    /// Mass, kg.
    pub mass: f64,
    /// Yaw inertia about the origin, kg m^2.
    pub izz: f64,
    scales: Scales,
    relations: CompiledRelations,
}

const STATES: &[StateDef] = super::PLANAR_STATES;

crate::coefficient_table! {
    /// Coefficient vector layout; derived ones (paper eq. 4) are filled by the relations.
    COEFFICIENTS;
    // added mass
    XUD = sname::XUD,
    YVD = sname::YVD,
    YRD = sname::YRD,
    NVD = sname::NVD,
    NRD = sname::NRD,
    // surge
    XUU = sname::XUU,
    XUV = sname::XUV,
    XVV = sname::XVV,
    XVR = sname::XVR,
    XRR = sname::XRR,
    // sway
    YVV = sname::YVV,
    YRR = sname::YRR,
    YUR = sname::YUR,
    YUV = sname::YUV,
    YUVD = sname::YUVD,
    YUVL = sname::YUVL,
    // yaw
    NVV = sname::NVV,
    NRR = sname::NRR,
    NUR = sname::NUR,
    NUV = sname::NUV,
    NUVA = sname::NUVA,
    NUVL = sname::NUVL,
}

/// The "true" coefficients of the bundled synthetic spheroid runs (SI): the paper's Table 3
/// polar coefficients, Lamb's added mass (Fossen 1994; Kpd = 0) and the bounded yaw of
/// docs/simulate.md (Nvv = +10, Nrr = -5, Yrr = +0.5), with a light roll damping for the
/// 6-DOF model. `configs/simulate/*.toml` hold the same values.
pub const BOUNDED_TRUTH: &[(&str, f64)] = &[
    ("Xud", -1.1640),
    ("Yvd", -23.626),
    ("Yrd", 0.0),
    ("Nrd", -1.4532),
    ("Kpd", 0.0),
    ("Xuu", -1.33),
    ("Xuv", 0.44),
    ("Xvv", -5.38),
    ("Yvv", -0.44),
    ("Yrr", 0.5),
    ("Yuvd", 1.33),
    ("Yuvl", -16.31),
    ("Nvv", 10.0),
    ("Nrr", -5.0),
    ("Nuvl", 13.43),
    ("Kpp", -0.05),
];

impl Spheroid3 {
    /// The paper's vehicle (Table 1: m = 50 kg, Izz = 3.7 kg m^2, L = 1.2 m, q = 0.5 rho
    /// pi b^2 = 16.10 kg/m) with Lamb's added mass as prior scales.
    pub fn paper_vehicle() -> Self {
        Spheroid3::new(
            50.0,
            3.7,
            Scales {
                q: 0.5 * 1025.0 * std::f64::consts::PI * 0.01,
                length: 1.2,
                added: Some(super::AddedMass {
                    xud: -1.1640,
                    yvd: -23.626,
                    nrd: -1.4532,
                }),
            },
        )
    }

    /// A model for mass `mass` (kg) and yaw inertia `izz` (kg m^2).
    pub fn new(mass: f64, izz: f64, scales: Scales) -> Self {
        Spheroid3 {
            mass,
            izz,
            scales,
            relations: CompiledRelations::compile(&[SYMMETRY], &names(COEFFICIENTS)),
        }
    }
}

impl Model for Spheroid3 {
    const NAME: &'static str = "spheroid3";
    const DESCRIPTION: &'static str = "horizontal-plane spheroid: surge, sway and yaw with added \
        mass and nonlinear damping (Rasekh & Mahdi 2020, eq. 2-4)";
    const COEFFICIENTS: &'static [CoefDef] = COEFFICIENTS;
    const INPUTS: &'static [InputDef] = &[InputDef {
        quantity: Quantity::Thrust,
        rule: InputRule::Interpolate,
    }];

    const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[SYMMETRY];

    fn build(v: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
        v.no_particulars(Self::NAME)?;
        Ok(Spheroid3::new(v.mass, v.izz, v.spheroid_scales()))
    }

    /// Total: Nuv free, Nuvl = Nuv - Nuva derived; lift-only: Nuv = Nuva + Nuvl (paper eq. 2
    /// and 4).
    fn with_yaw_moment(self, reading: YawMoment) -> Self {
        Spheroid3 {
            relations: CompiledRelations::compile_for(
                Self::COMPLETING_RELATIONS,
                &names(COEFFICIENTS),
                reading,
            ),
            ..self
        }
    }

    fn states(&self) -> &'static [StateDef] {
        STATES
    }

    fn relations(&self) -> &CompiledRelations {
        &self.relations
    }

    fn compared(&self) -> &'static [Quantity] {
        &[Quantity::U, Quantity::V, Quantity::R, Quantity::Yaw]
    }

    fn typical_magnitude(&self, name: &str) -> f64 {
        self.scales.of_name(name)
    }

    fn example_vehicle() -> Vehicle {
        Vehicle::paper_spheroid()
    }

    fn example(&self) -> Example {
        Example {
            coefficients: BOUNDED_TRUTH,
            state: vec![3.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            inputs: vec![22.0],
            estimated: &["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"],
            duration: 20.0,
        }
    }

    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]) {
        let (uu, v, r, psi) = (x[0], x[1], x[2], x[5]);
        let m = self.mass;
        // paper eq. 3: external forces, the rigid-body Coriolis terms m v r and -m u r moved
        // to the right-hand side
        let [hx, hy, hn] = hydrodynamic(x, u, c);
        let fx = v * r * m + hx;
        let fy = -(uu * r * m) + hy;
        // paper eq. 2: mass matrix [[m - Yvd, -Yrd], [-Nvd, Izz - Nrd]] for (v_dot, r_dot)
        let m11 = -c[YVD] + m;
        let m12 = -c[YRD];
        let m21 = -c[NVD];
        let m22 = -c[NRD] + self.izz;
        let inv_det = (m11 * m22 - m12 * m21).recip();
        dx[0] = fx / (-c[XUD] + m);
        dx[1] = (fy * m22 - hn * m12) * inv_det;
        dx[2] = (hn * m11 - fy * m21) * inv_det;
        // kinematics (paper eq. 2, last line)
        let (s, co) = psi.sin_cos();
        dx[3] = uu * co - v * s;
        dx[4] = uu * s + v * co;
        dx[5] = r;
    }

    fn force_quantities(&self) -> &'static [Quantity] {
        &[Quantity::Fx, Quantity::Fy, Quantity::Mz]
    }

    fn captive_forces<T: Scalar>(&self, x: &[T], x_dot: &[T], u: &[f64], c: &[T], out: &mut [T]) {
        // paper eq. 2 with the rigid-body terms taken out: the fluid (and thrust) force on
        // the body moved along the path is the added-mass inertia Xud u_dot, Yvd v_dot +
        // Yrd r_dot, Nvd v_dot + Nrd r_dot plus the terms of eq. 3
        let [hx, hy, hn] = hydrodynamic(x, u, c);
        out[0] = hx + c[XUD] * x_dot[0];
        out[1] = hy + c[YVD] * x_dot[1] + c[YRD] * x_dot[2];
        out[2] = hn + c[NVD] * x_dot[1] + c[NRD] * x_dot[2];
    }

    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical> {
        positive_inertia("m - Xud", self.mass - c[XUD])?;
        positive_inertia("m - Yvd", self.mass - c[YVD])?;
        positive_inertia("Izz - Nrd", self.izz - c[NRD])?;
        let det = (self.mass - c[YVD]) * (self.izz - c[NRD]) - c[YRD] * c[NVD];
        positive_inertia("det of the sway-yaw mass matrix", det)?;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Unphysical::NotFinite("state"));
        }
        Ok(())
    }
}

/// The forces of paper eq. 3 without the rigid-body Coriolis terms: damping, lift, the
/// added-mass Coriolis terms (Xvr, Xrr, Yur, Nur, Nuva through Nuv; eq. 4) and the thrust.
fn hydrodynamic<T: Scalar>(x: &[T], u: &[f64], c: &[T]) -> [T; 3] {
    let (uu, v, r) = (x[0], x[1], x[2]);
    let fx = c[XUU] * uu * uu.abs()
        + c[XUV] * uu * v
        + c[XVV] * v * v
        + c[XVR] * v * r
        + c[XRR] * r * r
        + u[0];
    let fy = c[YVV] * v * v.abs() + c[YRR] * r * r.abs() + c[YUR] * uu * r + c[YUV] * uu * v;
    let fn_ = c[NVV] * v * v.abs() + c[NRR] * r * r.abs() + c[NUR] * uu * r + c[NUV] * uu * v;
    [fx, fy, fn_]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::ad;

    fn paper_coefficients(model: &Spheroid3) -> Vec<f64> {
        model.coefficient_vector(BOUNDED_TRUTH)
    }

    fn model() -> Spheroid3 {
        Spheroid3::paper_vehicle()
    }

    #[test]
    fn relations_fill_the_coriolis_terms() {
        let m = model();
        let c = paper_coefficients(&m);
        assert_eq!(c[XVR], 23.626);
        assert_eq!(c[YUR], -1.164);
        assert!((c[NUV] - (-23.626 + 1.164 + 13.43)).abs() < 1e-12);
        assert!(m.is_derived("Xvr") && !m.is_derived("Yvd"));
    }

    /// Along the model's own motion the captive forces are what Newton gives the rigid body
    /// (origin at the centre of gravity): m (u_dot - v r), m (v_dot + u r), Izz r_dot.
    #[test]
    fn captive_forces_balance_the_rigid_body_along_the_motion() {
        let m = model();
        let c = paper_coefficients(&m);
        let x = [3.0, 1.0, -0.2, 1.0, 2.0, 0.4];
        let mut dx = [0.0; 6];
        m.derivatives(&x, &[22.0], &c, &mut dx);
        let mut f = [0.0; 3];
        m.captive_forces(&x, &dx, &[22.0], &c, &mut f);
        let newton = [
            m.mass * (dx[0] - x[1] * x[2]),
            m.mass * (dx[1] + x[0] * x[2]),
            m.izz * dx[2],
        ];
        for (a, b) in f.iter().zip(newton) {
            assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{f:?} vs {newton:?}");
        }
    }

    #[test]
    fn straight_run_has_no_sway() {
        let m = model();
        let c = paper_coefficients(&m);
        let mut dx = [0.0; 6];
        m.derivatives(&[2.0, 0.0, 0.0, 0.0, 0.0, 0.0], &[22.0], &c, &mut dx);
        assert!((dx[0] - (22.0 - 1.33 * 4.0) / 51.164).abs() < 1e-12);
        assert_eq!(dx[1], 0.0);
        assert_eq!(dx[2], 0.0);
    }

    #[test]
    fn ad_jacobian_matches_finite_differences() {
        let m = model();
        let c = paper_coefficients(&m);
        let x = [3.0, 1.0, -0.2, 1.0, 2.0, 0.4];
        let mut val = [0.0; 6];
        let mut ja = [0.0; 36];
        ad::jacobian(
            &x,
            6,
            |xd, out| {
                let cd: Vec<ad::Dual> = c.iter().map(|&v| ad::constant(v)).collect();
                m.derivatives(xd, &[22.0], &cd, out)
            },
            &mut val,
            &mut ja,
        );
        let mut jf = [0.0; 36];
        ad::jacobian_fd(
            &x,
            6,
            |xs, out| m.derivatives(xs, &[22.0], &c, out),
            &mut jf,
        );
        for (a, b) in ja.iter().zip(&jf) {
            assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }
}
