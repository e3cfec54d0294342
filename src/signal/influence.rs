//! Influence-coefficient balancing (the workshop method: a reference run, one trial-mass run
//! per plane, least-squares corrections over several planes and speeds at once).
//!
//! In: per measurement row r (a speed, sensor and direction) the complex 1× of the reference
//! run b_r [µm] and of each plane's trial run [µm], and each trial mass as a complex unbalance
//! U_p = m_p e^{iφ_p} [g] (mass at the plane's radius, body angle φ, the scene's convention);
//! optional constraints per plane: the angles a mass may sit at (bolt holes), a maximum mass.
//! Out: the influence coefficients α_rp = (A_rp − b_r)/U_p [µm/g] (response per gram at angle
//! 0), the corrections W_p = m e^{iφ} [g] minimising Σ_r |b_r + Σ_p α_rp W_p|², and the
//! predicted residual per row.
//!
//! Method: the response of a linear rotor is linear in the complex unbalance, so one trial per
//! plane identifies that plane's column. Without constraints W is the least-squares solution
//! (SVD, minimum norm when planes cannot be told apart). With constraints the problem stays a
//! convex quadratic over a convex set — free-angle planes: |W_p| ≤ M (a disc); hole planes:
//! W_p = Σ_j m_j e^{iφ_j} with m_j ≥ 0, Σ m_j ≤ M — solved by accelerated projected gradient
//! (FISTA, step 1/L with L the largest eigenvalue of the real-stacked normal matrix) to a
//! relative change below 1e-12 or 200 000 iterations; deterministic. Hole masses carry a small
//! cost (1e-5 of the largest initial gradient per gram; it biases the masses by about 1e-5), so that of equally good fits (masses
//! in opposite holes cancel) the lightest is found.

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;

use crate::numerics::svd::bounded_svd;

/// Constraints of one balancing plane.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlaneLimits {
    /// The angles [rad] a mass may sit at; empty: any angle.
    pub angles: Vec<f64>,
    /// The largest mass [g] in the plane (the sum over its holes); `None`: no limit.
    pub max_mass: Option<f64>,
}

/// The influence matrix [rows × planes] from the reference 1× `reference` [rows], the trial
/// runs' 1× `trials` [planes][rows] and the trial unbalances `trial_masses` [planes][rows]
/// (g e^{iφ}; a plane may use another trial mass at each speed).
pub fn influence(
    reference: &[Complex64],
    trials: &[Vec<Complex64>],
    trial_masses: &[Vec<Complex64>],
) -> DMatrix<Complex64> {
    DMatrix::from_fn(reference.len(), trials.len(), |r, p| {
        (trials[p][r] - reference[r]) / trial_masses[p][r]
    })
}

/// The least-squares corrections for `alpha` and `reference` under `limits` (one per plane;
/// module doc): per plane its masses (mass [g], angle [rad] in [0, 2π)) — one for a free
/// angle, one per used hole (masses below 1e-9 g left out) for a plane with holes; one NaN mass
/// per plane when a coefficient or reference value is not finite.
pub fn corrections(
    alpha: &DMatrix<Complex64>,
    reference: &[Complex64],
    limits: &[PlaneLimits],
) -> Vec<Vec<(f64, f64)>> {
    let tau = std::f64::consts::TAU;
    // A coefficient or reference that is not finite has no corrections (the SVD and the
    // eigenvalues below would iterate for ever on it): NaN, which the caller reports.
    if !(alpha.iter().all(|z| z.is_finite()) && reference.iter().all(|z| z.is_finite())) {
        return limits.iter().map(|_| vec![(f64::NAN, f64::NAN)]).collect();
    }
    let polar = |w: Complex64| vec![(w.norm(), w.arg().rem_euclid(tau))];
    let b = DVector::from_column_slice(reference);
    let free = limits
        .iter()
        .all(|l| l.angles.is_empty() && l.max_mass.is_none());
    if free {
        // No SVD (a coefficient that is not finite): NaN corrections, which the caller reports.
        let w = match bounded_svd(alpha.clone()) {
            Some(svd) => svd
                .solve(&(-b), 1e-12 * alpha.norm())
                .unwrap_or_else(|_| DVector::zeros(alpha.ncols())),
            None => DVector::from_element(alpha.ncols(), Complex64::new(f64::NAN, f64::NAN)),
        };
        return w.iter().map(|z| polar(*z)).collect();
    }
    let x = constrained(alpha, &b, limits);
    let mut out = Vec::new();
    let mut at = 0;
    for l in limits {
        out.push(if l.angles.is_empty() {
            polar(Complex64::new(x[at], x[at + 1]))
        } else {
            l.angles
                .iter()
                .enumerate()
                .filter(|(j, _)| x[at + j] > 1e-9)
                .map(|(j, a)| (x[at + j], a.rem_euclid(tau)))
                .collect()
        });
        at += unknowns(l);
    }
    out
}

