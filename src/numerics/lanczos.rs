//! The lowest eigenpairs of a large sparse generalized symmetric problem K φ = λ M φ.
//!
//! In: K symmetric and M symmetric positive definite ([`Sparse`]), a shift σ below the lowest
//! eigenvalue (0 for a positive-definite K; negative for a free body, whose rigid-body modes
//! have λ = 0), the Cholesky factor of K − σM ([`Cholesky`]) and how many pairs are wanted.
//! Out: [`Modes`]: the lowest `count` eigenvalues λ = ω² ascending and their M-normalised eigenvectors (φᵀMφ = 1) as the columns of an
//! n × count matrix; or [`EigenError::NoConvergence`]. Units as K and M (λ in rad²/s² for N/m
//! and kg).
//! Method: the spectral-transformation Lanczos method with shift 0 (Ericsson & Ruhe, "The
//! spectral transformation Lanczos method for the numerical solution of large sparse
//! generalized symmetric eigenvalue problems", Math. Comp. 35 (1980) 1251–1268): Lanczos on
//! A = (K − σM)⁻¹M, self-adjoint in the M inner product, whose largest eigenvalues
//! θ = 1/(λ − σ) are the problem's lowest; full reorthogonalisation (two classical Gram–Schmidt passes in the M inner
//! product) every step, so no spurious copies appear. A Ritz pair has converged when its
//! residual estimate |β_j s_{j,i}| ≤ [`TOLERANCE`] θ_i; the check runs every
//! [`CHECK_EVERY`] steps. An invariant subspace (β ≈ 0) is continued from a new start vector
//! M-orthogonal to the basis. Bounded: at most min(n, 6·count + 100) steps, then an error; the
//! returned pairs are checked once more by their backward error |Kφ − λMφ| ≤ [`MAX_RESIDUAL`]
//! (‖K‖₁ + λ‖M‖₁) |φ| (relative to |Kφ| it cannot be small: on a fine beam mesh ‖K‖ is 10¹¹
//! times λ‖M‖, and rounding in Kφ alone is that much larger than Kφ). Cost: per step one solve with the factor, three products with M and O(n j) for the
//! reorthogonalisation; memory n × (steps) for the basis. No dense n × n matrix.

use faer::Mat;
use nalgebra::DMatrix;

use super::eigen::EigenError;
use super::rng::SplitMix64;
use super::sparse::{Cholesky, Sparse};

/// Relative residual estimate of a converged Ritz pair (of A = K⁻¹M).
pub const TOLERANCE: f64 = 1e-12;

/// Steps between convergence checks.
pub const CHECK_EVERY: usize = 5;

/// Largest backward error |Kφ − λMφ| / ((‖K‖₁ + λ‖M‖₁) |φ|) accepted.
pub const MAX_RESIDUAL: f64 = 1e-10;

