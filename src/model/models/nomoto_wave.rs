//! Course keeping in waves: Nomoto's first-order steering model with a rudder bias, and the
//! linear wave-induced yaw that a compass sees on top of it (../shared/docs/
//! nomoto-wave-ekf.md: Dinh, Hoang & Pham 2016, "the paper"; Fossen 2011, Handbook of Marine
//! Craft Hydrodynamics and Motion Control, 7.2 (Nomoto) and 8.2.1 (linear wave model)).
//!
//! ```text
//! psi_L_dot = r_L,   T r_L_dot + r_L = K (delta - delta_0)           (paper eq. 20, Fossen 7.2)
//! xi_dot    = psi_H
//! psi_H_dot = -w0^2 xi - 2 zeta w0 psi_H + K_w w_H                    (Fossen 2011, 8.2.1)
//! compass   = psi_L + psi_H   (Fossen: psi_H / w_H = K_w s / (s^2 + 2 zeta w0 s + w0^2))
//!           = psi_L + xi      (the paper's eq. 25 as printed: K_w / (s^2 + 2 zeta w0 s + w0^2))
//! gyro      = r_L + psi_H_dot (Fossen)  or  r_L + psi_H (the paper's form)
//! ```
//!
//! States `[r_L, psi_L, xi, psi_H]`; input the rudder (held); outputs the compass (yaw) and
//! a yaw-rate gyro (r), of which a run measures what its log has. The white noise w_H is the
//! filter's process noise on psi_H (K_w^2 per second): K_w is a tuning, not a coefficient.
//! The rudder bias, K and 1/T (`inv_T`, as the paper estimates it: the equation is then
//! finite at 1/T = 0, where a filter may start) are the coefficients an identification
//! estimates; the paper lets them wander as random walks (`hekf.process_noise`).

use super::{
    CoefDef, Example, InputDef, InputRule, Model, OutputDef, Size, StateDef, Unphysical, Vehicle,
    VehicleProblem,
};
use crate::numerics::ad::Scalar;
use crate::model::coefficients::{CompiledRelations, Relation};
use crate::base::quantity::Quantity;
use crate::base::units::wrap_pi;

const fn c(name: &'static str, unit: &'static str, meaning: &'static str, size: f64) -> CoefDef {
    CoefDef::fixed(name, unit, meaning, size, None)
}

crate::coefficient_table! {
    /// Coefficient vector layout (paper eq. 20-25; Fossen 2011, 7.2 and 8.2.1).
    pub COEFFICIENTS;
    K = c("K", "1/s", "Nomoto gain K: steady yaw rate per rudder angle", 0.1),
    INV_T = c("inv_T", "1/s", "reciprocal 1/T of the Nomoto time constant (the paper's x3)", 0.05),
    DELTA0 = c("delta0", "rad", "rudder bias delta_0 (the rudder angle that holds a straight course)", 0.02).zero_unless_given(),
    // a frequency and a damping ratio: positive (Fossen 2011, 8.2.1); K's sign follows the
    // rudder's convention and 1/T is negative for a course-unstable ship: not bounded
    W0 = c("w0", "rad/s", "wave peak (encounter) frequency w_0 of the wave-yaw model", 0.8)
        .positive()
        .of_disturbance()
        .at_bound_means("a wave frequency falling to zero: the compass shows no wave yaw the \
            model can place (no waves in the data, or a heading record too short or sampled \
            too coarsely for the wave period), or the wave yaw is slower than the ship's own \
            response; hold w0 at the sea's encounter frequency or estimate it from a longer run"),
    ZETA = c("zeta_w", "-", "relative damping of the wave-yaw model", 0.1)
        .positive()
        .of_disturbance()
        .at_bound_means("a wave-yaw damping falling to zero: the wave yaw is narrow-banded \
            (a swell) or w0 is off; hold zeta_w at a typical 0.05 to 0.2"),
}

