//! Which BDF orders are stable for a system's modes at a step size.
//!
//! In: the eigenvalues λ of the system linearised at the start (M λ² + C λ + K = 0 from the
//! problem's mass and Newton matrices), a step h and an order k. Out: whether every mode's hλ
//! lies where BDF-k does not amplify it.
//!
//! Why: BDF 1 and 2 are A-stable, BDF 3–5 only A(α)-stable (α = 86.0°, 73.4°, 51.8°). Beside the
//! imaginary axis each has a lobe of the left half-plane where a decaying mode grows instead:
//! for an undamped mode (hλ = ±i hω) BDF-3 amplifies it for hω up to 1.93 (at most 4.6 % per
//! step), BDF-4 up to 4.64 (19 %), BDF-5 up to 9.28 (38 %). On a rotor whose high modes are
//! lightly damped (no modal damping, only bearings), a step set by accuracy leaves some mode in
//! such a lobe; it grows until the error test rejects the step, the step shrinks, and the order
//! control, which only weighs error against step length, climbs back: the step then follows the
//! instability (tens of thousands of steps whatever the tolerance), and at loose tolerances the
//! grown mode is accepted as the solution. Capping the order at the largest k whose lobes hold
//! no mode at the step taken, and cutting the step proposed for an order back to the edge of
//! its lobes ([`Modes::stable_step`]), keeps BDF on the accuracy-limited step (Hairer & Wanner, Solving
//! ODEs II, §V.2 for the stability regions).
//!
//! Method: for each order 3–5 and each damping ratio ζ on a grid 0, 0.01, …, 0.99, the interval
//! of r = |hλ| along the ray of angle arccos ζ from the negative real axis on which the largest
//! root of ρ(ξ) − hλ ξᵏ exceeds 1 + 10⁻⁴ per step (sampled at 120 radii from 0.01 to 30, widened
//! by one sample each side; roots by Durand–Kerner, each solve started from the last along the ray); a mode's ζ is rounded down to the grid, whose
//! lobes are the wider; above cos α (the A(α) angle) there is none. Growth below 10⁻⁴ per step (under e over 10⁴ steps) is left to the error
//! test: it is the truncation error of a resolved mode. Computed once per process (≈ 10 ms).

use std::sync::OnceLock;

use nalgebra::{Complex, DMatrix};

/// Growth per step above which a mode counts as amplified.
const GROWTH: f64 = 1e-4;
/// Damping-ratio grid: 0, 0.01, … 0.99.
const ZETA_STEPS: usize = 100;
/// Radii sampled on each ray.
const RADII: usize = 120;
const R_MIN: f64 = 0.01;
const R_MAX: f64 = 30.0;

/// ρ(ξ) of BDF-k, monic coefficients of ξᵏ … ξ⁰ times k-independent scale: Σⱼ (1/j)(ξ−1)ʲ ξᵏ⁻ʲ.
fn rho(k: usize) -> Vec<f64> {
    let mut p = vec![0.0; k + 1];
    for j in 1..=k {
        // (ξ − 1)^j ξ^(k−j): coefficients from the highest power.
        let mut q = vec![1.0];
        for _ in 0..j {
            let mut next = vec![0.0; q.len() + 1];
            for (i, c) in q.iter().enumerate() {
                next[i] += c;
                next[i + 1] -= c;
            }
            q = next;
        }
        for (i, c) in q.iter().enumerate() {
            p[i] += c / j as f64;
        }
    }
    p
}

/// Largest root modulus of ρ(ξ) − z ξᵏ (Durand–Kerner from the roots in `roots`, which it
/// leaves at the roots found: along a ray each solve starts from the last).
fn spectral_radius_from(rho: &[f64], z: Complex<f64>, roots: &mut [Complex<f64>]) -> f64 {
    let k = rho.len() - 1;
    let mut c: Vec<Complex<f64>> = rho.iter().map(|&x| Complex::new(x, 0.0)).collect();
    c[0] -= z;
    let lead = c[0];
    for x in &mut c {
        *x /= lead;
    }
    let eval = |x: Complex<f64>| c.iter().fold(Complex::new(0.0, 0.0), |acc, &a| acc * x + a);
    for _ in 0..200 {
        let mut moved: f64 = 0.0;
        for i in 0..k {
            let mut den = Complex::new(1.0, 0.0);
            for j in 0..k {
                if i != j {
                    den *= roots[i] - roots[j];
                }
            }
            let step = eval(roots[i]) / den;
            roots[i] -= step;
            moved = moved.max(step.norm_sqr());
        }
        if moved < 1e-28 {
            break;
        }
    }
    roots
        .iter()
        .map(|r| r.norm_sqr())
        .fold(0.0, f64::max)
        .sqrt()
}

