//! Reference frames: the body-to-earth rotation of zyx Euler angles, and earth-frame velocity
//! columns rotated into the body frame.

use crate::error::{InputError, Place};
use crate::quantity::Quantity;
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