/// Which transfer function the compass sees from the wave states.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaveForm {
    /// Fossen's linear wave-yaw model, K_w s / (s^2 + 2 zeta w0 s + w0^2): the compass
    /// measures psi_L + psi_H (the default).
    #[default]
    Fossen,
    /// The paper's state equations as printed, K_w / (s^2 + 2 zeta w0 s + w0^2): the compass
    /// measures psi_L + xi.
    Paper,
}

#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ParticularsIn {
    #[serde(default)]
    wave_model: Option<WaveForm>,
}

/// The Nomoto ship with its wave-yaw states.
#[derive(Debug, Clone)]
pub struct NomotoWave {
    /// The wave model the compass sees.
    pub form: WaveForm,
    relations: CompiledRelations,
}

const STATES: &[StateDef] = &[
    StateDef {
        name: "r_L",
        quantity: Quantity::R,
    },
    StateDef {
        name: "psi_L",
        quantity: Quantity::Yaw,
    },
    StateDef {
        name: "xi",
        quantity: Quantity::WaveYawIntegral,
    },
    StateDef {
        name: "psi_H",
        quantity: Quantity::WaveYaw,
    },
];

const OUTPUTS: &[OutputDef] = &[
    OutputDef {
        name: "compass",
        quantity: Quantity::Yaw,
    },
    OutputDef {
        name: "gyro",
        quantity: Quantity::R,
    },
];

impl NomotoWave {
    /// The wave-yaw rate psi_H_dot (Fossen 2011, 8.2.1, without the white noise).
    fn wave_rate<T: Scalar>(x: &[T], c: &[T]) -> T {
        let w0 = c[W0];
        -(w0 * w0) * x[2] - w0 * c[ZETA] * x[3] * 2.0
    }
}