/// The predicted 1× after the corrections: b + α W per row.
pub fn predicted(
    alpha: &DMatrix<Complex64>,
    reference: &[Complex64],
    w: &[Complex64],
) -> Vec<Complex64> {
    let wv = DVector::from_column_slice(w);
    let aw = alpha * wv;
    reference
        .iter()
        .zip(aw.iter())
        .map(|(b, a)| b + a)
        .collect()
}

/// The real unknowns of one plane: two (Re, Im) for a free angle, one mass per hole.
fn unknowns(l: &PlaneLimits) -> usize {
    if l.angles.is_empty() {
        2
    } else {
        l.angles.len()
    }
}

/// Projects one plane's unknowns onto its feasible set.
fn project(l: &PlaneLimits, x: &mut [f64]) {
    if l.angles.is_empty() {
        if let Some(m) = l.max_mass {
            let r = x[0].hypot(x[1]);
            if r > m {
                x[0] *= m / r;
                x[1] *= m / r;
            }
        }
        return;
    }
    x.iter_mut().for_each(|v| *v = v.max(0.0));
    if let Some(m) = l.max_mass {
        if x.iter().sum::<f64>() > m {
            // Projection onto the simplex {x ≥ 0, Σx = m} (Duchi et al. 2008): sort, find θ.
            let mut s: Vec<f64> = x.to_vec();
            s.sort_by(|a, b| b.total_cmp(a));
            let (mut acc, mut theta) = (0.0, 0.0);
            for (i, v) in s.iter().enumerate() {
                acc += v;
                let t = (acc - m) / (i + 1) as f64;
                if v - t > 0.0 {
                    theta = t;
                }
            }
            x.iter_mut().for_each(|v| *v = (*v - theta).max(0.0));
        }
    }
}

/// The constrained problem's real unknowns (module doc), plane after plane.
fn constrained(
    alpha: &DMatrix<Complex64>,
    b: &DVector<Complex64>,
    limits: &[PlaneLimits],
) -> DVector<f64> {
    let rows = alpha.nrows();
    let n: usize = limits.iter().map(unknowns).sum();
    // Real-stacked linear map x → b + G x, G [2 rows × n].
    let mut g = DMatrix::<f64>::zeros(2 * rows, n);
    let mut col = 0;
    for (p, l) in limits.iter().enumerate() {
        let dirs: Vec<Complex64> = if l.angles.is_empty() {
            vec![Complex64::new(1.0, 0.0), Complex64::new(0.0, 1.0)]
        } else {
            l.angles
                .iter()
                .map(|a| Complex64::from_polar(1.0, *a))
                .collect()
        };
        for d in dirs {
            for r in 0..rows {
                let z = alpha[(r, p)] * d;
                g[(2 * r, col)] = z.re;
                g[(2 * r + 1, col)] = z.im;
            }
            col += 1;
        }
    }
    let bb = DVector::from_fn(
        2 * rows,
        |i, _| if i % 2 == 0 { b[i / 2].re } else { b[i / 2].im },
    );
    let h = g.transpose() * &g;
    let mut gb = g.transpose() * &bb;
    // Among equally good hole masses (opposite holes cancel each other) the lightest: a cost of
    // 1e-5 × the largest initial gradient per gram of hole mass.
    let lambda = 1e-5 * gb.amax();
    let mut at = 0;
    for l in limits {
        let k = unknowns(l);
        if !l.angles.is_empty() {
            gb.rows_mut(at, k).add_scalar_mut(lambda);
        }
        at += k;
    }
    let lip = h.symmetric_eigenvalues().max().max(1e-300);
    let mut x = DVector::<f64>::zeros(n);
    let mut y = x.clone();
    let mut t = 1.0f64;
    let proj = |v: &mut DVector<f64>| {
        let mut at = 0;
        for l in limits {
            let k = unknowns(l);
            project(l, &mut v.as_mut_slice()[at..at + k]);
            at += k;
        }
    };
    for _ in 0..200_000 {
        let grad = &h * &y + &gb;
        let mut xn = &y - grad / lip;
        proj(&mut xn);
        let tn = 0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt());
        let step = (&xn - &x).norm();
        y = &xn + (&xn - &x) * ((t - 1.0) / tn);
        let done = step <= 1e-12 * xn.norm().max(1e-30);
        x = xn;
        t = tn;
        if done {
            break;
        }
    }
    x
}

