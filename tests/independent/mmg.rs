//! KVLCC2 free-running model (1/45.7), 3-DOF MMG standard method, from the published
//! equations: Yasukawa & Yoshimura (2015), "Introduction of MMG standard method for ship
//! maneuvering predictions", J. Mar. Sci. Technol. 20:37-52 (eq. numbers as in that paper),
//! with its KVLCC2 parameters (Tables 2-3; fixture kvlcc2_mmg_yasukawa2015.csv). Written
//! from that paper's equations and ../shared/docs/ship-3dof-ekf.md, not from src/models.
//!
//! Motion about midship (v_m: sway velocity at midship), x_G from midship (eq. 4):
//!
//!     (m + m_x) u_dot - (m + m_y) v_m r - x_G m r^2 = X_H + X_R + X_P
//!     (m + m_y) v_m_dot + (m + m_x) u r + x_G m r_dot = Y_H + Y_R
//!     (I_zG + x_G^2 m + J_z) r_dot + x_G m (v_m_dot + u r) = N_H + N_R
//!
//! Hull (eq. 7-8): X_H = 0.5 rho L d U^2 X'_H, Y_H = 0.5 rho L d U^2 Y'_H,
//! N_H = 0.5 rho L^2 d U^2 N'_H with v' = v_m / U, r' = r L / U and
//!
//!     X'_H = -R'_0 + X'_vv v'^2 + X'_vr v' r' + X'_rr r'^2 + X'_vvvv v'^4
//!     Y'_H = Y'_v v' + Y'_r r' + Y'_vvv v'^3 + Y'_vvr v'^2 r' + Y'_vrr v' r'^2 + Y'_rrr r'^3
//!     N'_H = N'_v v' + N'_r r' + N'_vvv v'^3 + N'_vvr v'^2 r' + N'_vrr v' r'^2 + N'_rrr r'^3
//!
//! Propeller (eq. 9-11, 15-16): X_P = (1 - t_P) rho n^2 D_P^4 K_T(J_P),
//! K_T = k_0 + k_1 J_P + k_2 J_P^2, J_P = u (1 - w_P) / (n D_P),
//! (1 - w_P) / (1 - w_P0) = 1 + (1 - exp(-C_1 |beta_P|)) (C_2 - 1), beta_P = beta - x'_P r',
//! beta = atan(-v_m / u).
//!
//! Rudder (eq. 12-14, 23-29): X_R = -(1 - t_R) F_N sin delta, Y_R = -(1 + a_H) F_N cos delta,
//! N_R = -(x_R + a_H x_H) F_N cos delta, F_N = 0.5 rho A_R U_R^2 f_alpha sin alpha_R,
//! alpha_R = delta - atan(v_R / u_R), v_R = U gamma_R beta_R, beta_R = beta - l'_R r',
//! u_R = eps u_P sqrt(eta {1 + kappa (sqrt(1 + 8 K_T / (pi J_P^2)) - 1)}^2 + (1 - eta)),
//! u_P = (1 - w_P) u, eta = D_P / H_R; x_R = -0.5 L, x_H = x'_H L.
//!
//! Added masses: m_x = m'_x 0.5 rho L^2 d, m_y likewise, J_z = J'_z 0.5 rho L^4 d.
//! Positive rudder angle to starboard, turning the ship to starboard (r > 0); x north, y
//! east, heading from north to east.

use super::{published, rk4, value, Noise, Series, Servo, ZigZag};

/// Model-scale particulars and the MMG parameters.
#[derive(Debug, Clone)]
pub struct Kvlcc2 {
    pub rho: f64,
    pub lpp: f64,
    pub draught: f64,
    pub mass: f64,
    pub x_g: f64,
    /// I_zG + x_G^2 m: yaw inertia about midship.
    pub izz_midship: f64,
    pub d_p: f64,
    pub a_r: f64,
    pub h_r: f64,
    /// Published MMG parameters by the fixture's names.
    pub p: std::collections::BTreeMap<String, f64>,
    // the parameters read once
    r0: f64,
    xvv: f64,
    xvr: f64,
    xrr: f64,
    xvvvv: f64,
    yv: f64,
    yr: f64,
    yvvv: f64,
    yvvr: f64,
    yvrr: f64,
    yrrr: f64,
    nv: f64,
    nr: f64,
    nvvv: f64,
    nvvr: f64,
    nvrr: f64,
    nrrr: f64,
    m_x: f64,
    m_y: f64,
    j_z: f64,
    t_p: f64,
    w_p0: f64,
    x_p: f64,
    c1: f64,
    c2_plus: f64,
    c2_minus: f64,
    k: [f64; 3],
    t_r: f64,
    a_h: f64,
    x_h: f64,
    f_alpha: f64,
    epsilon: f64,
    kappa: f64,
    l_r: f64,
    gamma_plus: f64,
    gamma_minus: f64,
}

