//! An FE body from files: read, checked, converted to SI and to the rotor's DOF order.
//!
//! In: [`BodyFiles`]: the mass and stiffness matrices (Matrix Market, [`super::matrix_market`],
//! an Abaqus coordinate file, [`super::abaqus`], Nastran DMIG cards, [`super::dmig`], or a
//! Nastran OP4 ASCII file, [`super::op4`], the last two by matrix name), the node table and,
//! for Matrix Market and OP4, the DOF table ([`super::tables`]), the unit system, and optionally the body-frame rotating terms
//! a rotorsweep export writes (Coriolis G_c, spin softening E, angular acceleration C,
//! stationary gyroscopic G_s and the loads f_c, f_t, g_x, g_y), and optionally a stiffness
//! exported at a reference speed Ω_ref ([`StressFiles`]: stress stiffening).
//! Out: an [`ImportedBody`]: the node ids and z [m] in ascending z, the body-frame
//! [`FeMatrices`] over six DOFs per node in the order of `fe` (u_x, u_y, u_z, θ_x, θ_y, θ_z),
//! SI, with the stress stiffening per (rad/s)² K_σ = ΔK/Ω_ref² ([`FeMatrices::ks`]; ΔK the file's
//! matrix, or the file's matrix less K when it holds the total stiffness at Ω_ref), its
//! [`Invariants`] and whether it is axisymmetric; or an [`InputError`] naming the file
//! and the line or entry: a matrix not symmetric, a size that does not match the DOF table, a
//! node that does not exist, a mass matrix that is not positive definite, a truncated file, a
//! file whose `% units:` differs from the scene's, a node off the axis.
//! Method: every matrix read dense; entries scaled by mass × length^r (r = rotation DOFs among
//! the entry's row and column: t → kg, t mm → kg m, t mm² → kg m², N/mm → N/m, N mm → N m);
//! symmetry checked to 1e-10 of the largest entry; Cholesky of M; rotating terms from the files
//! or, without them, from M and the node coordinates ([`super::invariants`]). A scene attaches
//! bodies whose nodes lie on the rotor axis with all six DOFs (beam-like models, rotorsweep's
//! own export); a solid or shell body (nodes off the axis) is refused here with that reason,
//! and [`read_body`] reads any body (its nodes anywhere) with every other check, for the
//! general rotating terms of [`super::invariants::rotating_terms`].

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::{DMatrix, DVector, Vector3};

use super::files::{dof_table, same_size, units_check};
pub use super::files::{BodyFiles, Format, RotatingFiles, StressFiles, StressKind};
use super::invariants::{invariants, rigid_modes, rotating_terms, Invariants};
use super::matrix_market;
use super::tables::{self, Dof, Node, Units, DOF_NAMES};
use crate::error::InputError;
use crate::rotor::fe::{FeMatrices, NDOF};

/// An imported body (module doc).
#[derive(Debug, Clone)]
pub struct ImportedBody {
    /// Node ids, ascending z.
    pub node_ids: Vec<i64>,
    /// Node z [m], ascending.
    pub node_z: Vec<f64>,
    /// Named nodes (name → index in `node_ids`), as a scene names them; empty when read.
    pub named: BTreeMap<String, usize>,
    /// Body-frame matrices in `fe`'s DOF order, SI.
    pub matrices: FeMatrices,
    /// Rigid-body inertia.
    pub invariants: Invariants,
    /// Whether M, K, the rotating terms and the stress stiffening are unchanged by a quarter
    /// turn about z and the body has no unbalance (to [`AXISYMMETRY_TOLERANCE`]).
    pub axisymmetric: bool,
    /// A solid or shell body ([`super::solid`]), reduced sparse
    /// ([`crate::rotor::solid_reduction`]): then `matrices` are empty (0 × 0), `node_ids` and
    /// `node_z` are its attachment points (ids 1, 2, … in ascending z) and `named` indexes them.
    pub solid: Option<std::sync::Arc<super::solid::SolidBody>>,
}

/// Relative tolerance of [`ImportedBody::axisymmetric`] (the beam rotor's own test's).
pub const AXISYMMETRY_TOLERANCE: f64 = 1e-7;

/// Relative asymmetry a symmetric matrix may have (of its largest entry).
const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// A matrix and its DOFs, read in the file's units.
struct Read {
    matrix: DMatrix<f64>,
    dofs: Vec<Dof>,
}

fn read_market(path: &Path, units: Units) -> Result<DMatrix<f64>, InputError> {
    let m = matrix_market::read(path)?;
    units_check(path, &m.units, units)?;
    Ok(m.matrix)
}

