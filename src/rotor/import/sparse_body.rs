//! A large FE body read sparse: the matrices as entries, checked, in SI, for the sparse
//! reduction ([`crate::rotor::sparse_reduction`]).
//!
//! In: the [`BodyFiles`] of a body in any format the dense path reads (Matrix Market, Abaqus,
//! DMIG, OP4: mass, stiffness, node table, DOF table where the format needs one, units; an
//! optional stress stiffness ΔK at a reference speed Ω_ref, [`StressFiles`]).
//! Out: a [`SparseBody`]: M and K (and K_σ = ΔK/Ω_ref² per (rad/s)², a `total` file less K) as
//! [`Sparse`] matrices in the files' DOF order, SI (kg, N/m, kg m², N m/rad …), with the node
//! and DOF tables; or an [`InputError`] naming the file and the
//! line or entry: a truncated file, an entry given twice, a size that does not match the DOF
//! table or the other matrix, a matrix not symmetric, wrong units (`% units:` differing from
//! the scene's), a node the DOF table names that the node table lacks, a mass matrix that is
//! not positive definite, a stress stiffness of another size or not symmetric (checked entry by
//! entry in every format), and every error of the format's reader.
//! Method: each format's reader gives its [`Entries`] (the same readers as the dense path's:
//! [`super::matrix_market::read_sparse`], [`super::abaqus`], [`super::dmig`], [`super::op4`]),
//! so a body reads alike in every format; symmetry of a Matrix Market `general` file and of an
//! Abaqus file checked entry by entry against its mirror (binary search), to 1e-10 of the
//! largest entry, as the dense reader does (the DMIG and OP4 readers check their own); stored
//! zeros dropped (OP4 stores none), so a body has one pattern whatever its format; the
//! same unit scaling as [`super::body`] (mass × length^r, r the rotation DOFs among row and
//! column); positive-definite mass by its sparse
//! Cholesky factor. Nodes may lie anywhere (no axis check: the reduction does not need one).
//! Memory: the entries (24 bytes each, both triangles) and the compressed matrices.

use std::path::Path;

use super::entries::Entries;
use super::files::{dof_table, same_size, units_check, BodyFiles, Format, StressFiles, StressKind};
use super::matrix_market::{self, Symmetry};
use super::tables::{self, Dof, Node, Units, DOF_NAMES};
use super::{abaqus, dmig, op4};
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
    /// Stress stiffening per (rad/s)², K_σ = ΔK/Ω_ref² (SI, the files' DOF order), if the files
    /// give it ([`StressFiles`]).
    pub stress: Option<Sparse>,
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

/// A Matrix Market file's entries, its units checked; whether its symmetry is still to check
/// (a `general` file).
fn read_market(path: &Path, units: Units) -> Result<(Entries, bool), InputError> {
    let m = matrix_market::read_sparse(path)?;
    units_check(path, &m.units, units)?;
    if m.symmetry == Symmetry::SkewSymmetric {
        return Err(InputError::new(
            path,
            "the file is skew-symmetric: a mass or stiffness matrix must be symmetric",
        )
        .at_line(1));
    }
    let e = Entries {
        n: m.n,
        entries: m.entries,
    };
    Ok((e, m.symmetry == Symmetry::General))
}

/// A reader's entries as a sparse matrix, checked symmetric when `check` (module doc) and
/// scaled to SI.
fn finish(
    path: &Path,
    e: Entries,
    dofs: &[Dof],
    units: Units,
    check: bool,
) -> Result<Sparse, InputError> {
    // A stored zero is no entry (OP4 stores none): the same pattern, so the same fill-reducing
    // order and the same numbers, from every format.
    let mut entries = e.entries;
    entries.retain(|&(_, _, x)| x != 0.0);
    let mut a = Sparse::from_entries(e.n, entries);
    if check {
        symmetric(path, &a, dofs)?;
    }
    let rot = |k: usize| i32::from(dofs[k].dof >= 3);
    a.map(|i, j, x| x * units.mass() * units.length().powi(rot(i) + rot(j)));
    Ok(a)
}

/// A matrix's entries and whether its symmetry is still to check.
type ToCheck = (Entries, bool);

