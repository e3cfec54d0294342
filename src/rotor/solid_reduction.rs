//! The reduced model of a solid or shell body in a scene: Craig–Bampton at its attachments,
//! orthogonalised, with the rotating-frame terms of a general body, seen at its attachment
//! points.
//!
//! In: a [`SolidBody`] (SI: sparse M and K, optionally K_σ, each DOF's node position, the attachment points)
//! and the number of fixed-interface normal modes. Out: a [`ReducedModel`] as the beam rotor's
//! (physics.md §3–§4): mass-normalised modes (five rigid: translations x, y, z, tilts about x
//! and y; the spin dropped), every body-frame matrix and load projected on them, and Φ's rows
//! at the attachment points only (six per point, ascending z: `node_z` their z [m]), so the
//! supports, sensors and drive of a scene act on a ring's RBE3 reference point; `rotation` the
//! rotation generator ΦᵀMS̄Φ; or a [`ReductionError`].
//! Method: the sparse Craig–Bampton basis T of [`super::sparse_reduction::craig_bampton`]
//! (interface: every DOF of the attachment nodes; Ψ and the lowest normal modes from one
//! sparse Cholesky factor), orthogonalised as the beam rotor's
//! ([`super::reduction::orthogonalise`]); Φ = T V over the body's DOFs (n × modes, dense).
//! Rotating terms (the floating-frame formulation's inertia terms of a general body, as
//! [`super::import::invariants::rotating_terms`] but projected without a dense n × n matrix):
//! with S̄ = ẑ× on each node's translation (and rotation) triple and A = (MΦ)ᵀ(S̄Φ) = ΦᵀMS̄Φ,
//! G_c = ½(A − Aᵀ), C = A, G_s = −A − Aᵀ, E = (S̄Φ)ᵀM(S̄Φ), f_t = (MΦ)ᵀr_z, f_c = (S̄Φ)ᵀM r_z,
//! g_x|y = (MΦ)ᵀr_x|y (r the rigid motions). A stress stiffening K_σ (per (rad/s)²) is
//! projected on the same basis, ΦᵀK_σΦ = Vᵀ K̂_σ V (the Craig–Bampton K̂_σ of the sparse
//! reduction), as the dense path projects an axis body's. Exact for translation DOFs (solids); a shell's
//! rotation DOFs miss the second-order rotary-inertia terms (the invariants' module doc).
//! Kinetic energy by family from M restricted to the u_x (and θ_y), u_y (θ_x), u_z and θ_z
//! rows. Cost: the sparse reduction, three sparse × (n × modes) products and the dense
//! modes × modes ones.

use faer::Mat;
use nalgebra::{DMatrix, DVector};

use super::import::invariants::{rigid_modes, spin_operator};
use super::import::solid::SolidBody;
use super::reduction::{family, orthogonalise, ReducedModel, ReductionError};
use super::sparse_reduction::craig_bampton;

fn to_na(a: &Mat<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// The reduced model of `solid` with `n_normal` normal modes (module doc).
pub fn reduce(solid: &SolidBody, n_normal: usize) -> Result<ReducedModel, ReductionError> {
    let body = &solid.body;
    let b = &solid.interface;
    let n = body.dofs.len();
    let cb = craig_bampton(
        &body.stiffness,
        &body.mass,
        body.stress.as_ref(),
        b,
        n_normal,
        true,
    )?;
    let (interior, t_i) = cb.basis.as_ref().expect("basis kept");
    let rigid = rigid_modes(&body.dofs, &solid.positions);
    let nb = b.len();
    let rigid_b = DMatrix::from_fn(nb, 6, |j, c| rigid[(b[j], c)]);
    let o = orthogonalise(&cb.k, &cb.m, &rigid_b, n_normal)?;
    let nm = o.v.ncols();
    let v = Mat::from_fn(o.v.nrows(), nm, |i, j| o.v[(i, j)]);
    let tv = t_i * &v;
    let mut phi = Mat::zeros(n, nm);
    for (j, &r) in b.iter().enumerate() {
        for c in 0..nm {
            phi[(r, c)] = v[(j, c)];
        }
    }
    for (i, &r) in interior.iter().enumerate() {
        for c in 0..nm {
            phi[(r, c)] = tv[(i, c)];
        }
    }
    let spin = spin_operator(&body.dofs);
    let sphi = Mat::from_fn(n, nm, |i, c| spin[i].map_or(0.0, |(k, s)| s * phi[(k, c)]));
    let mphi = body.mass.mul(&phi);
    let msphi = body.mass.mul(&sphi);
    let a = to_na(&(mphi.transpose() * &sphi));
    let e = to_na(&(sphi.transpose() * &msphi));
    let sym = |x: DMatrix<f64>| 0.5 * (&x + x.transpose());
    let col = |c: usize| Mat::from_fn(n, 1, |i, _| rigid[(i, c)]);
    let modal = |x: &Mat<f64>, r: &Mat<f64>| -> DVector<f64> {
        let y = x.transpose() * r;
        DVector::from_fn(nm, |i, _| y[(i, 0)])
    };
    let mrz = body.mass.mul(&col(5));
    let family_mass = std::array::from_fn(|f| {
        let mut mf = body.mass.clone();
        let fam = |i: usize| family(body.dofs[i].dof);
        mf.map(|i, j, x| if fam(i) == f && fam(j) == f { x } else { 0.0 });
        sym(to_na(&(phi.transpose() * mf.mul(&phi))))
    });
    let order = by_z(solid);
    let mut rows = DMatrix::zeros(6 * order.len(), nm);
    for (p, &k) in order.iter().enumerate() {
        for (d, row) in solid.attachments[k].rows.iter().enumerate() {
            for &(r, x) in row {
                for c in 0..nm {
                    rows[(6 * p + d, c)] += x * phi[(r, c)];
                }
            }
        }
    }
    let mut model = ReducedModel {
        index: Vec::new(),
        freq_hz: Vec::new(),
        labels: Vec::new(),
        kinds: Vec::new(),
        phi: rows,
        k: sym(o.v.transpose() * &cb.k * &o.v),
        m: sym(o.v.transpose() * &cb.m * &o.v),
        gc: 0.5 * (&a - a.transpose()),
        e: sym(e),
        c: a.clone(),
        gs: -(&a + a.transpose()),
        ks: cb.ks.as_ref().map(|a| sym(o.v.transpose() * a * &o.v)),
        family_mass,
        fc: modal(&sphi, &mrz),
        ft: modal(&mphi, &col(5)),
        gx: modal(&mphi, &col(0)),
        gy: modal(&mphi, &col(1)),
        node_z: order
            .iter()
            .map(|&k| solid.attachments[k].centre[2])
            .collect(),
        rotation: Some(a),
        cb_normal: 0,
        selection: String::new(),
    };
    o.finish(&mut model, n_normal);
    Ok(model)
}

/// The attachment names of `solid` in the order of [`reduce`]'s rows (ascending z): name →
/// point index.
pub fn attachment_order(solid: &SolidBody) -> Vec<(String, usize)> {
    by_z(solid)
        .iter()
        .enumerate()
        .map(|(p, &k)| (solid.attachments[k].name.clone(), p))
        .collect()
}

/// The attachments' indices by ascending z (stable: equal z keep their order).
fn by_z(solid: &SolidBody) -> Vec<usize> {
    let mut order: Vec<usize> = (0..solid.attachments.len()).collect();
    order.sort_by(|&x, &y| {
        let z = |k: usize| solid.attachments[k].centre[2];
        z(x).total_cmp(&z(y))
    });
    order
}