fn symmetric(path: &Path, a: &DMatrix<f64>, dofs: &[Dof]) -> Result<(), InputError> {
    let scale = a.amax();
    let n = a.nrows();
    for j in 0..n {
        for i in j + 1..n {
            if (a[(i, j)] - a[(j, i)]).abs() > SYMMETRY_TOLERANCE * scale {
                let name = |k: usize| format!("node {} {}", dofs[k].node, DOF_NAMES[dofs[k].dof]);
                return Err(InputError::new(
                    path,
                    format!(
                        "the matrix is not symmetric: entry ({}, {}) = {:e} ({} × {}) but ({}, {}) = {:e}",
                        i + 1,
                        j + 1,
                        a[(i, j)],
                        name(i),
                        name(j),
                        j + 1,
                        i + 1,
                        a[(j, i)]
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn scale_matrix(a: &mut DMatrix<f64>, dofs: &[Dof], units: Units) {
    let rot = |k: usize| i32::from(dofs[k].dof >= 3);
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            a[(i, j)] *= units.mass() * units.length().powi(rot(i) + rot(j));
        }
    }
}

fn read_pair(f: &BodyFiles, nodes: &[Node]) -> Result<(Read, DMatrix<f64>), InputError> {
    match f.format {
        Format::MatrixMarket => {
            let m = read_market(&f.mass, f.units)?;
            let k = read_market(&f.stiffness, f.units)?;
            same_size(f, m.nrows(), k.nrows())?;
            let dofs = dof_table(f, m.nrows(), nodes)?;
            Ok((Read { matrix: m, dofs }, k))
        }
        // The other formats by the one reader of every format (their entries), made dense.
        _ => {
            let ((m, _), (k, _), dofs) = super::sparse_body::read_pair(f, nodes)?;
            let matrix = m.dense(&f.mass)?;
            Ok((Read { matrix, dofs }, k.dense(&f.stiffness)?))
        }
    }
}

fn read_loads(
    path: &Path,
    n: usize,
    dofs: &[Dof],
    units: Units,
) -> Result<[DVector<f64>; 4], InputError> {
    let mut out: [DVector<f64>; 4] = std::array::from_fn(|_| DVector::zeros(n));
    let text = crate::error::read_text(path)
        .map_err(|e| InputError::new(path, format!("cannot read the loads: {e}")))?;
    let mut seen = vec![false; n];
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, "index,fc,ft,gx,gy")) => {}
        _ => {
            return Err(
                InputError::new(path, "the loads need the header `index,fc,ft,gx,gy`").at_line(1),
            )
        }
    }
    for (i, l) in lines {
        let err = |r: String| InputError::new(path, r).at_line(i + 1);
        let v: Vec<&str> = l.split(',').map(str::trim).collect();
        let row = v
            .first()
            .and_then(|s| s.parse::<usize>().ok())
            .filter(|r| (1..=n).contains(r) && v.len() == 5)
            .ok_or_else(|| {
                err(format!(
                    "expected `index,fc,ft,gx,gy` with index in 1..={n}, got `{l}`"
                ))
            })?;
        if std::mem::replace(&mut seen[row - 1], true) {
            return Err(err(format!("row {row} is given twice")));
        }
        let rot = i32::from(dofs[row - 1].dof >= 3);
        for (c, o) in out.iter_mut().enumerate() {
            let x: f64 = v[c + 1]
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| err(format!("`{}` is not a finite number", v[c + 1])))?;
            // f_c and f_t are a mass times a length, g_x and g_y a mass (per unit field).
            let length = if c < 2 { units.length() } else { 1.0 };
            o[row - 1] = x * units.mass() * length * units.length().powi(rot);
        }
    }
    if let Some(r) = seen.iter().position(|s| !s) {
        return Err(InputError::new(
            path,
            format!("row {} has no line: truncated file", r + 1),
        ));
    }
    Ok(out)
}

fn positive_definite(path: &Path, m: &DMatrix<f64>, dofs: &[Dof]) -> Result<(), InputError> {
    // faer's blocked Cholesky: nalgebra's took seconds at 3000 DOFs.
    let f = faer::Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)]);
    if f.llt(faer::Side::Lower).is_ok() {
        return Ok(());
    }
    let lowest = m.clone().symmetric_eigenvalues().min();
    let at = (0..m.nrows())
        .find(|&i| m[(i, i)] <= 0.0)
        .map(|i| {
            format!(
                "; diagonal entry ({}, {}) of node {} {} is {:e}",
                i + 1,
                i + 1,
                dofs[i].node,
                DOF_NAMES[dofs[i].dof],
                m[(i, i)]
            )
        })
        .unwrap_or_default();
    Err(InputError::new(
        path,
        format!("the mass matrix is not positive definite (lowest eigenvalue {lowest:e}){at}"),
    ))
}

