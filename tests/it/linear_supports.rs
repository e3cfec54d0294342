//! Support handling of the linear system, on a hollow roll-like tube (Ø320 mm, wall 18.72 mm,
//! 4.5 m: the reference roll's shell, physics.md §10) on linear bearings at its ends.
//! - Isotropic supports: every bending frequency comes as a horizontal–vertical pair in
//!   `supported_hz` (an axisymmetric rotor on isotropic supports has degenerate pairs; the
//!   eigen-solver returns arbitrary combinations of a pair, which used to be classed "mixed" and
//!   dropped), for several mode sets. Compared below 500 Hz: a mode set whose cut falls
//!   between the two members of a degenerate fixed-interface pair (60n+12st here) has a basis
//!   that is not closed under rotation, so its pairs differ slightly (9e-6 at 199 Hz) and its
//!   highest modes lose their partners.
//! - One support with zero stiffness: the rigid motion it leaves free has zero frequency; the
//!   Campbell sweep warns about it and its critical speeds are exactly the undamped synchronous
//!   roots of (K − Ω²(M − iG_s)) X = 0, found independently by `linear::critical_map`.

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::campbell::sweep;
use rotorsweep::linear::critical_map::undamped_critical_hz;
use rotorsweep::rotor::reduction::{ModeKind, ModeSelection};

fn tube(ka: f64, kb: f64) -> rotorsweep::scene::Scene {
    let text = format!(
        r#"name = "tube"
[materials.steel]
youngs_modulus_gpa = 210.0
poisson = 0.3
density_kg_m3 = 7850.0
[rotor]
[[rotor.segments]]
length_mm = 4500.0
outer_diameter_mm = 320.0
inner_diameter_mm = 282.56
elements = 30
material = "steel"
[rotor.nodes]
bearing_a = 0.0
bearing_b = 4500.0
[[rotor.sensors]]
name = "centre"
z_mm = 2250.0
[[supports]]
node = "bearing_a"
type = "linear"
spring = {{ kx_n_per_m = {ka}, ky_n_per_m = {ka} }}
[[supports]]
node = "bearing_b"
type = "linear"
spring = {{ kx_n_per_m = {kb}, ky_n_per_m = {kb} }}
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1.0e8
[damping]
bands = []
above_ratio = 0.0
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "30n+12st"
"#
    );
    support::scene_from_text("tube.toml", &text)
}

#[test]
fn isotropic_supports_keep_every_pair() {
    let s = tube(1e8, 1e8);
    for modes in ["10n+2st", "20n+12st", "30n+12st", "60n+12st"] {
        let sel = ModeSelection::parse(modes).unwrap();
        let model = Model::build(&s, Some(&sel)).unwrap();
        let sys = LinearSystem::of_scene(&s, &model).unwrap();
        let modes_ = sys.standstill_modes().unwrap();
        let pick = |k: ModeKind| -> Vec<f64> {
            modes_
                .iter()
                .filter(|m| m.kind == k && m.freq_hz > 1e-6 && m.freq_hz < 500.0)
                .map(|m| m.freq_hz)
                .collect()
        };
        let (h, v) = (pick(ModeKind::BendingX), pick(ModeKind::BendingY));
        let mixed = modes_
            .iter()
            .filter(|m| m.kind == ModeKind::Mixed && m.freq_hz < 500.0)
            .count();
        assert_eq!(mixed, 0, "{modes}: {mixed} mixed modes");
        assert_eq!(
            h.len(),
            v.len(),
            "{modes}: horizontal {h:?}, vertical {v:?}"
        );
        assert!(h.len() >= 3, "{modes}: {h:?}");
        for (a, b) in h.iter().zip(&v) {
            assert!((a / b - 1.0).abs() < 1e-4, "{modes}: pair {a} / {b} Hz");
        }
    }
}

#[test]
fn zero_stiffness_support_warns_and_finds_only_real_critical_speeds() {
    let s = tube(1e8, 0.0);
    let model = Model::build(&s, None).unwrap();
    let sys = LinearSystem::of_scene(&s, &model).unwrap();
    let speeds: Vec<f64> = (0..=100).map(|i| i as f64).collect();
    let data = sweep(&sys, &speeds, None).unwrap();
    assert!(
        data.warnings.iter().any(|w| w.contains("0 Hz")),
        "{:?}",
        data.warnings
    );
    let got: Vec<f64> = data.critical.iter().map(|c| c.speed_hz).collect();
    let want: Vec<f64> = undamped_critical_hz(&sys)
        .unwrap()
        .into_iter()
        .filter(|f| *f < 100.0)
        .collect();
    assert!(!want.is_empty());
    assert_eq!(
        got.len(),
        want.len(),
        "Campbell {got:?}, synchronous roots {want:?}"
    );
    for (a, b) in got.iter().zip(&want) {
        assert!(
            (a / b - 1.0).abs() < 1e-6,
            "Campbell {a} Hz, synchronous root {b} Hz"
        );
    }
}

#[test]
fn static_sag_and_support_forces_match_beam_theory() {
    use rotorsweep::rotor::section::tube_shear_factor;
    use std::f64::consts::PI;
    // Simply supported uniform beam under its weight q (Timoshenko & Gere, Mechanics of
    // Materials): midspan sag 5qL⁴/(384EI) + qL²/(8κGA) (shear), reactions qL/2.
    let s = tube(1e13, 1e13);
    let model = Model::build(&s, None).unwrap();
    let st = rotorsweep::linear::statics::solve(&s, &model).unwrap();
    let (ro, ri, l) = (0.160_f64, 0.14128_f64, 4.5_f64);
    let a = PI * (ro * ro - ri * ri);
    let i = PI / 4.0 * (ro.powi(4) - ri.powi(4));
    let (e, nu, g) = (210e9, 0.3, 9.81);
    let q = 7850.0 * a * g;
    let kappa = tube_shear_factor(ri / ro, nu);
    let sag = 5.0 * q * l.powi(4) / (384.0 * e * i) + q * l * l / (8.0 * kappa * e / 2.6 * a);
    let centre = st.sensors[0].1;
    assert!(
        (-centre.y / sag - 1.0).abs() < 2e-3,
        "sag {} um, beam theory {} um",
        -1e6 * centre.y,
        1e6 * sag
    );
    assert!(centre.x.abs() < 1e-6 * sag);
    for sp in &st.supports {
        assert!((sp.force.y / (0.5 * q * l) - 1.0).abs() < 1e-6, "{sp:?}");
    }
    assert!((st.weight / (q * l) - 1.0).abs() < 1e-9);
}
