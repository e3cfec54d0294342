//! Random wall-thickness fields: a roll's wall as a stationary Gaussian random field, one seeded
//! realisation per scene, and the statistics a realisation has.
//!
//! **In:** a [`RandomFieldSpec`]: seed, mean and standard deviation of the wall [m], correlation
//! lengths around the shell (arc length at the wall's mid radius `radius_m`) and along it [m],
//! the grid (angles × stations), and the shell length L [m].
//! **Out:** the [`ThicknessMap`] of that seed ([`ThicknessMap::random_field`]), bit-identical for
//! the same spec; the specified correlation at a lag ([`RandomFieldSpec::correlation`]); and a
//! map's realised statistics ([`FieldStats::of`]): mean, population standard deviation over the
//! grid, and the amplitudes of its first two angular harmonics weighted by the first bending
//! mode (mm).
//!
//! # Method
//! The field is t(φ, z) = mean + σ Σ_{k=0}^{K} √w_k (A_k(z) cos kφ + B_k(z) sin kφ) (B_0 = 0),
//! with A_k, B_k independent unit-variance Gaussian processes along z of correlation
//! exp(−Δz²/2ℓ_z²). Around the shell the correlation is the wrapped Gaussian
//! ρ(Δφ) = Σ w_k cos kΔφ, w_0 ∝ 1, w_k ∝ 2 exp(−k²ℓ_φ²/2) for k ≥ 1 (the Fourier series of the
//! normal density of variance ℓ_φ² wrapped on the circle, ℓ_φ = ℓ_around / radius: close to
//! exp(−Δφ²/2ℓ_φ²) while ℓ_φ is well below π), kept up to the highest order the grid resolves,
//! K = ⌊(n_angles − 1)/2⌋, and scaled to Σ w_k = 1, so every point has variance σ² exactly.
//! The processes along z are drawn exactly on the stations: each is B ξ with ξ standard normal
//! (SplitMix64 + Box–Muller, [`SplitMix64`]) and B = V Λ^{1/2} from the symmetric eigen-
//! decomposition of the stations' correlation matrix (negative rounding eigenvalues set to 0).
//! The numbers are drawn order by order (A_k then B_k), station by station, from the one seed.
//!
//! The realised harmonic amplitude of order k is |Σ_j s_j c_k(z_j)| / Σ_j s_j, with
//! c_k(z) = (2/n) Σ_i t(φ_i, z) e^{−ikφ_i} the station's complex Fourier coefficient and
//! s_j = sin²(π z_j / L) the weight of the first bending mode's curvature squared on a
//! simply supported shell: order 1 is the eccentric bore the balancing corrects, order 2 the
//! oval bore whose stiffness asymmetry drives the 2× half-critical response.

use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, SymmetricEigen};

use super::map::{mean_std, Station, ThicknessMap};
use crate::numerics::rng::SplitMix64;

/// Recipe of a random wall: a stationary Gaussian field (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct RandomFieldSpec {
    /// Seed of the realisation; the same seed gives a bit-identical map.
    pub seed: u64,
    /// Mean wall thickness, m.
    pub mean_m: f64,
    /// Standard deviation of the wall at every point, m.
    pub std_m: f64,
    /// Correlation length around the shell, arc length at `radius_m`, m.
    pub around_m: f64,
    /// Correlation length along the shell, m.
    pub along_m: f64,
    /// Radius the arc length `around_m` is measured at (the wall's mid radius), m.
    pub radius_m: f64,
    /// Uniformly spaced angles per station (≥ 3).
    pub n_angles: usize,
    /// Uniformly spaced stations from z = 0 to z = L (≥ 2).
    pub n_stations: usize,
}

/// A map's realised statistics (module doc), mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldStats {
    /// Mean over the grid, mm.
    pub mean_mm: f64,
    /// Population standard deviation over the grid, mm.
    pub std_mm: f64,
    /// Mode-weighted amplitude of angular order 1 (eccentric bore), mm.
    pub h1_mm: f64,
    /// Mode-weighted amplitude of angular order 2 (oval bore), mm.
    pub h2_mm: f64,
}

