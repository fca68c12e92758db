//! Reference frames: the body-to-earth rotation of zyx Euler angles, and earth-frame velocity
//! columns rotated into the body frame.

use crate::base::error::{InputError, Place};
use crate::base::quantity::Quantity;
use std::collections::BTreeMap;
use std::path::Path;

/// Which velocity groups a file gives in the earth frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Groups {
    /// u, v, w (dx/dt, dy/dt, dz/dt in the file).
    pub linear: bool,
    /// p, q, r.
    pub angular: bool,
}

/// Rotates earth-frame linear and angular velocities (the `groups` the file gives in the earth
/// frame) into the body frame (Fossen 2011, eq. 2.18 and 2.29 with the zyx Euler angles):
/// nu1 = R^T eta1_dot, omega_b = R^T omega_e.
pub fn rotate_to_body(
    ch: &mut BTreeMap<Quantity, Vec<f64>>,
    constants: &BTreeMap<Quantity, f64>,
    source: &Path,
    groups: Groups,
) -> Result<(), InputError> {
    let n = ch.values().next().map_or(0, Vec::len);
    let angle = |q: Quantity, i: usize| -> Option<f64> {
        ch.get(&q)
            .map(|v| v[i])
            .or_else(|| constants.get(&q).copied())
    };
    if angle(Quantity::Yaw, 0).is_none() && n > 0 {
        return Err(InputError::new(
            Place::file(source),
            "velocity_frame = \"earth\" needs a yaw column to rotate velocities into the body frame",
        ));
    }
    let mut rotated: Vec<(Quantity, Vec<f64>)> = Vec::new();
    for (qs, label) in [
        ([Quantity::U, Quantity::V, Quantity::W], "linear"),
        ([Quantity::P, Quantity::Q, Quantity::R], "angular"),
    ] {
        let wanted = match label {
            "linear" => groups.linear,
            _ => groups.angular,
        };
        if !wanted || !qs.iter().any(|q| ch.contains_key(q)) {
            continue;
        }
        let mut out = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for i in 0..n {
            let phi = angle(Quantity::Roll, i).unwrap_or(0.0);
            let th = angle(Quantity::Pitch, i).unwrap_or(0.0);
            let psi = angle(Quantity::Yaw, i).unwrap_or(0.0);
            let e = [0, 1, 2].map(|k| ch.get(&qs[k]).map_or(0.0, |v| v[i]));
            let r = rotation_zyx(phi, th, psi);
            for (row, o) in out.iter_mut().enumerate() {
                // body = R^T e
                o[i] = r[0][row] * e[0] + r[1][row] * e[1] + r[2][row] * e[2];
            }
        }
        for (k, q) in qs.iter().enumerate() {
            rotated.push((*q, std::mem::take(&mut out[k])));
        }
    }
    for (q, v) in rotated {
        ch.insert(q, v);
    }
    Ok(())
}

/// The print resolution of earth-frame velocities carried into the body frame with them
/// (before [`rotate_to_body`] turns the channels): rounding errors of variance d^2 / 12 in
/// the earth components and the heading add up as u_b = c u_e + s v_e, v_b = -s u_e + c v_e
/// do (first order, in the heading only: d u_b / d psi = v_b, d v_b / d psi = -u_b), kept as
/// the resolution with the same variance. Roll and pitch are taken as small here.
pub fn rotate_resolution(
    ch: &BTreeMap<Quantity, Vec<f64>>,
    constants: &BTreeMap<Quantity, f64>,
    resolution: &mut BTreeMap<Quantity, Vec<f64>>,
    groups: Groups,
) {
    for (qs, wanted) in [
        ([Quantity::U, Quantity::V], groups.linear),
        ([Quantity::P, Quantity::Q], groups.angular),
    ] {
        let involved = [qs[0], qs[1], Quantity::Yaw];
        if !wanted || !involved.iter().any(|q| resolution.contains_key(q)) {
            continue;
        }
        let (Some(a), Some(b)) = (ch.get(&qs[0]), ch.get(&qs[1])) else {
            continue;
        };
        let var = |q: Quantity, i: usize| resolution.get(&q).map_or(0.0, |r| r[i] * r[i]);
        let n = a.len();
        let (mut ra, mut rb) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            let psi = ch
                .get(&Quantity::Yaw)
                .map(|v| v[i])
                .or_else(|| constants.get(&Quantity::Yaw).copied())
                .unwrap_or(0.0);
            let (s, c) = psi.sin_cos();
            let (ab, bb) = (c * a[i] + s * b[i], -s * a[i] + c * b[i]);
            let (va, vb, vp) = (var(qs[0], i), var(qs[1], i), var(Quantity::Yaw, i));
            ra[i] = (c * c * va + s * s * vb + bb * bb * vp).sqrt();
            rb[i] = (s * s * va + c * c * vb + ab * ab * vp).sqrt();
        }
        resolution.insert(qs[0], ra);
        resolution.insert(qs[1], rb);
    }
}

