//! Where an FE body's files are and what they hold: the matrices' format, the unit system, the
//! optional rotating terms and stress stiffness ([`BodyFiles`]), as a scene's `[fe]` names them.
//!
//! In: nothing read yet (paths). Out: the descriptions the readers take
//! ([`super::body::load`], [`super::sparse_body::load`]), and the two checks both readers make
//! of what the files hold against them: a file's `% units:` comment against the scene's units,
//! the stiffness's size against the mass's, and the DOF table read for the matrices' size (an
//! [`InputError`] naming the file and line).
//! Method: plain data.

use std::path::{Path, PathBuf};

use super::tables::Units;
use crate::error::InputError;

/// The file format of an FE body's matrices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Matrix Market coordinate files with a DOF table.
    MatrixMarket,
    /// Abaqus `*MATRIX OUTPUT, FORMAT=COORDINATE` files (node, dof, node, dof, value).
    Abaqus,
    /// Nastran DMIG bulk-data cards (GRID and component address every entry).
    Dmig,
    /// Nastran OUTPUT4 ASCII files with a DOF table.
    Op4,
}

impl Format {
    /// Whether the format's files hold named matrices (DMIG, OP4), possibly several.
    pub fn named_matrices(self) -> bool {
        matches!(self, Format::Dmig | Format::Op4)
    }
}

/// The names of the matrices in DMIG or OP4 files (`None`: the file's only matrix).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MatrixNames {
    /// The mass matrix's name (`fe.mass_matrix`).
    pub mass: Option<String>,
    /// The stiffness matrix's name (`fe.stiffness_matrix`).
    pub stiffness: Option<String>,
    /// The stress stiffness's name (`fe.stress_stiffness_matrix`).
    pub stress: Option<String>,
}

/// The files of the rotating terms (module doc), all Matrix Market but the loads (`index,fc,
/// ft,gx,gy`, one line per matrix row).
#[derive(Debug, Clone, PartialEq)]
pub struct RotatingFiles {
    /// G_c.
    pub coriolis: PathBuf,
    /// E.
    pub spin_softening: PathBuf,
    /// C.
    pub angular_acceleration: PathBuf,
    /// G_s.
    pub gyroscopic: PathBuf,
    /// f_c, f_t, g_x, g_y.
    pub loads: PathBuf,
}

/// What a stress-stiffness file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StressKind {
    /// The stiffness change ΔK at the reference speed (the geometric stiffness of the
    /// centrifugal prestress).
    Increment,
    /// The whole stiffness at the reference speed, K + ΔK (what an FE code exports after a
    /// prestressed step); ΔK is it less the body's stiffness.
    Total,
}

/// A stiffness exported at a reference speed (stress stiffening): K(Ω) = K + (Ω/Ω_ref)² ΔK.
/// The file must not contain spin softening (an FE code's "spin softening" option): the engine
/// adds that itself from the mass matrix (or `[fe.rotating]`'s E).
#[derive(Debug, Clone, PartialEq)]
pub struct StressFiles {
    /// The matrix file, in the format and units of the mass and stiffness.
    pub stiffness: PathBuf,
    /// What it holds.
    pub kind: StressKind,
    /// The reference speed Ω_ref [Hz] (> 0) at which it was computed.
    pub reference_hz: f64,
}

/// Where an FE body is and in which units (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyFiles {
    /// The matrices' format.
    pub format: Format,
    /// Mass matrix.
    pub mass: PathBuf,
    /// Stiffness matrix.
    pub stiffness: PathBuf,
    /// Node table.
    pub nodes: PathBuf,
    /// DOF table (Matrix Market and OP4; Abaqus and DMIG files name their DOFs).
    pub dofs: Option<PathBuf>,
    /// The matrices' names in DMIG or OP4 files.
    pub names: MatrixNames,
    /// Unit system of every file.
    pub units: Units,
    /// The rotating terms, if the files carry them.
    pub rotating: Option<RotatingFiles>,
    /// The stress stiffening, if the body has it (none by default).
    pub stress: Option<StressFiles>,
}

impl BodyFiles {
    /// The file that says which DOF each matrix row is, as an error names it: the DOF table, or
    /// for an Abaqus or DMIG body the mass matrix.
    pub fn dofs_file(&self) -> String {
        self.dofs
            .as_deref()
            .unwrap_or(&self.mass)
            .display()
            .to_string()
    }
}

/// The `% units:` comment of a file against the scene's units.
pub(super) fn units_check(
    path: &Path,
    found: &Option<(String, usize)>,
    units: Units,
) -> Result<(), InputError> {
    match found {
        Some((u, line)) if !u.starts_with(units.name()) => Err(InputError::new(
            path,
            format!(
                "the file is in units `{u}`, the scene says `{}`",
                units.name()
            ),
        )
        .at_line(*line)),
        _ => Ok(()),
    }
}

/// The stiffness's size `k` against the mass's `m`.
pub(super) fn same_size(f: &BodyFiles, m: usize, k: usize) -> Result<(), InputError> {
    if k == m {
        return Ok(());
    }
    Err(InputError::new(
        &f.stiffness,
        format!(
            "the stiffness matrix is {k} × {k}, the mass matrix {} is {m} × {m}",
            f.mass.display()
        ),
    ))
}

/// The DOF table of a Matrix Market or OP4 body of `n` rows, read against the node table.
pub(super) fn dof_table(
    f: &BodyFiles,
    n: usize,
    nodes: &[super::tables::Node],
) -> Result<Vec<super::tables::Dof>, InputError> {
    let dofs_path = f.dofs.as_ref().ok_or_else(|| {
        InputError::new(
            &f.mass,
            "a Matrix Market or OP4 body needs a DOF table (`dofs`)",
        )
    })?;
    super::tables::read_dofs(dofs_path, n, nodes, &f.nodes)
}
