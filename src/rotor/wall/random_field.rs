//! Random wall-thickness fields: a roll's wall as a stationary Gaussian random field, one seeded
//! realisation per scene, and the statistics a realisation has.
//!
//! **In:** a [`RandomFieldSpec`]: seed, mean wall [m], the angular content ([`Angular`]: a
//! standard deviation with a correlation length around the shell (arc length at the wall's mid
//! radius), or a standard deviation per circumferential harmonic), the correlation length along
//! it [m] (or none: each harmonic the same along the whole shell), the grid (angles ×
//! stations), and the shell length L [m].
//! **Out:** the [`ThicknessMap`] of that seed ([`ThicknessMap::random_field`]), bit-identical for
//! the same spec; the specified variance at a point ([`RandomFieldSpec::point_variance`]) and
//! correlation at a lag ([`RandomFieldSpec::correlation`]); and a map's realised statistics
//! ([`FieldStats::of`]): mean, population standard deviation over the grid, and the amplitudes
//! of its first two angular harmonics weighted by the first bending mode (mm).
//!
//! # Method
//! The field is t(φ, z) = mean + Σ_k s_k (A_k(z) cos kφ + B_k(z) sin kφ) (B_0 = 0), with A_k,
//! B_k independent unit-variance Gaussian processes along z of correlation exp(−Δz²/2ℓ_z²)
//! (with no ℓ_z, one standard normal number each, the same at every station), so a point has
//! variance Σ s_k² and harmonic k's complex amplitude at a station, s_k (A_k − i B_k), has a
//! Rayleigh-distributed modulus of scale s_k.
//!
//! - **Correlation around** ([`Angular::Correlation`]): s_k = σ √w_k for k = 0 … K, with
//!   w_0 ∝ 1, w_k ∝ 2 exp(−k²ℓ_φ²/2) for k ≥ 1 — the wrapped Gaussian correlation
//!   ρ(Δφ) = Σ w_k cos kΔφ, the Fourier series of the normal density of variance ℓ_φ² wrapped on
//!   the circle, ℓ_φ = ℓ_around / radius: close to exp(−Δφ²/2ℓ_φ²) while ℓ_φ is well below π —
//!   kept up to the highest order the grid resolves, K = ⌊(n_angles − 1)/2⌋, and scaled to
//!   Σ w_k = 1, so every point has variance σ² exactly. (Computed as σ · Σ √w_k (…).)
//! - **Spectrum** ([`Angular::Spectrum`]): s_n = σ_n, the given standard deviation of each
//!   listed harmonic n (1 ≤ n ≤ K; no order 0, so every realisation's mean around the shell is
//!   the mean), so a point has variance Σ σ_n² and harmonic n a Rayleigh amplitude of scale σ_n
//!   (mean σ_n √(π/2), root mean square √2 σ_n).
//!
//! The processes along z are drawn exactly on the stations: each is B ξ with ξ standard normal
//! (SplitMix64 + Box–Muller, [`SplitMix64`]) and B = V Λ^{1/2} from the symmetric eigen-
//! decomposition of the stations' correlation matrix (negative rounding eigenvalues set to 0).
//! The numbers are drawn order by order in increasing order (A_k then B_k), station by station
//! (one number per process with no ℓ_z), from the one seed.
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
    /// How the field varies around the shell.
    pub angular: Angular,
    /// Correlation length along the shell, m; None: each harmonic the same at every station.
    pub along_m: Option<f64>,
    /// Uniformly spaced angles per station (≥ 3).
    pub n_angles: usize,
    /// Uniformly spaced stations from z = 0 to z = L (≥ 2).
    pub n_stations: usize,
}

/// The angular content of a random wall (module doc).
#[derive(Debug, Clone, PartialEq)]
pub enum Angular {
    /// A wrapped Gaussian correlation around the shell.
    Correlation {
        /// Standard deviation of the wall at every point, m.
        std_m: f64,
        /// Correlation length around the shell, arc length at `radius_m`, m.
        around_m: f64,
        /// Radius the arc length `around_m` is measured at (the wall's mid radius), m.
        radius_m: f64,
    },
    /// A standard deviation per circumferential harmonic: (order n ≥ 1, σ_n [m]), in any
    /// order, each order once.
    Spectrum(Vec<(usize, f64)>),
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
    /// The highest angular order the grid resolves, K = ⌊(n_angles − 1)/2⌋.
    pub fn top_order(&self) -> usize {
        (self.n_angles - 1) / 2
    }

