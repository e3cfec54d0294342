//! Cross-section properties of a beam element, by quadrature over the angle.
//!
//! In: the outer radius R_o [m] and the inner radius R_i(φ) [m] as a function of the body-frame
//! angle φ [rad] (from a wall-thickness map, R_i = R_o − t), or a solid/uniform circle.
//! Out: [`Section`]: area, first and second moments about the element's *reference axis* (the
//! nominal geometric axis x = y = 0 of the body frame, not the centroid), torsion constant and
//! Timoshenko shear factor. SI units throughout (m², m³, m⁴).
//!
//! The moments are exact integrals of the annulus between R_i(φ) and R_o sampled at `n` equally
//! spaced angles (the trapezoidal rule, spectrally accurate for smooth periodic maps): for instance
//! `qx = ∫∫ x dA = ∫ (R_o³ − R_i³)/3 · cos φ dφ`. A 1st angular harmonic of the thickness moves
//! the centroid off the axis (distributed unbalance); a 2nd harmonic makes `sxx ≠ syy`.

use std::f64::consts::PI;

/// Geometric properties of one cross-section about the reference axis (x = y = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Area A [m²].
    pub area: f64,
    /// First moment ∫x dA [m³].
    pub qx: f64,
    /// First moment ∫y dA [m³].
    pub qy: f64,
    /// Second moment ∫x² dA [m⁴] (resists bending in the x–z plane).
    pub sxx: f64,
    /// Second moment ∫y² dA [m⁴] (resists bending in the y–z plane).
    pub syy: f64,
    /// Product moment ∫xy dA [m⁴].
    pub sxy: f64,
    /// Saint-Venant torsion constant J_t [m⁴].
    pub torsion: f64,
    /// Timoshenko shear correction factor κ [-].
    pub shear_factor: f64,
}

impl Section {
    /// A solid circular section of diameter `d` [m].
    pub fn solid(d: f64, nu: f64) -> Self {
        Self::tube(d, 0.0, nu)
    }

    /// A uniform tube of outer and inner diameter [m] (`inner = 0` for a solid shaft).
    pub fn tube(outer: f64, inner: f64, nu: f64) -> Self {
        let (ro, ri) = (0.5 * outer, 0.5 * inner);
        let area = PI * (ro * ro - ri * ri);
        let s = 0.25 * PI * (ro.powi(4) - ri.powi(4));
        Self {
            area,
            qx: 0.0,
            qy: 0.0,
            sxx: s,
            syy: s,
            sxy: 0.0,
            torsion: 2.0 * s,
            shear_factor: tube_shear_factor(ri / ro, nu),
        }
    }

    /// A tube with outer radius `ro` and inner radius `ri(φ)`, integrated over `n` angles.
    ///
    /// The torsion constant is the closed thin-walled one, 4 A_m² / ∮ ds/t, with the mid-wall
    /// line r_m = (R_o + R_i)/2; the shear factor is Cowper's for the mean wall.
    pub fn from_inner_radius(ro: f64, ri: impl Fn(f64) -> f64, n: usize, nu: f64) -> Self {
        let dphi = 2.0 * PI / n as f64;
        let (mut area, mut qx, mut qy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut am, mut ds_over_t, mut ri_mean) = (0.0, 0.0, 0.0);
        for k in 0..n {
            let phi = k as f64 * dphi;
            let r = ri(phi);
            let (s, c) = phi.sin_cos();
            let a2 = 0.5 * (ro * ro - r * r);
            let a3 = (ro.powi(3) - r.powi(3)) / 3.0;
            let a4 = 0.25 * (ro.powi(4) - r.powi(4));
            area += a2;
            qx += a3 * c;
            qy += a3 * s;
            sxx += a4 * c * c;
            syy += a4 * s * s;
            sxy += a4 * s * c;
            let rm = 0.5 * (ro + r);
            am += 0.5 * rm * rm;
            ds_over_t += rm / (ro - r);
            ri_mean += r;
        }
        let w = dphi;
        let am = am * w;
        let ri_mean = ri_mean / n as f64;
        Self {
            area: area * w,
            qx: qx * w,
            qy: qy * w,
            sxx: sxx * w,
            syy: syy * w,
            sxy: sxy * w,
            torsion: 4.0 * am * am / (ds_over_t * w),
            shear_factor: tube_shear_factor(ri_mean / ro, nu),
        }
    }

