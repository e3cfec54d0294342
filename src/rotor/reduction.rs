//! Reduction: Craig–Bampton at the journal nodes, orthogonalised like ADAMS/Flex.
//!
//! In: the rotor mesh and its [`FeMatrices`], the boundary (journal) nodes, the number of
//! fixed-interface normal modes.
//! Out: a [`ReducedModel`]: a mass-normalised modal basis Φ (physical DOFs × modes) with
//! diagonal stiffness ω², a label (normal / static correction) and a kind per mode, and every
//! body-frame matrix and load of `fe` projected on it (physics.md §3–§4), the stress stiffening
//! K_σ of an imported body among them (on the standstill modes: the stiffened shapes are as well
//! represented as the kept modes span them). Frequencies in Hz.
//!
//! Procedure (physics.md §3): boundary DOFs B are the six DOFs of each journal node; constraint
//! modes Ψ = −K_II⁻¹ K_IB; fixed-interface normal modes K_II φ = ω² M_II φ (lowest n); the
//! Craig–Bampton basis T = [[I, 0], [Ψ, Φ_n]]; then the reduced eigenproblem of TᵀKT, TᵀMT gives
//! the orthogonalised modes. Its six zero-frequency modes are replaced by the explicit rigid
//! motions (translations x, y, z, then tilts about x and y, M-orthonormalised in that order, so
//! the tilts turn about the mass centre); the rigid spin about z is dropped because the spin is
//! prescribed.
//!
//! Labels: each orthogonalised mode's kinetic-energy share in the normal-mode coordinates ranks
//! it; the n modes with the largest share are "normal", the other twelve "static" (the six rigid
//! modes, which come entirely from the constraint modes, among them). Labels are for reporting:
//! the lowest bending modes of a roll are mostly constraint-mode motion, so selecting by label
//! would drop them. Selecting "N n + M st" builds the Craig–Bampton basis with N normal modes
//! and keeps the rigid modes (always: the body frame does not float) and the lowest
//! N + max(M − 6, 0) elastic modes by frequency; "30n+12st" is the whole set (41 coordinates:
//! 5 rigid, 36 elastic), "10n+2st" keeps 5 rigid + 10 elastic.

use std::fmt;

use nalgebra::{DMatrix, DVector};

use crate::numerics::eigen::{self, EigenError};
use crate::rotor::fe::{FeMatrices, Rotor, NDOF};

/// Whether a mode came mostly from the fixed-interface normal modes or from the constraint modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ModeLabel {
    /// Dominated by fixed-interface normal modes.
    Normal,
    /// Dominated by constraint (static correction) modes.
    Static,
}

/// The character of a mode, from its kinetic energy by DOF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeKind {
    /// Zero frequency: a rigid-body motion.
    Rigid,
    /// Bending in the x–z plane (u_x, θ_y) of the body frame.
    BendingX,
    /// Bending in the y–z plane (u_y, θ_x).
    BendingY,
    /// Axial (u_z).
    Axial,
    /// Torsion (θ_z).
    Torsion,
    /// No family above 80 % of the kinetic energy.
    Mixed,
}

impl fmt::Display for ModeLabel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ModeLabel::Normal => "normal",
            ModeLabel::Static => "static",
        })
    }
}

impl fmt::Display for ModeKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ModeKind::Rigid => "rigid",
            ModeKind::BendingX => "bending-x",
            ModeKind::BendingY => "bending-y",
            ModeKind::Axial => "axial",
            ModeKind::Torsion => "torsion",
            ModeKind::Mixed => "mixed",
        })
    }
}

/// Which modes of an orthogonalised set to keep.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModeSelection {
    /// "N n + M st": N normal modes and M static modes (module doc).
    Counts {
        /// Normal modes.
        normal: usize,
        /// Static modes, the six rigid ones counted first.
        statics: usize,
    },
    /// Explicit indices into the full orthogonalised set (rigid modes are added if missing).
    List(Vec<usize>),
}

