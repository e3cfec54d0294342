//! physics.md §9 check 3: for an axisymmetric rotor, the body-frame eigenvalues equal the
//! stationary-frame forward/backward whirl frequencies shifted by Ω, at several Ω. This proves
//! the body-frame Coriolis (G_c), spin-softening and rotary-inertia (E) matrices against the
//! independently written stationary-frame gyroscopic matrix (Lalanne & Ferraris: J_p Ω on the
//! tilts), on the FE model and on its reduced model.

use crate::support;

use std::f64::consts::PI;

use nalgebra::DMatrix;
use rotorsweep::numerics::eigen::general;
use rotorsweep::rotor::fe::{DiskSpec, Rotor, RotorSpec, SectionSpec, SegmentSpec, NDOF};
use rotorsweep::rotor::reduction::craig_bampton;
use support::{inverse_state_matrix, state_matrix, STEEL};

/// A stepped shaft with a heavy disk: strong gyroscopic splitting. Few elements keep the highest
/// frequency (and so the round-off of the non-symmetric eigen-solution) low.
fn rotor_spec() -> RotorSpec {
    let seg = |length, outer, inner, elements| SegmentSpec {
        length,
        section: SectionSpec::Tube {
            outer,
            inner,
            asymmetry: 0.0,
        },
        elements,
        material: STEEL,
    };
    RotorSpec {
        z_start: 0.0,
        segments: vec![
            seg(0.3, 0.05, 0.0, 4),
            seg(0.6, 0.08, 0.03, 8),
            seg(0.3, 0.05, 0.0, 4),
        ],
        disks: vec![DiskSpec {
            z: 0.75,
            mass: 40.0,
            polar: 0.8,
            diametral: 0.45,
        }],
        point_masses: Vec::new(),
        named_points: vec![("a".into(), 0.1), ("b".into(), 1.1)],
        balancing: None,
    }
}

/// Isotropic bearings at a and b (lateral springs), plus axial and torsional springs at a:
/// isotropic supports are the same in both frames.
fn support_stiffness(rotor: &Rotor, n: usize) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(n, n);
    for name in ["a", "b"] {
        let o = NDOF * rotor.named[name];
        k[(o, o)] += 2e8;
        k[(o + 1, o + 1)] += 2e8;
    }
    let o = NDOF * rotor.named["a"];
    k[(o + 2, o + 2)] += 1e9;
    k[(o + 5, o + 5)] += 1e6;
    k
}