/// The mass and stiffness entries of any format (the dense path reads Abaqus, DMIG and OP4
/// bodies by it too), the DOFs, and whether each one's symmetry is still to check.
pub(super) fn read_pair(
    f: &BodyFiles,
    nodes: &[Node],
) -> Result<(ToCheck, ToCheck, Vec<Dof>), InputError> {
    let table = |n: usize| dof_table(f, n, nodes);
    match f.format {
        Format::MatrixMarket => {
            let m = read_market(&f.mass, f.units)?;
            let dofs = table(m.0.n)?;
            let k = read_market(&f.stiffness, f.units)?;
            same_size(f, m.0.n, k.0.n)?;
            Ok((m, k, dofs))
        }
        Format::Op4 => {
            // The reader checks symmetry (OP4 stores every entry).
            let m = op4::read(&f.mass, f.names.mass.as_deref(), "fe.mass_matrix")?;
            let dofs = table(m.n)?;
            let k = op4::read(
                &f.stiffness,
                f.names.stiffness.as_deref(),
                "fe.stiffness_matrix",
            )?;
            same_size(f, m.n, k.n)?;
            Ok(((m, false), (k, false), dofs))
        }
        Format::Dmig => {
            // The reader checks symmetry (IFO 1 both triangles, IFO 6 mirrored).
            let ((m, um), (k, uk), dofs) = dmig::read_pair(
                dmig::Named {
                    path: &f.mass,
                    name: f.names.mass.as_deref(),
                    key: "fe.mass_matrix",
                },
                dmig::Named {
                    path: &f.stiffness,
                    name: f.names.stiffness.as_deref(),
                    key: "fe.stiffness_matrix",
                },
                nodes,
                &f.nodes,
            )?;
            units_check(&f.mass, &um, f.units)?;
            units_check(&f.stiffness, &uk, f.units)?;
            Ok(((m, false), (k, false), dofs))
        }
        Format::Abaqus => {
            // Both triangles kept where both are given: checked here.
            let (m, k, dofs) = abaqus::read_pair(&f.mass, &f.stiffness, nodes, &f.nodes)?;
            Ok(((m, true), (k, true), dofs))
        }
    }
}

/// The entries of the stress-stiffness file `path` in the body's format (the dense path reads
/// Abaqus, DMIG and OP4 stress files by it too), a DMIG file's units checked; Abaqus and DMIG
/// entries on the body's DOFs `dofs`.
pub(super) fn stress_entries(
    f: &BodyFiles,
    path: &Path,
    nodes: &[Node],
    dofs: &[Dof],
) -> Result<Entries, InputError> {
    Ok(match f.format {
        Format::MatrixMarket => read_market(path, f.units)?.0,
        Format::Abaqus => abaqus::read_on(path, dofs, nodes, &f.nodes)?,
        Format::Dmig => {
            let named = dmig::Named {
                path,
                name: f.names.stress.as_deref(),
                key: "fe.stress_stiffness_matrix",
            };
            let (e, u) = dmig::read_on(named, dofs, nodes, &f.nodes)?;
            units_check(path, &u, f.units)?;
            e
        }
        Format::Op4 => op4::read(
            path,
            f.names.stress.as_deref(),
            "fe.stress_stiffness_matrix",
        )?,
    })
}

/// The stress stiffening per (rad/s)², K_σ = ΔK/Ω_ref², in the DOF order `dofs` and SI
/// (module doc; as [`super::body`]'s dense reader): the file in the body's format, checked
/// symmetric entry by entry whatever its format, of the body's size; a `total` file less the
/// body's stiffness `k` (SI).
fn read_stress(
    f: &BodyFiles,
    s: &StressFiles,
    nodes: &[Node],
    dofs: &[Dof],
    k: &Sparse,
) -> Result<Sparse, InputError> {
    let path = &s.stiffness;
    let e = stress_entries(f, path, nodes, dofs)?;
    if e.n != dofs.len() {
        return Err(InputError::new(
            path,
            format!(
                "the stress stiffness is {} × {}, the body has {} DOFs (the mass matrix {})",
                e.n,
                e.n,
                dofs.len(),
                f.mass.display()
            ),
        ));
    }
    let mut a = finish(path, e, dofs, f.units, true)?;
    if s.kind == StressKind::Total {
        a = a.plus_scaled(k, -1.0);
    }
    let w = std::f64::consts::TAU * s.reference_hz;
    a.map(|_, _, x| x / (w * w));
    Ok(a)
}

/// Reads and checks a body sparse (module doc).
pub fn load(f: &BodyFiles) -> Result<SparseBody, InputError> {
    let nodes = tables::read_nodes(&f.nodes, f.units)?;
    let ((m, check_m), (k, check_k), dofs) = read_pair(f, &nodes)?;
    let mass = finish(&f.mass, m, &dofs, f.units, check_m)?;
    let stiffness = finish(&f.stiffness, k, &dofs, f.units, check_k)?;
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
    let stress = match &f.stress {
        Some(s) => Some(read_stress(f, s, &nodes, &dofs, &stiffness)?),
        None => None,
    };
    Ok(SparseBody {
        mass,
        stiffness,
        stress,
        dofs,
        nodes,
    })
}