    /// The section with its second moments about the body axes made I(1 + a) and I(1 − a)
    /// (`sxx`, `syy`; I their mean), the product moment, area, centroid and torsion constant
    /// kept: a shaft whose bending stiffness differs between two perpendicular planes (flats, a
    /// keyway, a slot), (I_x − I_y)/(I_x + I_y) = a. Any a for a round section; the scene keeps
    /// |a| ≤ 0.9.
    pub fn with_asymmetry(self, a: f64) -> Self {
        let mean = 0.5 * (self.sxx + self.syy);
        let half = 0.5 * (self.sxx - self.syy);
        Self {
            sxx: mean * (1.0 + a) + half,
            syy: mean * (1.0 - a) - half,
            ..self
        }
    }

    /// Centroid (e_x, e_y) [m] relative to the reference axis.
    pub fn centroid(&self) -> (f64, f64) {
        (self.qx / self.area, self.qy / self.area)
    }

    /// Mean bending second moment about the centroid, ½(I_x + I_y) [m⁴] (for the shear parameter).
    pub fn mean_centroidal_inertia(&self) -> f64 {
        let (ex, ey) = self.centroid();
        0.5 * (self.sxx + self.syy - self.area * (ex * ex + ey * ey))
    }

    /// The weighted mean of several sections, property by property (weights sum to 1).
    pub fn weighted_mean(items: &[(f64, Section)]) -> Self {
        let sum = |f: fn(&Section) -> f64| items.iter().map(|(w, s)| w * f(s)).sum::<f64>();
        Self {
            area: sum(|s| s.area),
            qx: sum(|s| s.qx),
            qy: sum(|s| s.qy),
            sxx: sum(|s| s.sxx),
            syy: sum(|s| s.syy),
            sxy: sum(|s| s.sxy),
            torsion: sum(|s| s.torsion),
            shear_factor: sum(|s| s.shear_factor),
        }
    }
}