    /// The field as σ · Σ_k s_k (…): the factor σ [m] and each order k with its scale s_k (σ = 1
    /// m and s_k in m for a spectrum), in increasing order (module doc).
    fn orders(&self) -> (f64, Vec<(usize, f64)>) {
        match &self.angular {
            Angular::Correlation { std_m, .. } => (
                *std_m,
                self.order_weights()
                    .into_iter()
                    .enumerate()
                    .map(|(k, w)| (k, w.sqrt()))
                    .collect(),
            ),
            Angular::Spectrum(lines) => {
                let mut lines = lines.clone();
                lines.sort_by_key(|&(n, _)| n);
                (1.0, lines)
            }
        }
    }

    /// The variance shares w_0 … w_K of the angular orders of a correlation around the shell
    /// (module doc), summing to 1; a spectrum's shares σ_n² / Σ σ_m² at orders 0 … K.
    pub fn order_weights(&self) -> Vec<f64> {
        let top = self.top_order();
        let raw: Vec<f64> = match &self.angular {
            Angular::Correlation {
                around_m, radius_m, ..
            } => {
                let l = around_m / radius_m;
                (0..=top)
                    .map(|k| {
                        let c = (-0.5 * (k as f64 * l).powi(2)).exp();
                        if k == 0 {
                            c
                        } else {
                            2.0 * c
                        }
                    })
                    .collect()
            }
            Angular::Spectrum(lines) => (0..=top)
                .map(|k| {
                    lines
                        .iter()
                        .filter(|&&(n, _)| n == k)
                        .map(|(_, s)| s * s)
                        .sum()
                })
                .collect(),
        };
        let total: f64 = raw.iter().sum();
        raw.iter().map(|w| w / total).collect()
    }

    /// The specified variance of the wall at every point, m²: σ², or Σ σ_n² of a spectrum.
    pub fn point_variance(&self) -> f64 {
        match &self.angular {
            Angular::Correlation { std_m, .. } => std_m * std_m,
            Angular::Spectrum(lines) => lines.iter().map(|(_, s)| s * s).sum(),
        }
    }

    /// The specified correlation between two points `dphi_rad` apart around and `dz_m` along
    /// the shell: Σ w_k cos(k Δφ) · exp(−Δz²/2ℓ_z²) (the second factor 1 without ℓ_z).
    pub fn correlation(&self, dphi_rad: f64, dz_m: f64) -> f64 {
        let around: f64 = self
            .order_weights()
            .iter()
            .enumerate()
            .map(|(k, w)| w * (k as f64 * dphi_rad).cos())
            .sum();
        around
            * self
                .along_m
                .map_or(1.0, |l| (-0.5 * (dz_m / l).powi(2)).exp())
    }

