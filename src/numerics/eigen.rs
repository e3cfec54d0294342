//! Dense eigen-solvers for the model's matrices.
//!
//! In: symmetric K and symmetric positive-definite M (any consistent units), or a real
//! non-symmetric state matrix.
//! Out: eigenvalues ascending with M-normalised eigenvectors (φᵀMφ = 1), or complex eigenpairs.
//!
//! The generalized problem K φ = λ M φ goes through the Cholesky factor M = L Lᵀ, the standard
//! problem L⁻¹ K L⁻ᵀ y = λ y and φ = L⁻ᵀ y. faer's self-adjoint solver is forced onto its QR
//! path: its divide-and-conquer path (taken by default from n = 128) returned wrong eigenpairs
//! on beam-rotor matrices (`docs/dependencies.md`); [`max_residual`] lets every caller check.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{
    self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors, SelfAdjointEvdParams,
};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{auto, Mat, Par, Side, Spec};
use nalgebra::{DMatrix, DVector};

/// Why an eigen-solution failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EigenError {
    /// M is not positive definite (a DOF without mass, or a negative mass).
    #[error("the mass matrix is not positive definite")]
    MassNotPositiveDefinite,
    /// The iterative solver did not converge.
    #[error("the eigen-solver did not converge")]
    NoConvergence,
}

/// Eigenvalues (ascending) and M-normalised eigenvectors (columns).
#[derive(Debug, Clone)]
pub struct Eigen {
    /// λ = ω² [rad²/s² for K in N/m and M in kg].
    pub values: DVector<f64>,
    /// Columns φ_i with φ_iᵀ M φ_i = 1.
    pub vectors: DMatrix<f64>,
}

fn to_faer(a: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

fn from_faer(a: faer::MatRef<'_, f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// Solves K φ = λ M φ for all eigenpairs.
pub fn generalized_symmetric(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Result<Eigen, EigenError> {
    let n = k.nrows();
    let llt = to_faer(m)
        .llt(Side::Lower)
        .map_err(|_| EigenError::MassNotPositiveDefinite)?;
    let l = llt.L();
    // A = L⁻¹ K L⁻ᵀ = L⁻¹ (L⁻¹ K)ᵀ since K is symmetric.
    let mut x = to_faer(k);
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    let mut a = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let params = Spec::new(SelfAdjointEvdParams {
        recursion_threshold: usize::MAX,
        ..auto!(f64)
    });
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        Par::Seq,
        params,
    ));
    self_adjoint_evd(
        a.as_ref(),
        s.as_mut(),
        Some(u.as_mut()),
        Par::Seq,
        MemStack::new(&mut mem),
        params,
    )
    .map_err(|_| EigenError::NoConvergence)?;
    solve_upper_triangular_in_place(l.transpose(), u.as_mut(), Par::Seq);
    Ok(Eigen {
        values: DVector::from_fn(n, |i, _| s[i]),
        vectors: from_faer(u.as_ref()),
    })
}

/// Largest backward error max_i |K φ_i − λ_i M φ_i| / ((‖K‖ + |λ_i| ‖M‖) ‖φ_i‖) over the
/// first `count` pairs (Frobenius norms): round-off level for a correct solver, O(1) for a wrong
/// eigenpair, and meaningful for zero eigenvalues too.
pub fn max_residual(k: &DMatrix<f64>, m: &DMatrix<f64>, eig: &Eigen, count: usize) -> f64 {
    let (nk, nm) = (k.norm(), m.norm());
    (0..count.min(eig.values.len()))
        .map(|i| {
            let phi = eig.vectors.column(i);
            let lam = eig.values[i];
            (k * phi - lam * (m * phi)).norm() / ((nk + lam.abs() * nm) * phi.norm())
        })
        .fold(0.0, f64::max)
}

/// Complex eigenvalues and right eigenvectors of a real square matrix.
pub fn general(a: &DMatrix<f64>) -> Result<(Vec<faer::c64>, faer::Mat<faer::c64>), EigenError> {
    let evd = to_faer(a).eigen().map_err(|_| EigenError::NoConvergence)?;
    let n = a.nrows();
    let values = (0..n).map(|i| evd.S()[i]).collect();
    Ok((values, evd.U().to_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_mass_chain_matches_closed_form() {
        // Fixed–free chain of n equal masses m and springs k:
        // ω_j² = 4k/m sin²((2j−1)π/(2(2n+1))), j = 1..n (standard closed form).
        let (n, kk, mm) = (200, 3.0e6, 2.0);
        let k = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                if i == n - 1 {
                    kk
                } else {
                    2.0 * kk
                }
            } else if i.abs_diff(j) == 1 {
                -kk
            } else {
                0.0
            }
        });
        let m = DMatrix::identity(n, n) * mm;
        let eig = generalized_symmetric(&k, &m).unwrap();
        for j in 1..=n {
            let s = ((2 * j - 1) as f64 * std::f64::consts::PI / (2.0 * (2 * n + 1) as f64)).sin();
            let exact = 4.0 * kk / mm * s * s;
            assert!((eig.values[j - 1] / exact - 1.0).abs() < 1e-9, "mode {j}");
        }
        let res = max_residual(&k, &m, &eig, n);
        assert!(res < 1e-13, "residual {res}");
        let gram = eig.vectors.transpose() * &m * &eig.vectors;
        assert!((gram - DMatrix::identity(n, n)).amax() < 1e-10);
    }

    #[test]
    fn indefinite_mass_is_an_error() {
        let k = DMatrix::identity(2, 2);
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
        assert_eq!(
            generalized_symmetric(&k, &m).unwrap_err(),
            EigenError::MassNotPositiveDefinite
        );
    }
}
