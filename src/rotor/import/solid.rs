//! A solid or shell body and its attachment points: named nodes and ring attachments, the
//! points a scene's supports, sensors and drive act on.
//!
//! In: a [`SparseBody`] (SI; nodes anywhere), the named nodes (name → node id) and the rings
//! ([`super::rings`]; name → [`Ring`]). Out: a [`SolidBody`]: the body, each DOF's node
//! position [m], its [`Invariants`] (from RᵀMR, R the rigid motions of
//! [`super::invariants::rigid_modes`], M sparse), the Craig–Bampton interface (every DOF of the
//! named nodes and of the ring nodes, ascending row order) and the [`Attachment`]s, named nodes
//! first then rings (each in name order); or a reason with the key to blame (`fe.named.<name>`
//! or `fe.rings.<name>`; the caller names the file): a named node without a row in the DOF
//! table, a ring node without its `ux uy uz` rows.
//! Method: an attachment's motion (u_x, u_y, u_z [m], θ_x, θ_y, θ_z [rad]) is six rows over the
//! body's DOFs: a named node's own DOFs (coefficient 1; a DOF the node lacks, such as a solid
//! node's rotations, gives an empty row: no motion, no force), a ring's RBE3 interpolation
//! matrix R over its nodes' translations. A force and moment F on the point act on the body as
//! (rows)ᵀ F, so a support spring k on a ring adds Rᵀ k R to the body's stiffness.

use std::collections::{BTreeMap, BTreeSet};

use faer::Mat;
use nalgebra::{DMatrix, Vector3};

use super::invariants::{invariants_of, rigid_modes, Invariants};
use super::rings::Ring;
use super::sparse_body::SparseBody;
use super::tables::DOF_NAMES;

/// An attachment point (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Attachment {
    /// Its name (`fe.named` or `fe.rings`).
    pub name: String,
    /// Whether it is a ring (else a named node).
    pub ring: bool,
    /// Its position [m]: the node's, or the ring's reference point.
    pub centre: [f64; 3],
    /// Six rows (u_x, u_y, u_z, θ_x, θ_y, θ_z): (body DOF row, coefficient).
    pub rows: [Vec<(usize, f64)>; 6],
}

/// A solid or shell body with its attachment points (module doc).
#[derive(Debug, Clone)]
pub struct SolidBody {
    /// The matrices and tables, SI.
    pub body: SparseBody,
    /// Each DOF's node position [m].
    pub positions: Vec<Vector3<f64>>,
    /// Rigid-body inertia.
    pub invariants: Invariants,
    /// The Craig–Bampton interface: body DOF rows, ascending.
    pub interface: Vec<usize>,
    /// The attachment points, named nodes then rings.
    pub attachments: Vec<Attachment>,
}

/// The body `body` with the attachments `named` and `rings` (module doc); an error is
/// (key, reason), `dofs_file` the DOF table's path as the reason names it.
pub fn attach(
    body: SparseBody,
    named: &BTreeMap<String, i64>,
    rings: &BTreeMap<String, Ring>,
    dofs_file: &str,
) -> Result<SolidBody, (String, String)> {
    let mut row_of = BTreeMap::new();
    for (r, d) in body.dofs.iter().enumerate() {
        row_of.insert((d.node, d.dof), r);
    }
    let mut attachments = Vec::new();
    for (name, &id) in named {
        let rows: [Vec<(usize, f64)>; 6] = std::array::from_fn(|d| {
            row_of
                .get(&(id, d))
                .map(|&r| (r, 1.0))
                .into_iter()
                .collect()
        });
        if rows.iter().all(Vec::is_empty) {
            return Err((
                format!("fe.named.{name}"),
                format!("node {id} has no row in the DOF table {dofs_file}"),
            ));
        }
        let centre = body
            .nodes
            .iter()
            .find(|n| n.id == id)
            .map_or([f64::NAN; 3], |n| n.x);
        attachments.push(Attachment {
            name: name.clone(),
            ring: false,
            centre,
            rows,
        });
    }
    for (name, ring) in rings {
        let mut cols = Vec::new();
        for &id in &ring.nodes {
            for (d, dof_name) in DOF_NAMES.iter().enumerate().take(3) {
                let r = row_of.get(&(id, d)).ok_or_else(|| {
                    (
                        format!("fe.rings.{name}"),
                        format!(
                            "ring node {id} has no {dof_name} row in the DOF table {dofs_file}"
                        ),
                    )
                })?;
                cols.push(*r);
            }
        }
        let rows = std::array::from_fn(|d| {
            cols.iter()
                .enumerate()
                .map(|(k, &c)| (c, ring.matrix[(d, k)]))
                .collect()
        });
        attachments.push(Attachment {
            name: name.clone(),
            ring: true,
            centre: ring.centre,
            rows,
        });
    }
    let ids: BTreeSet<i64> = named
        .values()
        .copied()
        .chain(rings.values().flat_map(|r| r.nodes.iter().copied()))
        .collect();
    let interface = (0..body.dofs.len())
        .filter(|&r| ids.contains(&body.dofs[r].node))
        .collect();
    let at: BTreeMap<i64, [f64; 3]> = body.nodes.iter().map(|n| (n.id, n.x)).collect();
    let positions: Vec<Vector3<f64>> = body
        .dofs
        .iter()
        .map(|d| Vector3::from(at[&d.node]))
        .collect();
    let rigid = rigid_modes(&body.dofs, &positions);
    let mr = body
        .mass
        .mul(&Mat::from_fn(rigid.nrows(), 6, |i, j| rigid[(i, j)]));
    let rmr = DMatrix::from_fn(6, 6, |a, b| {
        (0..rigid.nrows()).map(|i| rigid[(i, a)] * mr[(i, b)]).sum()
    });
    Ok(SolidBody {
        invariants: invariants_of(&(0.5 * (&rmr + rmr.transpose()))),
        body,
        positions,
        interface,
        attachments,
    })
}