/// The lowest eigenpairs (module doc).
#[derive(Debug, Clone)]
pub struct Modes {
    /// λ ascending.
    pub values: Vec<f64>,
    /// M-normalised eigenvectors, one per column.
    pub vectors: Mat<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

/// w minus its M-projection on the basis, twice (classical Gram–Schmidt with one repetition).
fn orthogonalise(m: &Sparse, q: &[Vec<f64>], w: &mut [f64]) {
    for _ in 0..2 {
        let z = m.mul_vec(w);
        let c: Vec<f64> = q.iter().map(|qi| dot(qi, &z)).collect();
        for (qi, ci) in q.iter().zip(c) {
            axpy(w, -ci, qi);
        }
    }
}

/// The Ritz values θ (descending) and the tridiagonal's eigenvectors (columns in that order).
fn ritz(alpha: &[f64], beta: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
    let j = alpha.len();
    let t = DMatrix::from_fn(j, j, |r, c| {
        if r == c {
            alpha[r]
        } else if r == c + 1 {
            beta[c]
        } else if c == r + 1 {
            beta[r]
        } else {
            0.0
        }
    });
    let e = t.symmetric_eigen();
    let mut order: Vec<usize> = (0..j).collect();
    order.sort_by(|&a, &b| e.eigenvalues[b].total_cmp(&e.eigenvalues[a]));
    let theta = order.iter().map(|&i| e.eigenvalues[i]).collect();
    let s = DMatrix::from_fn(j, j, |r, c| e.eigenvectors[(r, order[c])]);
    (theta, s)
}

/// The lowest `count` eigenpairs of K φ = λ M φ, `kf` the Cholesky factor of K − `shift` M
/// (module doc).
pub fn lowest(
    k: &Sparse,
    kf: &Cholesky,
    m: &Sparse,
    shift: f64,
    count: usize,
) -> Result<Modes, EigenError> {
    let n = k.n();
    assert!(count <= n, "more eigenpairs than the dimension");
    if count == 0 {
        return Ok(Modes {
            values: Vec::new(),
            vectors: Mat::zeros(n, 0),
        });
    }
    let max_steps = n.min(6 * count + 100);
    let mut rng = SplitMix64::new(0x5eed_1a9c);
    let mut start = |q: &[Vec<f64>]| -> Option<Vec<f64>> {
        let mut v: Vec<f64> = (0..n).map(|_| rng.uniform() - 0.5).collect();
        orthogonalise(m, q, &mut v);
        let norm = dot(&v, &m.mul_vec(&v)).sqrt();
        (norm > 0.0 && norm.is_finite()).then(|| v.iter().map(|x| x / norm).collect())
    };
    let mut q: Vec<Vec<f64>> = vec![start(&[]).ok_or(EigenError::NotFinite)?];
    let mut alpha: Vec<f64> = Vec::new();
    let mut beta: Vec<f64> = Vec::new();
    let (k_norm, m_norm) = (k.norm1(), m.norm1());
    let mut done = None;
    for j in 0..max_steps {
        let mq = m.mul_vec(&q[j]);
        let mut w = kf.solve_vec(&mq);
        if w.iter().any(|x| !x.is_finite()) {
            return Err(EigenError::NotFinite);
        }
        let a = dot(&mq, &w);
        axpy(&mut w, -a, &q[j]);
        if j > 0 {
            axpy(&mut w, -beta[j - 1], &q[j - 1]);
        }
        orthogonalise(m, &q, &mut w);
        let b = dot(&w, &m.mul_vec(&w)).max(0.0).sqrt();
        alpha.push(a);
        let last = j + 1 == max_steps;
        let broke = b <= 1e-13 * a.abs();
        if alpha.len() >= count && ((j + 1) % CHECK_EVERY == 0 || last || broke) {
            let (theta, s) = ritz(&alpha, &beta);
            let converged = (0..count).all(|i| (b * s[(j, i)]).abs() <= TOLERANCE * theta[i]);
            if converged {
                done = Some((theta, s));
                break;
            }
        }
        if last {
            break;
        }
        if broke {
            beta.push(0.0);
            q.push(start(&q).ok_or(EigenError::NoConvergence)?);
        } else {
            beta.push(b);
            q.push(w.iter().map(|x| x / b).collect());
        }
    }
    let (theta, s) = done.ok_or(EigenError::NoConvergence)?;
    let mut vectors = Mat::zeros(n, count);
    let mut values = Vec::with_capacity(count);
    for i in 0..count {
        if theta[i] <= 0.0 {
            return Err(EigenError::NoConvergence);
        }
        let mut x = vec![0.0; n];
        for (kq, qk) in q.iter().enumerate().take(alpha.len()) {
            axpy(&mut x, s[(kq, i)], qk);
        }
        let mx = m.mul_vec(&x);
        let norm = dot(&x, &mx).sqrt();
        let lambda = shift + 1.0 / theta[i];
        let kx = k.mul_vec(&x);
        let r: f64 = kx
            .iter()
            .zip(&mx)
            .map(|(a, b)| (a - lambda * b).powi(2))
            .sum::<f64>()
            .sqrt();
        let bound = MAX_RESIDUAL * (k_norm + lambda.abs() * m_norm) * dot(&x, &x).sqrt();
        if r.is_nan() || r > bound {
            return Err(EigenError::NoConvergence);
        }
        for (row, xi) in x.iter().enumerate() {
            vectors[(row, i)] = xi / norm;
        }
        values.push(lambda);
    }
    Ok(Modes { values, vectors })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fixed_fixed_spring_mass_chain_has_its_closed_form_frequencies() {
        // N equal masses m between N + 1 equal springs k, both ends fixed: K = k tridiag(−1, 2,
        // −1), whose eigenvalues are 4 k sin²(r π / (2 (N + 1))), so ω_r = 2 √(k/m)
        // sin(r π / (2 (N + 1))), r = 1 … N (G. Strang, Computational Science and Engineering
        // (2007), §1.5, the eigenvalues of K_n).
        let (nm, kk, mm) = (2000, 3.0e6, 0.7);
        let mut ke = Vec::new();
        let mut me = Vec::new();
        for i in 0..nm {
            ke.push((i, i, 2.0 * kk));
            me.push((i, i, mm));
            if i + 1 < nm {
                ke.push((i + 1, i, -kk));
                ke.push((i, i + 1, -kk));
            }
        }
        let k = Sparse::from_entries(nm, ke);
        let m = Sparse::from_entries(nm, me);
        let f = k.cholesky().expect("positive definite");
        let modes = lowest(&k, &f, &m, 0.0, 20).expect("converges");
        for (r, l) in modes.values.iter().enumerate() {
            let s = ((r + 1) as f64 * std::f64::consts::PI / (2.0 * (nm + 1) as f64)).sin();
            let exact = 2.0 * (kk / mm).sqrt() * s;
            assert!(
                (l.sqrt() - exact).abs() < 1e-9 * exact,
                "mode {r}: {} vs {exact}",
                l.sqrt()
            );
        }
        let x = &modes.vectors;
        let mx = m.mul(x);
        for i in 0..20 {
            for j in 0..20 {
                let p: f64 = (0..nm).map(|r| x[(r, i)] * mx[(r, j)]).sum();
                assert!((p - f64::from(u8::from(i == j))).abs() < 1e-10);
            }
        }
    }
    #[test]
    fn a_free_free_chain_has_its_closed_form_frequencies_by_a_negative_shift() {
        // N equal masses m joined by N − 1 equal springs k, both ends free: K = k B_N with
        // B_N = tridiag(−1, 2, −1) but 1 in both corners, singular (the rigid translation),
        // whose eigenvalues are 2 − 2 cos(r π / N) = 4 sin²(r π / (2N)), r = 0 … N − 1
        // (G. Strang, Computational Science and Engineering (2007), §1.5, the matrix B_n). K is
        // not positive definite, so the factor is of K − σM with σ = −(2π · 1 Hz)².
        let (nm, kk, mm) = (1500, 3.0e6, 0.7);
        let mut ke = Vec::new();
        for i in 0..nm - 1 {
            ke.push((i, i, kk));
            ke.push((i + 1, i + 1, kk));
            ke.push((i + 1, i, -kk));
            ke.push((i, i + 1, -kk));
        }
        let k = Sparse::from_entries(nm, ke);
        let m = Sparse::from_entries(nm, (0..nm).map(|i| (i, i, mm)).collect());
        assert!(k.cholesky().is_none(), "the free chain's K is singular");
        let shift = -(2.0 * std::f64::consts::PI).powi(2);
        let f = k.plus_scaled(&m, -shift).cholesky().expect("K − σM > 0");
        let modes = lowest(&k, &f, &m, shift, 12).expect("converges");
        assert!(
            modes.values[0].abs() < 1e-6,
            "rigid mode {}",
            modes.values[0]
        );
        for (r, l) in modes.values.iter().enumerate().skip(1) {
            let s = (r as f64 * std::f64::consts::PI / (2.0 * nm as f64)).sin();
            let exact = 2.0 * (kk / mm).sqrt() * s;
            assert!(
                (l.sqrt() - exact).abs() < 1e-9 * exact,
                "mode {r}: {} vs {exact}",
                l.sqrt()
            );
        }
    }
}
