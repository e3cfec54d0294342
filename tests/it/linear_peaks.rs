//! The unbalance response's peaks with the default sweep (1 Hz steps): the refined peak at each
//! critical speed against a 0.005 Hz reference sweep around it (the reference is the same
//! frequency-domain solve, so the two differ only by where they sample), and the `coarse` flag
//! where the 1 Hz sweep misses a peak. On the reference roll (anisotropic stands, criticals
//! 30.52, 32.35 and 82.45 Hz, docs/linear.md) and the Jeffcott rotor.

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::request::{compute, parse_speeds, Request};
use rotorsweep::linear::response::plane_response;
use rotorsweep::scene::Scene;

const TAU: f64 = 2.0 * std::f64::consts::PI;

fn check(scene_path: &str) {
    let path = support::repo().join(scene_path);
    let scene = Scene::load(&path, &[]).unwrap();
    let model = Model::build(&scene, None).unwrap();
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();
    let req = Request {
        speeds_hz: parse_speeds("0:100:101").unwrap(),
        max_freq_hz: None,
        unbalance: None,
        response: true,
        floquet: false,
        floquet_cutoff_hz: None,
        statics: false,
        critical_map: false,
        shapes: false,
    };
    let r = compute(&req, &scene, &model, &sys).unwrap();
    let resp = r.response.unwrap();
    assert!(!resp.peaks.is_empty(), "{scene_path}: no peak");
    for p in &resp.peaks {
        let plane = sys
            .sensors
            .iter()
            .find(|s| s.0 == p.plane)
            .expect("a sensor");
        // Reference: 0.005 Hz steps over ±1 Hz around the critical speed.
        let reference = (0..=400)
            .map(|i| p.critical_hz - 1.0 + 0.005 * i as f64)
            .map(|s| {
                let r = plane_response(&sys, TAU * s, &sys.unbalance, std::slice::from_ref(plane))
                    .unwrap();
                1e6 * r[0].major()
            })
            .fold(0.0, f64::max);
        assert!(
            (p.major_um / reference - 1.0).abs() < 0.01 && p.major_um >= reference * (1.0 - 1e-9),
            "{scene_path} {} at {} Hz: {} µm vs reference {} µm",
            p.plane,
            p.speed_hz,
            p.major_um,
            reference
        );
        assert_eq!(p.coarse, p.sampled_um < 0.99 * p.major_um);
    }
}

#[test]
fn reference_roll_peaks_match_a_fine_sweep() {
    check("studies/scenes/reference-roll.toml");
}

#[test]
fn jeffcott_peaks_match_a_fine_sweep() {
    check("studies/scenes/jeffcott.toml");
}
