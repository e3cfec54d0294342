//! Correlated samples through a Gaussian copula.
//!
//! In: a correlation matrix R of the sampled parameters (d × d, in `[[sample.parameters]]`
//! order) and unit points u ∈ (0, 1)^d. Out: unit points whose normal scores z = Φ⁻¹(u) are
//! correlated by R: z' = L z with R = L Lᵀ (Cholesky), u' = Φ(z'). The parameters' quantile
//! functions then give each its own marginal, and the normal scores of the samples have
//! correlation R (Nelsen, *An Introduction to Copulas*, 2006, §2.3; the product-moment
//! correlation of the samples themselves is R's for normal marginals). Errors: the reason a
//! matrix is not a correlation matrix (not square, not symmetric, diagonal not 1, an entry
//! outside [−1, 1], not positive definite).

use nalgebra::{Cholesky, DMatrix, Dyn};
use statrs::distribution::{ContinuousCDF, Normal};

/// A Gaussian copula (module doc).
#[derive(Debug, Clone)]
pub struct Copula {
    l: DMatrix<f64>,
}

impl Copula {
    /// The copula of correlation matrix `r` for `d` parameters, or why `r` is not one.
    pub fn new(r: &[Vec<f64>], d: usize) -> Result<Copula, String> {
        if r.len() != d || r.iter().any(|row| row.len() != d) {
            return Err(format!(
                "the correlation matrix must be {d} × {d} (one row and column per sampled \
                 parameter, in order)"
            ));
        }
        for (i, row) in r.iter().enumerate() {
            if row[i] != 1.0 {
                return Err(format!("diagonal entry {} is {}, not 1", i + 1, row[i]));
            }
            for (j, &x) in row.iter().enumerate() {
                if !(-1.0..=1.0).contains(&x) {
                    return Err(format!(
                        "entry ({}, {}) = {x} is outside [-1, 1]",
                        i + 1,
                        j + 1
                    ));
                }
                if x != r[j][i] {
                    return Err(format!(
                        "not symmetric: entry ({}, {}) = {x} but ({}, {}) = {}",
                        i + 1,
                        j + 1,
                        j + 1,
                        i + 1,
                        r[j][i]
                    ));
                }
            }
        }
        let m = DMatrix::from_fn(d, d, |i, j| r[i][j]);
        let chol: Option<Cholesky<f64, Dyn>> = Cholesky::new(m);
        let l = chol
            .map(|c| c.l())
            .filter(|l| (0..d).all(|i| l[(i, i)] > 1e-10))
            .ok_or("the correlation matrix is not positive definite (no Cholesky factor)")?;
        Ok(Copula { l })
    }

    /// The point `u` correlated (module doc).
    pub fn apply(&self, u: &[f64]) -> Vec<f64> {
        let std = Normal::standard();
        let z: Vec<f64> = u.iter().map(|x| std.inverse_cdf(*x)).collect();
        (0..u.len())
            .map(|i| {
                let zi: f64 = (0..=i).map(|k| self.l[(i, k)] * z[k]).sum();
                // Kept inside (0, 1): the quantiles of unbounded distributions are finite there.
                std.cdf(zi)
                    .clamp(f64::MIN_POSITIVE, 1.0 - f64::EPSILON / 2.0)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_positive_definite_is_refused() {
        // Pairwise correlations 0.9, 0.9, −0.9: a valid-looking matrix with a negative
        // eigenvalue (1 − 0.9 − 0.9 … ; det = 1 − 3·0.81 − 2·0.729 < 0).
        let r = vec![
            vec![1.0, 0.9, 0.9],
            vec![0.9, 1.0, -0.9],
            vec![0.9, -0.9, 1.0],
        ];
        assert!(Copula::new(&r, 3)
            .unwrap_err()
            .contains("positive definite"));
        assert!(Copula::new(&[vec![1.0, 0.5], vec![0.4, 1.0]], 2)
            .unwrap_err()
            .contains("symmetric"));
    }
}