/// Body-to-earth rotation matrix R(phi, theta, psi), zyx convention (Fossen 2011, eq. 2.18).
pub fn rotation_zyx(phi: f64, theta: f64, psi: f64) -> [[f64; 3]; 3] {
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    [
        [cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st],
        [sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf],
        [-st, ct * sf, ct * cf],
    ]
}

/// The unit quaternion [eta, eps1, eps2, eps3] (scalar first) of the zyx Euler angles: the
/// product of the yaw, pitch and roll half-angle rotations (Fossen 2011, section 2.2.2, the
/// quaternion of R(phi, theta, psi) in eq. 2.18), with eta >= 0.
pub fn quaternion_from_zyx(phi: f64, theta: f64, psi: f64) -> [f64; 4] {
    let (sf, cf) = (0.5 * phi).sin_cos();
    let (st, ct) = (0.5 * theta).sin_cos();
    let (sp, cp) = (0.5 * psi).sin_cos();
    let q = [
        cp * ct * cf + sp * st * sf,
        cp * ct * sf - sp * st * cf,
        cp * st * cf + sp * ct * sf,
        sp * ct * cf - cp * st * sf,
    ];
    if q[0] < 0.0 {
        q.map(|v| -v)
    } else {
        q
    }
}

/// The zyx Euler angles (phi, theta, psi) of a unit quaternion [eta, eps1, eps2, eps3]
/// (scalar first): read off the rotation matrix R(q) (Fossen 2011, eq. 2.72, the
/// Euler angles from R as in section 2.2.3): phi = atan2(R32, R33), theta = -asin(R31),
/// psi = atan2(R21, R11). `q` must be normalised; theta is clamped at +-90 deg.
pub fn zyx_from_quaternion(q: [f64; 4]) -> (f64, f64, f64) {
    let [e, x, y, z] = q;
    let r11 = 1.0 - 2.0 * (y * y + z * z);
    let r21 = 2.0 * (x * y + z * e);
    let r31 = 2.0 * (x * z - y * e);
    let r32 = 2.0 * (y * z + x * e);
    let r33 = 1.0 - 2.0 * (x * x + y * y);
    (r32.atan2(r33), -r31.clamp(-1.0, 1.0).asin(), r21.atan2(r11))
}

/// How far the norm of a quaternion read from a file may be from 1 before the row is
/// refused (a file rounds its parts; a larger error is not a rotation).
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternion_and_euler_angles_round_trip() {
        for &(phi, th, psi) in &[
            (0.0, 0.0, 0.0),
            (0.3, -0.2, 2.9),
            (-1.2, 0.7, -3.0),
            (2.5, 1.3, 0.4),
            (0.1, -1.4, -1.7),
        ] {
            let q = quaternion_from_zyx(phi, th, psi);
            let norm: f64 = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!((norm - 1.0).abs() < 1e-14, "norm {norm}");
            let (a, b, c) = zyx_from_quaternion(q);
            assert!((a - phi).abs() < 1e-12, "phi {a} vs {phi}");
            assert!((b - th).abs() < 1e-12, "theta {b} vs {th}");
            assert!((c - psi).abs() < 1e-12, "psi {c} vs {psi}");
        }
    }

    #[test]
    fn the_quaternion_rotates_like_the_euler_matrix() {
        // R(q) = I + 2 eta S(eps) + 2 S(eps)^2 (Fossen 2011, eq. 2.72) against eq. 2.18
        let (phi, th, psi) = (0.4, -0.3, 1.1);
        let [e, x, y, z] = quaternion_from_zyx(phi, th, psi);
        let rq = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - z * e),
                2.0 * (x * z + y * e),
            ],
            [
                2.0 * (x * y + z * e),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - x * e),
            ],
            [
                2.0 * (x * z - y * e),
                2.0 * (y * z + x * e),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let r = rotation_zyx(phi, th, psi);
        for i in 0..3 {
            for j in 0..3 {
                assert!((rq[i][j] - r[i][j]).abs() < 1e-14, "R[{i}][{j}]");
            }
        }
    }
}