impl Model for NomotoWave {
    const NAME: &'static str = "nomoto_wave";
    const DESCRIPTION: &'static str = "course keeping in waves: first-order Nomoto steering \
        with a rudder bias and the linear wave-induced yaw a compass sees (Fossen 2011, 7.2 \
        and 8.2.1; Dinh, Hoang & Pham 2016)";
    const COEFFICIENTS: &'static [CoefDef] = COEFFICIENTS;
    const INPUTS: &'static [InputDef] = &[InputDef {
        quantity: Quantity::Rudder,
        rule: InputRule::Hold,
    }];
    const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[];

    fn build(v: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
        let p: ParticularsIn = v.particulars(Self::NAME)?;
        Ok(NomotoWave {
            form: p.wave_model.unwrap_or_default(),
            relations: CompiledRelations::compile(&[], &[]),
        })
    }

    fn states(&self) -> &'static [StateDef] {
        STATES
    }

    fn outputs(&self) -> &'static [OutputDef] {
        OUTPUTS
    }

    fn measure<T: Scalar>(&self, x: &[T], _u: &[f64], c: &[T], y: &mut [T]) {
        let (r, psi, xi, psi_h) = (x[0], x[1], x[2], x[3]);
        match self.form {
            // Fossen 2011, 8.2.1 and 11.3: compass psi_L + psi_H
            WaveForm::Fossen => {
                y[0] = psi + psi_h;
                y[1] = r + Self::wave_rate(x, c);
            }
            // the paper's eq. 25: z = x5 + x7 (x7 = xi here)
            WaveForm::Paper => {
                y[0] = psi + xi;
                y[1] = r + psi_h;
            }
        }
    }

    fn relations(&self) -> &CompiledRelations {
        &self.relations
    }

    fn compared(&self) -> &'static [Quantity] {
        &[Quantity::Yaw]
    }

    fn typical_magnitude(&self, name: &str) -> f64 {
        COEFFICIENTS
            .iter()
            .find(|d| d.name == name)
            .map_or(1.0, |d| match d.size {
                Size::Fixed(v) => v,
                _ => 1.0,
            })
    }

    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]) {
        let r = x[0];
        // T r_dot + r = K (delta - delta_0), written with 1/T as the paper estimates it:
        // r_dot = -r / T + (K / T) (delta - delta_0) (paper eq. 20; Fossen 2011, 7.2)
        dx[0] = (c[K] * (-c[DELTA0] + u[0]) - r) * c[INV_T];
        dx[1] = r;
        // linear wave-yaw model (Fossen 2011, 8.2.1), the white noise left to the filter
        dx[2] = x[3];
        dx[3] = Self::wave_rate(x, c);
    }

    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical> {
        // a filter's 1/T may pass through zero on its way (the equations stay finite there):
        // only non-finite values are an error
        if x.iter().chain(c).any(|v| !v.is_finite()) {
            return Err(Unphysical::NotFinite("state or a coefficient"));
        }
        Ok(())
    }

    /// The wave frequency from the compass: the peak of the heading rate's periodogram between
    /// wave periods of 3 and 30 s (Fossen 2011, 8.2: the peak frequency of the wave-yaw
    /// spectrum), the slow part taken away by a 30 s moving average.
    fn initial_guess(&self, name: &str, runs: &[crate::io::record::Record]) -> Option<f64> {
        if name != "w0" {
            return None;
        }
        let rec = runs.first()?;
        let (t, psi) = (rec.time()?, rec.channel(Quantity::Yaw)?);
        // the peak of the heading RATE's periodogram (backward differences at the interval
        // midpoints): the wave yaw's rate peaks at w0 as its heading does (Fossen 2011, 8.2.1:
        // s^2 / (s^2 + 2 zeta w0 s + w0^2) for small zeta), while the ship's own turning is
        // weighted down by w^2 against it; on the heading itself what a 30 s moving average
        // leaves of a zig-zag's swing outweighs a degree of 5 or 8 s waves, and the peak fell
        // on the band's lower edge
        let (mid, rate): (Vec<f64>, Vec<f64>) = t
            .windows(2)
            .zip(psi.windows(2))
            .filter(|(a, _)| a[1] > a[0])
            // a heading wrapped at +-180 deg steps by a turn, not a rate
            .map(|(a, p)| (0.5 * (a[0] + a[1]), wrap_pi(p[1] - p[0]) / (a[1] - a[0])))
            .unzip();
        let two_pi = 2.0 * std::f64::consts::PI;
        crate::numerics::signal::spectral_peak(&mid, &rate, 30.0, two_pi / 30.0, two_pi / 3.0)
    }

    /// w0 of the wave-yaw model (Fossen 2011, 8.2.1), when positive.
    fn wave_frequency(&self, c: &[f64]) -> Option<f64> {
        (c[W0].is_finite() && c[W0] > 0.0).then_some(c[W0])
    }

    fn nomoto_gains(&self, c: &[f64]) -> Option<Result<(f64, f64), String>> {
        let inv_t = c[INV_T];
        Some(if inv_t > 0.0 && inv_t.is_finite() {
            Ok((c[K], 1.0 / inv_t))
        } else if inv_t == 0.0 {
            Err("1/T = inv_T = 0: no yaw damping (T infinite, the yaw rate grows without \
                 bound under a held rudder): Nomoto's K and T are not defined; a course-stable \
                 ship has inv_T > 0"
                .into())
        } else {
            Err(format!(
                "1/T = inv_T = {inv_t} 1/s is not positive: a course-unstable Nomoto model \
                 (T = {} s), which the pole-placement tuning and the plant's indices do not \
                 take; a course-stable ship has inv_T > 0",
                crate::base::numfmt::num(1.0 / inv_t)
            ))
        })
    }

    fn example_vehicle() -> Vehicle {
        // the frigate of Van Amerongen (1982) at 9 m/s; the model reads only the particulars
        Vehicle {
            mass: 3.0e6,
            length: 120.0,
            diameter: None,
            ixx: None,
            iyy: None,
            izz: 3.0e6 * 30.0 * 30.0,
            reference_area: 120.0 * 4.0,
            buoyancy: None,
            bg: None,
            rho: 1025.0,
            particulars: toml::Table::new(),
        }
    }

    fn example(&self) -> Example {
        Example {
            coefficients: FRIGATE_9MS,
            state: vec![0.005, 0.1, 0.0, 0.0],
            inputs: vec![5f64.to_radians()],
            estimated: &["K"],
            duration: 120.0,
        }
    }
}