impl ModeSelection {
    /// Parses "30n+12st" (spaces allowed) or a list "0-4,7,9".
    pub fn parse(s: &str) -> Result<Self, String> {
        let t: String = s.chars().filter(|c| !c.is_whitespace()).collect();
        let t = t.to_ascii_lowercase();
        if let Some((a, b)) = t.split_once('+') {
            let n = a
                .strip_suffix('n')
                .and_then(|x| x.parse().ok())
                .ok_or_else(|| format!("`{s}`: expected the form `30n+12st`"))?;
            let st = b
                .strip_suffix("st")
                .and_then(|x| x.parse().ok())
                .ok_or_else(|| format!("`{s}`: expected the form `30n+12st`"))?;
            return Ok(Self::Counts {
                normal: n,
                statics: st,
            });
        }
        let mut list = Vec::new();
        for part in t.split(',') {
            let bad = || format!("`{s}`: expected `30n+12st` or a list like `0-4,7,9`");
            if let Some((a, b)) = part.split_once('-') {
                let (a, b): (usize, usize) =
                    (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
                if b < a {
                    return Err(bad());
                }
                list.extend(a..=b);
            } else {
                list.push(part.parse().map_err(|_| bad())?);
            }
        }
        Ok(Self::List(list))
    }

    /// The Craig–Bampton normal-mode count used for explicit lists: the source's 30.
    pub fn default_normal() -> usize {
        30
    }

    /// The number of normal modes the Craig–Bampton basis must contain for this selection.
    pub fn normal_needed(&self) -> Option<usize> {
        match self {
            Self::Counts { normal, .. } => Some(*normal),
            Self::List(_) => None,
        }
    }
}

/// Why a reduction failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReductionError {
    /// Eigen-solver failure.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// K_II is singular: the journals do not hold the rotor (e.g. a free part between them).
    #[error("the rotor is not held by its boundary nodes (K_II is singular)")]
    InteriorSingular,
    /// K − σM is not positive definite: K has a negative eigenvalue below σ, or M is singular.
    #[error(
        "K + (2π · {0} Hz)² M is not positive definite: the body's K has a negative eigenvalue"
    )]
    ShiftedSingular(f64),
    /// More modes of a whole body were asked for than it has DOFs.
    #[error("{asked} modes of the whole body asked for, it has only {available} DOFs")]
    TooManyBodyModes {
        /// Asked for.
        asked: usize,
        /// The body's DOFs.
        available: usize,
    },
    /// More normal modes were asked for than interior DOFs exist.
    #[error("{asked} normal modes asked for, the interior has only {available} DOFs")]
    TooManyModes {
        /// Asked for.
        asked: usize,
        /// Available.
        available: usize,
    },
    /// The reduced problem did not show six rigid-body modes.
    #[error(
        "expected six rigid-body modes, the seventh eigenvalue is not separated (ratio {0:e})"
    )]
    RigidModes(f64),
    /// A selected index or count does not exist.
    #[error("mode selection: {0}")]
    Selection(String),
}

/// The reduced rotor model (module doc). Matrices are modal (nm × nm), loads modal (nm).
#[derive(Debug, Clone)]
pub struct ReducedModel {
    /// Index of each kept mode in the full orthogonalised set.
    pub index: Vec<usize>,
    /// Natural frequency of the free-free rotor [Hz] (0 for rigid modes).
    pub freq_hz: Vec<f64>,
    /// Label per mode.
    pub labels: Vec<ModeLabel>,
    /// Kind per mode.
    pub kinds: Vec<ModeKind>,
    /// Basis Φ (physical DOFs × modes), ΦᵀMΦ = I.
    pub phi: DMatrix<f64>,
    /// Modal stiffness ΦᵀKΦ (diagonal ω², rad²/s²).
    pub k: DMatrix<f64>,
    /// Modal mass ΦᵀMΦ (identity to round-off).
    pub m: DMatrix<f64>,
    /// ΦᵀG_cΦ.
    pub gc: DMatrix<f64>,
    /// ΦᵀEΦ.
    pub e: DMatrix<f64>,
    /// ΦᵀCΦ.
    pub c: DMatrix<f64>,
    /// ΦᵀG_sΦ (stationary-frame gyroscopic).
    pub gs: DMatrix<f64>,
    /// ΦᵀK_σΦ, the stress stiffening per (rad/s)² ([`FeMatrices::ks`]) on the standstill modes;
    /// `None` without it.
    pub ks: Option<DMatrix<f64>>,
    /// Kinetic-energy matrices per DOF family (bending-x, bending-y, axial, torsion): Φᵀ M_f Φ,
    /// with M_f the rows and columns of M of that family; they sum to the modal mass.
    pub family_mass: [DMatrix<f64>; 4],
    /// Φᵀf_c.
    pub fc: DVector<f64>,
    /// Φᵀf_t.
    pub ft: DVector<f64>,
    /// Φᵀg_x.
    pub gx: DVector<f64>,
    /// Φᵀg_y.
    pub gy: DVector<f64>,
    /// Node z [m] of the mesh the basis lives on (a solid body's: its attachment points').
    pub node_z: Vec<f64>,
    /// Ŝ, the rotation generator ẑ× in modal coordinates, where Φ's rows are not every DOF of
    /// the body (a solid body's Φ holds its attachment points only): ΦᵀMS̄Φ over the body's
    /// DOFs (ΦᵀMΦ = I). `None`: the least-squares projection from Φ's own rows.
    pub rotation: Option<DMatrix<f64>>,
    /// Number of normal modes in the Craig–Bampton basis this set came from.
    pub cb_normal: usize,
    /// The selection that made this set, "Nn+Mst" or "list of K modes".
    pub selection: String,
}

