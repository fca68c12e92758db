//! Axisymmetric 6-DOF spheroid: heave and pitch mirror sway and yaw, Munk moments from the
//! added-mass matrix, weight, buoyancy and BG restoring.
//!
//! States [u, v, w, p, q, r, x, y, z, phi, theta, psi]; input `[thrust]`. Origin at the centre
//! of buoyancy, centre of gravity BG below it. Equations: M nu_dot + C_RB(nu) nu +
//! C_A(nu) nu + g(eta) = tau_visc + tau_prop (Fossen 2011, eq. 7.190), eta_dot = J(eta) nu.
//! In the horizontal plane (w = p = q = 0, phi = theta = 0) it reduces to the paper's eq. 2.

use super::rigid_body::{
    added_mass_coriolis, kinematics, restoring, rigid_body_coriolis, rigid_body_mass, solve,
};
use super::{
    positive_inertia, sname, CoefDef, Example, InputDef, InputRule, Model, Scales, StateDef, Unphysical,
    Vehicle, VehicleProblem,
};
use crate::numerics::ad::Scalar;
use crate::model::coefficients::{CompiledRelations, Relation, YawMoment, AXISYMMETRY, SYMMETRY};
use crate::base::quantity::Quantity;

/// Standard gravity, m/s^2.
pub const G: f64 = 9.80665;

/// The 6-DOF axisymmetric spheroid.
#[derive(Debug, Clone)]
pub struct Spheroid6 {
    /// Mass, kg.
    pub mass: f64,
    /// Principal inertias about the origin (Ixx, Iyy, Izz), kg m^2.
    pub inertia: [f64; 3],
    /// Buoyancy, N.
    pub buoyancy: f64,
    /// Distance of the centre of gravity below the centre of buoyancy (BG), m.
    pub zg: f64,
    scales: Scales,
    relations: CompiledRelations,
}


crate::coefficient_table! {
    /// Coefficient vector layout; derived ones are filled by the relations.
    COEFFICIENTS;
    // added mass (Fossen 2011, section 6.3)
    XUD = sname::XUD,
    YVD = sname::YVD,
    YRD = sname::YRD,
    NVD = sname::NVD,
    NRD = sname::NRD,
    ZWD = sname::ZWD,
    ZQD = sname::ZQD,
    MWD = sname::MWD,
    MQD = sname::MQD,
    KPD = sname::KPD,
    // viscous
    XUU = sname::XUU,
    XUV = sname::XUV,
    XVV = sname::XVV,
    XUW = sname::XUW,
    XWW = sname::XWW,
    YVV = sname::YVV,
    YRR = sname::YRR,
    YUV = sname::YUV,
    YUVD = sname::YUVD,
    YUVL = sname::YUVL,
    NVV = sname::NVV,
    NRR = sname::NRR,
    NUVL = sname::NUVL,
    // the total linear yaw moment and its Munk part: not in the dynamics (the Munk moment
    // comes from C_A), tied to Nuvl by paper eq. 2 and 4 in either yaw-moment reading
    NUVA = sname::NUVA,
    NUV = sname::NUV,
    ZWW = sname::ZWW,
    ZQQ = sname::ZQQ,
    ZUW = sname::ZUW,
    MWW = sname::MWW,
    MQQ = sname::MQQ,
    MUWL = sname::MUWL,
    KPP = sname::KPP,
}

impl Spheroid6 {
    /// A model for the given mass (kg), inertias (kg m^2), buoyancy (N) and BG (m).
    pub fn new(mass: f64, inertia: [f64; 3], buoyancy: f64, bg: f64, scales: Scales) -> Self {
        Spheroid6 {
            mass,
            inertia,
            buoyancy,
            zg: bg,
            scales,
            relations: CompiledRelations::compile(
                Self::COMPLETING_RELATIONS,
                &super::names(COEFFICIENTS),
            ),
        }
    }

    /// The added-mass matrix M_A = -[X_udot ...] (Fossen 2011, eq. 6.27), symmetric.
    fn added_mass<T: Scalar>(c: &[T]) -> [[T; 6]; 6] {
        let z = T::from(0.0);
        let mut ma = [[z; 6]; 6];
        ma[0][0] = -c[XUD];
        ma[1][1] = -c[YVD];
        ma[2][2] = -c[ZWD];
        ma[3][3] = -c[KPD];
        ma[4][4] = -c[MQD];
        ma[5][5] = -c[NRD];
        ma[1][5] = -c[YRD];
        ma[5][1] = -c[NVD];
        ma[2][4] = -c[ZQD];
        ma[4][2] = -c[MWD];
        ma
    }
}

