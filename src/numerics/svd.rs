//! The singular value decomposition with a bounded iteration, for the least-squares solves of
//! the signal stage (line fits, influence-coefficient balancing).
//!
//! In: a dense matrix (f64 or complex). Out: its SVD with U and V, or `None` when the matrix
//! holds a value that is not finite or the iteration has not converged after
//! [`MAX_SWEEPS_PER_SIZE`] × (size + 1) implicit-shift steps. Method: nalgebra's Golub–Kahan
//! SVD with the tolerance nalgebra's own `svd` uses (5 ε); `svd` itself iterates without limit,
//! and a NaN anywhere in the matrix keeps it iterating for ever (a line fit of order 1e308,
//! balancing from NaN amplitudes). A finite matrix converges in a few steps per singular value,
//! so the bound never cuts a solve that would have finished, and the result is nalgebra's
//! `svd`'s to the bit.

use nalgebra::{ComplexField, DMatrix, Dyn, SVD};

/// Implicit-shift steps allowed per singular value (module doc).
pub const MAX_SWEEPS_PER_SIZE: usize = 1000;

/// The SVD of `a` with U and V, or `None` (module doc).
pub fn bounded_svd<T: ComplexField>(a: DMatrix<T>) -> Option<SVD<T, Dyn, Dyn>> {
    if !a.iter().all(|v| v.clone().is_finite()) {
        return None;
    }
    let size = a.nrows().min(a.ncols());
    // nalgebra's own `svd` tolerance, 5 ε (its real field is f64 here).
    let eps: T::RealField = nalgebra::convert(5.0 * f64::EPSILON);
    a.try_svd(true, true, eps, MAX_SWEEPS_PER_SIZE * (size + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matrix_with_nan_has_no_svd_and_a_finite_one_has_nalgebras() {
        let mut a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 3.0, 4.0]);
        let ours = bounded_svd(a.clone()).unwrap();
        let theirs = a.clone().svd(true, true);
        assert_eq!(ours.singular_values, theirs.singular_values);
        a[(0, 1)] = f64::NAN;
        assert!(bounded_svd(a).is_none());
    }
}
