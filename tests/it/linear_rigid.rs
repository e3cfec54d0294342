//! Linear analyses that always finish: rigid-body modes, the reduced basis, and where Floquet is
//! needed, on the hollow roll of tests/fixtures/hollow-roll.toml (Ø320/282.56 × 4 500 mm shell,
//! isotropic 1e8 N/m bearings without damping, no axial restraint).
//! - The axial rigid-body mode has zero frequency (a free body along its axis: F = m a, no
//!   restoring force, ω = 0 exactly) and is set apart: the other damped eigenvalues equal the
//!   ones of the full first-order form (the same matrices solved without setting it apart).
//! - The damped modes on the undamped modes below 30× the range agree with the full solve (the
//!   reduction's own statement: exact as the cut coupling goes to zero) on the modes listed.
//! - An axisymmetric rotor on isotropic supports has a time-invariant body-frame system (its
//!   matrices commute with the rotation), so no parametric instability: Floquet is not run; the
//!   reference roll (anisotropic stands) needs it.

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::basis::Coordinates;
use rotorsweep::linear::campbell::sweep;
use rotorsweep::linear::floquet::time_invariant;
use rotorsweep::linear::modes::{damped_modes, damped_modes_in, Kind, Split, ZERO_RAD_S};
use rotorsweep::numerics::eigen::general;
use rotorsweep::rotor::reduction::{ModeKind, ModeSelection};
use rotorsweep::scene::Scene;

const TAU: f64 = 2.0 * std::f64::consts::PI;

fn hollow(modes: &str) -> (Model, LinearSystem) {
    let path = support::repo().join("tests/fixtures/hollow-roll.toml");
    let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let sel = ModeSelection::parse(modes).unwrap();
    let model = Model::build(&scene, Some(&sel)).unwrap();
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();
    (model, sys)
}

#[test]
fn axial_rigid_mode_is_zero_and_set_apart() {
    let (_, sys) = hollow("30n+12st");
    let zero: Vec<_> = sys
        .standstill_modes()
        .unwrap()
        .into_iter()
        .filter(|m| m.freq_hz < 0.01)
        .collect();
    assert_eq!(zero.len(), 1, "{zero:?}");
    assert_eq!(zero[0].kind, ModeKind::Axial);
    let omega = TAU * 40.0;
    let set = damped_modes(&sys, omega, Split::Whirl).unwrap();
    assert_eq!(set.rigid, vec![Kind::Axial]);
    assert_eq!(set.zero_lateral, 0);
    // The full first-order form of the same matrices, rigid mode included.
    let (k, c) = sys.at(omega);
    let c = c + omega * &sys.gs;
    let a = support::state_matrix(&sys.m, &c, &k);
    let (values, _) = general(&a).unwrap();
    let mut full: Vec<f64> = values
        .iter()
        .filter(|l| l.im > 1e-9 * l.norm() && l.norm() > ZERO_RAD_S && -l.re / l.norm() < 0.95)
        .map(|l| l.im / TAU)
        .collect();
    full.sort_by(f64::total_cmp);
    let ours: Vec<f64> = set.modes.iter().map(|m| m.freq_hz).collect();
    assert_eq!(ours.len(), full.len());
    for (a, b) in ours.iter().zip(&full) {
        assert!((a / b - 1.0).abs() < 1e-8, "{a} vs {b}");
    }
}

#[test]
fn reduced_basis_matches_the_full_solve() {
    // 100n+12st: 112 coordinates, above FULL_MAX, so a range truncates the basis.
    let (_, sys) = hollow("100n+12st");
    let coords = Coordinates::new(&sys, Some(100.0)).unwrap();
    assert_eq!(coords.cutoff_hz, Some(3000.0));
    let (mut df, mut dz) = (0.0f64, 0.0f64);
    for speed in [0.0, 25.0, 80.0] {
        let full = damped_modes(&sys, TAU * speed, Split::Whirl).unwrap();
        let red = damped_modes_in(&coords, TAU * speed, Split::Whirl).unwrap();
        assert!(red.cutoff_hz.is_some());
        for m in red.modes.iter().filter(|m| m.freq_hz < 300.0) {
            let best = full
                .modes
                .iter()
                .min_by(|a, b| {
                    (a.freq_hz - m.freq_hz)
                        .abs()
                        .total_cmp(&(b.freq_hz - m.freq_hz).abs())
                })
                .unwrap();
            df = df.max((best.freq_hz / m.freq_hz - 1.0).abs());
            dz = dz.max((best.damping_ratio - m.damping_ratio).abs());
        }
    }
    // Measured: frequency 2.1e-5 (the 248.6 Hz mode at 80 Hz; at a 1 kHz cut-off 1.2e-3).
    eprintln!("reduced against full below 300 Hz: frequency {df:.2e}, damping ratio {dz:.2e}");
    assert!(df < 5e-5 && dz < 2e-5, "frequency {df}, damping ratio {dz}");
}

#[test]
fn the_200_mode_hollow_roll_sweeps_in_seconds() {
    let (_, sys) = hollow("200n+12st");
    let speeds: Vec<f64> = (0..=100).map(f64::from).collect();
    let t0 = std::time::Instant::now();
    let c = sweep(&sys, &speeds, None).unwrap();
    let took = t0.elapsed().as_secs_f64();
    assert!(took < 60.0, "{took} s");
    assert!(c.warnings.iter().any(|w| w.contains("rigid-body")));
    // First bending pair on 1e8 N/m bearings: critical speeds below 100 Hz.
    assert!(!c.critical.is_empty());
}

#[test]
fn axisymmetric_rotor_on_isotropic_supports_needs_no_floquet() {
    // 200n+12st cuts a degenerate pair (mode 200, bending-x, has no partner): the check is
    // on the mesh, so the rotor still counts as axisymmetric.
    for modes in ["30n+12st", "200n+12st"] {
        let (model, sys) = hollow(modes);
        for s in [1.0, 30.0, 100.0] {
            assert!(
                time_invariant(&sys, &model.rotor, TAU * s),
                "{modes} {s} Hz"
            );
        }
    }
    let path = support::repo().join("studies/scenes/reference-roll.toml");
    let scene = Scene::load(&path, &[]).unwrap();
    let model = Model::build(&scene, None).unwrap();
    let rref = LinearSystem::of_scene(&scene, &model).unwrap();
    assert!(!time_invariant(&rref, &model.rotor, TAU * 16.4));
}
