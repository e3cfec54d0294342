//! A large FE body read sparse: the matrices as entries, checked, in SI, for the sparse
//! reduction ([`crate::rotor::sparse_reduction`]).
//!
//! In: the [`BodyFiles`] of a Matrix Market body (mass, stiffness, node and DOF tables, units).
//! Out: a [`SparseBody`]: M and K as [`Sparse`] matrices in the files' DOF order, SI (kg, N/m,
//! kg m², N m/rad …), with the node and DOF tables; or an [`InputError`] naming the file and the
//! line or entry: a truncated file, an entry given twice, a size that does not match the DOF
//! table or the other matrix, a matrix not symmetric, wrong units (`% units:` differing from
//! the scene's), a node the DOF table names that the node table lacks, a mass matrix that is
//! not positive definite, an Abaqus, DMIG or OP4 body (read dense only).
//! Method: the Matrix Market entries ([`super::matrix_market::read_sparse`]); symmetry of a
//! `general` file checked entry by entry against its mirror (binary search), to 1e-10 of the
//! largest entry, as the dense reader does; the same unit scaling as [`super::body`] (mass ×
//! length^r, r the rotation DOFs among row and column); positive-definite mass by its sparse
//! Cholesky factor. Nodes may lie anywhere (no axis check: the reduction does not need one).
//! Memory: the entries (24 bytes each, both triangles) and the compressed matrices.

use std::path::Path;

use super::files::{BodyFiles, Format};
use super::matrix_market::{self, Symmetry};
use super::tables::{self, Dof, Node, Units, DOF_NAMES};
use crate::error::InputError;
use crate::numerics::sparse::Sparse;

/// Relative asymmetry a symmetric matrix may have (of its largest entry), as [`super::body`].
const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// A body read sparse (module doc).
#[derive(Debug, Clone)]
pub struct SparseBody {
    /// Mass matrix, SI, the files' DOF order.
    pub mass: Sparse,
    /// Stiffness matrix, SI, the files' DOF order.
    pub stiffness: Sparse,
    /// The DOF of each matrix row.
    pub dofs: Vec<Dof>,
    /// The node table, SI.
    pub nodes: Vec<Node>,
}

fn dof_name(d: &Dof) -> String {
    format!("node {} {}", d.node, DOF_NAMES[d.dof])
}

/// A `general` file's matrix checked against its transpose (module doc).
fn symmetric(path: &Path, a: &Sparse, dofs: &[Dof]) -> Result<(), InputError> {
    let scale = a.amax();
    for j in 0..a.n() {
        for (i, x) in a.column(j) {
            let y = a.get(j, i);
            if i != j && (x - y).abs() > SYMMETRY_TOLERANCE * scale {
                return Err(InputError::new(
                    path,
                    format!(
                        "the matrix is not symmetric: entry ({}, {}) = {x:e} ({} × {}) but ({}, {}) = {y:e}",
                        i + 1,
                        j + 1,
                        dof_name(&dofs[i]),
                        dof_name(&dofs[j]),
                        j + 1,
                        i + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The matrix of a file, checked symmetric and scaled to SI (module doc).
fn read_matrix(
    path: &Path,
    units: Units,
    dofs_of: &mut dyn FnMut(usize) -> Result<Vec<Dof>, InputError>,
) -> Result<(Sparse, Vec<Dof>), InputError> {
    let m = matrix_market::read_sparse(path)?;
    if let Some((u, line)) = &m.units {
        if !u.starts_with(units.name()) {
            return Err(InputError::new(
                path,
                format!(
                    "the file is in units `{u}`, the scene says `{}`",
                    units.name()
                ),
            )
            .at_line(*line));
        }
    }
    if m.symmetry == Symmetry::SkewSymmetric {
        return Err(InputError::new(
            path,
            "the file is skew-symmetric: a mass or stiffness matrix must be symmetric",
        )
        .at_line(1));
    }
    let dofs = dofs_of(m.n)?;
    let mut a = Sparse::from_entries(m.n, m.entries);
    if m.symmetry == Symmetry::General {
        symmetric(path, &a, &dofs)?;
    }
    let rot = |k: usize| i32::from(dofs[k].dof >= 3);
    a.map(|i, j, x| x * units.mass() * units.length().powi(rot(i) + rot(j)));
    Ok((a, dofs))
}

/// Reads and checks a body sparse (module doc).
pub fn load(f: &BodyFiles) -> Result<SparseBody, InputError> {
    if f.format != Format::MatrixMarket {
        return Err(InputError::new(
            &f.mass,
            "the sparse reduction reads Matrix Market bodies (`format = \"matrix-market\"`); \
             Abaqus, DMIG and OP4 files are read dense",
        ));
    }
    let dofs_path = f.dofs.as_ref().ok_or_else(|| {
        InputError::new(&f.mass, "a Matrix Market body needs a DOF table (`dofs`)")
    })?;
    let nodes = tables::read_nodes(&f.nodes, f.units)?;
    let mut table = None;
    let mut dofs_of = |n: usize| -> Result<Vec<Dof>, InputError> {
        if let Some((m, d)) = &table {
            if *m != n {
                return Err(InputError::new(
                    &f.stiffness,
                    format!(
                        "the stiffness matrix is {n} × {n}, the mass matrix {} is {m} × {m}",
                        f.mass.display()
                    ),
                ));
            }
            return Ok(Vec::clone(d));
        }
        let d = tables::read_dofs(dofs_path, n, &nodes, &f.nodes)?;
        table = Some((n, d.clone()));
        Ok(d)
    };
    let (mass, dofs) = read_matrix(&f.mass, f.units, &mut dofs_of)?;
    let (stiffness, _) = read_matrix(&f.stiffness, f.units, &mut dofs_of)?;
    if mass.cholesky().is_none() {
        let at = (0..mass.n())
            .find(|&i| !mass.column(i).any(|(r, x)| r == i && x > 0.0))
            .map(|i| {
                format!(
                    "; diagonal entry ({}, {}) of {} is not positive",
                    i + 1,
                    i + 1,
                    dof_name(&dofs[i])
                )
            })
            .unwrap_or_default();
        return Err(InputError::new(
            &f.mass,
            format!("the mass matrix is not positive definite{at}"),
        ));
    }
    Ok(SparseBody {
        mass,
        stiffness,
        dofs,
        nodes,
    })
}
