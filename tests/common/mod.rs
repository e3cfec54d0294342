//! Shared helpers for the physics tests: uniform tubes, constrained eigen-solutions, state matrices.
#![allow(dead_code)]

use nalgebra::DMatrix;
use rotorsweep::fe::{Material, RotorSpec, SectionSpec, SegmentSpec};

/// Structural steel of physics.md §10.
pub const STEEL: Material = Material {
    youngs_modulus: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A uniform tube of `length` [m], outer/inner diameter [m], `n` elements, from z = 0.
pub fn tube(length: f64, outer: f64, inner: f64, n: usize) -> RotorSpec {
    RotorSpec {
        z_start: 0.0,
        segments: vec![SegmentSpec {
            length,
            section: SectionSpec::Tube { outer, inner },
            elements: n,
            material: STEEL,
        }],
        disks: Vec::new(),
        point_masses: Vec::new(),
        named_points: Vec::new(),
        balancing: None,
    }
}

/// Keeps the rows and columns of `keep`.
pub fn restrict(a: &DMatrix<f64>, keep: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(keep.len(), keep.len(), |i, j| a[(keep[i], keep[j])])
}

/// Natural frequencies [Hz] of K, M restricted to the DOFs not in `fixed`, ascending.
pub fn frequencies(k: &DMatrix<f64>, m: &DMatrix<f64>, fixed: &[usize]) -> Vec<f64> {
    let keep: Vec<usize> = (0..k.nrows()).filter(|i| !fixed.contains(i)).collect();
    let eig = rotorsweep::eigen::generalized_symmetric(&restrict(k, &keep), &restrict(m, &keep))
        .expect("eigen-solution");
    eig.values
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// First-order state matrix [[0, I], [−M⁻¹K, −M⁻¹C]].
pub fn state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let minv = m.clone().cholesky().expect("M positive definite").inverse();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-&minv * k));
    a.view_mut((n, n), (n, n)).copy_from(&(-&minv * c));
    a
}

/// Inverse of the state matrix, [[−K⁻¹C, −K⁻¹M], [I, 0]] (K must be non-singular).
pub fn inverse_state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let lu = k.clone().lu();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, 0), (n, n))
        .copy_from(&(-lu.solve(c).expect("K non-singular")));
    a.view_mut((0, n), (n, n))
        .copy_from(&(-lu.solve(m).expect("K non-singular")));
    a.view_mut((n, 0), (n, n)).fill_with_identity();
    a
}
