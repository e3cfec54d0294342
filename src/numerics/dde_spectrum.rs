//! Characteristic roots of a linear delay equation by spectral collocation of its generator.
//!
//! In: a linear autonomous retarded delay differential equation with one delay,
//! ẏ(t) = A₀ y(t) + A₁ y(t − τ), y ∈ ℝᵈ (A₀, A₁: d × d in 1/s, τ > 0 in s), and the number of
//! Chebyshev intervals N. Out: the eigenvalues [1/s] of the discretised generator, the
//! approximations of the characteristic roots λ (det(λI − A₀ − A₁e^{−λτ}) = 0); the solution is
//! stable when every root has Re λ < 0.
//!
//! Method: the infinitesimal generator of the solution semigroup on the history space
//! C([−τ, 0], ℝᵈ) is φ ↦ φ′ with the domain condition φ′(0) = A₀φ(0) + A₁φ(−τ). It is
//! collocated at the N + 1 Chebyshev points θ_j = (τ/2)(cos(jπ/N) − 1), θ₀ = 0, θ_N = −τ
//! (Breda, Maset & Vermiglio, SIAM J. Sci. Comput. 27 (2005) 482–495): the first block row is
//! the domain condition, the others the derivative (2/τ)·D ⊗ I_d with D Trefethen's Chebyshev
//! differentiation matrix (*Spectral Methods in MATLAB*, 2000, `cheb`). The roots of modulus
//! well below N/τ converge spectrally in N; the others are artefacts, so a caller keeps the
//! eigenvalues in a disk it can bound and checks convergence by raising N. Cost: one dense
//! non-symmetric eigenproblem of size d(N + 1) ([`eigen::general`], bounded).

use nalgebra::{Complex, DMatrix};

use super::eigen::{self, EigenError};

/// Most Chebyshev intervals accepted (a matrix of size d·(MAX_INTERVALS + 1)).
pub const MAX_INTERVALS: usize = 1000;

/// Why the spectrum could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DdeError {
    /// A matrix is not d × d or the delay or N is out of range.
    #[error("delay equation: {0}")]
    Input(String),
    /// The eigen-solver failed.
    #[error(transparent)]
    Eigen(#[from] EigenError),
}

/// Chebyshev points x_j = cos(jπ/N), j = 0..N, and the differentiation matrix on them.
pub fn chebyshev(n: usize) -> (Vec<f64>, DMatrix<f64>) {
    let x: Vec<f64> = (0..=n)
        .map(|j| (std::f64::consts::PI * j as f64 / n as f64).cos())
        .collect();
    let c = |j: usize| {
        let end = if j == 0 || j == n { 2.0 } else { 1.0 };
        if j.is_multiple_of(2) {
            end
        } else {
            -end
        }
    };
    let mut d = DMatrix::zeros(n + 1, n + 1);
    for i in 0..=n {
        let mut sum = 0.0;
        for j in (0..=n).filter(|j| *j != i) {
            d[(i, j)] = c(i) / c(j) / (x[i] - x[j]);
            sum += d[(i, j)];
        }
        d[(i, i)] = -sum;
    }
    (x, d)
}

/// The collocated generator, size d(N + 1), of ẏ = A₀ y + A₁ y(t − τ) on N intervals.
pub fn generator(
    a0: &DMatrix<f64>,
    a1: &DMatrix<f64>,
    tau: f64,
    n: usize,
) -> Result<DMatrix<f64>, DdeError> {
    let d = a0.nrows();
    if d == 0 || a0.ncols() != d || a1.nrows() != d || a1.ncols() != d {
        return Err(DdeError::Input(format!(
            "A0 is {}x{} and A1 {}x{}; both must be the same square size",
            a0.nrows(),
            a0.ncols(),
            a1.nrows(),
            a1.ncols()
        )));
    }
    if !(tau.is_finite() && tau > 0.0) {
        return Err(DdeError::Input(format!(
            "the delay must be positive and finite, got {tau} s"
        )));
    }
    if !(1..=MAX_INTERVALS).contains(&n) {
        return Err(DdeError::Input(format!(
            "the number of Chebyshev intervals must be 1..={MAX_INTERVALS}, got {n}"
        )));
    }
    let (_, dm) = chebyshev(n);
    let mut a = DMatrix::zeros(d * (n + 1), d * (n + 1));
    a.view_mut((0, 0), (d, d)).copy_from(a0);
    a.view_mut((0, d * n), (d, d)).copy_from(a1);
    for i in 1..=n {
        for j in 0..=n {
            let v = 2.0 / tau * dm[(i, j)];
            for r in 0..d {
                a[(d * i + r, d * j + r)] = v;
            }
        }
    }
    Ok(a)
}

/// The eigenvalues [1/s] of the collocated generator on N intervals (module doc).
pub fn roots(
    a0: &DMatrix<f64>,
    a1: &DMatrix<f64>,
    tau: f64,
    n: usize,
) -> Result<Vec<Complex<f64>>, DdeError> {
    let a = generator(a0, a1, tau, n)?;
    let (values, _) = eigen::general(&a)?;
    Ok(values.iter().map(|v| Complex::new(v.re, v.im)).collect())
}