/// The unbalance [g e^{iφ}] of a plane's masses (mass [g], angle [rad]).
pub fn unbalance(masses: &[(f64, f64)]) -> Complex64 {
    masses
        .iter()
        .map(|(m, a)| Complex64::from_polar(*m, *a))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    #[test]
    fn exact_influence_gives_exact_corrections_and_zero_residual() {
        // Two planes, four rows: b = −α W* for W* = (30 g at 40°, 12 g at 200°); α read back from
        // trial runs of 50 g at 0° and 20 g at 90°. The solution is W*, the residual zero.
        let alpha = DMatrix::from_row_slice(
            4,
            2,
            &[
                c(1.0, 0.2),
                c(0.1, -0.3),
                c(0.4, 0.9),
                c(-0.2, 0.5),
                c(0.05, 0.0),
                c(1.5, 0.1),
                c(0.7, -0.7),
                c(0.3, 0.3),
            ],
        );
        let w_true = [
            Complex64::from_polar(30.0, 40f64.to_radians()),
            Complex64::from_polar(12.0, 200f64.to_radians()),
        ];
        let b: Vec<Complex64> = (0..4)
            .map(|r| -(alpha[(r, 0)] * w_true[0] + alpha[(r, 1)] * w_true[1]))
            .collect();
        let u = [c(50.0, 0.0), c(0.0, 20.0)];
        let trials: Vec<Vec<Complex64>> = (0..2)
            .map(|p| (0..4).map(|r| b[r] + alpha[(r, p)] * u[p]).collect())
            .collect();
        let units: Vec<Vec<Complex64>> = u.iter().map(|x| vec![*x; 4]).collect();
        let a = influence(&b, &trials, &units);
        assert!((&a - &alpha).norm() < 1e-12);
        let w: Vec<Complex64> =
            corrections(&a, &b, &[PlaneLimits::default(), PlaneLimits::default()])
                .iter()
                .map(|m| unbalance(m))
                .collect();
        for (x, y) in w.iter().zip(&w_true) {
            assert!((x - y).norm() < 1e-9, "{x} {y}");
        }
        assert!(predicted(&a, &b, &w).iter().all(|z| z.norm() < 1e-9));
        // The same with free angles but a limit above the solution: the constrained solver
        // lands on it too.
        let lim = PlaneLimits {
            angles: vec![],
            max_mass: Some(100.0),
        };
        let w2 = corrections(&a, &b, &[lim.clone(), lim]);
        for (x, y) in w2.iter().zip(&w_true) {
            assert!((unbalance(x) - y).norm() < 1e-6, "{x:?} {y}");
        }
    }

    #[test]
    fn a_mass_limit_and_holes_are_kept() {
        // One plane, one row, α = 1: the correction must cancel b = −(30 g at 45°).
        let alpha = DMatrix::from_element(1, 1, c(1.0, 0.0));
        let b = [-Complex64::from_polar(30.0, 45f64.to_radians())];
        // At most 10 g: 10 g at 45° (the disc's nearest point).
        let w = corrections(
            &alpha,
            &b,
            &[PlaneLimits {
                angles: vec![],
                max_mass: Some(10.0),
            }],
        );
        assert!((unbalance(&w[0]) - Complex64::from_polar(10.0, 45f64.to_radians())).norm() < 1e-6);
        // Holes at 0° and 90° only: 30 g at 45° = 21.21 g at 0° + 21.21 g at 90° (the classic
        // split onto the bracketing holes, m = 30 sin 45° / sin 90°), exact but for that bias.
        let holes = vec![0.0, std::f64::consts::FRAC_PI_2];
        let w = corrections(
            &alpha,
            &b,
            &[PlaneLimits {
                angles: holes.clone(),
                max_mass: None,
            }],
        );
        // (The small cost on hole mass, module doc, biases them by ~1e-5: within 1 mg.)
        assert!((unbalance(&w[0]) + b[0]).norm() < 1e-3, "{:?}", w[0]);
        assert_eq!(w[0].len(), 2);
        let m = 30.0 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(w[0].iter().all(|(g, _)| (g - m).abs() < 1e-3), "{:?}", w[0]);
        // Holes at 0° and 180° cannot make 45°: the best is the 0° hole's share, 30 cos 45°.
        let w = corrections(
            &alpha,
            &b,
            &[PlaneLimits {
                angles: vec![0.0, std::f64::consts::PI],
                max_mass: None,
            }],
        );
        assert_eq!(w[0].len(), 1, "{:?}", w[0]);
        assert!(
            (w[0][0].0 - m).abs() < 1e-3 && w[0][0].1.abs() < 1e-12,
            "{:?}",
            w[0]
        );
    }
}
