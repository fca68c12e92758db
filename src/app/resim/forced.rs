//! The identified model re-simulated with its process noise: the run's initial state and
//! inputs, and after every sample interval a Gaussian increment of variance q dt on each
//! state with a process noise density q (Euler-Maruyama on dx = f dt + sqrt(q) dW; Kloeden &
//! Platen 1992, 9.1), the noise the filter assumed; a state the run gives as a constant is
//! held to it. A parametric bootstrap's replica of a
//! run whose states the filter lets wander (`hydroid calibrate`): the wave-induced yaw of
//! `nomoto_wave`, or the process noise calibrated from a model's misfit.

use super::{integrate, outputs_of, prepared, start_state, trace, Prepared, ResimTrace};
use crate::base::error::{Error, Result};
use crate::io::record::Record;
use crate::model::coefficients::CoefficientSet;
use crate::model::models::{with_model, Model, ModelName, ModelVisitor, RunVehicle};
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// Process noise density (SI^2/s) of a state, given its index and name.
pub type Density<'a> = &'a dyn Fn(usize, &str) -> f64;

/// The model `model` of `vehicle` with the coefficients of `set` along `rec`, forced by the
/// process noise densities `q` gives each state, drawn from `rng`; an error when the
/// simulation stops before the run's end.
pub fn forced(
    model: ModelName,
    vehicle: &RunVehicle,
    set: &CoefficientSet,
    rec: &Record,
    q: Density,
    rng: &mut StdRng,
) -> Result<ResimTrace> {
    with_model(model, vehicle, Forced { set, rec, q, rng }).map_err(Error::vehicle)?
}

struct Forced<'a> {
    set: &'a CoefficientSet,
    rec: &'a Record,
    q: Density<'a>,
    rng: &'a mut StdRng,
}

impl ModelVisitor for Forced<'_> {
    type Output = Result<ResimTrace>;

    fn visit<M: Model>(self, model: &M) -> Self::Output {
        let Prepared { times, c, inputs } = prepared(model, self.set, self.rec)?;
        let x0 = start_state(model, self.rec, &times);
        // a state the run gives as a constant (a straight run's v = 0) is held to it: the
        // filter treats it as measured exactly, and forcing it would let an unstable mode
        // (a body's sway-yaw divergence) carry the replica off the run
        let q: Vec<f64> = (model.states().iter().enumerate())
            .map(
                |(j, s)| match self.rec.constants.contains_key(&s.quantity) {
                    true => 0.0,
                    false => (self.q)(j, s.name),
                },
            )
            .collect();
        let rng = self.rng;
        let mut forcing = |x: &mut [f64], dt: f64| {
            for (xi, qi) in x.iter_mut().zip(&q) {
                if *qi > 0.0 && dt > 0.0 {
                    if let Ok(d) = Normal::new(0.0, (qi * dt).sqrt()) {
                        *xi += d.sample(rng);
                    }
                }
            }
        };
        let (xs, stopped) = integrate(model, &c, x0, &inputs, &times, &mut forcing);
        if let Some(why) = stopped {
            return Err(Error::numerical(
                "calibrate",
                format!(
                    "run '{}': the identified model forced by its process noise stopped: {why}",
                    self.rec.name
                ),
            ));
        }
        let ys = outputs_of(model, &xs, &times, &inputs, &c);
        Ok(trace(model, times, xs, ys))
    }
}
