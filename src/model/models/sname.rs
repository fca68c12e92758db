//! The standard SNAME coefficients of the spheroid family (Fossen 1994 and 2011 notation:
//! `Xud` = X_udot, `Yuv` = Y_uv ...), each defined once for the model tables that use them.

use super::coefficient::{AddedMassTerm, CoefDef};

// added mass (Fossen 1994, section 2.4); the diagonal terms are negative in this convention
// (the added-mass matrix is M_A = -[X_udot ...], positive definite for a body moving in an
// ideal fluid: Fossen 2011, section 6.3.1), the couplings of either sign
/// Surge added mass X_udot.
pub const XUD: CoefDef =
    CoefDef::added("Xud", "kg", "surge added mass X_udot", AddedMassTerm::Surge).non_positive();
/// Sway added mass Y_vdot.
pub const YVD: CoefDef =
    CoefDef::added("Yvd", "kg", "sway added mass Y_vdot", AddedMassTerm::Sway).non_positive();
/// Sway force from yaw acceleration Y_rdot.
pub const YRD: CoefDef = CoefDef::added(
    "Yrd",
    "kg m",
    "sway force from yaw acceleration Y_rdot",
    AddedMassTerm::Coupling,
);
/// Yaw moment from sway acceleration N_vdot.
pub const NVD: CoefDef = CoefDef::added(
    "Nvd",
    "kg m",
    "yaw moment from sway acceleration N_vdot",
    AddedMassTerm::Coupling,
);
/// Yaw added inertia N_rdot.
pub const NRD: CoefDef = CoefDef::added(
    "Nrd",
    "kg m^2",
    "yaw added inertia N_rdot",
    AddedMassTerm::Yaw,
)
.non_positive();
/// Heave added mass Z_wdot.
pub const ZWD: CoefDef =
    CoefDef::added("Zwd", "kg", "heave added mass Z_wdot", AddedMassTerm::Sway).non_positive();
/// Heave force from pitch acceleration Z_qdot.
pub const ZQD: CoefDef = CoefDef::added(
    "Zqd",
    "kg m",
    "heave force from pitch acceleration Z_qdot",
    AddedMassTerm::Coupling,
);
/// Pitch moment from heave acceleration M_wdot.
pub const MWD: CoefDef = CoefDef::added(
    "Mwd",
    "kg m",
    "pitch moment from heave acceleration M_wdot",
    AddedMassTerm::Coupling,
);
/// Pitch added inertia M_qdot.
pub const MQD: CoefDef = CoefDef::added(
    "Mqd",
    "kg m^2",
    "pitch added inertia M_qdot",
    AddedMassTerm::Yaw,
)
.non_positive();
/// Roll added inertia K_pdot.
pub const KPD: CoefDef = CoefDef::added(
    "Kpd",
    "kg m^2",
    "roll added inertia K_pdot",
    AddedMassTerm::Yaw,
)
.non_positive();
// surge (paper eq. 3)
/// Axial drag X_u|u|.
pub const XUU: CoefDef = CoefDef::prime("Xuu", "kg/m", "axial drag X_u|u|");
/// Surge force from drift X_uv.
pub const XUV: CoefDef = CoefDef::prime("Xuv", "kg/m", "surge force from drift X_uv");
/// Surge force from drift squared X_vv.
pub const XVV: CoefDef = CoefDef::prime("Xvv", "kg/m", "surge force from drift squared X_vv");
/// Added-mass Coriolis X_vr.
pub const XVR: CoefDef = CoefDef::prime("Xvr", "kg", "added-mass Coriolis X_vr");
/// Added-mass Coriolis X_rr.
pub const XRR: CoefDef = CoefDef::prime("Xrr", "kg m", "added-mass Coriolis X_rr");
/// Surge force from heave squared X_ww.
pub const XWW: CoefDef = CoefDef::prime("Xww", "kg/m", "surge force from heave squared X_ww");
// sway
/// Sway cross-flow drag Y_v|v|.
pub const YVV: CoefDef = CoefDef::prime("Yvv", "kg/m", "sway cross-flow drag Y_v|v|");
/// Sway force from yaw rate Y_r|r|.
pub const YRR: CoefDef = CoefDef::prime("Yrr", "kg m", "sway force from yaw rate Y_r|r|");
/// Sway force Y_ur (added-mass Coriolis).
pub const YUR: CoefDef = CoefDef::prime("Yur", "kg", "sway force Y_ur (added-mass Coriolis)");
/// Sway force Y_uv (body lift and drag).
pub const YUV: CoefDef = CoefDef::prime("Yuv", "kg/m", "sway force Y_uv (body lift and drag)");
/// Drag part of Y_uv.
pub const YUVD: CoefDef = CoefDef::prime("Yuvd", "kg/m", "drag part of Y_uv");
/// Lift part of Y_uv.
pub const YUVL: CoefDef = CoefDef::prime("Yuvl", "kg/m", "lift part of Y_uv");
// yaw
/// Yaw moment N_v|v|.
pub const NVV: CoefDef = CoefDef::prime("Nvv", "kg", "yaw moment N_v|v|");
/// Yaw damping N_r|r|.
pub const NRR: CoefDef = CoefDef::prime("Nrr", "kg m^2", "yaw damping N_r|r|");
/// Yaw moment N_ur (added-mass Coriolis).
pub const NUR: CoefDef = CoefDef::prime("Nur", "kg m", "yaw moment N_ur (added-mass Coriolis)");
/// Yaw moment N_uv (Munk moment and lift).
pub const NUV: CoefDef = CoefDef::prime("Nuv", "kg", "yaw moment N_uv (Munk moment and lift)");
/// Munk moment part of N_uv.
pub const NUVA: CoefDef = CoefDef::prime("Nuva", "kg", "Munk moment part of N_uv");
/// Lift part of N_uv.
pub const NUVL: CoefDef = CoefDef::prime("Nuvl", "kg", "lift part of N_uv");
// heave and pitch (axisymmetric mirror of sway and yaw)
/// Surge force from heave X_uw.
pub const XUW: CoefDef = CoefDef::prime("Xuw", "kg/m", "surge force from heave X_uw");
/// Heave cross-flow drag Z_w|w|.
pub const ZWW: CoefDef = CoefDef::prime("Zww", "kg/m", "heave cross-flow drag Z_w|w|");
/// Heave force from pitch rate Z_q|q|.
pub const ZQQ: CoefDef = CoefDef::prime("Zqq", "kg m", "heave force from pitch rate Z_q|q|");
/// Heave force Z_uw (body lift and drag).
pub const ZUW: CoefDef = CoefDef::prime("Zuw", "kg/m", "heave force Z_uw (body lift and drag)");
/// Pitch moment M_w|w|.
pub const MWW: CoefDef = CoefDef::prime("Mww", "kg", "pitch moment M_w|w|");
/// Pitch damping M_q|q|.
pub const MQQ: CoefDef = CoefDef::prime("Mqq", "kg m^2", "pitch damping M_q|q|");
/// Lift part of the pitch moment M_uw.
pub const MUWL: CoefDef = CoefDef::prime("Muwl", "kg", "lift part of the pitch moment M_uw");
// roll
/// Roll damping K_p|p|.
pub const KPP: CoefDef = CoefDef::prime("Kpp", "kg m^2", "roll damping K_p|p|");