/// Eigen-frequencies [Hz] (positive imaginary parts) and, for the stationary frame, whether
/// each is a forward whirl: x + iy turning with the spin (u_y = −i u_x for λ = iω).
/// `a_inv` is the inverse state matrix: its largest eigenvalues μ = 1/λ are the lowest modes,
/// which it resolves to round-off relative to themselves rather than to the highest mode.
fn spectrum(a_inv: &DMatrix<f64>, n: usize) -> Vec<(f64, f64)> {
    let (mu, vectors) = general(a_inv).unwrap();
    let values: Vec<faer::c64> = mu
        .iter()
        .map(|m| {
            let d = m.re * m.re + m.im * m.im;
            faer::c64::new(m.re / d, -m.im / d)
        })
        .collect();
    let mut out: Vec<(f64, f64)> = values
        .iter()
        .enumerate()
        .filter(|(_, l)| l.im > 1e-6)
        .map(|(i, l)| {
            // Σ Im(conj(u_x) u_y) over nodes, against the motion of all DOFs (θ_z at a 50 mm
            // radius): ≈ −½ forward, +½ backward, ≈ 0 for axial and torsion modes.
            let mut s = 0.0;
            let mut norm = 0.0;
            for node in 0..n / NDOF {
                let o = NDOF * node;
                let (ux, uy) = (vectors[(o, i)], vectors[(o + 1, i)]);
                s += ux.re * uy.im - ux.im * uy.re;
                for (d, w) in [(0, 1.0), (1, 1.0), (2, 1.0), (5, 0.05)] {
                    let v = vectors[(o + d, i)];
                    norm += w * w * (v.re * v.re + v.im * v.im);
                }
            }
            (l.im / (2.0 * PI), if norm > 0.0 { s / norm } else { 0.0 })
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

fn expected_body(stationary: &[(f64, f64)], spin_hz: f64) -> Vec<f64> {
    let mut v: Vec<f64> = stationary
        .iter()
        .map(|&(f, dir)| {
            if dir < -0.1 {
                (f - spin_hz).abs()
            } else if dir > 0.1 {
                f + spin_hz
            } else {
                f
            }
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v
}

#[test]
fn body_frame_equals_shifted_stationary_frame_on_the_fe_model() {
    let rotor = Rotor::mesh(&rotor_spec()).unwrap();
    let fe = rotor.assemble();
    let n = rotor.ndof();
    let k = &fe.k + support_stiffness(&rotor, n);
    let mut checked = 0;
    for spin_hz in [0.0, 20.0, 60.0, 150.0] {
        let w = 2.0 * PI * spin_hz;
        let stat = spectrum(&inverse_state_matrix(&fe.m, &(w * &fe.gs), &k), n);
        let body = spectrum(
            &inverse_state_matrix(&fe.m, &(2.0 * w * &fe.gc), &(&k - w * w * &fe.e)),
            n,
        );
        let want = expected_body(&stat, spin_hz);
        // Compare the lowest 16 frequencies (to ≈ 1.5 kHz) to 1e-8 relative (dropping the rotary-inertia
        // stiffening K_r from E, for instance, breaks this by 1e-4).
        for i in 0..16 {
            let got = body[i].0;
            assert!(
                (got - want[i]).abs() < 1e-8 * want[i],
                "Ω = {spin_hz} Hz, #{i}: body {got} vs shifted stationary {}",
                want[i]
            );
            checked += 1;
        }
        if spin_hz > 0.0 {
            // The gyroscopic disk splits forward and backward whirl visibly (0.24 % at 20 Hz).
            let lowest: Vec<&(f64, f64)> =
                stat.iter().filter(|s| s.1.abs() > 0.1).take(2).collect();
            assert!(
                lowest[1].0 / lowest[0].0 > 1.001,
                "no gyroscopic split at {spin_hz} Hz"
            );
        }
    }
    assert_eq!(checked, 64);
}

#[test]
fn body_frame_equals_shifted_stationary_frame_on_the_reduced_model() {
    let rotor = Rotor::mesh(&rotor_spec()).unwrap();
    let mut fe = rotor.assemble();
    fe.k += support_stiffness(&rotor, rotor.ndof());
    let b = [rotor.named["a"], rotor.named["b"]];
    // With the supports inside K there are no rigid modes to replace: reduce a free copy
    // instead, then project the supported K.
    let free = rotor.assemble();
    let red = craig_bampton(&rotor, &free, &b, 20).unwrap();
    let phi = &red.phi;
    let k = phi.transpose() * &fe.k * phi;
    let nm = red.len();
    for spin_hz in [0.0, 40.0, 120.0] {
        let w = 2.0 * PI * spin_hz;
        let stat = modal_spectrum(&red.m, &(w * &red.gs), &k, phi, rotor.ndof());
        let body_a = state_matrix(&red.m, &(2.0 * w * &red.gc), &(&k - w * w * &red.e));
        let (values, _) = general(&body_a).unwrap();
        let mut body: Vec<f64> = values
            .iter()
            .filter(|l| l.im > 1e-6)
            .map(|l| l.im / (2.0 * PI))
            .collect();
        body.sort_by(f64::total_cmp);
        let want = expected_body(&stat, spin_hz);
        for i in 0..12 {
            assert!(
                (body[i] - want[i]).abs() < 1e-7 * want[i].max(1.0),
                "reduced, Ω = {spin_hz} Hz, #{i}: {} vs {}",
                body[i],
                want[i]
            );
        }
        assert_eq!(body.len(), nm);
    }
}

/// Stationary spectrum of a modal model, with the whirl direction read in physical DOFs.
fn modal_spectrum(
    m: &DMatrix<f64>,
    c: &DMatrix<f64>,
    k: &DMatrix<f64>,
    phi: &DMatrix<f64>,
    ndof: usize,
) -> Vec<(f64, f64)> {
    let nm = m.nrows();
    let (values, vectors) = general(&state_matrix(m, c, k)).unwrap();
    let mut out: Vec<(f64, f64)> = values
        .iter()
        .enumerate()
        .filter(|(_, l)| l.im > 1e-6)
        .map(|(i, l)| {
            let (mut s, mut norm) = (0.0, 0.0);
            let u = |dof: usize| {
                (0..nm).fold((0.0, 0.0), |acc, j| {
                    let v = vectors[(j, i)];
                    (acc.0 + phi[(dof, j)] * v.re, acc.1 + phi[(dof, j)] * v.im)
                })
            };
            for node in 0..ndof / NDOF {
                let o = NDOF * node;
                let (ux, uy) = (u(o), u(o + 1));
                s += ux.0 * uy.1 - ux.1 * uy.0;
                for (d, w) in [(0, 1.0), (1, 1.0), (2, 1.0), (5, 0.05)] {
                    let v = u(o + d);
                    norm += w * w * (v.0 * v.0 + v.1 * v.1);
                }
            }
            (l.im / (2.0 * PI), if norm > 0.0 { s / norm } else { 0.0 })
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}