/// The stress stiffening per (rad/s)², K_σ = ΔK/Ω_ref², in the file's DOF order and SI
/// (module doc); `k` is the body's stiffness in SI.
fn read_stress(
    f: &BodyFiles,
    s: &StressFiles,
    nodes: &[Node],
    dofs: &[Dof],
    k: &DMatrix<f64>,
) -> Result<DMatrix<f64>, InputError> {
    let path = &s.stiffness;
    let n = dofs.len();
    let mut a = match f.format {
        Format::MatrixMarket => read_market(path, f.units)?,
        _ => super::sparse_body::stress_entries(f, path, nodes, dofs)?.dense(path)?,
    };
    if a.nrows() != n {
        return Err(InputError::new(
            path,
            format!(
                "the stress stiffness is {} × {}, the body has {n} DOFs (the mass matrix {})",
                a.nrows(),
                a.nrows(),
                f.mass.display()
            ),
        ));
    }
    symmetric(path, &a, dofs)?;
    scale_matrix(&mut a, dofs, f.units);
    if s.kind == StressKind::Total {
        a -= k;
    }
    let w = std::f64::consts::TAU * s.reference_hz;
    Ok(a / (w * w))
}

/// A body's matrices as read and checked, in SI and the files' DOF order, before it is made an
/// axis body: any body, its nodes anywhere (solids, shells, rings).
#[derive(Debug, Clone)]
pub struct ReadBody {
    /// The node table, positions in metres.
    pub nodes: Vec<Node>,
    /// What each matrix row is.
    pub dofs: Vec<Dof>,
    /// Each row's node position [m].
    pub positions: Vec<Vector3<f64>>,
    /// Mass M [kg, kg m, kg m²].
    pub m: DMatrix<f64>,
    /// Stiffness K [N/m, N, N m].
    pub k: DMatrix<f64>,
    /// Stress stiffening per (rad/s)², K_σ = ΔK/Ω_ref², if the files give it.
    pub ks: Option<DMatrix<f64>>,
}

/// Reads a body's matrices and tables with every check of [`load`] but the axis body's (module
/// doc); [`super::invariants::rotating_terms`] then gives the rotating terms of any body.
pub fn read_body(f: &BodyFiles) -> Result<ReadBody, InputError> {
    let nodes = tables::read_nodes(&f.nodes, f.units)?;
    let (
        Read {
            matrix: mut m,
            dofs,
        },
        mut k,
    ) = read_pair(f, &nodes)?;
    symmetric(&f.mass, &m, &dofs)?;
    symmetric(&f.stiffness, &k, &dofs)?;
    scale_matrix(&mut m, &dofs, f.units);
    scale_matrix(&mut k, &dofs, f.units);
    positive_definite(&f.mass, &m, &dofs)?;
    let ks = match &f.stress {
        Some(s) => Some(read_stress(f, s, &nodes, &dofs, &k)?),
        None => None,
    };
    let positions = dofs
        .iter()
        .map(|d| {
            let p = nodes.iter().find(|p| p.id == d.node).expect("checked");
            Vector3::from(p.x)
        })
        .collect();
    Ok(ReadBody {
        nodes,
        dofs,
        positions,
        m,
        k,
        ks,
    })
}

