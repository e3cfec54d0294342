//! Dense eigen-solvers for the model's matrices.
//!
//! In: symmetric K and symmetric positive-definite M (any consistent units), or a real
//! non-symmetric state matrix.
//! Out: eigenvalues ascending with M-normalised eigenvectors (φᵀMφ = 1), or complex eigenpairs.
//!
//! Every solve is bounded: a matrix with a non-finite entry is refused before any iteration,
//! and the non-symmetric problem ([`general`]) runs faer's unblocked double-shift QR (LAPACK's
//! `lahqr`: at most 30·max(10, n) sweeps, then an error). faer's blocked multishift path with
//! aggressive early deflation (taken by default from n = 75) looped without end on the state
//! matrix of a hollow roll with a free axial rigid-body mode and on a model with E = 1e30 Pa
//! (its deflation window's bubble sort of the Schur blocks has no bound). The matrix is first
//! balanced, as LAPACK's `dgeev` does (`gebal`'s diagonal scaling by powers of two, at most
//! [`BALANCE_SWEEPS`] sweeps: a state matrix's position and velocity blocks differ by ω², and
//! unbalanced the small eigenvalues lose relative accuracy); when that QR does not converge the
//! unbalanced matrix is solved once more; a second failure is an error.
//! The generalized problem K φ = λ M φ goes through the Cholesky factor M = L Lᵀ, the standard
//! problem L⁻¹ K L⁻ᵀ y = λ y and φ = L⁻ᵀ y. faer's self-adjoint solver is forced onto its QR
//! path: its divide-and-conquer path (taken by default from n = 128) returned wrong eigenpairs
//! on beam-rotor matrices (`docs/dependencies.md`); [`max_residual`] lets every caller check.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::schur::SchurParams;
use faer::linalg::evd::{
    evd_real, evd_scratch, self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors,
    EvdParams, SelfAdjointEvdParams,
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
    /// A matrix entry is infinite or NaN (a model value out of range).
    #[error("a matrix entry is not finite (a model value out of range)")]
    NotFinite,
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
    if k.iter().chain(m.iter()).any(|x| !x.is_finite()) {
        return Err(EigenError::NotFinite);
    }
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

/// Most balancing sweeps of [`general`]'s fallback.
pub const BALANCE_SWEEPS: usize = 100;

/// Complex eigenvalues and right eigenvectors of a real square matrix, bounded (module doc).
pub fn general(a: &DMatrix<f64>) -> Result<(Vec<faer::c64>, faer::Mat<faer::c64>), EigenError> {
    if a.iter().any(|x| !x.is_finite()) {
        return Err(EigenError::NotFinite);
    }
    let (b, d) = balance(a);
    match real_evd(&to_faer(&b)) {
        Ok((values, mut vectors)) => {
            for (i, di) in d.iter().enumerate() {
                for j in 0..vectors.ncols() {
                    vectors[(i, j)] *= *di;
                }
            }
            Ok((values, vectors))
        }
        Err(_) => real_evd(&to_faer(a)),
    }
}

/// faer's real eigendecomposition on the unblocked QR path (module doc), pairs as complex.
fn real_evd(a: &Mat<f64>) -> Result<(Vec<faer::c64>, Mat<faer::c64>), EigenError> {
    let n = a.nrows();
    let params = Spec::new(EvdParams {
        schur: SchurParams {
            blocking_threshold: usize::MAX,
            ..auto!(f64)
        },
        ..auto!(f64)
    });
    let mut u = Mat::<f64>::zeros(n, n);
    let mut s_re = faer::diag::Diag::<f64>::zeros(n);
    let mut s_im = faer::diag::Diag::<f64>::zeros(n);
    let mut mem = MemBuffer::new(evd_scratch::<f64>(
        n,
        ComputeEigenvectors::No,
        ComputeEigenvectors::Yes,
        Par::Seq,
        params,
    ));
    evd_real(
        a.as_ref(),
        s_re.as_mut(),
        s_im.as_mut(),
        None,
        Some(u.as_mut()),
        Par::Seq,
        MemStack::new(&mut mem),
        params,
    )
    .map_err(|_| EigenError::NoConvergence)?;
    let mut values = Vec::with_capacity(n);
    let mut vectors = Mat::<faer::c64>::zeros(n, n);
    let mut j = 0;
    while j < n {
        if s_im[j] == 0.0 || j + 1 == n {
            values.push(faer::c64::new(s_re[j], 0.0));
            for i in 0..n {
                vectors[(i, j)] = faer::c64::new(u[(i, j)], 0.0);
            }
            j += 1;
        } else {
            values.push(faer::c64::new(s_re[j], s_im[j]));
            values.push(faer::c64::new(s_re[j], -s_im[j]));
            for i in 0..n {
                vectors[(i, j)] = faer::c64::new(u[(i, j)], u[(i, j + 1)]);
                vectors[(i, j + 1)] = faer::c64::new(u[(i, j)], -u[(i, j + 1)]);
            }
            j += 2;
        }
    }
    if values
        .iter()
        .any(|v| !(v.re.is_finite() && v.im.is_finite()))
    {
        return Err(EigenError::NoConvergence);
    }
    Ok((values, vectors))
}

/// LAPACK `gebal`'s scaling: B = D⁻¹ A D with D a diagonal of powers of two that makes each
/// row's and column's off-diagonal 1-norms alike; at most [`BALANCE_SWEEPS`] sweeps. Returns
/// B and D's diagonal (an eigenvector x of B is D x of A).
fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let n = a.nrows();
    let mut b = a.clone();
    let mut d = vec![1.0; n];
    for _ in 0..BALANCE_SWEEPS {
        let mut done = true;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&k| k != i).map(|k| b[(k, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&k| k != i).map(|k| b[(i, k)].abs()).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let mut f = 1.0;
            let (mut cc, mut rr) = (c, r);
            while cc < 0.5 * rr && f < 1e150 {
                f *= 2.0;
                cc *= 2.0;
                rr *= 0.5;
            }
            while cc >= 2.0 * rr && f > 1e-150 {
                f *= 0.5;
                cc *= 0.5;
                rr *= 2.0;
            }
            if cc + rr < 0.95 * (c + r) {
                done = false;
                d[i] *= f;
                for k in 0..n {
                    b[(k, i)] *= f;
                    b[(i, k)] /= f;
                }
            }
        }
        if done {
            break;
        }
    }
    (b, d)
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
    fn general_is_bounded_and_exact_on_a_jordan_block_and_a_wide_scale() {
        // A free mass (a rigid-body mode: a 2 × 2 Jordan block at 0) beside an oscillator
        // ω = 1e15 rad/s, the sizes of a model with E = 1e30 Pa: eigenvalues 0, 0, ±iω
        // (x'' = 0; y'' = −ω² y).
        let w2 = 1e30;
        let mut a = DMatrix::zeros(80, 80);
        for i in 0..40 {
            a[(i, 40 + i)] = 1.0;
            a[(40 + i, i)] = -w2 * (i as f64 / 39.0);
        }
        let (values, _) = general(&a).unwrap();
        let mut im: Vec<f64> = values.iter().map(|v| v.im.abs()).collect();
        im.sort_by(f64::total_cmp);
        assert!(im[0] < 1e3 && im[1] < 1e3, "{:?}", &im[..2]);
        let top = *im.last().unwrap();
        assert!((top / 1e15 - 1.0).abs() < 1e-9, "{top}");
    }

    #[test]
    fn general_refuses_non_finite() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
        assert_eq!(general(&a).unwrap_err(), EigenError::NotFinite);
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
