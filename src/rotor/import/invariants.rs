//! The inertia invariants and rotating-frame terms of a general FE body, from its mass matrix
//! and its node coordinates.
//!
//! In: the mass matrix M (SI) of a body and, per matrix row, the position of its node [m] and
//! which DOF it is ([`Dof`](super::tables::Dof) numbering: 0–2 translations, 3–5 rotations).
//! Out: the six rigid-body motions in those DOFs ([`rigid_modes`]), the [`Invariants`] (mass
//! [kg], first moment [kg m], mass centre [m], inertia tensor about the origin and about the
//! mass centre [kg m²]: the invariants of the floating-frame formulation that a rigid body
//! needs), and the body-frame terms of a body spinning about z ([`rotating_terms`]).
//! Method: with R the rigid motions (translations x, y, z; rotations about x, y, z through the
//! origin), RᵀMR is the body's 6×6 rigid mass matrix [[m I, −[h]ₓ], [[h]ₓ, J_O]], exact for any
//! consistent or lumped mass matrix that moves rigidly with R. The rotating-frame terms follow
//! from the kinetic energy ½ (q̇ + Ω(r_z + S̄q))ᵀ M (q̇ + Ω(r_z + S̄q)), with r_z the rigid spin
//! and S̄ = ẑ× applied to every node's translation and rotation triple: Lagrange's equations give
//! G_c = ½(MS̄ + S̄M), E = S̄ᵀMS̄, C = MS̄, f_c = S̄ᵀM r_z, f_t = M r_z, g = M r_x|y and the
//! stationary-frame G_s = S̄M − MS̄ (the signs of `fe`'s module doc). This is exact for bodies
//! whose DOFs are translations of an isoparametric mesh (solids, point masses); for rotation
//! DOFs it leaves out the second-order rotary-inertia terms a beam or shell element has (the
//! `fe` module's ½ φ×(φ×d)), so an exported beam rotor carries its own matrices instead.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::tables::Dof;
use crate::rotor::fe::FeMatrices;

/// The rigid-body inertia of a body (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Invariants {
    /// Mass [kg].
    pub mass: f64,
    /// First moment Σ m s about the origin [kg m].
    pub first_moment: Vector3<f64>,
    /// Mass centre [m].
    pub centre: Vector3<f64>,
    /// Inertia tensor about the origin [kg m²].
    pub inertia_origin: Matrix3<f64>,
    /// Inertia tensor about the mass centre [kg m²].
    pub inertia_centre: Matrix3<f64>,
}

/// The six rigid motions (columns: translations x, y, z; rotations about x, y, z through the
/// origin) in the DOFs `dofs` of nodes at `pos` [m].
pub fn rigid_modes(dofs: &[Dof], pos: &[Vector3<f64>]) -> DMatrix<f64> {
    let mut r = DMatrix::zeros(dofs.len(), 6);
    for (i, (d, s)) in dofs.iter().zip(pos).enumerate() {
        if d.dof < 3 {
            r[(i, d.dof)] = 1.0;
            for a in 0..3 {
                r[(i, 3 + a)] = Vector3::ith(a, 1.0).cross(s)[d.dof];
            }
        } else {
            r[(i, d.dof)] = 1.0;
        }
    }
    r
}

/// The invariants of mass matrix `m` whose rigid motions are `rigid` ([`rigid_modes`]).
pub fn invariants(m: &DMatrix<f64>, rigid: &DMatrix<f64>) -> Invariants {
    invariants_of(&(rigid.transpose() * m * rigid))
}

/// The invariants of a body whose 6 × 6 rigid mass matrix RᵀMR is `r` ([`rigid_modes`]'s
/// order).
pub fn invariants_of(r: &DMatrix<f64>) -> Invariants {
    let mass = r[(0, 0)];
    // The translation–rotation block is −[h]ₓ: (e_a × h)_k = R[k, 3 + a].
    let h = Vector3::new(-r[(2, 4)], r[(2, 3)], r[(0, 4)]);
    let jo = Matrix3::from_fn(|i, j| r[(3 + i, 3 + j)]);
    let c = h / mass;
    // Parallel axes: J_O = J_C + m (|c|² I − c cᵀ).
    let jc = jo - mass * (Matrix3::identity() * c.norm_squared() - c * c.transpose());
    Invariants {
        mass,
        first_moment: h,
        centre: c,
        inertia_origin: jo,
        inertia_centre: jc,
    }
}

/// S̄ = ẑ× on every translation and rotation triple of `dofs`, as one entry per row: row i of
/// S̄ is ±1 in column j (x rows take −y, y rows take +x; z rows and a triple's missing partner
/// none). A triple must be complete for this to be the rotation of its vector.
pub(crate) fn spin_operator(dofs: &[Dof]) -> Vec<Option<(usize, f64)>> {
    let index: BTreeMap<(i64, usize), usize> = dofs
        .iter()
        .enumerate()
        .map(|(i, d)| ((d.node, d.dof), i))
        .collect();
    dofs.iter()
        .map(|d| {
            let base = d.dof - d.dof % 3;
            // (ẑ × v)_x = −v_y, (ẑ × v)_y = v_x.
            match d.dof % 3 {
                0 => index.get(&(d.node, base + 1)).map(|&j| (j, -1.0)),
                1 => index.get(&(d.node, base)).map(|&j| (j, 1.0)),
                _ => None,
            }
        })
        .collect()
}

/// S̄ A for S̄ given by rows ([`spin_operator`]).
fn spin_left(s: &[Option<(usize, f64)>], a: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
        s[i].map_or(0.0, |(k, v)| v * a[(k, j)])
    })
}

/// The body-frame matrices and loads of `fe`'s module doc for a body of mass matrix `m` and
/// stiffness `k` (module doc: exact for translation DOFs). S̄ has one entry per row, so its
/// products are index maps: A S̄ = (S̄ᵀ Aᵀ)ᵀ, S̄ᵀ = −S̄.
pub fn rotating_terms(
    m: &DMatrix<f64>,
    k: &DMatrix<f64>,
    dofs: &[Dof],
    pos: &[Vector3<f64>],
) -> FeMatrices {
    let s = spin_operator(dofs);
    let r = rigid_modes(dofs, pos);
    // M S̄ = (S̄ᵀ M)ᵀ = −(S̄ M)ᵀ for symmetric M.
    let sm = spin_left(&s, m);
    let ms = -sm.transpose();
    // E = S̄ᵀ M S̄ = −S̄ (M S̄).
    let e = -spin_left(&s, &ms);
    let col = |c: usize| -> DVector<f64> { m * r.column(c) };
    let ft = col(5);
    let fc = -spin_left(&s, &DMatrix::from_column_slice(ft.len(), 1, ft.as_slice()))
        .column(0)
        .into_owned();
    FeMatrices {
        gc: 0.5 * (&ms + &sm),
        e,
        c: ms.clone(),
        gs: &sm - &ms,
        fc,
        ft,
        gx: col(0),
        gy: col(1),
        m: m.clone(),
        k: k.clone(),
        ks: None,
    }
}