impl Model for Spheroid6 {
    const NAME: &'static str = "spheroid6";
    const DESCRIPTION: &'static str = "axisymmetric 6-DOF spheroid: heave and pitch mirror sway \
        and yaw (Fossen 2011, ch. 6; added-mass Coriolis terms from the added-mass matrix, \
        eq. 6.43)";
    const COEFFICIENTS: &'static [CoefDef] = COEFFICIENTS;
    const INPUTS: &'static [InputDef] = &[InputDef {
        quantity: Quantity::Thrust,
        rule: InputRule::Interpolate,
    }];

    const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[SYMMETRY, AXISYMMETRY];

    fn build(v: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
        v.no_particulars(Self::NAME)?;
        let mut missing = Vec::new();
        for (key, value) in [("ixx", v.ixx), ("iyy", v.iyy)] {
            if value.is_none() {
                missing.push(VehicleProblem {
                    key: format!("vehicle.{key}"),
                    message: format!("the spheroid6 model needs vehicle.{key} (kg m^2)"),
                });
            }
        }
        let (Some(ixx), Some(iyy)) = (v.ixx, v.iyy) else {
            return Err(missing);
        };
        let weight = v.mass * G;
        Ok(Spheroid6::new(
            v.mass,
            [ixx, iyy, v.izz],
            v.buoyancy.unwrap_or(weight),
            v.bg.unwrap_or(0.0),
            v.spheroid_scales(),
        ))
    }

    /// Total: Nuv free, Nuvl = Nuv - Nuva derived before Muwl = -Nuvl; lift-only: Nuv =
    /// Nuva + Nuvl (paper eq. 2 and 4; axisymmetry).
    fn with_yaw_moment(self, reading: YawMoment) -> Self {
        Spheroid6 {
            relations: CompiledRelations::compile_for(
                Self::COMPLETING_RELATIONS,
                &super::names(COEFFICIENTS),
                reading,
            ),
            ..self
        }
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
            Quantity::Yaw,
        ]
    }

    fn typical_magnitude(&self, name: &str) -> f64 {
        self.scales.of_name(name)
    }

    fn example_vehicle() -> Vehicle {
        Vehicle::paper_spheroid()
    }

    fn example(&self) -> Example {
        Example {
            coefficients: super::spheroid3::BOUNDED_TRUTH,
            // the paper's manoeuvre: with CG at CB the axisymmetric pitch plane is
            // Munk-unstable, so the example stays in the horizontal plane
            state: vec![3.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            inputs: vec![22.0],
            estimated: &["Yvd", "Yrd", "Nrd", "Nvv", "Nrr", "Yrr"],
            duration: 20.0,
        }
    }

    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]) {
        let nu = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let (uu, v, w, p, q, r) = (x[0], x[1], x[2], x[3], x[4], x[5]);
        let (phi, theta, psi) = (x[9], x[10], x[11]);
        // viscous forces: paper eq. 3 in the horizontal plane, mirrored by axisymmetry
        let tau = [
            c[XUU] * uu * uu.abs()
                + c[XUV] * uu * v
                + c[XVV] * v * v
                + c[XUW] * uu * w
                + c[XWW] * w * w
                + u[0],
            c[YVV] * v * v.abs() + c[YRR] * r * r.abs() + c[YUV] * uu * v,
            c[ZWW] * w * w.abs() + c[ZQQ] * q * q.abs() + c[ZUW] * uu * w,
            c[KPP] * p * p.abs(),
            c[MWW] * w * w.abs() + c[MQQ] * q * q.abs() + c[MUWL] * uu * w,
            c[NVV] * v * v.abs() + c[NRR] * r * r.abs() + c[NUVL] * uu * v,
        ];
        let ma = Self::added_mass(c);
        let crb = rigid_body_coriolis(self.mass, self.zg, self.inertia, &nu);
        let ca = added_mass_coriolis(&ma, &nu);
        let g = restoring(self.mass * G, self.buoyancy, self.zg, phi, theta);
        let mut rhs = [T::from(0.0); 6];
        for i in 0..6 {
            rhs[i] = tau[i] + crb[i] + ca[i] + g[i];
        }
        let mrb = rigid_body_mass(self.mass, self.zg, self.inertia);
        let mut mm = [T::from(0.0); 36];
        for i in 0..6 {
            for j in 0..6 {
                mm[i * 6 + j] = ma[i][j] + mrb[i][j];
            }
        }
        if !solve(&mut mm, &mut rhs, 6) {
            // A singular mass matrix: report non-finite rates; `check` names the cause.
            rhs = [T::from(f64::NAN); 6];
        }
        dx[..6].copy_from_slice(&rhs);
        let eta_dot = kinematics(&nu, phi, theta, psi);
        dx[6..12].copy_from_slice(&eta_dot);
    }

    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical> {
        positive_inertia("m - Xud", self.mass - c[XUD])?;
        positive_inertia("m - Yvd", self.mass - c[YVD])?;
        positive_inertia("m - Zwd", self.mass - c[ZWD])?;
        positive_inertia("Ixx - Kpd", self.inertia[0] - c[KPD])?;
        positive_inertia("Iyy - Mqd", self.inertia[1] - c[MQD])?;
        positive_inertia("Izz - Nrd", self.inertia[2] - c[NRD])?;
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::Spheroid3;

    fn scales() -> Scales {
        Scales {
            q: 16.1,
            length: 1.2,
            added: None,
        }
    }

    fn fill<M: Model>(m: &M, values: &[(&str, f64)]) -> Vec<f64> {
        let mut c = vec![0.0; m.coefficient_names().len()];
        for (n, v) in values {
            if let Some(i) = m.coefficient_index(n) {
                c[i] = *v;
            }
        }
        m.relations().apply(&mut c);
        c
    }

    /// The bounded truth with a non-zero Yrd, so that the off-diagonal added mass counts.
    fn paper() -> Vec<(&'static str, f64)> {
        crate::model::models::spheroid3::BOUNDED_TRUTH
            .iter()
            .map(|&(n, v)| (n, if n == "Yrd" { 0.1 } else { v }))
            .collect()
    }

    #[test]
    fn index_constants_match_the_list() {
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.0, scales());
        for (i, n) in [
            (XUD, "Xud"),
            (KPD, "Kpd"),
            (XUU, "Xuu"),
            (NUVL, "Nuvl"),
            (KPP, "Kpp"),
        ] {
            assert_eq!(m6.coefficient_index(n), Some(i));
        }
        assert_eq!(COEFFICIENTS.len(), KPP + 1);
    }

    #[test]
    fn reduces_to_the_paper_model_in_the_plane() {
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.0, scales());
        let m3 = Spheroid3::new(50.0, 3.7, scales()); // the same vehicle as m6
        let c6 = fill(&m6, &paper());
        let c3 = fill(&m3, &paper());
        let (u, v, r, psi) = (2.5, 0.7, -0.3, 0.4);
        let mut d6 = [0.0; 12];
        m6.derivatives(
            &[u, v, 0.0, 0.0, 0.0, r, 1.0, 2.0, 0.0, 0.0, 0.0, psi],
            &[22.0],
            &c6,
            &mut d6,
        );
        let mut d3 = [0.0; 6];
        m3.derivatives(&[u, v, r, 1.0, 2.0, psi], &[22.0], &c3, &mut d3);
        let pairs = [(0, 0), (1, 1), (5, 2), (6, 3), (7, 4), (11, 5)];
        for (i6, i3) in pairs {
            assert!(
                (d6[i6] - d3[i3]).abs() < 1e-12,
                "{i6}: {} vs {}",
                d6[i6],
                d3[i3]
            );
        }
        for i in [2, 3, 4, 8, 9, 10] {
            assert!(d6[i].abs() < 1e-12, "out-of-plane rate {i} = {}", d6[i]);
        }
    }

    #[test]
    fn heave_and_pitch_mirror_sway_and_yaw() {
        // A body of revolution rotated 90 deg about x: (v, r) -> (w, -q) gives (Y, N) -> (Z, -M).
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.0, scales());
        let c = fill(&m6, &paper());
        let (u, s, t) = (2.0, 0.6, 0.25);
        let mut dy = [0.0; 12];
        m6.derivatives(
            &[u, s, 0.0, 0.0, 0.0, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            &[0.0],
            &c,
            &mut dy,
        );
        let mut dz = [0.0; 12];
        m6.derivatives(
            &[u, 0.0, s, 0.0, -t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            &[0.0],
            &c,
            &mut dz,
        );
        assert!((dy[0] - dz[0]).abs() < 1e-12);
        assert!((dy[1] - dz[2]).abs() < 1e-12, "{} vs {}", dy[1], dz[2]);
        assert!((dy[5] + dz[4]).abs() < 1e-12, "{} vs {}", dy[5], dz[4]);
    }

    /// The lift-only truth as a total set: Nuvl replaced by Nuv = Nuva + Nuvl with
    /// Nuva = -(Xud - Yvd) (paper eq. 2 and 4).
    fn total(lift_only: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
        let get = |n: &str| lift_only.iter().find(|(k, _)| *k == n).unwrap().1;
        let nuv = get("Nuvl") - (get("Xud") - get("Yvd"));
        lift_only
            .iter()
            .map(|&(n, v)| if n == "Nuvl" { ("Nuv", nuv) } else { (n, v) })
            .collect()
    }

    #[test]
    fn the_total_reading_derives_nuvl_and_moves_nothing() {
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.0, scales());
        let m3 = Spheroid3::new(50.0, 3.7, scales());
        let (lift, tot) = (paper(), total(&paper()));
        let (m6t, m3t) = (
            m6.clone().with_yaw_moment(YawMoment::Total),
            m3.clone().with_yaw_moment(YawMoment::Total),
        );
        assert!(m6t.is_derived("Nuvl") && !m6t.is_derived("Nuv") && m6.is_derived("Nuv"));
        assert!(m3t.is_derived("Nuvl") && !m3t.is_derived("Nuv") && m3.is_derived("Nuv"));
        let c6 = fill(&m6t, &tot);
        assert!((c6[NUVL] - 13.43).abs() < 1e-12, "Nuvl = {}", c6[NUVL]);
        assert!((c6[MUWL] + 13.43).abs() < 1e-12, "Muwl = {}", c6[MUWL]);
        let c3 = fill(&m3t, &tot);
        let nuvl3 = c3[m3t.coefficient_index("Nuvl").unwrap()];
        assert!((nuvl3 - 13.43).abs() < 1e-12, "{nuvl3}");
        let x6 = [2.5, 0.7, 0.3, 0.1, -0.2, -0.3, 1.0, 2.0, 0.5, 0.1, 0.05, 0.4];
        let x3 = [2.5, 0.7, -0.3, 1.0, 2.0, 0.4];
        let (mut a, mut b) = ([0.0; 12], [0.0; 12]);
        m6.derivatives(&x6, &[22.0], &fill(&m6, &lift), &mut a);
        m6t.derivatives(&x6, &[22.0], &c6, &mut b);
        for (i, (a, b)) in a.iter().zip(&b).enumerate() {
            assert!((a - b).abs() < 1e-12, "spheroid6 rate {i}: {a} vs {b}");
        }
        let (mut a, mut b) = ([0.0; 6], [0.0; 6]);
        m3.derivatives(&x3, &[22.0], &fill(&m3, &lift), &mut a);
        m3t.derivatives(&x3, &[22.0], &c3, &mut b);
        for (i, (a, b)) in a.iter().zip(&b).enumerate() {
            assert!((a - b).abs() < 1e-12, "spheroid3 rate {i}: {a} vs {b}");
        }
    }

    #[test]
    fn steady_drift_moment_is_nuvl_plus_the_munk_moment_in_both_models() {
        // Yrd = Nvd = 0 (the bounded truth): the yaw moment is (Izz - Nrd) r_dot
        let truth = crate::model::models::spheroid3::BOUNDED_TRUTH;
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.0, scales());
        let m3 = Spheroid3::new(50.0, 3.7, scales());
        let (c6, c3) = (fill(&m6, truth), fill(&m3, truth));
        let (u, v) = (2.0, -0.3);
        let (mut d6, mut d3) = ([0.0; 12], [0.0; 6]);
        m6.derivatives(
            &[u, v, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            &[0.0],
            &c6,
            &mut d6,
        );
        m3.derivatives(&[u, v, 0.0, 0.0, 0.0, 0.0], &[0.0], &c3, &mut d3);
        let inertia = 3.7 - c6[NRD];
        let (n6, n3) = (inertia * d6[5], inertia * d3[2]);
        // spheroid3's N_uv u v (paper eq. 3) with Nuv = Nuvl + (Yvd - Xud) (paper eq. 2 and 4);
        // spheroid6's lift part plus the added-mass Coriolis moment (Fossen 2011, eq. 6.43)
        let nuv = 13.43 + (-23.626 - -1.164);
        let want = nuv * u * v + 10.0 * v * v.abs();
        assert!((n3 - want).abs() < 1e-9, "spheroid3: {n3} vs {want}");
        assert!((n6 - want).abs() < 1e-9, "spheroid6: {n6} vs {want}");
        assert!((c6[NUV] - nuv).abs() < 1e-12, "{}", c6[NUV]);
    }

    #[test]
    fn bottom_heavy_body_rights_itself_in_roll() {
        let m6 = Spheroid6::new(50.0, [0.5, 3.7, 3.7], 50.0 * G, 0.02, scales());
        let c = fill(&m6, &paper());
        let mut d = [0.0; 12];
        let mut x = [0.0; 12];
        x[9] = 0.2;
        m6.derivatives(&x, &[0.0], &c, &mut d);
        assert!(d[3] < 0.0, "roll acceleration {}", d[3]);
    }
}