/// The frigate of Van Amerongen (1982) at 9 m/s (../shared/data/frigate_nomoto_vanamerongen.csv:
/// K = 0.18 1/s, T = 27 s), a 1 deg rudder bias, waves of 8 s period (w0 = 2 pi / 8) and
/// damping 0.1.
pub const FRIGATE_9MS: &[(&str, f64)] = &[
    ("K", 0.18),
    ("inv_T", 1.0 / 27.0),
    ("delta0", 0.017453292519943295),
    ("w0", std::f64::consts::FRAC_PI_4),
    ("zeta_w", 0.1),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::sim::{simulate, InputSeries};

    fn model(form: &str) -> (NomotoWave, Vec<f64>) {
        let v = Vehicle {
            particulars: toml::toml! { wave_model = form },
            ..NomotoWave::example_vehicle()
        };
        let m = NomotoWave::build(&v).unwrap();
        let c = m.coefficient_vector(FRIGATE_9MS);
        (m, c)
    }

    /// A constant rudder settles at r = K (delta - delta_0) with time constant T.
    #[test]
    fn a_rudder_step_gives_the_nomoto_response() {
        let (m, c) = model("fossen");
        let delta = 5f64.to_radians();
        let times = [0.0, 27.0, 400.0];
        let xs = simulate(
            &m,
            &c,
            &[0.0; 4],
            &InputSeries::constant(&[delta]),
            &times,
            2000,
        )
        .unwrap();
        let steady = 0.18 * (delta - 1f64.to_radians());
        assert!((xs[1][0] / steady - (1.0 - (-1.0f64).exp())).abs() < 1e-6);
        assert!((xs[2][0] / steady - 1.0).abs() < 1e-6);
    }

    /// Free wave-yaw oscillation decays at zeta w0 and swings at w0 sqrt(1 - zeta^2); the
    /// compass sees psi_H in Fossen's form and xi in the paper's.
    #[test]
    fn the_wave_states_oscillate_at_the_wave_frequency_and_each_form_sees_its_own() {
        let (m, c) = model("fossen");
        let wd = std::f64::consts::FRAC_PI_4 * (1.0f64 - 0.01).sqrt();
        let period = 2.0 * std::f64::consts::PI / wd;
        let times = [0.0, period];
        let x0 = [0.0, 0.0, 0.0, 0.02];
        let xs = simulate(&m, &c, &x0, &InputSeries::constant(&[1f64.to_radians()]), &times, 4000)
            .unwrap();
        let decay = (-0.1 * std::f64::consts::FRAC_PI_4 * period).exp();
        assert!((xs[1][3] / 0.02 - decay).abs() < 1e-6, "{}", xs[1][3]);
        let y = m.output_values(&[0.0, 0.3, 0.05, 0.02], &[0.0], &c);
        assert!((y[0] - 0.32).abs() < 1e-12);
        let (paper, c) = model("paper");
        let y = paper.output_values(&[0.0, 0.3, 0.05, 0.02], &[0.0], &c);
        assert!((y[0] - 0.35).abs() < 1e-12 && (y[1] - 0.02).abs() < 1e-12);
    }

    #[test]
    fn an_unknown_wave_model_names_the_key() {
        let v = Vehicle {
            particulars: toml::toml! { wave_model = "pierson" },
            ..NomotoWave::example_vehicle()
        };
        let e = NomotoWave::build(&v).unwrap_err();
        assert!(e.iter().any(|p| p.key.contains("wave_model")), "{e:?}");
    }
}
