//! Craig–Bampton reduction of a large sparse body, with no dense n × n matrix.
//!
//! In: sparse symmetric K and M of a body (SI, [`Sparse`]), optionally its stress stiffening
//! per (rad/s)² K_σ (K(Ω) = K + Ω² K_σ), the interface DOFs B (row indices: the DOFs of the
//! body's attachment nodes) and the number of fixed-interface normal modes.
//! Out: a [`SparseReduction`]: the Craig–Bampton matrices K̂ and M̂ (and K̂_σ on the same
//! standstill basis, as the dense path projects it: exact as far as the basis spans the
//! stiffened shapes) (dense, (|B| + n) square,
//! coordinates the interface DOFs in the order given, then the normal modes), the
//! fixed-interface frequencies [Hz], the frequencies of the reduced body (free at its
//! interface) [Hz], and the time each step took; or a [`ReductionError`].
//! Method (physics.md §3, as [`super::reduction::craig_bampton`] but sparse): interior I = the
//! other DOFs; one sparse Cholesky factor of K_II ([`Sparse::cholesky`]) gives the constraint
//! modes Ψ = −K_II⁻¹ K_IB (n_I × |B|, dense) and drives the shift-invert Lanczos solver for the
//! lowest fixed-interface modes K_II Φ = M_II Φ Ω² ([`lanczos::lowest`]); with T_I = [Ψ Φ] and
//! T_B = [I 0], K̂ = T_Bᵀ K_BB T_B + T_Bᵀ K_BI T_I + T_Iᵀ K_IB T_B + T_Iᵀ K_II T_I (M̂, K̂_σ alike)
//! from sparse × tall products; the reduced problem's eigenvalues by the dense solver
//! ([`eigen::generalized_symmetric`]). Memory: the factor's fill, the Lanczos basis and T_I
//! (n_I × (|B| + n)); time: the factorisation, |B| + (Lanczos steps) solves, and the products.
//! [`body_modes`]: the lowest modes of the whole body, free or held by its own K, by the same
//! solver on a factor of K − σM, σ < 0 (the full model's own modes, not the reduced ones).

use std::time::Instant;

use faer::Mat;
use nalgebra::DMatrix;

use super::reduction::ReductionError;
use crate::numerics::eigen;
use crate::numerics::lanczos;
use crate::numerics::sparse::Sparse;

/// The reduced body (module doc).
#[derive(Debug, Clone)]
pub struct SparseReduction {
    /// K̂ [SI], interface DOFs then normal modes.
    pub k: DMatrix<f64>,
    /// M̂ [SI].
    pub m: DMatrix<f64>,
    /// K̂_σ = Tᵀ K_σ T, the stress stiffening per (rad/s)² on the same basis, when given.
    pub ks: Option<DMatrix<f64>>,
    /// Fixed-interface normal-mode frequencies [Hz], ascending.
    pub fixed_hz: Vec<f64>,
    /// Frequencies of the reduced body, free at its interface [Hz], ascending (rigid-body
    /// modes near zero; a negative eigenvalue's frequency as 0).
    pub free_hz: Vec<f64>,
    /// Seconds spent: blocks, factorisation, constraint modes, normal modes, projection,
    /// reduced eigenproblem.
    pub seconds: [f64; 6],
    /// With `keep_basis`: the interior DOFs I (ascending) and T_I = [Ψ Φ] (|I| × (|B| + n)),
    /// the interior rows of the Craig–Bampton basis.
    pub basis: Option<(Vec<usize>, Mat<f64>)>,
}