impl RandomFieldSpec {
    /// The angular correlation length ℓ_φ, rad.
    fn around_rad(&self) -> f64 {
        self.around_m / self.radius_m
    }

    /// The variance shares w_0 … w_K of the angular orders (module doc), summing to 1.
    pub fn order_weights(&self) -> Vec<f64> {
        let top = (self.n_angles - 1) / 2;
        let l = self.around_rad();
        let raw: Vec<f64> = (0..=top)
            .map(|k| {
                let c = (-0.5 * (k as f64 * l).powi(2)).exp();
                if k == 0 {
                    c
                } else {
                    2.0 * c
                }
            })
            .collect();
        let total: f64 = raw.iter().sum();
        raw.iter().map(|w| w / total).collect()
    }

    /// The specified correlation between two points `dphi_rad` apart around and `dz_m` along
    /// the shell: Σ w_k cos(k Δφ) · exp(−Δz²/2ℓ_z²).
    pub fn correlation(&self, dphi_rad: f64, dz_m: f64) -> f64 {
        let around: f64 = self
            .order_weights()
            .iter()
            .enumerate()
            .map(|(k, w)| w * (k as f64 * dphi_rad).cos())
            .sum();
        around * (-0.5 * (dz_m / self.along_m).powi(2)).exp()
    }

    /// Checks that the field exists on a shell of `length_m`; the reason says which field is
    /// wrong. [`ThicknessMap::random_field`] requires this to pass.
    pub fn validate(&self, length_m: f64) -> Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        for (name, v) in [
            ("the shell length", length_m),
            ("mean_m", self.mean_m),
            ("std_m", self.std_m),
            ("around_m", self.around_m),
            ("along_m", self.along_m),
            ("radius_m", self.radius_m),
        ] {
            if !positive(v) {
                return Err(format!("{name} must be a positive number, got {v}"));
            }
        }
        if self.n_angles < 3 || self.n_stations < 2 {
            return Err(format!(
                "the grid needs at least 3 angles and 2 stations, got {} and {}",
                self.n_angles, self.n_stations
            ));
        }
        Ok(())
    }
}

impl ThicknessMap {
    /// The realisation of `spec` on a shell of `length_m` (module doc, method).
    ///
    /// # Panics
    /// If `spec.validate(length_m)` fails; callers reading user input validate first.
    pub fn random_field(spec: &RandomFieldSpec, length_m: f64) -> Self {
        if let Err(reason) = spec.validate(length_m) {
            panic!("invalid random wall field: {reason}");
        }
        let n_st = spec.n_stations;
        let z: Vec<f64> = (0..n_st)
            .map(|j| length_m * j as f64 / (n_st - 1) as f64)
            .collect();
        let factor = axial_factor(&z, spec.along_m);
        let mut rng = SplitMix64::new(spec.seed);
        let mut draw = || -> Vec<f64> {
            let xi: Vec<f64> = (0..n_st).map(|_| rng.normal()).collect();
            (&factor * nalgebra::DVector::from_vec(xi))
                .iter()
                .copied()
                .collect()
        };
        // (order, √w_k, A_k(z), B_k(z)), drawn A then B, order by order.
        let terms: Vec<(f64, f64, Vec<f64>, Vec<f64>)> = spec
            .order_weights()
            .into_iter()
            .enumerate()
            .map(|(k, w)| {
                let a = draw();
                let b = if k == 0 { vec![0.0; n_st] } else { draw() };
                (k as f64, w.sqrt(), a, b)
            })
            .collect();
        let phi: Vec<f64> = (0..spec.n_angles)
            .map(|i| TAU * i as f64 / spec.n_angles as f64)
            .collect();
        let stations = z
            .iter()
            .enumerate()
            .map(|(j, &z_m)| Station {
                z_m,
                phi_rad: phi.clone(),
                t_m: phi
                    .iter()
                    .map(|&p| {
                        let sum: f64 = terms
                            .iter()
                            .map(|(k, s, a, b)| s * (a[j] * (k * p).cos() + b[j] * (k * p).sin()))
                            .sum();
                        spec.mean_m + spec.std_m * sum
                    })
                    .collect(),
            })
            .collect();
        Self { length_m, stations }
    }
}

