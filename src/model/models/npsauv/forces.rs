//! The Healey & Lienard (1993) forces of the NPS AUV II: hydrodynamic terms, control
//! surfaces and propulsion with the eps(n) corrections; the cross-flow drag is [`cross_flow`].
//!
//! The arrangement of the terms (which coefficient multiplies which product, on which scale
//! 0.5 rho L^2..L^5) is Healey & Lienard's as coded in Fossen's MSS npsauv.m (read there,
//! written here from the equations); the rigid-body terms that file folds into X..N are left
//! out here (the model adds -C_RB(nu) nu from Fossen's kinetics).

use super::*;

/// Speed below which the propulsion law's 1/u is kept finite (m/s): u is replaced by
/// 0.5 (u + sqrt(u^2 + e^2)), equal to u within e^2 / (4 u), 1.25e-5 m/s at 2 m/s.
const U_FLOOR: f64 = 0.01;

/// Hydrodynamic + control + propulsion + cross-flow forces at nu for inputs
/// `[delta_r, delta_s, delta_b, n]` (rad, rad, rad, rev/s).
pub(super) fn total<T: Scalar>(m: &NpsAuv, nu: &[T; 6], inputs: &[f64], c: &[T]) -> [T; 6] {
    let (u, v, w, p, q, r) = (nu[0], nu[1], nu[2], nu[3], nu[4], nu[5]);
    let (dr, ds) = (inputs[0], inputs[1]);
    // both bow planes at delta_b: delta_bp + delta_bs (the `..db2` terms, MSS npsauv.m)
    let db2 = 2.0 * inputs[2];
    let n = inputs[3];
    let (r2, r3, r4, r5) = (m.r(2), m.r(3), m.r(4), m.r(5));
    let s = &m.particulars;
    let l = m.length;

    // Propulsion (Healey & Lienard 1993; MSS npsauv.m): eta = k n / u with n in rad/s,
    // X_prop = C_d0 (eta |eta| - 1) on 0.5 rho L^2 u^2, i.e. thrust
    // 0.5 rho L^2 C_d0 (k n)|k n| less the hull resistance 0.5 rho L^2 C_d0 u|u| (the same
    // for u > 0, no division by u).
    let n_rad = 2.0 * std::f64::consts::PI * n;
    let kn = s.propeller_k * n_rad;
    let x_prop = (-(u * u.abs()) + kn * kn.abs()) * (r2 * s.cd0);
    // eps(n) = -1 + sgn(n) / sgn(u) (sqrt(C_t + 1) - 1) / (sqrt(C_t1 + 1) - 1),
    // C_t = 0.5 c_t L^2 eta |eta|, C_t1 = 0.5 c_t L^2 (MSS npsauv.m), for forward motion
    // (u > 0; the floor keeps 1/u finite at rest)
    let u_pos = (u + (u * u + U_FLOOR * U_FLOOR).sqrt()) * 0.5;
    let eta = u_pos.recip() * kn.abs();
    let ct_gain = 0.5 * s.propeller_ct * l * l;
    let ct1 = (ct_gain + 1.0).sqrt() - 1.0;
    let eps = ((eta * eta * ct_gain + 1.0).sqrt() - 1.0) * (n.signum() / ct1) - 1.0;

    // X (Healey & Lienard 1993; terms as in MSS npsauv.m, rigid-body terms removed)
    let x = (c[XVV] * v * v + c[XWW] * w * w) * r2
        + (c[XVR] * v * r + c[XWQ] * w * q + c[XVP] * v * p) * r3
        + (c[XQQ] * q * q + c[XRR] * r * r + c[XPR] * p * r + c[XPP] * p * p) * r4
        // control surfaces
        + (c[XRDR] * u * r * dr + (c[XQDS] * ds + c[XQDB2] * db2) * u * q) * r3
        + (c[XVDR] * u * v * dr
            + (c[XWDS] * ds + c[XWDB2] * db2) * u * w
            + (c[XDSDS] * (ds * ds) + c[XDRDR] * (dr * dr)) * u * u)
            * r2
        // propulsion corrections eps(n)
        + (c[XQDSN] * u * q * (ds * r3)
            + (c[XWDSN] * u * w * ds + c[XDSDSN] * u * u * (ds * ds)) * r2)
            * eps
        + x_prop;
    // Y
    let y = (c[YV] * u * v + c[YVW] * v * w + c[YDR] * u * u * dr) * r2
        + (c[YP] * u * p + c[YR] * u * r + c[YVQ] * v * q + c[YWP] * w * p + c[YWR] * w * r) * r3
        + (c[YPQ] * p * q + c[YQR] * q * r) * r4;
    // Z
    let z = (c[ZW] * u * w + c[ZVV] * v * v + (c[ZDS] * ds + c[ZDB2] * db2) * u * u) * r2
        + (c[ZQ] * u * q + c[ZVP] * v * p + c[ZVR] * v * r) * r3
        + (c[ZPP] * p * p + c[ZPR] * p * r + c[ZRR] * r * r) * r4
        + (c[ZQN] * u * q * r3 + (c[ZWN] * u * w + c[ZDSN] * u * u * ds) * r2) * eps;
    // K (MSS npsauv.m writes the propeller torque as r3 u^3 K_prop, which is not a moment;
    // taken here as r3 u^2 K_prop, 0 in the published set either way)
    let k = (c[KV] * u * v + c[KVW] * v * w + (c[KDB2] * db2 + c[KPROP]) * u * u) * r3
        + (c[KP] * u * p + c[KR] * u * r + c[KVQ] * v * q + c[KWP] * w * p + c[KWR] * w * r) * r4
        + (c[KPQ] * p * q + c[KQR] * q * r) * r5
        + c[KPN] * u * p * eps * r4;
    // M (Mq = M_uq, Mw = M_uw)
    let mm = (c[MW] * u * w + c[MVV] * v * v + (c[MDS] * ds + c[MDB2] * db2) * u * u) * r3
        + (c[MQ] * u * q + c[MVP] * v * p + c[MVR] * v * r) * r4
        + (c[MPP] * p * p + c[MPR] * p * r + c[MRR] * r * r) * r5
        + (c[MQN] * u * q * r4 + (c[MWN] * u * w + c[MDSN] * u * u * ds) * r3) * eps;
    // N
    let nn = (c[NV] * u * v + c[NVW] * v * w + (c[NDR] * dr + c[NPROP]) * u * u) * r3
        + (c[NP] * u * p + c[NR] * u * r + c[NVQ] * v * q + c[NWP] * w * p + c[NWR] * w * r) * r4
        + (c[NPQ] * p * q + c[NQR] * q * r) * r5;

    let cf = cross_flow::drag(m, v, w, q, r);
    [x, y + cf[0], z + cf[1], k, mm + cf[2], nn + cf[3]]
}