fn hz(lambda: f64) -> f64 {
    lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// T̂ᵀ A T̂ for T = [[I 0], [T_I]] over the interface (first) and interior rows.
fn project(a_ii: &Sparse, a_ib: &Mat<f64>, a_bb: &Mat<f64>, t_i: &Mat<f64>) -> DMatrix<f64> {
    let nb = a_bb.nrows();
    let mut y = a_ii.mul(t_i);
    for c in 0..nb {
        for r in 0..y.nrows() {
            y[(r, c)] += a_ib[(r, c)];
        }
    }
    let mut out = t_i.transpose() * &y;
    let top = a_ib.transpose() * t_i;
    for r in 0..nb {
        for c in 0..out.ncols() {
            out[(r, c)] += top[(r, c)];
        }
        for c in 0..nb {
            out[(r, c)] += a_bb[(r, c)];
        }
    }
    let n = out.nrows();
    DMatrix::from_fn(n, n, |i, j| 0.5 * (out[(i, j)] + out[(j, i)]))
}

/// The shift of [`body_modes`] [Hz]: σ = −(2π · 1 Hz)², below the rigid-body (or a supported
/// body's free spin) modes' λ = 0, so the factor of K − σM exists for a free body, and far below
/// any elastic mode.
pub const BODY_SHIFT_HZ: f64 = 1.0;

/// The lowest `count` modes of the whole body (K, M), free at every DOF unless K holds it:
/// λ ascending [rad²/s²] and M-normalised shapes, by the shift-invert Lanczos solver on one
/// sparse Cholesky factor of K − σM with σ = −(2π [`BODY_SHIFT_HZ`])². Rigid-body modes come
/// out near 0.
pub fn body_modes(k: &Sparse, m: &Sparse, count: usize) -> Result<lanczos::Modes, ReductionError> {
    if count > k.n() {
        return Err(ReductionError::TooManyBodyModes {
            asked: count,
            available: k.n(),
        });
    }
    let shift = -(2.0 * std::f64::consts::PI * BODY_SHIFT_HZ).powi(2);
    let factor = k
        .plus_scaled(m, -shift)
        .cholesky()
        .ok_or(ReductionError::ShiftedSingular(BODY_SHIFT_HZ))?;
    Ok(lanczos::lowest(k, &factor, m, shift, count)?)
}

/// The Craig–Bampton reduction of (K, M) at `boundary` with `n_normal` normal modes (module
/// doc); with `keep_basis` it also returns the basis' interior rows.
pub fn craig_bampton(
    k: &Sparse,
    m: &Sparse,
    stress: Option<&Sparse>,
    boundary: &[usize],
    n_normal: usize,
    keep_basis: bool,
) -> Result<SparseReduction, ReductionError> {
    let mut seconds = [0.0; 6];
    let mut clock = Instant::now();
    let mut lap = |i: usize, seconds: &mut [f64; 6]| {
        seconds[i] = clock.elapsed().as_secs_f64();
        clock = Instant::now();
    };
    let n = k.n();
    let mut is_b = vec![false; n];
    for &b in boundary {
        is_b[b] = true;
    }
    let int: Vec<usize> = (0..n).filter(|&i| !is_b[i]).collect();
    if n_normal > int.len() {
        return Err(ReductionError::TooManyModes {
            asked: n_normal,
            available: int.len(),
        });
    }
    let nb = boundary.len();
    let k_ii = k.block(&int, &int).into_square();
    let m_ii = m.block(&int, &int).into_square();
    let k_ib = k.block(&int, boundary).to_dense();
    let m_ib = m.block(&int, boundary).to_dense();
    let k_bb = k.block(boundary, boundary).to_dense();
    let m_bb = m.block(boundary, boundary).to_dense();
    lap(0, &mut seconds);
    let factor = k_ii.cholesky().ok_or(ReductionError::InteriorSingular)?;
    lap(1, &mut seconds);
    let mut t_i = Mat::zeros(int.len(), nb + n_normal);
    let mut psi = k_ib.clone();
    factor.solve_in_place(&mut psi);
    for c in 0..nb {
        for r in 0..int.len() {
            t_i[(r, c)] = -psi[(r, c)];
        }
    }
    drop(psi);
    lap(2, &mut seconds);
    let normal = lanczos::lowest(&k_ii, &factor, &m_ii, 0.0, n_normal)?;
    for c in 0..n_normal {
        for r in 0..int.len() {
            t_i[(r, nb + c)] = normal.vectors[(r, c)];
        }
    }
    drop(factor);
    lap(3, &mut seconds);
    let kh = project(&k_ii, &k_ib, &k_bb, &t_i);
    let mh = project(&m_ii, &m_ib, &m_bb, &t_i);
    let ks = stress.map(|a| {
        let a_ii = a.block(&int, &int).into_square();
        let a_ib = a.block(&int, boundary).to_dense();
        let a_bb = a.block(boundary, boundary).to_dense();
        project(&a_ii, &a_ib, &a_bb, &t_i)
    });
    lap(4, &mut seconds);
    let red = eigen::generalized_symmetric(&kh, &mh)?;
    lap(5, &mut seconds);
    Ok(SparseReduction {
        fixed_hz: normal.values.iter().map(|&l| hz(l)).collect(),
        free_hz: red.values.iter().map(|&l| hz(l)).collect(),
        k: kh,
        m: mh,
        ks,
        seconds,
        basis: keep_basis.then_some((int, t_i)),
    })
}