/// Durand–Kerner's usual start: k points on a circle, off the real axis.
fn start_roots(k: usize) -> Vec<Complex<f64>> {
    (0..k)
        .map(|i| Complex::from_polar(1.0, 0.4 + 2.0 * std::f64::consts::PI * i as f64 / k as f64))
        .collect()
}

/// Largest root modulus of ρ(ξ) − z ξᵏ.
#[cfg(test)]
fn spectral_radius(rho: &[f64], z: Complex<f64>) -> f64 {
    spectral_radius_from(rho, z, &mut start_roots(rho.len() - 1))
}

/// For orders 3, 4, 5 and each ζ of the grid: the amplifying interval (r_lo, r_hi) of |hλ|,
/// empty as (∞, 0).
fn lobes() -> &'static [[(f64, f64); ZETA_STEPS]; 3] {
    static LOBES: OnceLock<[[(f64, f64); ZETA_STEPS]; 3]> = OnceLock::new();
    LOBES.get_or_init(|| {
        let mut out = [[(f64::INFINITY, 0.0); ZETA_STEPS]; 3];
        let radii: Vec<f64> = (0..RADII)
            .map(|i| R_MIN * (R_MAX / R_MIN).powf(i as f64 / (RADII - 1) as f64))
            .collect();
        for (ki, k) in (3..=5).enumerate() {
            let p = rho(k);
            // A(α)-stability: no lobe where ζ > cos α (α = 86.03°, 73.35°, 51.84°).
            let last_zeta = [0.07, 0.29, 0.62][ki];
            for (zi, slot) in out[ki].iter_mut().enumerate() {
                let zeta = zi as f64 / ZETA_STEPS as f64;
                if zeta > last_zeta + 0.015 {
                    break;
                }
                let dir = Complex::new(-zeta, (1.0 - zeta * zeta).sqrt());
                let mut roots = start_roots(k);
                // The lobe is one interval of r: stop at the first stable radius after it.
                let (mut lo, mut hi) = (None, None);
                for (i, &r) in radii.iter().enumerate() {
                    let amplifies = spectral_radius_from(&p, dir * r, &mut roots) > 1.0 + GROWTH;
                    if amplifies {
                        lo.get_or_insert(i);
                        hi = Some(i);
                    } else if hi.is_some() {
                        break;
                    }
                }
                if let (Some(lo), Some(hi)) = (lo, hi) {
                    *slot = (radii[lo.saturating_sub(1)], radii[(hi + 1).min(RADII - 1)]);
                }
            }
        }
        out
    })
}

/// The steps at which BDF-3, -4 and -5 amplify some mode of a linearised system: for each
/// order, sorted disjoint intervals of h [s]. Rigid (λ = 0) and well-damped modes lie in no
/// lobe.
#[derive(Debug, Clone, Default)]
pub struct Modes {
    forbidden: [Vec<(f64, f64)>; 3],
}

