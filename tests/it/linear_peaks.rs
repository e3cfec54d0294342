//! The unbalance response's peaks with the default sweep (1 Hz steps): each refined peak, and the
//! highest, against a 0.005 Hz reference sweep (the reference is the same frequency-domain
//! solve, so the two differ only by where they sample: the measure), and the `coarse`
//! flag where the 1 Hz sweep misses a peak. On the reference roll (anisotropic stands, criticals
//! 30.52, 32.35 and 82.45 Hz, docs/linear.md), a new roll whose first critical pair falls
//! between the samples (tests/fixtures/new-roll.toml) and the Jeffcott rotor. No peak is
//! reported twice.

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
    // A 0.005 Hz sweep over [a, b]: its interior local maxima (speed [Hz], major semi-axis [µm]).
    let fine = |plane: &(String, nalgebra::DMatrix<f64>), a: f64, b: f64| {
        let n = ((b - a) / 0.005).round() as usize;
        let curve: Vec<(f64, f64)> = (0..=n)
            .map(|i| a + 0.005 * i as f64)
            .map(|s| {
                let r = plane_response(&sys, TAU * s, &sys.unbalance, std::slice::from_ref(plane))
                    .unwrap();
                (s, 1e6 * r[0].major())
            })
            .collect();
        curve
            .windows(3)
            .filter(|w| w[1].1 >= w[0].1 && w[1].1 > w[2].1)
            .map(|w| w[1])
            .collect::<Vec<_>>()
    };
    for (name, rows) in &sys.sensors {
        let plane = (name.clone(), rows.clone());
        let ours: Vec<_> = resp.peaks.iter().filter(|p| &p.plane == name).collect();
        // Each peak: within 1 % of the nearest local maximum of a 0.005 Hz sweep ±0.25 Hz
        // around it, and within a step of it.
        for p in &ours {
            let (at, reference) = fine(&plane, p.speed_hz - 0.25, p.speed_hz + 0.25)
                .into_iter()
                .min_by(|x, y| {
                    (x.0 - p.speed_hz)
                        .abs()
                        .total_cmp(&(y.0 - p.speed_hz).abs())
                })
                .expect("a local maximum of the fine sweep");
            eprintln!(
                "{scene_path} {name}: peak {:.4} µm at {:.4} Hz (critical {:.4} Hz), 0.005 Hz \
                 sweep {reference:.4} µm at {at:.3} Hz, the 1 Hz sweep shows {:.4} µm, coarse {}",
                p.major_um, p.speed_hz, p.critical_hz, p.sampled_um, p.coarse
            );
            assert!(
                (p.major_um / reference - 1.0).abs() < 0.01 && (at - p.speed_hz).abs() <= 0.005,
                "{scene_path} {name} at {} Hz: {} µm vs reference {reference} µm at {at} Hz",
                p.speed_hz,
                p.major_um
            );
            assert_eq!(p.coarse, p.sampled_um < 0.99 * p.major_um);
        }
        // The Bode's highest peak: the largest reported against the largest local maximum of a
        // 0.005 Hz sweep over every critical speed's neighbourhood (±3 Hz).
        let (a, b) = ours.iter().fold((f64::MAX, 0.0f64), |(a, b), p| {
            (a.min(p.critical_hz - 3.0), b.max(p.critical_hz + 3.0))
        });
        let reference = fine(&plane, a.max(0.0), b.min(100.0))
            .into_iter()
            .map(|x| x.1)
            .fold(0.0, f64::max);
        let top = ours.iter().map(|p| p.major_um).fold(0.0, f64::max);
        eprintln!(
            "{scene_path} {name}: highest peak {top:.4} µm, 0.005 Hz sweep {reference:.4} µm"
        );
        assert!((top / reference - 1.0).abs() < 0.01, "{top} vs {reference}");
    }
    // No peak twice.
    for (i, p) in resp.peaks.iter().enumerate() {
        assert!(
            !resp.peaks[..i]
                .iter()
                .any(|q| q.plane == p.plane && (q.speed_hz - p.speed_hz).abs() < 1e-3),
            "{scene_path}: {p:?} twice"
        );
    }
}

#[test]
fn reference_roll_peaks_match_a_fine_sweep() {
    check("studies/scenes/reference-roll.toml");
}

#[test]
fn new_roll_peaks_match_a_fine_sweep() {
    // Criticals 26.12 and 27.25 Hz fall between the 1 Hz samples: both peaks coarse in the sweep.
    check("tests/fixtures/new-roll.toml");
}

#[test]
fn jeffcott_peaks_match_a_fine_sweep() {
    check("studies/scenes/jeffcott.toml");
}