    /// Checks that the field exists on a shell of `length_m`; the reason says which field is
    /// wrong. [`ThicknessMap::random_field`] requires this to pass.
    pub fn validate(&self, length_m: f64) -> Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let mut named = vec![("the shell length", length_m), ("mean_m", self.mean_m)];
        if let Some(l) = self.along_m {
            named.push(("along_m", l));
        }
        if let Angular::Correlation {
            std_m,
            around_m,
            radius_m,
        } = &self.angular
        {
            named.extend([
                ("std_m", *std_m),
                ("around_m", *around_m),
                ("radius_m", *radius_m),
            ]);
        }
        for (name, v) in named {
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
        if let Angular::Spectrum(lines) = &self.angular {
            let top = self.top_order();
            for (i, &(n, s)) in lines.iter().enumerate() {
                if !(1..=top).contains(&n) {
                    return Err(format!(
                        "harmonic {i}: order {n} is outside 1 … {top}, the orders {} angles \
                         resolve",
                        self.n_angles
                    ));
                }
                if !(s.is_finite() && s >= 0.0) {
                    return Err(format!(
                        "harmonic {i}: the standard deviation must be a number ≥ 0, got {s}"
                    ));
                }
                if lines[..i].iter().any(|&(m, _)| m == n) {
                    return Err(format!("harmonic {i}: order {n} is given twice"));
                }
            }
            if !positive(self.point_variance()) {
                return Err(
                    "the spectrum needs a harmonic with a positive standard deviation".into(),
                );
            }
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
        let factor = spec.along_m.map(|l| axial_factor(&z, l));
        let mut rng = SplitMix64::new(spec.seed);
        let mut draw = || -> Vec<f64> {
            match &factor {
                Some(b) => {
                    let xi: Vec<f64> = (0..n_st).map(|_| rng.normal()).collect();
                    (b * nalgebra::DVector::from_vec(xi))
                        .iter()
                        .copied()
                        .collect()
                }
                None => vec![rng.normal(); n_st],
            }
        };
        let (sigma, orders) = spec.orders();
        // (order, s_k, A_k(z), B_k(z)), drawn A then B, order by order.
        let terms: Vec<(f64, f64, Vec<f64>, Vec<f64>)> = orders
            .into_iter()
            .map(|(k, s)| {
                let a = draw();
                let b = if k == 0 { vec![0.0; n_st] } else { draw() };
                (k as f64, s, a, b)
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
                        spec.mean_m + sigma * sum
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
        Self {
            mean_mm: mean * 1e3,
            std_mm: std * 1e3,
            h1_mm: harmonic_amplitude(map, 1.0) * 1e3,
            h2_mm: harmonic_amplitude(map, 2.0) * 1e3,
        }
    }
}

/// The mode-weighted amplitude of angular order `k` of `map` (module doc), m.
fn harmonic_amplitude(map: &ThicknessMap, k: f64) -> f64 {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(seed: u64) -> RandomFieldSpec {
        RandomFieldSpec {
            seed,
            mean_m: 18.72e-3,
            angular: Angular::Correlation {
                std_m: 0.30e-3,
                around_m: 0.08,
                radius_m: 0.15064,
            },
            along_m: Some(0.6),
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
        let sigma = s.point_variance().sqrt();
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
        let l_phi = 0.08 / 0.15064;
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
        let rho_along = (-0.5 * (0.45_f64 / 0.6).powi(2)).exp();
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

    /// A spectral field of harmonics 1, 2 and 3 with standard deviations 0.20, 0.15 and
    /// 0.05 mm on the 36 × 31 grid of a 4.5 m shell, `along_m` the correlation along.
    fn spectral(seed: u64, along_m: Option<f64>) -> RandomFieldSpec {
        RandomFieldSpec {
            seed,
            mean_m: 18.72e-3,
            angular: Angular::Spectrum(vec![(2, 0.15e-3), (1, 0.20e-3), (3, 0.05e-3)]),
            along_m,
            n_angles: 36,
            n_stations: 31,
        }
    }

    /// The Kolmogorov–Smirnov distance sup |F_M − F| of the sample `x` against the Rayleigh
    /// CDF of scale `s`, 1 − exp(−x²/2s²).
    fn ks_rayleigh(mut x: Vec<f64>, s: f64) -> f64 {
        x.sort_by(f64::total_cmp);
        let m = x.len() as f64;
        x.iter()
            .enumerate()
            .map(|(i, v)| {
                let f = 1.0 - (-0.5 * (v / s).powi(2)).exp();
                (f - i as f64 / m).abs().max(((i + 1) as f64 / m - f).abs())
            })
            .fold(0.0, f64::max)
    }

    /// The complex Fourier coefficient's modulus of order `k` at station `j`, (2/n)|Σ t e^{−ikφ}|.
    fn station_amplitude(map: &ThicknessMap, j: usize, k: f64) -> f64 {
        let s = &map.stations[j];
        let n = s.t_m.len() as f64;
        let (re, im) = s
            .phi_rad
            .iter()
            .zip(&s.t_m)
            .fold((0.0, 0.0), |(re, im), (p, t)| {
                (re + t * (k * p).cos(), im - t * (k * p).sin())
            });
        2.0 / n * re.hypot(im)
    }

    #[test]
    fn a_spectral_field_has_the_variance_of_its_harmonics_and_rayleigh_amplitudes() {
        // M realisations of the field t = mean + Σ σ_n (A_n(z) cos nφ + B_n(z) sin nφ), A_n,
        // B_n unit Gaussian processes along z (600 mm). Closed forms (module doc):
        // - at a point, Var t = Σ σ_n² = 0.065 mm²; the sample variance's standard error
        //   σ²√(2/(M − 1)) (Kendall & Stuart vol. 1, §10.5);
        // - over the grid, the population variance is Σ_n σ_n² X_n, X_n = (1/S) Σ_j
        //   (A_n(z_j)² + B_n(z_j)²)/2 (each order 1 … 17 averages cos² over 36 angles to ½ and
        //   leaves the grid mean at the mean), so its expectation is Σ σ_n² and, as Cov(A_j²,
        //   A_l²) = 2ρ_jl² for jointly Gaussian A, its variance is Σ σ_n⁴ (1/S²) Σ_jl ρ_jl²;
        //   the mean over M draws has that over M;
        // - harmonic n's modulus at a station, σ_n |A_n − i B_n|, is Rayleigh of scale σ_n;
        //   the mode-weighted amplitude (FieldStats::h1_mm, h2_mm) is a weighted mean of the
        //   stations' complex coefficients, complex Gaussian too: Rayleigh of scale
        //   σ_n √(wᵀ R w)/Σ w, w_j = sin²(π z_j/L), R the stations' correlation.
        // Each moment within 4 standard errors; each Kolmogorov–Smirnov distance below
        // 1.628/√M, the 1 % critical value (Massey 1951, Table 1, large samples).
        let m = 2000;
        let sigmas = [(1, 0.20e-3), (2, 0.15e-3), (3, 0.05e-3)];
        let spec = spectral(0, Some(0.6));
        let var: f64 = sigmas.iter().map(|(_, s)| s * s).sum();
        assert!((spec.point_variance() - var).abs() < 1e-20);
        let (length, stations) = (4.5, 31);
        let z: Vec<f64> = (0..stations)
            .map(|j| length * j as f64 / (stations - 1) as f64)
            .collect();
        let rho = |a: f64, b: f64| (-0.5 * ((a - b) / 0.6).powi(2)).exp();
        let sum_rho2: f64 = z
            .iter()
            .flat_map(|a| z.iter().map(move |b| rho(*a, *b).powi(2)))
            .sum();
        let w: Vec<f64> = z
            .iter()
            .map(|zj| (PI * zj / length).sin().powi(2))
            .collect();
        let wrw: f64 = z
            .iter()
            .zip(&w)
            .flat_map(|(a, wa)| z.iter().zip(&w).map(move |(b, wb)| wa * wb * rho(*a, *b)))
            .sum();
        let mode_share = wrw.sqrt() / w.iter().sum::<f64>();
        let maps: Vec<ThicknessMap> = (0..m as u64)
            .map(|seed| ThicknessMap::random_field(&spectral(seed, Some(0.6)), length))
            .collect();
        let point: Vec<f64> = maps.iter().map(|p| p.stations[15].t_m[4]).collect();
        let (pm, ps) = mean_std(&point);
        let point_var = ps * ps * m as f64 / (m - 1) as f64;
        let se = var * (2.0 / (m - 1) as f64).sqrt();
        let stats: Vec<FieldStats> = maps.iter().map(FieldStats::of).collect();
        let grid_var = stats.iter().map(|s| (s.std_mm * 1e-3).powi(2)).sum::<f64>() / m as f64;
        let grid_se = (sigmas.iter().map(|(_, s)| s.powi(4)).sum::<f64>() * sum_rho2
            / (stations * stations) as f64
            / m as f64)
            .sqrt();
        eprintln!(
            "spectral wall, M = {m}: point mean {:.5} mm, variance {:.5} mm² (0.065, SE {:.5}); \
             grid variance {:.5} mm² (SE {:.5})",
            pm * 1e3,
            point_var * 1e6,
            se * 1e6,
            grid_var * 1e6,
            grid_se * 1e6
        );
        assert!((pm - 18.72e-3).abs() < 4.0 * var.sqrt() / (m as f64).sqrt());
        assert!(
            (point_var - var).abs() < 4.0 * se,
            "point variance {point_var}"
        );
        assert!(
            (grid_var - var).abs() < 4.0 * grid_se,
            "grid variance {grid_var}"
        );
        // No order 0: every realisation's grid mean is the mean (to rounding).
        assert!(stats.iter().all(|s| (s.mean_mm - 18.72).abs() < 1e-9));
        let critical = 1.628 / (m as f64).sqrt();
        for (n, sigma) in sigmas {
            let at_station: Vec<f64> = maps
                .iter()
                .map(|p| station_amplitude(p, 15, n as f64))
                .collect();
            let d = ks_rayleigh(at_station, sigma);
            eprintln!("harmonic {n} at a station: KS distance {d:.4} (1 % critical {critical:.4})");
            assert!(d < critical, "harmonic {n}: KS {d}");
        }
        for (n, sigma, h) in [
            (
                1,
                0.20e-3,
                stats.iter().map(|s| s.h1_mm * 1e-3).collect::<Vec<_>>(),
            ),
            (2, 0.15e-3, stats.iter().map(|s| s.h2_mm * 1e-3).collect()),
        ] {
            let d = ks_rayleigh(h, sigma * mode_share);
            eprintln!(
                "mode-weighted harmonic {n}: KS distance {d:.4} against Rayleigh({:.4} mm)",
                sigma * mode_share * 1e3
            );
            assert!(d < critical, "mode-weighted harmonic {n}: KS {d}");
        }
        // An order the spectrum leaves out is absent (rounding only).
        assert!(maps.iter().all(|p| station_amplitude(p, 15, 4.0) < 1e-15));
    }

    #[test]
    fn a_spectral_field_is_its_seed_whatever_the_order_of_its_lines() {
        let a = ThicknessMap::random_field(&spectral(7, Some(0.6)), 4.5);
        let listed = RandomFieldSpec {
            angular: Angular::Spectrum(vec![(3, 0.05e-3), (1, 0.20e-3), (2, 0.15e-3)]),
            ..spectral(7, Some(0.6))
        };
        assert_eq!(a, ThicknessMap::random_field(&listed, 4.5));
        assert_ne!(a, ThicknessMap::random_field(&spectral(8, Some(0.6)), 4.5));
        // Without a correlation along, every station is the same ring.
        let rigid = ThicknessMap::random_field(&spectral(7, None), 4.5);
        assert!(rigid
            .stations
            .iter()
            .all(|s| s.t_m == rigid.stations[0].t_m));
        assert_ne!(rigid.stations[0].t_m, a.stations[0].t_m);
    }

    #[test]
    fn a_spectrum_outside_the_grid_or_negative_is_refused() {
        let with = |lines: Vec<(usize, f64)>| RandomFieldSpec {
            angular: Angular::Spectrum(lines),
            ..spectral(0, None)
        };
        let reason = |lines| with(lines).validate(4.5).unwrap_err();
        // 36 angles resolve the orders 1 … 17.
        assert!(reason(vec![(0, 1e-4)]).contains("order 0 is outside 1 … 17"));
        assert!(reason(vec![(18, 1e-4)]).contains("order 18 is outside 1 … 17"));
        assert!(reason(vec![(2, -1e-4)]).contains("≥ 0, got -0.0001"));
        assert!(reason(vec![(2, f64::NAN)]).contains("got NaN"));
        assert!(reason(vec![(2, 1e-4), (2, 2e-4)]).contains("order 2 is given twice"));
        assert!(reason(vec![(2, 0.0)]).contains("a positive standard deviation"));
        assert!(reason(vec![]).contains("a positive standard deviation"));
        assert!(with(vec![(17, 1e-4)]).validate(4.5).is_ok());
    }
}