impl Modes {
    /// From the eigenvalues of the state matrix [[0, I], [−M⁻¹K, −M⁻¹C]] of M q̈ + C q̇ + K q = 0
    /// (K = −∂F/∂q, C = −∂F/∂q̇); none when M is singular.
    pub fn of_system(m: &DMatrix<f64>, k: &DMatrix<f64>, c: &DMatrix<f64>) -> Modes {
        let n = m.nrows();
        let Some(minv) = m.clone().try_inverse() else {
            return Modes::default();
        };
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n)).copy_from(&(-&minv * k));
        a.view_mut((n, n), (n, n)).copy_from(&(-&minv * c));
        let modes: Vec<(f64, usize)> = a
            .complex_eigenvalues()
            .iter()
            .filter(|l| l.im > 0.0 && l.norm() > 0.0 && l.norm().is_finite())
            .filter_map(|l| {
                let zeta = (-l.re / l.norm()).max(0.0);
                let zi = (zeta * ZETA_STEPS as f64).floor() as usize;
                (zi < ZETA_STEPS).then_some((l.norm(), zi))
            })
            .collect();
        let lobes = lobes();
        let forbidden = std::array::from_fn(|ki| {
            let mut iv: Vec<(f64, f64)> = modes
                .iter()
                .map(|&(w, zi)| (lobes[ki][zi], w))
                .filter(|((lo, hi), _)| lo <= hi)
                .map(|((lo, hi), w)| (lo / w, hi / w))
                .collect();
            iv.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut merged: Vec<(f64, f64)> = Vec::with_capacity(iv.len());
            for (lo, hi) in iv {
                match merged.last_mut() {
                    Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
                    _ => merged.push((lo, hi)),
                }
            }
            merged
        });
        Modes { forbidden }
    }

    /// The highest BDF order ≤ `max_order` that amplifies no mode at step `h`.
    pub fn stable_order(&self, h: f64, max_order: usize) -> usize {
        (3..=max_order.min(5))
            .take_while(|&k| {
                let iv = &self.forbidden[k - 3];
                // The last interval starting at or below h holds h, or none does.
                let i = iv.partition_point(|&(lo, _)| lo <= h);
                i == 0 || iv[i - 1].1 < h
            })
            .last()
            .unwrap_or(max_order.min(2))
    }

    /// The longest step up to `h` at which [`Modes::stable_order`] allows `order`, that is at
    /// which BDF-3 … BDF-`order` amplify no mode: `h` itself when it lies in none of their
    /// intervals, else just below the start of the interval holding it, repeated until none
    /// does (orders 1 and 2, A-stable, always `h`). Below the current step when that step is
    /// unstable for the order.
    pub fn stable_step(&self, order: usize, h: f64) -> f64 {
        let mut x = h;
        loop {
            let held = (3..=order.min(5)).find_map(|k| {
                let iv = &self.forbidden[k - 3];
                let i = iv.partition_point(|&(lo, _)| lo <= x);
                iv.get(i.wrapping_sub(1))
                    .filter(|&&(_, hi)| x <= hi)
                    .map(|&(lo, _)| lo * (1.0 - 1e-9))
            });
            match held {
                Some(below) => x = below,
                None => return x,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bdf2_is_a_stable_and_bdf3_to_5_have_their_published_imaginary_axis_lobes() {
        // BDF-2 is A-stable: no amplification anywhere on the imaginary axis.
        let p2 = rho(2);
        for i in 0..200 {
            let y = 0.01 * 1.05f64.powi(i);
            assert!(
                spectral_radius(&p2, Complex::new(0.0, y)) <= 1.0 + 1e-12,
                "{y}"
            );
        }
        // The undamped lobes end where the boundary locus of BDF-k crosses the imaginary axis:
        // hω = 1.94 (k = 3), 4.64 (k = 4), 9.28 (k = 5), as in Hairer & Wanner II, Fig. V.2.1;
        // the table's end lies at most two radius samples (7 % each) beyond.
        let l = lobes();
        let sample = (R_MAX / R_MIN).powf(1.0 / (RADII - 1) as f64);
        for (k, end) in [(3, 1.93), (4, 4.64), (5, 9.28)] {
            let hi = l[k - 3][0].1;
            assert!(
                hi >= end && hi <= end * sample * sample,
                "BDF-{k}: lobe to {hi}"
            );
        }
        // Damping closes them: above cos α (α = 86.0°, 73.4°, 51.8°, the A(α) angles) none is
        // left: ζ = 0.07, 0.29, 0.62.
        for (k, zeta) in [(3, 0.08), (4, 0.30), (5, 0.63)] {
            let zi = (zeta * ZETA_STEPS as f64) as usize;
            assert!(l[k - 3][zi].0.is_infinite(), "BDF-{k} at ζ = {zeta}");
        }
    }

    #[test]
    fn the_order_is_capped_only_while_a_mode_sits_in_a_lobe() {
        // One undamped mode of ω = 1000 rad/s (M = 1, K = 1e6, C = 0).
        let one = DMatrix::from_element(1, 1, 1.0);
        let modes = Modes::of_system(&one, &(&one * 1e6), &(&one * 0.0));
        assert_eq!(modes.stable_order(1e-5, 5), 5, "hω = 0.01: resolved");
        assert_eq!(
            modes.stable_order(1.5e-3, 5),
            2,
            "hω = 1.5: BDF-3..5 amplify"
        );
        assert_eq!(
            modes.stable_order(3e-3, 5),
            3,
            "hω = 3: past the lobe of 3 only"
        );
        assert_eq!(
            modes.stable_order(6e-3, 5),
            4,
            "hω = 6: past the lobes of 3 and 4"
        );
        assert_eq!(modes.stable_order(2e-2, 5), 5, "hω = 20: past every lobe");
        assert_eq!(modes.stable_order(3e-3, 1), 1, "never above max_order");
        // The longest stable step of an order ends where its lobe starts: stable there, not a
        // hair above; past BDF-3's lobe (hω = 1.93, Hairer & Wanner II, Fig. V.2.1) no cap.
        let h5 = modes.stable_step(5, 1e-3);
        assert!(h5 > 1e-5 && h5 < 1e-3, "BDF-5 cap {h5}");
        assert_eq!(modes.stable_order(h5, 5), 5, "at the cap");
        assert!(modes.stable_order(h5 * 1.000001, 5) < 5, "above the cap");
        assert_eq!(modes.stable_step(5, 2e-2), 2e-2, "past the lobe");
        assert_eq!(modes.stable_step(2, 1.5e-3), 1.5e-3, "BDF-2 is A-stable");
        assert_eq!(modes.stable_step(3, 3e-3), 3e-3, "past BDF-3's lobe");
    }
}