/// State: u, v_m, r, x, y, psi, rudder angle.
pub type State = [f64; 7];

impl Kvlcc2 {
    /// The 1/45.7 model of Yasukawa & Yoshimura (2015, Table 1, model column: L_pp 7.00 m,
    /// d 0.46 m, displacement 3.27 m^3, x_G 0.25 m, D_P 0.216 m, A_R 0.0539 m^2, H_R
    /// 0.345 m; the full-scale figures of the fixture divided by 45.7 and 45.7^2 agree to
    /// the digits printed), fresh water 1000 kg/m^3, k_zz = 0.25 L_pp.
    pub fn model() -> Self {
        let set = published("kvlcc2_mmg_yasukawa2015.csv");
        let p: std::collections::BTreeMap<String, f64> = set.iter().cloned().collect();
        let g = |n: &str| value(&set, n);
        let rho = 1000.0;
        let lpp: f64 = 7.0;
        let draught = 0.46;
        let mass = rho * 3.27;
        let x_g = 0.25;
        let izz_midship = mass * (0.25 * lpp).powi(2) + mass * x_g * x_g;
        let half = 0.5 * rho * lpp * lpp * draught;
        Kvlcc2 {
            rho,
            lpp,
            draught,
            mass,
            x_g,
            izz_midship,
            d_p: 0.216,
            a_r: 0.0539,
            h_r: 0.345,
            r0: g("R_0_dash"),
            xvv: g("X_vv_dash"),
            xvr: g("X_vr_dash"),
            xrr: g("X_rr_dash"),
            xvvvv: g("X_vvvv_dash"),
            yv: g("Y_v_dash"),
            yr: g("Y_r_dash"),
            yvvv: g("Y_vvv_dash"),
            yvvr: g("Y_vvr_dash"),
            yvrr: g("Y_vrr_dash"),
            yrrr: g("Y_rrr_dash"),
            nv: g("N_v_dash"),
            nr: g("N_r_dash"),
            nvvv: g("N_vvv_dash"),
            nvvr: g("N_vvr_dash"),
            nvrr: g("N_vrr_dash"),
            nrrr: g("N_rrr_dash"),
            m_x: g("m_x_dash") * half,
            m_y: g("m_y_dash") * half,
            j_z: g("J_z_dash") * half * lpp * lpp,
            t_p: g("t_P"),
            w_p0: g("w_P0"),
            x_p: g("x_P_dash"),
            c1: g("C_1"),
            c2_plus: g("C_2_plus"),
            c2_minus: g("C_2_minus"),
            k: [g("k_0"), g("k_1"), g("k_2")],
            t_r: g("t_R"),
            a_h: g("a_H"),
            x_h: g("x_H_dash") * lpp,
            f_alpha: g("f_alpha"),
            epsilon: g("epsilon"),
            kappa: g("kappa"),
            l_r: g("l_R"),
            gamma_plus: g("gamma_R_plus"),
            gamma_minus: g("gamma_R_minus"),
            p,
        }
    }

    /// Propeller thrust T (N) and K_T, J_P, 1 - w_P at (u, v_m, r) and n rev/s.
    fn propeller(&self, u: f64, v: f64, r: f64, n: f64) -> (f64, f64, f64, f64) {
        let big_u = (u * u + v * v).sqrt();
        let (beta, r_dash) = if big_u > 0.0 {
            ((-v).atan2(u), r * self.lpp / big_u)
        } else {
            (0.0, 0.0)
        };
        let beta_p = beta - self.x_p * r_dash;
        let c2 = if beta_p > 0.0 {
            self.c2_plus
        } else {
            self.c2_minus
        };
        let one_minus_wp =
            (1.0 - self.w_p0) * (1.0 + (1.0 - (-self.c1 * beta_p.abs()).exp()) * (c2 - 1.0));
        let j = u * one_minus_wp / (n * self.d_p);
        let kt = self.k[0] + self.k[1] * j + self.k[2] * j * j;
        let thrust = self.rho * n * n * self.d_p.powi(4) * kt;
        (thrust, kt, j, one_minus_wp)
    }

