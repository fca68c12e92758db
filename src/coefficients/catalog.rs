//! The SNAME coefficient names hydroid knows, with their SI units and meanings.

/// What a coefficient means and its SI unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoefInfo {
    /// ASCII SNAME name.
    pub name: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// One-line meaning.
    pub meaning: &'static str,
}

macro_rules! info {
    ($n:literal, $u:literal, $m:literal) => {
        CoefInfo {
            name: $n,
            unit: $u,
            meaning: $m,
        }
    };
}

/// Every coefficient name hydroid knows, with its unit (kg, m, s; rates in rad/s count as 1/s).
pub const CATALOG: &[CoefInfo] = &[
    // added mass (Fossen 1994, section 2.4)
    info!("Xud", "kg", "surge added mass X_udot"),
    info!("Yvd", "kg", "sway added mass Y_vdot"),
    info!("Yrd", "kg m", "sway force from yaw acceleration Y_rdot"),
    info!("Nvd", "kg m", "yaw moment from sway acceleration N_vdot"),
    info!("Nrd", "kg m^2", "yaw added inertia N_rdot"),
    info!("Zwd", "kg", "heave added mass Z_wdot"),
    info!("Zqd", "kg m", "heave force from pitch acceleration Z_qdot"),
    info!("Mwd", "kg m", "pitch moment from heave acceleration M_wdot"),
    info!("Mqd", "kg m^2", "pitch added inertia M_qdot"),
    info!("Kpd", "kg m^2", "roll added inertia K_pdot"),
    // surge (paper eq. 3)
    info!("Xuu", "kg/m", "axial drag X_u|u|"),
    info!("Xuv", "kg/m", "surge force from drift X_uv"),
    info!("Xvv", "kg/m", "surge force from drift squared X_vv"),
    info!("Xvr", "kg", "added-mass Coriolis X_vr"),
    info!("Xrr", "kg m", "added-mass Coriolis X_rr"),
    info!("Xww", "kg/m", "surge force from heave squared X_ww"),
    // sway
    info!("Yvv", "kg/m", "sway cross-flow drag Y_v|v|"),
    info!("Yrr", "kg m", "sway force from yaw rate Y_r|r|"),
    info!("Yur", "kg", "sway force Y_ur (added-mass Coriolis)"),
    info!("Yuv", "kg/m", "sway force Y_uv (body lift and drag)"),
    info!("Yuvd", "kg/m", "drag part of Y_uv"),
    info!("Yuvl", "kg/m", "lift part of Y_uv"),
    // yaw
    info!("Nvv", "kg", "yaw moment N_v|v|"),
    info!("Nrr", "kg m^2", "yaw damping N_r|r|"),
    info!("Nur", "kg m", "yaw moment N_ur (added-mass Coriolis)"),
    info!("Nuv", "kg", "yaw moment N_uv (Munk moment and lift)"),
    info!("Nuva", "kg", "Munk moment part of N_uv"),
    info!("Nuvl", "kg", "lift part of N_uv"),
    // heave and pitch (axisymmetric mirror of sway and yaw)
    info!("Xuw", "kg/m", "surge force from heave X_uw"),
    info!("Zww", "kg/m", "heave cross-flow drag Z_w|w|"),
    info!("Zqq", "kg m", "heave force from pitch rate Z_q|q|"),
    info!("Zuw", "kg/m", "heave force Z_uw (body lift and drag)"),
    info!("Mww", "kg", "pitch moment M_w|w|"),
    info!("Mqq", "kg m^2", "pitch damping M_q|q|"),
    info!("Muwl", "kg", "lift part of the pitch moment M_uw"),
    // roll
    info!("Kpp", "kg m^2", "roll damping K_p|p|"),
];

/// Looks up a coefficient's unit and meaning.
pub fn info(name: &str) -> Option<&'static CoefInfo> {
    CATALOG.iter().find(|c| c.name == name)
}

/// The closest known coefficient name, for "did you mean" messages.
pub fn nearest_name(name: &str) -> Option<&'static str> {
    crate::suggest::nearest(name, CATALOG.iter().map(|c| c.name))
}