/// Builds the full orthogonalised Craig–Bampton set with `n_normal` normal modes.
pub fn craig_bampton(
    rotor: &Rotor,
    fe: &FeMatrices,
    boundary_nodes: &[usize],
    n_normal: usize,
) -> Result<ReducedModel, ReductionError> {
    let ndof = rotor.ndof();
    let mut is_b = vec![false; ndof];
    for &n in boundary_nodes {
        for d in 0..NDOF {
            is_b[NDOF * n + d] = true;
        }
    }
    let b: Vec<usize> = (0..ndof).filter(|&i| is_b[i]).collect();
    let int: Vec<usize> = (0..ndof).filter(|&i| !is_b[i]).collect();
    if n_normal > int.len() {
        return Err(ReductionError::TooManyModes {
            asked: n_normal,
            available: int.len(),
        });
    }
    let sub = |a: &DMatrix<f64>, r: &[usize], c: &[usize]| {
        DMatrix::from_fn(r.len(), c.len(), |i, j| a[(r[i], c[j])])
    };
    let kii = sub(&fe.k, &int, &int);
    let mii = sub(&fe.m, &int, &int);
    let kib = sub(&fe.k, &int, &b);
    let fixed = eigen::generalized_symmetric(&kii, &mii)?;
    let chol = kii
        .clone()
        .cholesky()
        .ok_or(ReductionError::InteriorSingular)?;
    let psi = -chol.solve(&kib);
    let nb = b.len();
    let ncb = nb + n_normal;
    let mut t = DMatrix::zeros(ndof, ncb);
    for (j, &bj) in b.iter().enumerate() {
        t[(bj, j)] = 1.0;
        for (i, &ii) in int.iter().enumerate() {
            t[(ii, j)] = psi[(i, j)];
        }
    }
    for j in 0..n_normal {
        for (i, &ii) in int.iter().enumerate() {
            t[(ii, nb + j)] = fixed.vectors[(i, j)];
        }
    }
    let kh = t.transpose() * &fe.k * &t;
    let mh = t.transpose() * &fe.m * &t;
    let kh = 0.5 * (&kh + kh.transpose());
    let mh = 0.5 * (&mh + mh.transpose());
    // Explicit rigid modes in CB coordinates: boundary rows of the rigid motions.
    let rigid_phys = rotor.rigid_body_modes();
    let rigid_b = DMatrix::from_fn(nb, 6, |j, col| rigid_phys[(b[j], col)]);
    let o = orthogonalise(&kh, &mh, &rigid_b, n_normal)?;
    let phi = &t * &o.v;
    let mut model = project(fe, phi, rotor.node_z.clone());
    o.finish(&mut model, n_normal);
    Ok(model)
}

/// The orthogonalised set of a Craig–Bampton model (module doc): the coordinates V of each mode
/// in the Craig–Bampton basis (columns), their frequencies [Hz] and labels.
pub(crate) struct Orthogonal {
    /// Modes in Craig–Bampton coordinates (interface, then normal modes), M̂-orthonormal.
    pub v: DMatrix<f64>,
    freq: Vec<f64>,
    labels: Vec<ModeLabel>,
    nb: usize,
}

