//! Seeded measurement noise: independent Gaussian samples added to a series, shared by the
//! synthetic exports (`hydroid simulate`) and the replicas of `hydroid calibrate`.

use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// Adds independent N(0, sigma^2) samples from `rng` to each of `values`; the error says why
/// `sigma` is not a standard deviation (not finite).
pub fn add_gaussian(values: &mut [f64], sigma: f64, rng: &mut StdRng) -> Result<(), String> {
    let dist = Normal::new(0.0, sigma.abs()).map_err(|e| format!("noise sigma {sigma}: {e}"))?;
    for v in values.iter_mut() {
        *v += dist.sample(rng);
    }
    Ok(())
}