/// B = V Λ^{1/2} of the correlation matrix exp(−Δz²/2ℓ²) of the stations `z` [m].
fn axial_factor(z: &[f64], along_m: f64) -> DMatrix<f64> {
    let n = z.len();
    let c = DMatrix::from_fn(n, n, |i, j| {
        (-0.5 * ((z[i] - z[j]) / along_m).powi(2)).exp()
    });
    let eig = SymmetricEigen::new(c);
    let mut b = eig.eigenvectors;
    for (mut col, lambda) in b.column_iter_mut().zip(eig.eigenvalues.iter()) {
        col *= lambda.max(0.0).sqrt();
    }
    b
}

impl FieldStats {
    /// The realised statistics of `map` over its grid (module doc), in mm.
    pub fn of(map: &ThicknessMap) -> Self {
        let all: Vec<f64> = map
            .stations
            .iter()
            .flat_map(|s| s.t_m.iter().copied())
            .collect();
        let (mean, std) = mean_std(&all);
        let amplitude = |k: f64| {
            let (mut re, mut im, mut weights) = (0.0, 0.0, 0.0);
            for s in &map.stations {
                let w = (PI * s.z_m / map.length_m).sin().powi(2);
                let n = s.t_m.len() as f64;
                for (p, t) in s.phi_rad.iter().zip(&s.t_m) {
                    re += w * 2.0 / n * t * (k * p).cos();
                    im -= w * 2.0 / n * t * (k * p).sin();
                }
                weights += w;
            }
            re.hypot(im) / weights
        };
        Self {
            mean_mm: mean * 1e3,
            std_mm: std * 1e3,
            h1_mm: amplitude(1.0) * 1e3,
            h2_mm: amplitude(2.0) * 1e3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(seed: u64) -> RandomFieldSpec {
        RandomFieldSpec {
            seed,
            mean_m: 18.72e-3,
            std_m: 0.30e-3,
            around_m: 0.08,
            along_m: 0.6,
            radius_m: 0.15064,
            n_angles: 36,
            n_stations: 31,
        }
    }

    /// Ensemble of `m` realisations: the thickness at three points, (φ, z) index pairs.
    fn ensemble(m: usize, points: &[(usize, usize)]) -> Vec<Vec<f64>> {
        (0..m as u64)
            .map(|seed| {
                let map = ThicknessMap::random_field(&spec(seed), 4.5);
                points
                    .iter()
                    .map(|&(i, j)| map.stations[j].t_m[i])
                    .collect()
            })
            .collect()
    }

    fn correlation(x: &[f64], y: &[f64]) -> f64 {
        let (mx, sx) = mean_std(x);
        let (my, sy) = mean_std(y);
        let c = x
            .iter()
            .zip(y)
            .map(|(a, b)| (a - mx) * (b - my))
            .sum::<f64>()
            / x.len() as f64;
        c / (sx * sy)
    }

    #[test]
    fn realised_moments_and_correlations_match_the_specified_field() {
        // M independent realisations at a point (φ_0, z_15), one 2 angles around (20°) and one
        // 3 stations along (450 mm). Standard errors of the estimators for Gaussian samples
        // (Kendall & Stuart, The Advanced Theory of Statistics, vol. 1, §10.5 and §16.24): the
        // sample mean σ/√M, the sample variance σ²√(2/(M − 1)), the sample correlation
        // (1 − ρ²)/√(M − 1). Each estimate must lie within 4 standard errors.
        let m = 2000;
        let pts = [(0, 15), (2, 15), (0, 18)];
        let e = ensemble(m, &pts);
        let col = |c: usize| e.iter().map(|r| r[c]).collect::<Vec<f64>>();
        let s = spec(0);
        let sigma = s.std_m;
        let (mean, std) = mean_std(&col(0));
        let var = std * std * m as f64 / (m - 1) as f64;
        let se_mean = sigma / (m as f64).sqrt();
        let se_var = sigma * sigma * (2.0 / (m - 1) as f64).sqrt();
        eprintln!(
            "random wall, M = {m}: mean {:.5} mm (SE {:.5}), variance {:.5} mm² (0.09, SE {:.5})",
            mean * 1e3,
            se_mean * 1e3,
            var * 1e6,
            se_var * 1e6
        );
        assert!((mean - s.mean_m).abs() < 4.0 * se_mean, "mean {mean}");
        assert!((var - sigma * sigma).abs() < 4.0 * se_var, "variance {var}");
        // Around: closed form of the wrapped Gaussian, exp(−Δφ²/2ℓ_φ²) with ℓ_φ = 0.08/0.15064
        // rad (the wrapped terms are below 1e-30 here).
        let dphi = 2.0 * TAU / 36.0;
        let l_phi = s.around_m / s.radius_m;
        let rho_around = (-0.5 * (dphi / l_phi).powi(2)).exp();
        assert!((s.correlation(dphi, 0.0) - rho_around).abs() < 1e-9);
        let r = correlation(&col(0), &col(1));
        let se = (1.0 - rho_around.powi(2)) / ((m - 1) as f64).sqrt();
        eprintln!("around 20°: r = {r:.4} vs {rho_around:.4} (SE {se:.4})");
        assert!(
            (r - rho_around).abs() < 4.0 * se,
            "around {r} vs {rho_around}"
        );
        // Along: exp(−Δz²/2ℓ_z²), Δz = 3 × 150 mm.
        let rho_along = (-0.5 * (0.45_f64 / s.along_m).powi(2)).exp();
        let r = correlation(&col(0), &col(2));
        let se = (1.0 - rho_along.powi(2)) / ((m - 1) as f64).sqrt();
        eprintln!("along 450 mm: r = {r:.4} vs {rho_along:.4} (SE {se:.4})");
        assert!((r - rho_along).abs() < 4.0 * se, "along {r} vs {rho_along}");
    }

    #[test]
    fn a_seed_gives_the_same_map_and_another_seed_another() {
        let a = ThicknessMap::random_field(&spec(7), 4.5);
        let b = ThicknessMap::random_field(&spec(7), 4.5);
        let c = ThicknessMap::random_field(&spec(8), 4.5);
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn harmonic_amplitudes_of_a_known_map() {
        // t = 18 + 0.2 cos(φ − 0.3) + 0.1 cos 2φ mm, the same at every station: the weighted
        // amplitudes are the harmonics' own, 0.2 and 0.1 mm, and the mean 18 mm.
        let n = 36;
        let phi: Vec<f64> = (0..n).map(|i| TAU * i as f64 / n as f64).collect();
        let stations = (0..11)
            .map(|j| Station {
                z_m: 0.45 * j as f64,
                phi_rad: phi.clone(),
                t_m: phi
                    .iter()
                    .map(|p| 1e-3 * (18.0 + 0.2 * (p - 0.3).cos() + 0.1 * (2.0 * p).cos()))
                    .collect(),
            })
            .collect();
        let map = ThicknessMap {
            length_m: 4.5,
            stations,
        };
        let st = FieldStats::of(&map);
        assert!((st.mean_mm - 18.0).abs() < 1e-12);
        assert!((st.h1_mm - 0.2).abs() < 1e-12, "{}", st.h1_mm);
        assert!((st.h2_mm - 0.1).abs() < 1e-12, "{}", st.h2_mm);
        // Population std of the two harmonics: √(0.2²/2 + 0.1²/2).
        assert!((st.std_mm - (0.025_f64).sqrt()).abs() < 1e-12);
    }
}
