//! A ship steering in waves, from the published equations: Nomoto's first-order model with a
//! rudder bias (Dinh, Hoang & Pham 2016, eq. 20; ../shared/docs/nomoto-wave-ekf.md; Fossen
//! 2011, section 7.2) and Fossen's linear wave-induced yaw (Fossen 2011, section 8.2.1, the
//! form the shared document names as the default), written from those texts, not from
//! src/model/models:
//!
//!     psi_L_dot = r_L,   T r_L_dot + r_L = K (delta - delta_0)
//!     xi_dot = psi_H,    psi_H_dot = -w0^2 xi - 2 zeta w0 psi_H + w(t)
//!     compass = psi_L + psi_H + white noise
//!
//! so psi_H = s / (s^2 + 2 zeta w0 s + w0^2) w. The wave excitation w(t) is white noise of
//! spectral density q: over each fine RK4 step of length h it is held at a Gaussian sample
//! of variance q / h, which makes var(psi_H) = q / (4 zeta w0). The frigate of Van Amerongen
//! (1982) at 9 m/s: K = 0.18 1/s, T = 27 s (fixture frigate_nomoto_vanamerongen1982.csv; the
//! source's Norrbin term n3 r^3 is left out: a first-order linear ship).
//!
//! The rudder moves through a steering gear (2.32 deg/s, 0.2 s lag) integrated inside the
//! fine steps; the helm is a 20/20 zig-zag switched on the low-frequency heading psi_L (a
//! helmsman who does not chase the waves).

use super::{rk4, Noise, Series, Servo, ZigZag};

/// The ship and the sea.
#[derive(Debug, Clone, Copy)]
pub struct NomotoShip {
    /// Gain, 1/s.
    pub k: f64,
    /// Time constant, s.
    pub t: f64,
    /// Rudder bias delta_0, rad.
    pub delta0: f64,
    /// Wave peak frequency, rad/s.
    pub w0: f64,
    /// Relative damping of the wave-yaw model.
    pub zeta: f64,
    /// Standard deviation of the wave-induced yaw, rad.
    pub wave_sigma: f64,
}

impl NomotoShip {
    /// The frigate at 9 m/s (K, T from the fixture's 9 m/s row), a 1 deg rudder bias, waves
    /// of period `period` s with zeta 0.1 and 1 deg of wave yaw (standard deviation).
    pub fn frigate(period: f64) -> Self {
        let (k, t) = frigate_at(9.0);
        NomotoShip {
            k,
            t,
            delta0: 1f64.to_radians(),
            w0: 2.0 * std::f64::consts::PI / period,
            zeta: 0.1,
            wave_sigma: 1f64.to_radians(),
        }
    }

    /// The white noise's spectral density q for the wave yaw's standard deviation.
    pub fn wave_q(&self) -> f64 {
        4.0 * self.zeta * self.w0 * self.wave_sigma * self.wave_sigma
    }
}

/// K (1/s) and T (s) of the frigate at `speed` m/s, a row of the fixture.
pub fn frigate_at(speed: f64) -> (f64, f64) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/independent/frigate_nomoto_vanamerongen1982.csv");
    let text = std::fs::read_to_string(path).unwrap();
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<f64> = line.split(',').map(|c| c.trim().parse().unwrap()).collect();
        if f[0] == speed {
            return (f[1], f[2]);
        }
    }
    panic!("no row for {speed} m/s");
}

/// State: psi_L, r_L, xi, psi_H, delta.
pub type State = [f64; 5];

/// d/dt of the state with rudder command `cmd`, the wave excitation `w` held over the step.
pub fn derivatives(s: &NomotoShip, x: &State, cmd: f64, w: f64, servo: &Servo) -> State {
    [
        x[1],
        (s.k * (x[4] - s.delta0) - x[1]) / s.t,
        x[3],
        -s.w0 * s.w0 * x[2] - 2.0 * s.zeta * s.w0 * x[3] + w,
        servo.rate_of(x[4], cmd),
    ]
}

/// The steering gear: 2.32 deg/s (IMO), 0.2 s lag.
pub fn steering_gear() -> Servo {
    Servo {
        rate: 2.32f64.to_radians(),
        tau: 0.2,
    }
}

