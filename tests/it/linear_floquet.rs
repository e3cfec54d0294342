//! Floquet stability against closed forms.
//!
//! - The asymmetric Jeffcott shaft (mass m, shaft stiffnesses k_ξ < k_η along its body axes, on
//!   rigid supports; e.g. Genta, *Dynamics of Rotating Systems*, 2005, §6.2, or Friswell et al.,
//!   *Dynamics of Rotating Machines*, 2010, §3.9): undamped, it is unstable exactly for
//!   √(k_ξ/m) < Ω < √(k_η/m). Written in the inertial frame its stiffness
//!   R(θ) diag(k_ξ, k_η) R(θ)ᵀ turns with the shaft: a periodic system, whose monodromy over one
//!   revolution this checks. With enough stationary damping the band closes.
//! - An axisymmetric rotor on anisotropic supports is time-invariant in the inertial frame, so
//!   the body-frame periodic system (supports turning backwards) must have the multipliers
//!   e^{λT} of the stationary-frame eigenvalues λ: the largest growth per revolution
//!   ln|μ|max = T·max Re λ; also at 0.3 Hz, where one revolution is long against the fast modes
//!   and a single step count of the Magnus method has no finite multipliers (before step
//!   doubling, this speed failed).

use crate::support;

use std::f64::consts::PI;

use nalgebra::{DMatrix, Matrix2};
use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::floquet::{
    growth_per_rev, monodromy, multipliers, scene_multipliers, unstable_ranges,
};
use rotorsweep::linear::modes::{damped_modes, Split};

const M: f64 = 2.0;
const K_XI: f64 = 1.0e4;
const K_ETA: f64 = 1.44e4;

fn jeffcott_growth(c: f64, speed_hz: f64) -> f64 {
    let omega = 2.0 * PI * speed_hz;
    let m = DMatrix::identity(2, 2) * M;
    let phi = monodromy(&m, omega, 256, |theta| {
        let (s, co) = theta.sin_cos();
        let r = Matrix2::new(co, -s, s, co);
        let k = r * Matrix2::new(K_XI, 0.0, 0.0, K_ETA) * r.transpose();
        (
            DMatrix::from_column_slice(2, 2, k.as_slice()),
            DMatrix::identity(2, 2) * c,
        )
    })
    .unwrap();
    growth_per_rev(&multipliers(&phi).unwrap())
}

#[test]
fn asymmetric_shaft_is_unstable_exactly_between_its_two_frequencies() {
    let (f1, f2) = (
        (K_XI / M).sqrt() / (2.0 * PI),
        (K_ETA / M).sqrt() / (2.0 * PI),
    );
    let speeds: Vec<f64> = (0..=40).map(|i| 8.0 + 0.25 * i as f64).collect();
    let growth: Vec<f64> = speeds.iter().map(|s| jeffcott_growth(0.0, *s)).collect();
    let ranges = unstable_ranges(&speeds, &growth, |s| Ok(jeffcott_growth(0.0, s))).unwrap();
    eprintln!("undamped: unstable {ranges:?} Hz, closed form [{f1}, {f2}] Hz");
    assert_eq!(ranges.len(), 1, "{ranges:?}");
    assert!(
        (ranges[0][0] / f1 - 1.0).abs() < 1e-4,
        "{ranges:?} against {f1}"
    );
    assert!(
        (ranges[0][1] / f2 - 1.0).abs() < 1e-4,
        "{ranges:?} against {f2}"
    );
    // Stationary damping c/(2m) = 25 /s outgrows the band's largest growth rate
    // (k_η − k_ξ)/(4 m ω) ≈ 7 /s: stable at every speed.
    let damped: Vec<f64> = speeds.iter().map(|s| jeffcott_growth(100.0, *s)).collect();
    let ranges = unstable_ranges(&speeds, &damped, |s| Ok(jeffcott_growth(100.0, s))).unwrap();
    assert!(ranges.is_empty(), "damped: {ranges:?}");
    assert!(damped.iter().all(|g| *g < 0.0));
}

#[test]
fn axisymmetric_rotor_on_anisotropic_supports_matches_the_stationary_eigenvalues() {
    let text = format!(
        r#"name = "jeffcott-anisotropic"
{rotor}
[[supports]]
node = "bearing_a"
type = "linear"
spring = {{ kx_n_per_m = 2.0e6, ky_n_per_m = 8.0e6, kxy_n_per_m = 1.0e5, cx_ns_per_m = 300.0, cy_ns_per_m = 500.0 }}
mass_kg = 5.0
ground = {{ kx_n_per_m = 3.0e7, ky_n_per_m = 6.0e7, cx_ns_per_m = 500.0, cy_ns_per_m = 500.0 }}
[[supports]]
node = "bearing_b"
type = "linear"
spring = {{ kx_n_per_m = 2.0e6, ky_n_per_m = 8.0e6, cx_ns_per_m = 300.0, cy_ns_per_m = 500.0 }}
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1e7
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "8n+12st"
"#,
        rotor = support::JEFFCOTT_ROTOR,
    );
    let scene = support::scene_from_text("jeffcott-anisotropic.toml", &text);
    let model = Model::build(&scene, None).unwrap();
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();
    for hz in [0.3, 10.0, 35.0, 60.0] {
        let omega = 2.0 * PI * hz;
        let floquet = growth_per_rev(&scene_multipliers(&sys, omega, 1.0e5).unwrap());
        let g = rotorsweep::linear::floquet::scene_growth(&sys, omega, 1.0e5).unwrap();
        assert!(g.converged, "{hz} Hz: {g:?}");
        assert_eq!(
            g.growth, floquet,
            "{hz} Hz: scene_multipliers and scene_growth agree"
        );
        let set = damped_modes(&sys, omega, Split::Whirl).unwrap();
        let lti = set
            .modes
            .iter()
            .map(|m| m.eigenvalue.re)
            .fold(f64::NEG_INFINITY, f64::max)
            * 2.0
            * PI
            / omega;
        eprintln!("{hz} Hz: Floquet ln|μ|max {floquet:.6}, stationary T·max Re λ {lti:.6}");
        assert!(
            (floquet / lti - 1.0).abs() < 1e-3,
            "{hz} Hz: Floquet {floquet}, stationary {lti}"
        );
    }
}
