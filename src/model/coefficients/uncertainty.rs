//! Uncertainty as independent directions, and the correlations of jointly estimated
//! coefficients.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Correlation matrix between estimated coefficients.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Correlation {
    /// Coefficient names, in matrix order.
    pub names: Vec<String>,
    /// Row-major correlation matrix.
    pub matrix: Vec<Vec<f64>>,
}

impl Correlation {
    /// The correlations of `names` from their covariance `cov(a, b)`: cov_ab / (sigma_a
    /// sigma_b), within [-1, 1]; 1 on the diagonal and 0 off it for a coefficient without
    /// variance.
    pub fn from_covariance(names: Vec<String>, cov: impl Fn(usize, usize) -> f64) -> Self {
        let n = names.len();
        let sigma: Vec<f64> = (0..n).map(|a| cov(a, a).max(0.0).sqrt()).collect();
        let matrix = (0..n)
            .map(|a| {
                (0..n)
                    .map(|b| {
                        let d = sigma[a] * sigma[b];
                        if d > 0.0 {
                            (cov(a, b) / d).clamp(-1.0, 1.0)
                        } else {
                            f64::from(u8::from(a == b))
                        }
                    })
                    .collect()
            })
            .collect();
        Correlation { names, matrix }
    }

    /// Correlation between two named coefficients, if both are in the matrix.
    pub fn get(&self, a: &str, b: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == a)?;
        let j = self.names.iter().position(|n| n == b)?;
        Some(self.matrix[i][j])
    }
}

/// One independent source of uncertainty: the joint one-sigma change it causes in every
/// coefficient it reaches. A stage's uncertainty is a set of such directions (the
/// eigenvectors of its covariance scaled by the square roots of the eigenvalues), and a
/// later stage adds the change its own estimates undergo along each, so that correlations
/// between stages are carried through the pipeline (linear error propagation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Direction {
    /// What it is, starting with the stage: `polar drag 1`, `surge statistics`, `hekf 3`.
    pub source: String,
    /// One-sigma change of each coefficient it reaches, SI.
    pub deltas: BTreeMap<String, f64>,
}

impl Direction {
    /// The stage a direction comes from (the first word of its source).
    pub fn stage(&self) -> &str {
        self.source.split_whitespace().next().unwrap_or("")
    }
}

/// The directions of a covariance matrix over `names`: eigenvectors scaled by the square
/// roots of the (non-negative) eigenvalues, labelled `label 1`, `label 2`, ...
pub fn directions_of(label: &str, names: &[&str], covariance: &[Vec<f64>]) -> Vec<Direction> {
    let n = names.len();
    if n == 0 {
        return Vec::new();
    }
    let m = nalgebra::DMatrix::from_fn(n, n, |i, j| 0.5 * (covariance[i][j] + covariance[j][i]));
    let top = (0..n).map(|i| m[(i, i)].abs()).fold(0.0f64, f64::max);
    let eig = nalgebra::SymmetricEigen::new(m);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let mut out = Vec::new();
    for k in order {
        let lambda = eig.eigenvalues[k];
        if lambda.is_nan() || lambda <= 1e-14 * top {
            continue;
        }
        let s = lambda.sqrt();
        let deltas = names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.to_string(), s * eig.eigenvectors[(i, k)]))
            .filter(|(_, d)| *d != 0.0)
            .collect();
        out.push(Direction {
            source: format!("{label} {}", out.len() + 1),
            deltas,
        });
    }
    out
}