/// Cowper's shear factor of a hollow circle with radius ratio m = R_i/R_o (m = 0: solid).
pub fn tube_shear_factor(m: f64, nu: f64) -> f64 {
    let m2 = m * m;
    let a = (1.0 + m2) * (1.0 + m2);
    6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference roll shell (physics.md §10): R_o = 160 mm, mean wall 18.72 mm.
    const RO: f64 = 0.160;
    const T0: f64 = 0.01872;

    #[test]
    fn uniform_tube_matches_closed_form() {
        // Closed forms: A = π(R_o² − R_i²), I = π/4 (R_o⁴ − R_i⁴), J = 2I.
        let ri = RO - T0;
        let s = Section::from_inner_radius(RO, |_| ri, 64, 0.3);
        let a = PI * (RO * RO - ri * ri);
        let i = 0.25 * PI * (RO.powi(4) - ri.powi(4));
        assert!((s.area / a - 1.0).abs() < 1e-13);
        assert!((s.sxx / i - 1.0).abs() < 1e-13);
        assert!((s.syy / i - 1.0).abs() < 1e-13);
        assert!(s.sxy.abs() < 1e-16 && s.qx.abs() < 1e-16 && s.qy.abs() < 1e-16);
        // Thin-walled torsion constant 2π r_m³ t against the exact 2I: within (t/2r_m)² ≈ 0.4 %.
        assert!((s.torsion / (2.0 * i) - 1.0).abs() < 5e-3);
        assert_eq!(s, Section::from_inner_radius(RO, |_| ri, 64, 0.3));
        let t = Section::tube(2.0 * RO, 2.0 * ri, 0.3);
        assert!((t.area / a - 1.0).abs() < 1e-14);
    }

    #[test]
    fn an_asymmetric_tube_splits_its_second_moments() {
        // Closed form: I = π/4 (R_o⁴ − R_i⁴) of the round tube; with a = 0.05 the body-frame
        // moments are 1.05 I and 0.95 I, the area and torsion constant the round tube's.
        let ri = RO - T0;
        let i = 0.25 * PI * (RO.powi(4) - ri.powi(4));
        let round = Section::tube(2.0 * RO, 2.0 * ri, 0.3);
        let s = round.with_asymmetry(0.05);
        assert!((s.sxx / (1.05 * i) - 1.0).abs() < 1e-14, "{}", s.sxx / i);
        assert!((s.syy / (0.95 * i) - 1.0).abs() < 1e-14, "{}", s.syy / i);
        assert!(((s.sxx - s.syy) / (s.sxx + s.syy) - 0.05).abs() < 1e-14);
        assert_eq!((s.area, s.torsion, s.sxy), (round.area, round.torsion, 0.0));
        assert_eq!(round.with_asymmetry(0.0), round);
    }

    #[test]
    fn first_harmonic_moves_centroid() {
        // t = t0 + a cos φ → R_i = r0 − a cos φ; to first order in a:
        // Q_x = π r0² a, so e_x = π r0² a / A0 (derivation in the module doc).
        let a = 0.3e-3;
        let r0 = RO - T0;
        let s = Section::from_inner_radius(RO, |p| r0 - a * p.cos(), 128, 0.3);
        let a0 = PI * (RO * RO - r0 * r0);
        let (ex, ey) = s.centroid();
        let expected = PI * r0 * r0 * a / a0;
        // Second-order terms are O(a/r0) ≈ 0.2 % of the first-order value.
        assert!((ex / expected - 1.0).abs() < 3e-3, "{ex} vs {expected}");
        assert!(ey.abs() < 1e-15);
        // Rotating the harmonic by 90° moves the centroid to +y.
        let s90 = Section::from_inner_radius(RO, |p| r0 - a * p.sin(), 128, 0.3);
        assert!((s90.centroid().1 / expected - 1.0).abs() < 3e-3);
    }

    #[test]
    fn second_harmonic_makes_bending_stiffness_asymmetric() {
        // t = t0 + b cos 2φ → R_i = r0 − b cos 2φ; to first order:
        // ∫x² − ∫y² = ∫ (R_o⁴ − R_i⁴)/4 · cos 2φ dφ = π r0³ b, and the centroid stays on the axis.
        let b = 0.4e-3;
        let r0 = RO - T0;
        let s = Section::from_inner_radius(RO, |p| r0 - b * (2.0 * p).cos(), 128, 0.3);
        let expected = PI * r0.powi(3) * b;
        let diff = s.sxx - s.syy;
        // Next term is O((b/r0)²) relative: 1.5 (b/r0)² ≈ 1e-5.
        assert!((diff / expected - 1.0).abs() < 1e-4, "{diff} vs {expected}");
        let (ex, ey) = s.centroid();
        assert!(ex.abs() < 1e-15 && ey.abs() < 1e-15);
        assert!(s.sxy.abs() < 1e-15);
        // At 45° the asymmetry appears as a product moment: ∫xy = π r0³ b / 2.
        let s45 =
            Section::from_inner_radius(RO, |p| r0 - b * (2.0 * (p - PI / 4.0)).cos(), 128, 0.3);
        assert!((s45.sxy / (0.5 * expected) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn cowper_shear_factors() {
        // Cowper (1966): solid circle 6(1+ν)/(7+6ν) = 0.886 at ν = 0.3; thin tube → 2(1+ν)/(4+3ν) = 0.531.
        assert!((tube_shear_factor(0.0, 0.3) - 7.8 / 8.8).abs() < 1e-12);
        assert!((tube_shear_factor(1.0, 0.3) - 2.6 / 4.9).abs() < 1e-12);
    }
}
