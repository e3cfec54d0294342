//! First-order and total Sobol' indices from a Saltelli design, with bootstrap intervals.
//!
//! In: one output's values on the N rows of the matrices A and B and of each AB_i (A with
//! column i from B) of a Saltelli design (any unit; a row with a non-finite value in any of its
//! matrices is left out), the bootstrap's resample count and seed. Out: per parameter i the
//! first-order index S_i and the total index S_Ti, each with a 95 % percentile-bootstrap
//! interval (rows resampled with replacement, the same rows for every index; Archer, Saltelli &
//! Sobol' 1997), and the rows used.
//!
//! Estimators (Saltelli et al. 2010, *Comput. Phys. Commun.* 181, 259, Table 2): with
//! V = Var of the 2N outputs of A and B,
//!   S_i  = (1/N) Σ_j f(B)_j (f(AB_i)_j − f(A)_j) / V          (their (b), Saltelli 2010)
//!   S_Ti = (1/2N) Σ_j (f(A)_j − f(AB_i)_j)² / V               (their (f), Jansen 1999).
//! The outputs are first centred on the mean of A and B (as SALib does): the first-order sum
//! then does not carry the mean's square as noise (its expectation is unchanged, since
//! E[f(AB_i) − f(A)] = 0). For independent inputs S_i ≤ S_Ti, Σ S_i ≤ 1, and S_i = S_Ti for
//! an additive output; the estimates carry Monte Carlo error of order 1/√N, which the
//! intervals show.

use super::rng::SplitMix64;
use super::sample_statistics::{interval, Estimate};

/// The indices of one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Indices {
    /// First-order index S_i.
    pub first_order: Estimate,
    /// Total index S_Ti.
    pub total: Estimate,
}

/// The indices of every parameter from A, B and the AB_i (module doc) and the rows used;
/// `None` with fewer than 2 usable rows or no variance.
pub fn sobol_indices(
    a: &[f64],
    b: &[f64],
    ab: &[Vec<f64>],
    resamples: usize,
    seed: u64,
) -> Option<(Vec<Indices>, usize)> {
    let rows: Vec<usize> = (0..a.len())
        .filter(|&j| {
            a[j].is_finite()
                && b.get(j).is_some_and(|v| v.is_finite())
                && ab.iter().all(|m| m.get(j).is_some_and(|v| v.is_finite()))
        })
        .collect();
    if rows.len() < 2 {
        return None;
    }
    let point = estimate(a, b, ab, &rows)?;
    let mut rng = SplitMix64::new(seed);
    let d = ab.len();
    let mut boot_first = vec![Vec::with_capacity(resamples); d];
    let mut boot_total = vec![Vec::with_capacity(resamples); d];
    let mut pick = vec![0; rows.len()];
    for _ in 0..resamples {
        for p in pick.iter_mut() {
            *p = rows[(rng.next_u64() % rows.len() as u64) as usize];
        }
        if let Some(e) = estimate(a, b, ab, &pick) {
            for (i, (s, t)) in e.into_iter().enumerate() {
                boot_first[i].push(s);
                boot_total[i].push(t);
            }
        }
    }
    let out = point
        .into_iter()
        .enumerate()
        .map(|(i, (s, t))| Indices {
            first_order: interval(s, &mut boot_first[i]),
            total: interval(t, &mut boot_total[i]),
        })
        .collect();
    Some((out, rows.len()))
}

/// (S_i, S_Ti) of every parameter over the rows `rows` (module doc); `None` without variance.
fn estimate(a: &[f64], b: &[f64], ab: &[Vec<f64>], rows: &[usize]) -> Option<Vec<(f64, f64)>> {
    let n = rows.len() as f64;
    let mean = rows.iter().map(|&j| a[j] + b[j]).sum::<f64>() / (2.0 * n);
    let var = rows
        .iter()
        .map(|&j| (a[j] - mean).powi(2) + (b[j] - mean).powi(2))
        .sum::<f64>()
        / (2.0 * n - 1.0);
    if var.is_nan() || var <= 0.0 {
        return None;
    }
    Some(
        ab.iter()
            .map(|m| {
                let first = rows
                    .iter()
                    .map(|&j| (b[j] - mean) * (m[j] - a[j]))
                    .sum::<f64>()
                    / n;
                let total = rows.iter().map(|&j| (a[j] - m[j]).powi(2)).sum::<f64>() / (2.0 * n);
                (first / var, total / var)
            })
            .collect(),
    )
}
