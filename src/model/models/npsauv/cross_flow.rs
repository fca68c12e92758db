//! The cross-flow drag of the NPS AUV II hull (Healey & Lienard 1993, the integral drag
//! terms), in the three forms the literature uses ([`CrossFlow`]).
//!
//! At station x the section moves laterally at a = v + x r and vertically at b = w - x q,
//! U_cf = sqrt(a^2 + b^2), and with D = C_dy h a^2 + C_dz b_s b^2 (Healey & Lienard 1993):
//!
//! ```text
//! Y = -rho/2 Int D a / U_cf dx,    Z = -rho/2 Int D b / U_cf dx,
//! N = Int x dY,                    M = -Int x dZ   (the heave strip force's moment)
//! ```
//!
//! over the hull x = -L/2 .. L/2 (h, b_s the section height and breadth, constant: the MSS
//! block body).

use super::*;

/// Added to the cross-flow speed so that it never vanishes (m/s; MSS npsauv.m's
/// `epsilon_drag`, here inside the square root so the derivative stays finite at rest).
const UCF_FLOOR: f64 = 1e-6;

/// Panels of the composite Gauss-Legendre rule of [`CrossFlow::Integral`] (3 nodes each, exact
/// for a quintic on a panel); where a section's cross-flow changes sign (the a|a| kink) the
/// rule is less exact: within 1e-5 of the largest force or moment of a 400-panel rule
/// (`integral_converges` below).
const PANELS: usize = 12;

/// MSS npsauv.m's stations: x = -L/2, -L/2 + L/10, ..., L/2, each weighted L/10.
const MSS_STRIPS: usize = 10;

/// How the cross-flow integral is evaluated (`vehicle.particulars.cross_flow`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CrossFlow {
    /// `"integral"` (default): Healey & Lienard's integral over -L/2 .. L/2, evaluated by a
    /// composite 3-point Gauss-Legendre rule, the pitch moment that of the heave strip force.
    #[default]
    Integral,
    /// `"stations"`: MSS npsauv.m's sum over 11 stations each weighted L/10 (1.1 L in all;
    /// in pure yaw its moment is 1.44 times the integral's), with the heave strip force's
    /// pitch moment.
    Stations,
    /// `"mss"`: MSS npsauv.m as written: the 11-station sum, and the pitch integrand
    /// -(w + x q) x D / U_cf (the file's form, which is not the moment of its own heave force).
    Mss,
}

impl CrossFlow {
    /// Stations and weights (x, dx) of the form's quadrature over a hull of length `l`.
    pub(super) fn stations(self, l: f64) -> Vec<(f64, f64)> {
        match self {
            CrossFlow::Integral => gauss_legendre(l, PANELS),
            CrossFlow::Stations | CrossFlow::Mss => {
                let dx = l / MSS_STRIPS as f64;
                (0..=MSS_STRIPS).map(|k| (-0.5 * l + k as f64 * dx, dx)).collect()
            }
        }
    }
}

/// Composite 3-point Gauss-Legendre nodes and weights over -l/2 .. l/2 with `panels` panels
/// (Abramowitz & Stegun 25.4.29: nodes 0, +-sqrt(3/5), weights 8/9, 5/9 on [-1, 1]).
fn gauss_legendre(l: f64, panels: usize) -> Vec<(f64, f64)> {
    let node = (0.6f64).sqrt();
    let half = 0.5 * l / panels as f64;
    let mut out = Vec::with_capacity(3 * panels);
    for k in 0..panels {
        let mid = -0.5 * l + (2 * k + 1) as f64 * half;
        for (t, w) in [(-node, 5.0 / 9.0), (0.0, 8.0 / 9.0), (node, 5.0 / 9.0)] {
            out.push((mid + t * half, w * half));
        }
    }
    out
}

/// Cross-flow drag [Y, Z, M, N] at (v, w, q, r) in the vehicle's form (module doc).
pub(super) fn drag<T: Scalar>(m: &NpsAuv, v: T, w: T, q: T, r: T) -> [T; 4] {
    let mss = m.particulars.cross_flow == CrossFlow::Mss;
    drag_on(m, &m.cross_flow_stations, mss, [v, w, q, r])
}