/// Reads and checks an FE body (module doc).
pub fn load(f: &BodyFiles) -> Result<ImportedBody, InputError> {
    let ReadBody {
        nodes,
        dofs,
        positions: pos,
        m,
        k,
        ks,
    } = read_body(f)?;
    // The axis body: every node on the axis with its six DOFs.
    let extent = nodes.iter().map(|p| p.x[2].abs()).fold(1.0, f64::max);
    for p in &nodes {
        if p.x[0].hypot(p.x[1]) > 1e-9 * extent {
            return Err(InputError::new(
                &f.nodes,
                format!(
                    "node {} lies off the rotor axis (x = {:e} m, y = {:e} m): a scene attaches \
                     bodies whose nodes lie on the axis (beam-like models); solid and shell \
                     bodies attach through rings (fe.rings)",
                    p.id, p.x[0], p.x[1]
                ),
            ));
        }
        for (d, name) in DOF_NAMES.iter().enumerate() {
            if !dofs.iter().any(|q| q.node == p.id && q.dof == d) {
                return Err(InputError::new(
                    f.dofs.as_deref().unwrap_or(&f.mass),
                    format!(
                        "node {} has no {} row: a node on the axis needs all six DOFs",
                        p.id, name
                    ),
                ));
            }
        }
    }
    let mut order: Vec<&Node> = nodes.iter().collect();
    order.sort_by(|a, b| a.x[2].total_cmp(&b.x[2]));
    let n = dofs.len();
    // perm[new] = old row.
    let mut perm = vec![0; n];
    for (r, d) in dofs.iter().enumerate() {
        let rank = order
            .iter()
            .position(|p| p.id == d.node)
            .expect("checked above");
        perm[NDOF * rank + d.dof] = r;
    }
    let pm = |a: &DMatrix<f64>| DMatrix::from_fn(n, n, |i, j| a[(perm[i], perm[j])]);
    let pv = |a: &DVector<f64>| DVector::from_fn(n, |i, _| a[perm[i]]);
    let mut t = match &f.rotating {
        None => rotating_terms(&m, &k, &dofs, &pos),
        Some(r) => {
            let read = |p: &Path| -> Result<DMatrix<f64>, InputError> {
                let mut a = read_market(p, f.units)?;
                if a.nrows() != n {
                    return Err(InputError::new(
                        p,
                        format!(
                            "the matrix is {} × {}, the body has {n} DOFs",
                            a.nrows(),
                            a.nrows()
                        ),
                    ));
                }
                scale_matrix(&mut a, &dofs, f.units);
                Ok(a)
            };
            let [fc, ft, gx, gy] = read_loads(&r.loads, n, &dofs, f.units)?;
            FeMatrices {
                gc: read(&r.coriolis)?,
                e: read(&r.spin_softening)?,
                c: read(&r.angular_acceleration)?,
                gs: read(&r.gyroscopic)?,
                fc,
                ft,
                gx,
                gy,
                m: m.clone(),
                k: k.clone(),
                ks: None,
            }
        }
    };
    t = FeMatrices {
        m: pm(&t.m),
        k: pm(&t.k),
        gc: pm(&t.gc),
        e: pm(&t.e),
        c: pm(&t.c),
        gs: pm(&t.gs),
        fc: pv(&t.fc),
        ft: pv(&t.ft),
        gx: pv(&t.gx),
        gy: pv(&t.gy),
        ks: ks.as_ref().map(pm),
    };
    let node_z: Vec<f64> = order.iter().map(|p| p.x[2]).collect();
    let axis_dofs: Vec<Dof> = (0..n)
        .map(|i| Dof {
            node: order[i / NDOF].id,
            dof: i % NDOF,
        })
        .collect();
    let axis_pos: Vec<Vector3<f64>> = (0..n)
        .map(|i| Vector3::new(0.0, 0.0, node_z[i / NDOF]))
        .collect();
    let inv = invariants(&t.m, &rigid_modes(&axis_dofs, &axis_pos));
    let axisymmetric = axisymmetric(&t, inv.mass, extent);
    Ok(ImportedBody {
        node_ids: order.iter().map(|p| p.id).collect(),
        node_z,
        named: BTreeMap::new(),
        matrices: t,
        invariants: inv,
        axisymmetric,
        solid: None,
    })
}

/// Whether the matrices are unchanged by a quarter turn Q about z of every node's translation
/// and rotation (QᵀAQ = A) and the unbalance loads vanish, to [`AXISYMMETRY_TOLERANCE`]
/// (relative to each matrix's largest entry; the loads to mass × the body's length).
fn axisymmetric(t: &FeMatrices, mass: f64, length: f64) -> bool {
    let n = t.m.nrows();
    // Q e_x = e_y, Q e_y = −e_x on each triple: column i of Q has its one entry, ±1, in row
    // p(i), so (QᵀAQ)_ij = s_i s_j A[p(i), p(j)] (no dense products).
    let turn = |i: usize| match i % 3 {
        0 => (i + 1, 1.0),
        1 => (i - 1, -1.0),
        _ => (i, 1.0),
    };
    let tol = AXISYMMETRY_TOLERANCE;
    let same = |a: &DMatrix<f64>| {
        let bound = tol * a.amax();
        (0..n).all(|j| {
            let (pj, sj) = turn(j);
            (0..n).all(|i| {
                let (pi, si) = turn(i);
                (si * sj * a[(pi, pj)] - a[(i, j)]).abs() <= bound
            })
        })
    };
    // The unbalance: f_c, and f_t on the lateral translations.
    let lateral_ft = (0..n)
        .filter(|i| i % NDOF < 2)
        .fold(0.0, |m: f64, i| m.max(t.ft[i].abs()));
    let unbalance = t.fc.amax().max(lateral_ft);
    [&t.m, &t.k, &t.gc, &t.e, &t.c, &t.gs]
        .into_iter()
        .chain(&t.ks)
        .all(same)
        && unbalance <= tol * mass * length
}
