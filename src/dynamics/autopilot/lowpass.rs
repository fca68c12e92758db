//! The ordinary wave filter the paper compares its EKF with (Dinh, Hoang & Pham 2016, fig. 6:
//! "when the autopilot uses an ordinary filter"): a low-pass filter on the compass with its
//! cut-off below the wave band, so that the autopilot sees the slow heading without the
//! first-order wave yaw (Fossen 2011, Handbook of Marine Craft Hydrodynamics and Motion
//! Control, 11.1.1: low-pass filtering of the wave-induced motion, the cut-off w_f between the
//! control bandwidth and the wave frequency, w_b < w_f < w_e).
//!
//! The filter is the second-order Butterworth low-pass h(s) = w_f^2 / (s^2 + sqrt(2) w_f s +
//! w_f^2) (Fossen 2011, 11.1.1, the Butterworth filter of order 2), discretised by the
//! bilinear transform with the cut-off pre-warped (Oppenheim & Schafer, Discrete-Time Signal
//! Processing, 3rd ed., 7.2: s = (2/dt) (1 - z^-1) / (1 + z^-1)). With k = tan(w_f dt / 2)
//! and n = 1 + sqrt(2) k + k^2, the difference equation is
//!
//! ```text
//! y_k = b0 (u_k + 2 u_k-1 + u_k-2) - a1 y_k-1 - a2 y_k-2,
//! b0 = k^2 / n,  a1 = 2 (k^2 - 1) / n,  a2 = (1 - sqrt(2) k + k^2) / n,
//! ```
//!
//! unit gain at zero frequency. The yaw rate the autopilot is fed is the backward difference
//! of the filtered heading, (y_k - y_k-1) / dt: the compass alone, as the EKF wave filter has.

/// The cut-off, rad/s, by default: a quarter of the wave frequency `w0`. The second-order
/// Butterworth filter passes 1 / sqrt(1 + (w / w_f)^4) of a sine at w: 6.2 % of the wave yaw
/// at w0, while it delays the heading by its group delay sqrt(2) / w_f at low frequency
/// (Fossen 2011, 11.1.1: the lower the cut-off, the more phase lag in the loop).
pub fn default_cutoff(w0: f64) -> f64 {
    w0 / 4.0
}

/// The second-order Butterworth low-pass on the compass, with its last inputs and outputs.
#[derive(Debug, Clone)]
pub struct LowPass {
    b0: f64,
    a1: f64,
    a2: f64,
    dt: f64,
    /// u_k-1, u_k-2.
    u: [f64; 2],
    /// y_k-1, y_k-2.
    y: [f64; 2],
    started: bool,
}

impl LowPass {
    /// The filter with cut-off `cutoff` (rad/s, below the Nyquist frequency pi / `dt`) for
    /// samples every `dt` seconds.
    pub fn new(cutoff: f64, dt: f64) -> Self {
        let k = (cutoff * dt / 2.0).tan();
        let s2 = std::f64::consts::SQRT_2;
        let n = 1.0 + s2 * k + k * k;
        LowPass {
            b0: k * k / n,
            a1: 2.0 * (k * k - 1.0) / n,
            a2: (1.0 - s2 * k + k * k) / n,
            dt,
            u: [0.0; 2],
            y: [0.0; 2],
            started: false,
        }
    }

    /// The filtered heading and its backward difference after the reading `u`. The first
    /// reading starts the filter at rest on it (every past input and output equal to it: the
    /// ship on its course), so the filtered heading does not swing in from zero.
    pub fn step(&mut self, u: f64) -> (f64, f64) {
        if !self.started {
            self.u = [u; 2];
            self.y = [u; 2];
            self.started = true;
        }
        let y =
            self.b0 * (u + 2.0 * self.u[0] + self.u[1]) - self.a1 * self.y[0] - self.a2 * self.y[1];
        let rate = (y - self.y[0]) / self.dt;
        self.u = [u, self.u[0]];
        self.y = [y, self.y[0]];
        (y, rate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine well below the cut-off passes whole, one at four times the cut-off (the
    /// default's wave frequency) comes out at 1 / sqrt(1 + 4^4) = 6.2 % (the Butterworth
    /// magnitude, within the bilinear transform's warping, exact at the cut-off), and a
    /// constant heading stays put from the first sample.
    #[test]
    fn passes_the_slow_heading_and_stops_the_waves() {
        let (dt, wf) = (0.1, 0.2);
        let amplitude = |w: f64| {
            let mut f = LowPass::new(wf, dt);
            let mut peak: f64 = 0.0;
            for k in 0..20_000 {
                let (y, _) = f.step((w * k as f64 * dt).sin());
                if k > 10_000 {
                    peak = peak.max(y.abs());
                }
            }
            peak
        };
        assert!((amplitude(0.01) - 1.0).abs() < 1e-3);
        let want = 1.0 / (1.0f64 + 4f64.powi(4)).sqrt();
        assert!(
            (amplitude(4.0 * wf) / want - 1.0).abs() < 0.02,
            "{}",
            amplitude(0.8)
        );
        assert!((amplitude(wf) - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-3);
        let mut f = LowPass::new(wf, dt);
        for _ in 0..10 {
            let (y, rate) = f.step(0.3);
            assert!((y - 0.3).abs() < 1e-12 && rate.abs() < 1e-10, "{y} {rate}");
        }
    }
}