    /// Surge, sway force and yaw moment about midship: [X, Y, N].
    pub fn forces(&self, x: &State, n: f64) -> [f64; 3] {
        let (u, v, r, delta) = (x[0], x[1], x[2], x[6]);
        let big_u = (u * u + v * v).sqrt();
        let l = self.lpp;
        let (vd, rd) = (v / big_u, r * l / big_u);
        let qf = 0.5 * self.rho * l * self.draught * big_u * big_u;
        let xh = qf
            * (-self.r0
                + self.xvv * vd * vd
                + self.xvr * vd * rd
                + self.xrr * rd * rd
                + self.xvvvv * vd.powi(4));
        let yh = qf
            * (self.yv * vd
                + self.yr * rd
                + self.yvvv * vd.powi(3)
                + self.yvvr * vd * vd * rd
                + self.yvrr * vd * rd * rd
                + self.yrrr * rd.powi(3));
        let nh = qf
            * l
            * (self.nv * vd
                + self.nr * rd
                + self.nvvv * vd.powi(3)
                + self.nvvr * vd * vd * rd
                + self.nvrr * vd * rd * rd
                + self.nrrr * rd.powi(3));
        let (thrust, kt, j, one_minus_wp) = self.propeller(u, v, r, n);
        let xp = (1.0 - self.t_p) * thrust;
        // rudder
        let beta = (-v).atan2(u);
        let u_p = one_minus_wp * u;
        let eta = self.d_p / self.h_r;
        let slip =
            1.0 + self.kappa * ((1.0 + 8.0 * kt / (std::f64::consts::PI * j * j)).sqrt() - 1.0);
        let u_r = self.epsilon * u_p * (eta * slip * slip + (1.0 - eta)).sqrt();
        let beta_r = beta - self.l_r * rd;
        let gamma = if beta_r < 0.0 {
            self.gamma_minus
        } else {
            self.gamma_plus
        };
        let v_r = big_u * gamma * beta_r;
        let alpha_r = delta - v_r.atan2(u_r);
        let f_n =
            0.5 * self.rho * self.a_r * (u_r * u_r + v_r * v_r) * self.f_alpha * alpha_r.sin();
        let x_r = -0.5 * l;
        let xr = -(1.0 - self.t_r) * f_n * delta.sin();
        let yr = -(1.0 + self.a_h) * f_n * delta.cos();
        let nr = -(x_r + self.a_h * self.x_h) * f_n * delta.cos();
        [xh + xp + xr, yh + yr, nh + nr]
    }

    /// d/dt of the state with the rudder command `cmd` (rad) through `servo`, propeller at
    /// `n` rev/s.
    pub fn derivatives(&self, x: &State, cmd: f64, servo: &Servo, n: f64) -> State {
        let (u, v, r, psi) = (x[0], x[1], x[2], x[5]);
        let [fx, fy, fn_] = self.forces(x, n);
        let m = self.mass;
        let u_dot = (fx + (m + self.m_y) * v * r + self.x_g * m * r * r) / (m + self.m_x);
        // [[m + m_y, x_G m], [x_G m, Izz + J_z]] [v_dot, r_dot] = [Y - (m + m_x) u r, N - x_G m u r]
        let a11 = m + self.m_y;
        let a12 = self.x_g * m;
        let a22 = self.izz_midship + self.j_z;
        let b1 = fy - (m + self.m_x) * u * r;
        let b2 = fn_ - self.x_g * m * u * r;
        let det = a11 * a22 - a12 * a12;
        let v_dot = (a22 * b1 - a12 * b2) / det;
        let r_dot = (a11 * b2 - a12 * b1) / det;
        [
            u_dot,
            v_dot,
            r_dot,
            u * psi.cos() - v * psi.sin(),
            u * psi.sin() + v * psi.cos(),
            r,
            servo.rate_of(x[6], cmd),
        ]
    }

