//! The 150 m ship's heading loop written from the equations alone, the reference of
//! tests/autopilot_plant.rs and tests/autopilot_adaptive.rs: the linear sway-yaw model at
//! speed U (Fossen 2011, 7.1: v_dot = b1 v + (b2 + b4 U) r + b3 delta,
//! r_dot = c1 v + c2 r + c3 delta, configs/vehicles/ship150_clarke.toml's coefficients at
//! 8 m/s; each hydrodynamic derivative proportional to U, the rudder's to U^2), its Nomoto
//! indices (Fossen 2011, 7.2: K = (a21 b_v - a11 b_r) / det A, T = T1 + T2 - T3), a PID
//! placed on them (K_p = m w_n^2, K_d = 2 zeta w_n m - d, K_i = w_n K_p / 10, m = T/K,
//! d = 1/K) with anti-windup and a rate- and angle-limited rudder, a third-order reference
//! model (a first-order filter cascaded with a mass-damper-spring, Fossen 2011, 10.2.1), fed
//! the true heading, at 10 Hz with RK4 sub-steps.

use std::f64::consts::PI;

/// The vehicle file's sway-yaw coefficients (configs/vehicles/ship150_clarke.toml).
pub const B: [f64; 4] = [-3.546341e-2, 2.216678, -6.357587e-2, -4.983084e-1];
/// Its yaw coefficients.
pub const C: [f64; 3] = [-1.429146e-3, -1.162988e-1, 2.954610e-3];
/// The speed they hold for, m/s.
pub const U0: f64 = 8.0;
pub const DT: f64 = 0.1;
pub const OMEGA_N: f64 = 0.05;
pub const ZETA: f64 = 0.9;
pub const REFERENCE: (f64, f64) = (0.03, 1.0);
pub const RATE_LIMIT: f64 = 2.32 * PI / 180.0;
pub const ANGLE_LIMIT: f64 = 35.0 * PI / 180.0;

/// A sway-yaw system: A and b.
pub type SwayYaw = ([[f64; 2]; 2], [f64; 2]);

/// The linear sway-yaw system at speed `u` (the coefficients scaled by u / U0).
pub fn sway_yaw(u: f64) -> SwayYaw {
    let s = u / U0;
    (
        [[B[0] * s, B[1] * s + B[3] * u], [C[0] * s, C[1] * s]],
        [B[2] * s * s, C[2] * s * s],
    )
}

/// Nomoto's K and T of the sway-yaw system (Fossen 2011, 7.2).
pub fn nomoto((a, b): SwayYaw) -> (f64, f64) {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let k_num = a[1][0] * b[0] - a[0][0] * b[1];
    let t3 = b[1] / k_num;
    (k_num / det, -(a[0][0] + a[1][1]) / det - t3)
}

/// PID gains (K_p, K_d, K_i) placed on (k, t).
pub fn gains((k, t): (f64, f64)) -> (f64, f64, f64) {
    let (m, d) = (t / k, 1.0 / k);
    let kp = m * OMEGA_N * OMEGA_N;
    (kp, 2.0 * ZETA * OMEGA_N * m - d, OMEGA_N * kp / 10.0)
}

/// The paper's form of the ship at speed `u`: the first-order Nomoto model r' = (K delta -
/// r) / T (Dinh, Hoang & Pham 2016, the model of eq. 20) with the sway-yaw system's K and T,
/// written as a sway-yaw system whose sway is decoupled (a unit pole, v = 0): its
/// [`nomoto`] indices are the same K and T.
pub fn first_order(u: f64) -> SwayYaw {
    let (k, t) = nomoto(sway_yaw(u));
    ([[-1.0, 0.0], [0.0, -1.0 / t]], [0.0, k / t])
}

/// A run: the ship at 8 m/s, slowed to `slow.1` m/s at `slow.0` s (None: never), the gains
/// re-placed on the slow ship's indices at the change when `retune`, the heading ordered
/// `orders` (time s, heading rad) from the reference model, for `duration` s.
pub struct Run {
    /// The ship at a speed: [`sway_yaw`] or [`first_order`].
    pub plant: fn(f64) -> SwayYaw,
    pub slow: Option<(f64, f64)>,
    pub retune: bool,
    pub orders: Vec<(f64, f64)>,
    pub duration: f64,
}