/// [`drag`] over the given stations (x, dx); `mss_pitch` takes MSS's pitch integrand.
fn drag_on<T: Scalar>(m: &NpsAuv, stations: &[(f64, f64)], mss_pitch: bool, vwqr: [T; 4]) -> [T; 4] {
    let [v, w, q, r] = vwqr;
    let s = &m.particulars;
    let (ch, cb) = (s.cdy * s.hull_height, s.cdz * s.hull_breadth);
    let z = T::from(0.0);
    let (mut fy, mut fz, mut mm, mut nn) = (z, z, z, z);
    for &(x, dx) in stations {
        let a = v + r * x;
        let b = w - q * x;
        let ucf = (a * a + b * b + UCF_FLOOR * UCF_FLOOR).sqrt();
        let d = (a * a * ch + b * b * cb) / ucf * (0.5 * m.rho * dx);
        let dy = -(d * a);
        let dz = -(d * b);
        fy += dy;
        fz += dz;
        nn += dy * x;
        mm -= if mss_pitch { d * (w + q * x) * x } else { dz * x };
    }
    [fy, fz, mm, nn]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::models::Model;

    fn auv(form: CrossFlow) -> NpsAuv {
        let mut v = nps_auv_vehicle();
        let word = match form {
            CrossFlow::Integral => "integral",
            CrossFlow::Stations => "stations",
            CrossFlow::Mss => "mss",
        };
        v.particulars.insert("cross_flow".into(), toml::Value::String(word.into()));
        let a = NpsAuv::build(&v).unwrap();
        assert_eq!(a.particulars.cross_flow, form);
        a
    }

    /// States of a helix, a zig-zag, a dive, and the sign changes along the hull.
    const CASES: [[f64; 4]; 5] = [
        [0.1, 0.0, 0.0, 0.05],
        [-0.3, 0.05, 0.01, 0.2],
        [0.0, 0.2, -0.04, 0.0],
        [0.02, -0.01, 0.03, -0.01],
        [0.25, 0.1, 0.0, 0.0],
    ];

    #[test]
    fn integral_converges() {
        let a = auv(CrossFlow::Integral);
        let fine = gauss_legendre(a.length, 400);
        for c in CASES {
            let got = drag(&a, c[0], c[1], c[2], c[3]);
            let want = drag_on(&a, &fine, false, c);
            let scale = want.iter().map(|f| f.abs()).fold(1e-3, f64::max);
            for k in 0..4 {
                assert!((got[k] - want[k]).abs() < 1e-5 * scale, "{c:?} {k}: {got:?} {want:?}");
            }
        }
    }

    /// In pure sway the drag is -rho/2 C_dy h v|v| L (Healey & Lienard's integral of a
    /// constant section), and 1.1 times that with MSS's 11 stations; in pure yaw the
    /// integral's moment is -rho/2 C_dy h r|r| Int x^2 |x| dx = -rho/2 C_dy h r|r| L^4 / 32.
    #[test]
    fn pure_sway_and_pure_yaw_by_hand() {
        let a = auv(CrossFlow::Integral);
        let s = a.particulars;
        let k = 0.5 * a.rho * s.cdy * s.hull_height;
        let (v, r) = (0.3, 0.1);
        let sway = drag(&a, v, 0.0, 0.0, 0.0);
        assert!((sway[0] + k * v * v * a.length).abs() < 1e-9 * k);
        let yaw = drag(&a, 0.0, 0.0, 0.0, r);
        let want = -k * r * r * a.length.powi(4) / 32.0;
        assert!((yaw[3] - want).abs() < 1e-6 * want.abs(), "{} {want}", yaw[3]);
        let st = drag(&auv(CrossFlow::Stations), v, 0.0, 0.0, 0.0);
        assert!((st[0] / sway[0] - 1.1).abs() < 1e-9);
    }

    /// The MSS form differs from the station sum only in the pitch moment.
    #[test]
    fn mss_form_changes_only_the_pitch_moment() {
        let (st, mss) = (auv(CrossFlow::Stations), auv(CrossFlow::Mss));
        for c in CASES {
            let (a, b) = (drag(&st, c[0], c[1], c[2], c[3]), drag(&mss, c[0], c[1], c[2], c[3]));
            assert_eq!([a[0], a[1], a[3]], [b[0], b[1], b[3]]);
        }
        // heave with pitch rate: the forms' pitch moments differ
        let c: [f64; 4] = [0.0, 0.2, 0.05, 0.0];
        let (a, b) = (drag(&st, c[0], c[1], c[2], c[3]), drag(&mss, c[0], c[1], c[2], c[3]));
        assert!((a[2] - b[2]).abs() > 1.0, "{a:?} {b:?}");
    }
}