    /// The propeller speed (rev/s) at which the ship holds `u` straight ahead: X = 0.
    pub fn self_propulsion(&self, u: f64) -> f64 {
        let x = |n: f64| self.forces(&[u, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], n)[0];
        let (mut lo, mut hi) = (1.0, 60.0);
        assert!(x(lo) < 0.0 && x(hi) > 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if x(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// Approach speed of the model: 15.5 kn full scale (Y&Y 2015) Froude-scaled by sqrt(45.7).
pub fn approach_speed() -> f64 {
    15.5 * 1852.0 / 3600.0 / 45.7f64.sqrt()
}

/// The steering gear: 2.32 deg/s full scale (IMO: 35 deg port to 30 deg starboard in 28 s),
/// Froude-scaled to the model by sqrt(45.7) (15.68 deg/s), with a 0.1 s lag.
pub fn steering_gear() -> Servo {
    Servo {
        rate: (2.32 * 45.7f64.sqrt()).to_radians(),
        tau: 0.1,
    }
}

/// What the helm does.
#[derive(Debug, Clone, Copy)]
pub enum Helm {
    /// Rudder to `angle` (rad) at `at` s and held.
    Turn {
        angle: f64,
        at: f64,
    },
    ZigZag(ZigZag),
}

/// A run: the log and the noise-free states at the samples.
pub struct Run {
    pub log: Series,
    pub states: Vec<State>,
    pub times: Vec<f64>,
    /// Propeller speed, rev/s.
    pub rps: f64,
}

/// Sensor noise (standard deviations, SI).
#[derive(Debug, Clone, Copy)]
pub struct Sensors {
    pub velocity: f64,
    pub rate: f64,
    pub position: f64,
    pub heading: f64,
}

impl Sensors {
    /// A basin's instruments as the bundled examples assume them: u, v 2e-3 m/s, r 0.05
    /// deg/s, x, y 5 mm, heading 0.05 deg.
    pub fn basin() -> Self {
        Sensors {
            velocity: 2e-3,
            rate: 0.05f64.to_radians(),
            position: 5e-3,
            heading: 0.05f64.to_radians(),
        }
    }

    /// Every standard deviation times `k`.
    pub fn scaled(self, k: f64) -> Self {
        Sensors {
            velocity: self.velocity * k,
            rate: self.rate * k,
            position: self.position * k,
            heading: self.heading * k,
        }
    }
}

/// Runs the ship from straight ahead at the approach speed with the propeller at its
/// self-propulsion speed, `helm` through the steering gear, RK4 at `fine` s, logged every
/// `sample` s with `sensors` noise from `seed`. With `held`, the hull feels the rudder angle
/// of the last logged sample (a diagnostic: the rudder then acts exactly as hydroid's
/// mmg3 assumes between samples) while the logged rudder still moves continuously.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    ship: &Kvlcc2,
    held: bool,
    mut helm: Helm,
    duration: f64,
    fine: f64,
    sample: f64,
    sensors: Sensors,
    seed: u64,
    title: &str,
) -> Run {
    let per = (sample / fine).round() as usize;
    assert!((per as f64 * fine - sample).abs() < 1e-9);
    let u0 = approach_speed();
    let n = ship.self_propulsion(u0);
    let servo = steering_gear();
    let steps = (duration / fine).round() as usize;
    let mut x: State = [u0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut states = Vec::new();
    let mut times = Vec::new();
    let mut seen = x[6];
    for k in 0..=steps {
        let t = k as f64 * fine;
        if k % per == 0 {
            states.push(x);
            times.push(t);
            seen = x[6];
        }
        if k == steps {
            break;
        }
        let cmd = match &mut helm {
            Helm::Turn { angle, at } => {
                if t >= *at {
                    *angle
                } else {
                    0.0
                }
            }
            Helm::ZigZag(z) => z.command(t, x[5]),
        };
        let f = |s: &State| {
            if held {
                let mut h = *s;
                h[6] = seen;
                let mut d = ship.derivatives(&h, cmd, &servo, n);
                d[6] = servo.rate_of(s[6], cmd);
                d
            } else {
                ship.derivatives(s, cmd, &servo, n)
            }
        };
        x = rk4(&f, &x, fine);
    }
    let mut noise = Noise::new(seed);
    let col = |i: usize| states.iter().map(|s| s[i]).collect::<Vec<f64>>();
    let deg = |v: Vec<f64>| v.into_iter().map(f64::to_degrees).collect::<Vec<f64>>();
    let mut log = Series::new(title);
    log.push("time", "s", times.clone());
    log.push("x", "m", noise.add(&col(3), sensors.position));
    log.push("y", "m", noise.add(&col(4), sensors.position));
    log.push("heading", "deg", deg(noise.add(&col(5), sensors.heading)));
    log.push("u", "m/s", noise.add(&col(0), sensors.velocity));
    log.push("v", "m/s", noise.add(&col(1), sensors.velocity));
    log.push("yaw rate", "deg/s", deg(noise.add(&col(2), sensors.rate)));
    log.push("rudder", "deg", deg(col(6)));
    log.push("propeller", "rpm", vec![n * 60.0; times.len()]);
    Run {
        log,
        states,
        times,
        rps: n,
    }
}

/// A turning circle with the rudder to `angle` (rad, positive to starboard) at 5 s,
/// `duration` s, RK4 at 5 ms, logged at `rate_hz`.
pub fn turn(ship: &Kvlcc2, angle: f64, duration: f64, rate_hz: f64, seed: u64) -> Run {
    turn_held(ship, false, angle, duration, rate_hz, seed)
}

/// [`turn`], with the rudder held between samples as the hull feels it when `held`.
pub fn turn_held(
    ship: &Kvlcc2,
    held: bool,
    angle: f64,
    duration: f64,
    rate_hz: f64,
    seed: u64,
) -> Run {
    turn_sensed(ship, held, angle, duration, rate_hz, Sensors::basin(), seed)
}

/// [`turn_held`] with the sensors `sensors`.
pub fn turn_sensed(
    ship: &Kvlcc2,
    held: bool,
    angle: f64,
    duration: f64,
    rate_hz: f64,
    sensors: Sensors,
    seed: u64,
) -> Run {
    simulate(
        ship,
        held,
        Helm::Turn { angle, at: 5.0 },
        duration,
        0.005,
        1.0 / rate_hz,
        sensors,
        seed,
        &format!(
            "KVLCC2 1/45.7 turning circle, rudder {:+.0} deg (independent MMG generator)",
            angle.to_degrees()
        ),
    )
}

/// A 20/20 zig-zag, first order to starboard at 5 s, RK4 at 5 ms, logged at `rate_hz`.
pub fn zigzag(ship: &Kvlcc2, duration: f64, rate_hz: f64, seed: u64) -> Run {
    zigzag_held(ship, false, duration, rate_hz, seed)
}

/// [`zigzag`], with the rudder held between samples as the hull feels it when `held`.
pub fn zigzag_held(ship: &Kvlcc2, held: bool, duration: f64, rate_hz: f64, seed: u64) -> Run {
    zigzag_sensed(ship, held, duration, rate_hz, Sensors::basin(), seed)
}

/// [`zigzag_held`] with the sensors `sensors`.
pub fn zigzag_sensed(
    ship: &Kvlcc2,
    held: bool,
    duration: f64,
    rate_hz: f64,
    sensors: Sensors,
    seed: u64,
) -> Run {
    simulate(
        ship,
        held,
        Helm::ZigZag(ZigZag::new(
            20f64.to_radians(),
            20f64.to_radians(),
            1.0,
            5.0,
            0.0,
        )),
        duration,
        0.005,
        1.0 / rate_hz,
        sensors,
        seed,
        "KVLCC2 1/45.7 20/20 zig-zag (independent MMG generator)",
    )
}

/// Advance and tactical diameter (m) of a turn whose rudder was ordered at `execute` s: the
/// distance along the approach course from the point of the order when the heading has
/// changed by 90 deg, and the lateral distance from the approach course when it has changed
/// by 180 deg (linear interpolation between samples).
pub fn advance_and_tactical_diameter(run: &Run, execute: f64) -> (f64, f64) {
    let k0 = run.times.iter().position(|&t| t >= execute).unwrap();
    let x0 = run.states[k0][3];
    let at = |target: f64, i: usize| -> f64 {
        for k in 1..run.states.len() {
            let (a, b) = (run.states[k - 1][5].abs(), run.states[k][5].abs());
            if a < target && b >= target {
                let f = (target - a) / (b - a);
                return run.states[k - 1][i] + f * (run.states[k][i] - run.states[k - 1][i]);
            }
        }
        panic!("the heading never changed by {} deg", target.to_degrees());
    };
    let ninety = std::f64::consts::FRAC_PI_2;
    (at(ninety, 3) - x0, at(2.0 * ninety, 4).abs())
}

/// The twelve sway and yaw hull derivatives under hydroid's mmg3 names, with the truth.
pub fn hull_truth(ship: &Kvlcc2) -> super::Truth {
    vec![
        ("Yv_p", ship.yv),
        ("Yr_p", ship.yr),
        ("Yvvv_p", ship.yvvv),
        ("Yvvr_p", ship.yvvr),
        ("Yvrr_p", ship.yvrr),
        ("Yrrr_p", ship.yrrr),
        ("Nv_p", ship.nv),
        ("Nr_p", ship.nr),
        ("Nvvv_p", ship.nvvv),
        ("Nvvr_p", ship.nvvr),
        ("Nvrr_p", ship.nvrr),
        ("Nrrr_p", ship.nrrr),
    ]
}