/// Heading error and rudder per sample (the rudder held over the interval after each).
pub fn run(r: &Run) -> (Vec<f64>, Vec<f64>) {
    let mut plant = (r.plant)(U0);
    let (mut kp, mut kd, mut ki) = gains(nomoto(plant));
    let (mut x, mut rudder, mut integral) = ([0.0f64; 3], 0.0f64, 0.0f64);
    let (w, z) = REFERENCE;
    let (mut low, mut psi_d, mut r_d) = (0.0f64, 0.0f64, 0.0f64);
    let n = (r.duration / DT).round() as usize + 1;
    let (mut errors, mut rudders) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut slowed = false;
    for step in 0..n {
        let time = step as f64 * DT;
        if step > 0 {
            if let Some((at, u)) = r.slow.filter(|(at, _)| !slowed && time - DT >= *at) {
                let _ = at;
                plant = (r.plant)(u);
                slowed = true;
                if r.retune {
                    (kp, kd, ki) = gains(nomoto(plant));
                }
            }
            let (a, b) = plant;
            let f = |x: [f64; 3]| {
                [
                    a[0][0] * x[0] + a[0][1] * x[1] + b[0] * rudder,
                    a[1][0] * x[0] + a[1][1] * x[1] + b[1] * rudder,
                    x[1],
                ]
            };
            let add = |x: [f64; 3], k: [f64; 3], h: f64| {
                [x[0] + h * k[0], x[1] + h * k[1], x[2] + h * k[2]]
            };
            let h = DT / 4.0;
            for _ in 0..4 {
                let k1 = f(x);
                let k2 = f(add(x, k1, h / 2.0));
                let k3 = f(add(x, k2, h / 2.0));
                let k4 = f(add(x, k3, h));
                for i in 0..3 {
                    x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
            }
            let command = r
                .orders
                .iter()
                .rev()
                .find(|(at, _)| time >= *at)
                .map_or(0.0, |o| o.1);
            let h = DT / 50.0;
            for _ in 0..50 {
                let acc = w * w * (low - psi_d) - 2.0 * z * w * r_d;
                low += h * w * (command - low);
                psi_d += h * r_d;
                r_d += h * acc;
            }
        }
        let e = x[2] - psi_d;
        errors.push(e);
        rudders.push(rudder);
        let wanted = -(kp * e + kd * (x[1] - r_d) + ki * integral);
        let held = wanted.clamp(-ANGLE_LIMIT, ANGLE_LIMIT);
        if held == wanted {
            integral += e * DT;
        }
        rudder += (held - rudder).clamp(-RATE_LIMIT * DT, RATE_LIMIT * DT);
    }
    (errors, rudders)
}

/// RMS of `v` over the samples from `from` s on (to the end).
pub fn rms_from(v: &[f64], from: f64) -> f64 {
    let i = (from / DT).round() as usize;
    let tail = &v[i.min(v.len())..];
    (tail.iter().map(|x| x * x).sum::<f64>() / tail.len().max(1) as f64).sqrt()
}

/// hydroid's side: the autopilot step of `cfg` with the identified model nomoto_wave given
/// K and T `kt` (no bias, configs/nomoto.toml's waves and process noise) in `seas`, on the
/// plant `cfg` names.
pub fn hydroid_autopilot(
    cfg: &hydroid::config::autopilot::AutopilotConfig,
    (k, t): (f64, f64),
    seas: &hydroid::dynamics::autopilot::seas::Seas,
) -> hydroid::dynamics::autopilot::AutopilotResult {
    use hydroid::model::coefficients::{Coefficient, CoefficientSet, Source};
    let loaded = hydroid::config::load(&super::root().join("configs/nomoto.toml"), &[]).unwrap();
    let plant =
        hydroid::app::pipeline::autopilot::load_plant(cfg, &loaded.config, &loaded.base_dir)
            .unwrap();
    let mut set = CoefficientSet::new();
    for (n, v) in [
        ("K", k),
        ("inv_T", 1.0 / t),
        ("delta0", 0.0),
        ("w0", std::f64::consts::FRAC_PI_4), // 8 s waves
        ("zeta_w", 0.1),
    ] {
        set.insert(Coefficient::new(n, v, None, Source::Config));
    }
    hydroid::app::pipeline::autopilot::run(
        hydroid::model::models::ModelName::NomotoWave,
        &loaded.vehicle,
        &set,
        loaded.config.hekf.as_ref().unwrap(),
        cfg,
        (seas, plant.as_ref()),
    )
    .unwrap()
}

/// The `[plant.change]` section (under `[autopilot]`) that slows the ship to `u` m/s at `at`
/// s: its coefficients scaled by u / U0 (the rudder's by (u / U0)^2), the propeller at the
/// u m/s balance of configs/vehicles/ship150_clarke.toml (a9 n^2 + a8 u n + a1 u = 0).
pub fn slow_down_toml(at: f64, u: f64) -> String {
    let s = u / U0;
    let (a1, a8, a9) = (-2.203423e-3, -1.246920e-3, 1.097290e-2);
    let n = (-a8 * u + ((a8 * u).powi(2) - 4.0 * a9 * a1 * u).sqrt()) / (2.0 * a9);
    format!(
        "[plant.change]\nat = {at}\nspeed = \"{u} m/s\"\ninputs = {{ rpm = {n} }}\n\
         coefficients = {{ b1 = {}, b2 = {}, b3 = {}, c1 = {}, c2 = {}, c3 = {} }}\n",
        B[0] * s,
        B[1] * s,
        B[2] * s * s,
        C[0] * s,
        C[1] * s,
        C[2] * s * s
    )
}