/// A run: compass and rudder log, and the noise-free states at the samples.
pub struct Run {
    pub log: Series,
    pub states: Vec<State>,
    pub times: Vec<f64>,
}

/// What the helm does.
#[derive(Debug, Clone, Copy)]
pub enum Helm {
    /// Rudder to `angle` (rad) at `at` s.
    Step {
        angle: f64,
        at: f64,
    },
    ZigZag(ZigZag),
}

/// Runs the ship for `duration` s, RK4 at `fine` s, logged every `sample` s (compass noise
/// `compass` rad, seed `seed` for the waves and the compass).
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    ship: &NomotoShip,
    mut helm: Helm,
    servo: Servo,
    waves: bool,
    duration: f64,
    fine: f64,
    sample: f64,
    compass: f64,
    seed: u64,
) -> Run {
    let per = (sample / fine).round() as usize;
    assert!((per as f64 * fine - sample).abs() < 1e-9);
    let steps = (duration / fine).round() as usize;
    let mut wave_noise = Noise::new(seed);
    let w_sigma = if waves {
        (ship.wave_q() / fine).sqrt()
    } else {
        0.0
    };
    // start the waves in their stationary distribution: psi_H ~ N(0, sigma^2),
    // xi ~ N(0, sigma^2 / w0^2) (var(xi) = q / (4 zeta w0^3))
    let mut x: State = [0.0; 5];
    if waves {
        x[3] = ship.wave_sigma * wave_noise.standard();
        x[2] = ship.wave_sigma / ship.w0 * wave_noise.standard();
    }
    let mut states = Vec::new();
    let mut times = Vec::new();
    for k in 0..=steps {
        let t = k as f64 * fine;
        if k % per == 0 {
            states.push(x);
            times.push(t);
        }
        if k == steps {
            break;
        }
        let cmd = match &mut helm {
            Helm::Step { angle, at } => {
                if t >= *at {
                    *angle
                } else {
                    0.0
                }
            }
            Helm::ZigZag(z) => z.command(t, x[0]),
        };
        let w = w_sigma * wave_noise.standard();
        x = rk4(&|s: &State| derivatives(ship, s, cmd, w, &servo), &x, fine);
    }
    let mut noise = Noise::new(seed.wrapping_add(1000));
    let heading: Vec<f64> = states.iter().map(|s| s[0] + s[3]).collect();
    let mut log = Series::new(&format!(
        "frigate zig-zag in waves of {:.1} s (independent Nomoto generator)",
        2.0 * std::f64::consts::PI / ship.w0
    ));
    log.push("time", "s", times.clone());
    log.push(
        "compass",
        "deg",
        noise
            .add(&heading, compass)
            .into_iter()
            .map(f64::to_degrees)
            .collect(),
    );
    log.push(
        "rudder",
        "deg",
        states.iter().map(|s| s[4].to_degrees()).collect(),
    );
    Run { log, states, times }
}

/// The 20/20 zig-zag of [`zigzag_in_waves`] in calm water: the compass sees no wave yaw.
pub fn zigzag_in_calm(ship: &NomotoShip, seed: u64) -> Run {
    zigzag_20_20(ship, false, seed)
}

/// A 20/20 zig-zag in waves of `period` s: 600 s logged at 10 Hz (RK4 at 10 ms), compass
/// noise 0.1 deg, first rudder order at 10 s.
pub fn zigzag_in_waves(ship: &NomotoShip, seed: u64) -> Run {
    zigzag_20_20(ship, true, seed)
}

/// The 20/20 zig-zag, with or without the waves of `ship`.
fn zigzag_20_20(ship: &NomotoShip, waves: bool, seed: u64) -> Run {
    simulate(
        ship,
        Helm::ZigZag(ZigZag::new(
            20f64.to_radians(),
            20f64.to_radians(),
            1.0,
            10.0,
            0.0,
        )),
        steering_gear(),
        waves,
        600.0,
        0.01,
        0.1,
        0.1f64.to_radians(),
        seed,
    )
}