/// The orthogonalised modes of the Craig–Bampton matrices K̂, M̂ (interface coordinates first,
/// `n_normal` normal modes last), the interface rows of the six rigid motions `rigid_b`
/// (|B| × 6: translations x, y, z, rotations about x, y, z) replacing the reduced problem's six
/// zero-frequency modes (module doc).
pub(crate) fn orthogonalise(
    kh: &DMatrix<f64>,
    mh: &DMatrix<f64>,
    rigid_b: &DMatrix<f64>,
    n_normal: usize,
) -> Result<Orthogonal, ReductionError> {
    let ncb = kh.nrows();
    let nb = rigid_b.nrows();
    let red = eigen::generalized_symmetric(kh, mh)?;
    if ncb > 6 {
        let ratio = red.values[5].abs() / red.values[6];
        if ratio > 1e-6 {
            return Err(ReductionError::RigidModes(ratio));
        }
    }
    let mut basis: Vec<DVector<f64>> = Vec::new();
    for col in 0..5 {
        let mut v = DVector::zeros(ncb);
        for j in 0..nb {
            v[j] = rigid_b[(j, col)];
        }
        for u in &basis {
            let proj = (u.transpose() * mh * &v)[0];
            v -= proj * u;
        }
        let norm = (v.transpose() * mh * &v)[0].sqrt();
        basis.push(v / norm);
    }
    let mut freq = vec![0.0; 5];
    for i in 6..ncb {
        basis.push(red.vectors.column(i).into_owned());
        freq.push(red.values[i].max(0.0).sqrt() / (2.0 * std::f64::consts::PI));
    }
    let v = DMatrix::from_columns(&basis);
    let nm = v.ncols();
    // Labels: share of the normal-mode coordinates in each mode (M̂_NN = I for mass-normalised φ_n).
    let share: Vec<f64> = (0..nm)
        .map(|i| v.column(i).rows(nb, n_normal).norm_squared())
        .collect();
    let mut order: Vec<usize> = (5..nm).collect();
    order.sort_by(|&a, &b| share[b].total_cmp(&share[a]).then(a.cmp(&b)));
    let mut labels = vec![ModeLabel::Static; nm];
    for &i in order.iter().take(n_normal) {
        labels[i] = ModeLabel::Normal;
    }
    Ok(Orthogonal {
        v,
        freq,
        labels,
        nb,
    })
}

impl Orthogonal {
    /// Completes `model` (the projection on this set's modes): indices, frequencies, labels,
    /// kinds from its family masses, and the selection "Nn+Mst".
    pub(crate) fn finish(self, model: &mut ReducedModel, n_normal: usize) {
        let nm = self.v.ncols();
        model.kinds = (0..nm)
            .map(|i| {
                if i < 5 {
                    ModeKind::Rigid
                } else {
                    classify(std::array::from_fn(|f| model.family_mass[f][(i, i)]))
                }
            })
            .collect();
        model.index = (0..nm).collect();
        model.freq_hz = self.freq;
        model.labels = self.labels;
        model.cb_normal = n_normal;
        model.selection = format!("{n_normal}n+{}st", self.nb);
    }
}

/// DOF family of a physical DOF: 0 bending-x (u_x, θ_y), 1 bending-y (u_y, θ_x), 2 axial, 3 torsion.
pub(crate) fn family(dof: usize) -> usize {
    match dof % NDOF {
        0 | 4 => 0,
        1 | 3 => 1,
        2 => 2,
        _ => 3,
    }
}

/// The kind of a mode from its kinetic energy per family `e` (80 % rule).
pub fn classify(e: [f64; 4]) -> ModeKind {
    let total: f64 = e.iter().sum();
    let (best, val) = e
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .expect("four families");
    if *val < 0.8 * total {
        return ModeKind::Mixed;
    }
    [
        ModeKind::BendingX,
        ModeKind::BendingY,
        ModeKind::Axial,
        ModeKind::Torsion,
    ][best]
}

fn project(fe: &FeMatrices, phi: DMatrix<f64>, node_z: Vec<f64>) -> ReducedModel {
    let pt = phi.transpose();
    let proj = |a: &DMatrix<f64>| &pt * a * &phi;
    let sym = |a: DMatrix<f64>| 0.5 * (&a + a.transpose());
    let family_mass = std::array::from_fn(|f| {
        let mf = DMatrix::from_fn(fe.m.nrows(), fe.m.ncols(), |i, j| {
            if family(i) == f && family(j) == f {
                fe.m[(i, j)]
            } else {
                0.0
            }
        });
        sym(proj(&mf))
    });
    ReducedModel {
        family_mass,
        index: Vec::new(),
        freq_hz: Vec::new(),
        labels: Vec::new(),
        kinds: Vec::new(),
        k: sym(proj(&fe.k)),
        m: sym(proj(&fe.m)),
        gc: proj(&fe.gc),
        e: sym(proj(&fe.e)),
        c: proj(&fe.c),
        gs: proj(&fe.gs),
        ks: fe.ks.as_ref().map(|a| sym(proj(a))),
        fc: &pt * &fe.fc,
        ft: &pt * &fe.ft,
        gx: &pt * &fe.gx,
        gy: &pt * &fe.gy,
        phi,
        node_z,
        rotation: None,
        cb_normal: 0,
        selection: String::new(),
    }
}

impl ReducedModel {
    /// The body-frame Ω² stiffness change per (rad/s)², E − K_σ: the equations carry
    /// −Ω²(E − K_σ) (spin softening and rotary inertia less the stress stiffening). Without
    /// stress stiffening it is E itself (the same numbers, bit for bit).
    pub fn body_e(&self) -> DMatrix<f64> {
        match &self.ks {
            Some(ks) => &self.e - ks,
            None => self.e.clone(),
        }
    }

    /// Number of modal coordinates.
    pub fn len(&self) -> usize {
        self.freq_hz.len()
    }

    /// True when no mode is kept.
    pub fn is_empty(&self) -> bool {
        self.freq_hz.is_empty()
    }

    /// The selection that made this set: "Nn+Mst", or for a list "K modes (Nn+Mst labels)".
    pub fn counts_label(&self) -> String {
        self.selection.clone()
    }

    /// The label counts of this set, "Nn+Mst", the six rigid modes (spin included) counted as
    /// static.
    pub fn label_counts(&self) -> String {
        let n = self
            .labels
            .iter()
            .filter(|l| **l == ModeLabel::Normal)
            .count();
        let st = self.len() - n + 1;
        format!("{n}n+{st}st")
    }

    /// The 6 × nm rows of Φ at a node: (u_x, u_y, u_z, θ_x, θ_y, θ_z) per unit modal coordinate.
    pub fn node_rows(&self, node: usize) -> DMatrix<f64> {
        self.phi.rows(NDOF * node, NDOF).into_owned()
    }

    /// The subset chosen by `sel`, in ascending index order (rigid modes always kept).
    pub fn select(&self, sel: &ModeSelection) -> Result<ReducedModel, ReductionError> {
        let mut keep: Vec<usize> = (0..self.len())
            .filter(|&i| self.kinds[i] == ModeKind::Rigid)
            .collect();
        match sel {
            ModeSelection::Counts { normal, statics } => {
                let elastic: Vec<usize> = (0..self.len())
                    .filter(|&i| self.kinds[i] != ModeKind::Rigid)
                    .collect();
                let want = normal + statics.saturating_sub(6);
                if want > elastic.len() {
                    return Err(ReductionError::Selection(format!(
                        "{normal}n+{statics}st asks for {want} elastic modes, the set has {}",
                        elastic.len()
                    )));
                }
                keep.extend(&elastic[..want]);
            }
            ModeSelection::List(list) => {
                for &i in list {
                    if i >= self.len() {
                        return Err(ReductionError::Selection(format!(
                            "mode {i} does not exist (the set has {})",
                            self.len()
                        )));
                    }
                    keep.push(i);
                }
            }
        }
        keep.sort_unstable();
        keep.dedup();
        let mut out = self.subset(&keep);
        out.selection = match sel {
            ModeSelection::Counts { normal, statics } => format!("{normal}n+{statics}st"),
            ModeSelection::List(_) => format!("{} modes ({})", out.len(), out.label_counts()),
        };
        Ok(out)
    }

    fn subset(&self, keep: &[usize]) -> ReducedModel {
        let sq = |a: &DMatrix<f64>| {
            DMatrix::from_fn(keep.len(), keep.len(), |i, j| a[(keep[i], keep[j])])
        };
        let vec = |a: &DVector<f64>| DVector::from_fn(keep.len(), |i, _| a[keep[i]]);
        ReducedModel {
            index: keep.iter().map(|&i| self.index[i]).collect(),
            freq_hz: keep.iter().map(|&i| self.freq_hz[i]).collect(),
            labels: keep.iter().map(|&i| self.labels[i]).collect(),
            kinds: keep.iter().map(|&i| self.kinds[i]).collect(),
            phi: self.phi.select_columns(keep),
            k: sq(&self.k),
            m: sq(&self.m),
            gc: sq(&self.gc),
            e: sq(&self.e),
            c: sq(&self.c),
            gs: sq(&self.gs),
            ks: self.ks.as_ref().map(sq),
            family_mass: std::array::from_fn(|f| sq(&self.family_mass[f])),
            fc: vec(&self.fc),
            ft: vec(&self.ft),
            gx: vec(&self.gx),
            gy: vec(&self.gy),
            node_z: self.node_z.clone(),
            rotation: self.rotation.as_ref().map(sq),
            cb_normal: self.cb_normal,
            selection: self.selection.clone(),
        }
    }
}
