//! The model of a scene to files: the full FE body or the reduced model.
//!
//! In: a [`Scene`], its [`Model`], the scene's effective table (after `extends` and `--set`),
//! what to export ([`Which`]) and an output folder that does not exist yet.
//! Out (docs/export.md): `mass.mtx`, `stiffness.mtx` (symmetric), `coriolis.mtx`,
//! `gyroscopic.mtx` (skew-symmetric), `spin_softening.mtx` (symmetric),
//! `angular_acceleration.mtx` (general), for a body with stress stiffening
//! `stress_stiffness.mtx` (K_σ per (rad/s)², symmetric), `loads.csv` (f_c, f_t, g_x, g_y per row), `nodes.csv`
//! (id, x, y, z [m]), `dofs.csv` (row, node id, DOF) and `scene.toml` for the full body — the
//! scene with `[roll]` or `[rotor]` replaced by `[fe]` on these files, so `rotorsweep modes
//! DIR/scene.toml` reproduces the scene's model; for the reduced model the modal matrices
//! (`*.mtx`, modal coordinates, no node table). Both write `model.h5`: `/nodes`, `/dofs`,
//! `/matrices/<name>` (dense, `units` attribute), `/loads/<name>`, `/invariants` (mass, mass
//! centre, inertia tensors), `/interface` (the Craig–Bampton boundary nodes) and `/modes` (the
//! selected orthogonalised modes: frequency, label, kind, Φ and the modal matrices).
//! Method: the body-frame matrices of `fe` (assembled, or the imported body's) in SI; node ids
//! 1-based in ascending z, so an exported and re-imported body has the same DOF order and
//! every number written in its shortest round-trip form (bit-identical when read back).

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::{DMatrix, DVector, Vector3};

use crate::dynamics::model::Model;
use crate::rotor::fe::{FeMatrices, NDOF};
use crate::rotor::import::invariants::{invariants, rigid_modes, Invariants};
use crate::rotor::import::matrix_market::{format, Symmetry};
use crate::rotor::import::tables::{Dof, DOF_NAMES};
use crate::scene::{Scene, SupportModel};
use crate::store;

/// What to export.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// The full FE body (physical DOFs) and a scene on it.
    Full,
    /// The selected reduced model (modal coordinates).
    Reduced,
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// Matrix size.
    pub dofs: usize,
    /// Files written, in order.
    pub files: Vec<String>,
}

/// Why an export failed: the file and the cause.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Writing a file failed.
    #[error("{0}: {1}")]
    Io(std::path::PathBuf, std::io::Error),
    /// Writing the HDF5 file failed.
    #[error("{0}: {1}")]
    Hdf5(std::path::PathBuf, hdf5::Error),
    /// The scene table cannot be written as TOML.
    #[error("scene.toml: {0}")]
    Toml(#[from] toml::ser::Error),
    /// `--model` of a solid or shell body (its own files are the full model; the reduced
    /// model's Φ holds only its attachment points).
    #[error(
        "{0}: the body is a solid or shell body (fe.rings): its own files are the full model; \
         `--model` exports beam and axis bodies (use `rotorsweep reduce` for its reduced \
         matrices, `--state-space` for the plant)"
    )]
    Solid(std::path::PathBuf),
}

const MASS_UNITS: &str = "SI: kg (translations), kg m (translation-rotation), kg m2 (rotations)";
const STIFF_UNITS: &str =
    "SI: N/m (translations), N/rad (translation-rotation), N m/rad (rotations)";

/// How a matrix is stored: symmetric, skew-symmetric (to 1e-14 of its largest entry) or general.
fn symmetry_of(a: &DMatrix<f64>) -> Symmetry {
    let t = a.transpose();
    let scale = a.amax().max(f64::MIN_POSITIVE);
    if (a - &t).amax() <= 1e-14 * scale {
        Symmetry::Symmetric
    } else if (a + &t).amax() <= 1e-14 * scale {
        Symmetry::SkewSymmetric
    } else {
        Symmetry::General
    }
}

/// The matrix as its symmetry stores it: the mean of the two triangles.
fn stored(a: &DMatrix<f64>, s: Symmetry) -> DMatrix<f64> {
    match s {
        Symmetry::Symmetric => 0.5 * (a + a.transpose()),
        Symmetry::SkewSymmetric => 0.5 * (a - a.transpose()),
        Symmetry::General => a.clone(),
    }
}

fn write(dir: &Path, name: &str, text: &str, files: &mut Vec<String>) -> Result<(), ExportError> {
    let p = dir.join(name);
    std::fs::write(&p, text).map_err(|e| ExportError::Io(p, e))?;
    files.push(name.to_string());
    Ok(())
}

const STRESS_UNITS: &str = "SI: N/m (translations), N/rad (translation-rotation), N m/rad \
(rotations), per (rad/s)^2";

/// The reference speed [Hz] an export gives its stress stiffness: Ω_ref = 1 rad/s, so the file
/// holds K_σ = ΔK/Ω_ref² itself.
pub const STRESS_REFERENCE_HZ: f64 = 1.0 / std::f64::consts::TAU;

/// The matrices of an export: name, matrix, units, meaning.
fn matrices(f: &FeMatrices) -> Vec<(&'static str, &DMatrix<f64>, &'static str, &'static str)> {
    let mut out = vec![
        ("mass", &f.m, MASS_UNITS, "mass matrix M"),
        ("stiffness", &f.k, STIFF_UNITS, "stiffness matrix K"),
        ("coriolis", &f.gc, MASS_UNITS, "Coriolis matrix G_c; the body-frame equations carry 2 Omega G_c"),
        ("spin_softening", &f.e, MASS_UNITS, "spin-softening and rotary-inertia matrix E; the body-frame equations carry -Omega^2 E"),
        ("angular_acceleration", &f.c, MASS_UNITS, "angular-acceleration matrix C; the body-frame equations carry dOmega/dt C"),
        ("gyroscopic", &f.gs, MASS_UNITS, "stationary-frame gyroscopic matrix G_s; the stationary-frame equations carry Omega G_s"),
    ];
    if let Some(ks) = &f.ks {
        out.push(("stress_stiffness", ks, STRESS_UNITS, "stress stiffening K_sigma per (rad/s)^2 (dK at Omega_ref = 1 rad/s); the equations carry +Omega^2 K_sigma"));
    }
    out
}

fn loads(f: &FeMatrices) -> [(&'static str, &DVector<f64>, &'static str); 4] {
    [
        ("fc", &f.fc, "N/(rad/s)^2"),
        ("ft", &f.ft, "N/(rad/s^2)"),
        ("gx", &f.gx, "N/(m/s^2)"),
        ("gy", &f.gy, "N/(m/s^2)"),
    ]
}

/// The invariants of the full body (module doc of [`crate::rotor::import::invariants`]).
pub fn body_invariants(model: &Model, f: &FeMatrices) -> Invariants {
    let n = model.rotor.ndof();
    let dofs: Vec<Dof> = (0..n)
        .map(|i| Dof {
            node: (i / NDOF + 1) as i64,
            dof: i % NDOF,
        })
        .collect();
    let pos: Vec<Vector3<f64>> = (0..n)
        .map(|i| Vector3::new(0.0, 0.0, model.rotor.node_z[i / NDOF]))
        .collect();
    invariants(&f.m, &rigid_modes(&dofs, &pos))
}

/// The scene of the exported body: `table` (the scene's effective table) with `[roll]` and
/// `[rotor]` replaced by `[fe]` on the files of the export, and the boundary written out.
fn exported_scene(
    scene: &Scene,
    model: &Model,
    table: &toml::Value,
    stress: bool,
) -> Result<String, ExportError> {
    let mut t = table.as_table().cloned().unwrap_or_default();
    t.remove("roll");
    t.remove("rotor");
    t.remove("extends");
    let mut fe = toml::Table::new();
    for (k, v) in [
        ("format", "matrix-market"),
        ("mass", "mass.mtx"),
        ("stiffness", "stiffness.mtx"),
        ("nodes", "nodes.csv"),
        ("dofs", "dofs.csv"),
        ("units", "SI"),
    ] {
        fe.insert(k.into(), v.into());
    }
    if stress {
        fe.insert("stress_stiffness".into(), "stress_stiffness.mtx".into());
        fe.insert("stress_stiffness_kind".into(), "increment".into());
        fe.insert("stress_reference_hz".into(), STRESS_REFERENCE_HZ.into());
    }
    let mut rot = toml::Table::new();
    for k in [
        "coriolis",
        "spin_softening",
        "angular_acceleration",
        "gyroscopic",
    ] {
        rot.insert(k.into(), format!("{k}.mtx").into());
    }
    rot.insert("loads".into(), "loads.csv".into());
    fe.insert("rotating".into(), rot.into());
    let named: toml::Table = model
        .rotor
        .named
        .iter()
        .map(|(n, i)| (n.clone(), toml::Value::Integer(*i as i64 + 1)))
        .collect();
    fe.insert("named".into(), named.into());
    fe.insert(
        "sensors".into(),
        toml::Value::Array(scene.sensors.iter().map(|s| s.clone().into()).collect()),
    );
    t.insert("fe".into(), fe.into());
    // A roller support takes its journal's diameter from [roll] when it does not give it.
    if let Some(list) = t.get_mut("supports").and_then(|s| s.as_array_mut()) {
        for (entry, s) in list.iter_mut().zip(&scene.supports) {
            if let (Some(e), SupportModel::Rollers(r)) = (entry.as_table_mut(), &s.model) {
                e.entry("journal_diameter_mm")
                    .or_insert((r.journal_diameter * 1e3).into());
            }
        }
    }
    let red = t
        .entry("reduction")
        .or_insert_with(|| toml::Table::new().into());
    if let Some(r) = red.as_table_mut() {
        r.insert(
            "boundary".into(),
            toml::Value::Array(scene.boundary.iter().map(|s| s.clone().into()).collect()),
        );
    }
    let mut s = format!(
        "# The FE body of scene `{}` ({}),\n# exported by `rotorsweep export --model full`: \
         the scene with its rotor replaced by\n# the body's files (docs/export.md). SI units.\n",
        scene.name,
        scene.source.display()
    );
    s.push_str(&toml::to_string(&t)?);
    Ok(s)
}

/// Writes the export of `which` into `dir`, created here (module doc).
pub fn write_model(
    scene: &Scene,
    model: &Model,
    table: &toml::Value,
    which: Which,
    dir: &Path,
) -> Result<Written, ExportError> {
    if scene.body.as_ref().is_some_and(|b| b.solid.is_some()) {
        return Err(ExportError::Solid(scene.source.clone()));
    }
    std::fs::create_dir_all(dir).map_err(|e| ExportError::Io(dir.to_path_buf(), e))?;
    let full = model.rotor.assemble();
    let red = &model.reduced;
    let modal;
    let f = match which {
        Which::Full => &full,
        Which::Reduced => {
            modal = FeMatrices {
                m: red.m.clone(),
                k: red.k.clone(),
                gc: red.gc.clone(),
                e: red.e.clone(),
                c: red.c.clone(),
                gs: red.gs.clone(),
                fc: red.fc.clone(),
                ft: red.ft.clone(),
                gx: red.gx.clone(),
                gy: red.gy.clone(),
                ks: red.ks.clone(),
            };
            &modal
        }
    };
    let mut files = Vec::new();
    let coords = match which {
        Which::Full => "physical DOFs (rows: dofs.csv)",
        Which::Reduced => "modal coordinates (model.h5 /modes)",
    };
    for (name, a, units, what) in matrices(f) {
        let s = symmetry_of(a);
        let text = format(
            &stored(a, s),
            s,
            units,
            &format!("{what}, scene `{}`, {coords}", scene.name),
        );
        write(dir, &format!("{name}.mtx"), &text, &mut files)?;
    }
    let n = f.m.nrows();
    let mut l = String::from("index,fc,ft,gx,gy\n");
    for i in 0..n {
        let _ = writeln!(
            l,
            "{},{:e},{:e},{:e},{:e}",
            i + 1,
            f.fc[i],
            f.ft[i],
            f.gx[i],
            f.gy[i]
        );
    }
    write(dir, "loads.csv", &l, &mut files)?;
    if which == Which::Full {
        let mut nodes = String::from("id,x,y,z\n");
        for (i, z) in model.rotor.node_z.iter().enumerate() {
            let _ = writeln!(nodes, "{},0,0,{z:e}", i + 1);
        }
        write(dir, "nodes.csv", &nodes, &mut files)?;
        let mut dofs = String::from("index,node,dof\n");
        for i in 0..n {
            let _ = writeln!(dofs, "{},{},{}", i + 1, i / NDOF + 1, DOF_NAMES[i % NDOF]);
        }
        write(dir, "dofs.csv", &dofs, &mut files)?;
        write(
            dir,
            "scene.toml",
            &exported_scene(scene, model, table, f.ks.is_some())?,
            &mut files,
        )?;
    }
    let h5 = dir.join("model.h5");
    store::write_closed(&h5, |file| fill_h5(file, scene, model, &full, f, which))
        .map_err(|e| ExportError::Hdf5(h5.clone(), e))?;
    files.push("model.h5".into());
    Ok(Written { dofs: n, files })
}

/// The contents of `model.h5` (module doc).
fn fill_h5(
    file: &hdf5::File,
    scene: &Scene,
    model: &Model,
    full: &FeMatrices,
    f: &FeMatrices,
    which: Which,
) -> hdf5::Result<()> {
    let root = file.group("/")?;
    store::attr_str(
        &root,
        "format",
        "rotorsweep model export 1 (docs/export.md)",
    )?;
    store::attr_str(&root, "scene", &scene.name)?;
    store::attr_str(
        &root,
        "model",
        match which {
            Which::Full => "full",
            Which::Reduced => "reduced",
        },
    )?;
    store::attr_str(
        &root,
        "frame",
        "body frame spinning about z at Omega; DOFs per node ux uy uz rx ry rz",
    )?;
    let ids: Vec<f64> = (1..=model.rotor.node_z.len()).map(|i| i as f64).collect();
    store::dataset(&root, "nodes/id", &ids, "")?;
    store::dataset(&root, "nodes/z", &model.rotor.node_z, "m")?;
    let n = f.m.nrows();
    let g = root.create_group("matrices")?;
    for (name, a, units, what) in matrices(f) {
        store::dataset_2d(&g, name, (n, n), a.transpose().as_slice(), units)?;
        let ds = g.dataset(name)?;
        store::attr_str(&ds, "meaning", what)?;
    }
    for (name, v, units) in loads(f) {
        store::dataset(&root, &format!("loads/{name}"), v.as_slice(), units)?;
    }
    let inv = body_invariants(model, full);
    let gi = root.create_group("invariants")?;
    store::dataset(&gi, "mass", &[inv.mass], "kg")?;
    store::dataset(&gi, "first_moment", inv.first_moment.as_slice(), "kg m")?;
    store::dataset(&gi, "mass_centre", inv.centre.as_slice(), "m")?;
    store::dataset_2d(
        &gi,
        "inertia_origin",
        (3, 3),
        inv.inertia_origin.as_slice(),
        "kg m2",
    )?;
    store::dataset_2d(
        &gi,
        "inertia_centre",
        (3, 3),
        inv.inertia_centre.as_slice(),
        "kg m2",
    )?;
    let gb = root.create_group("interface")?;
    store::string_dataset(&gb, "names", &scene.boundary)?;
    let bid: Vec<f64> = scene
        .boundary
        .iter()
        .map(|b| (model.rotor.named[b] + 1) as f64)
        .collect();
    store::dataset(&gb, "node_ids", &bid, "")?;
    let red = &model.reduced;
    let gm = root.create_group("modes")?;
    store::attr_str(&gm, "selection", &red.selection)?;
    store::dataset(&gm, "freq_hz", &red.freq_hz, "Hz")?;
    store::string_dataset(
        &gm,
        "labels",
        &red.labels.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
    )?;
    store::string_dataset(
        &gm,
        "kinds",
        &red.kinds.iter().map(|k| k.to_string()).collect::<Vec<_>>(),
    )?;
    let (rows, cols) = red.phi.shape();
    store::dataset_2d(
        &gm,
        "phi",
        (rows, cols),
        red.phi.transpose().as_slice(),
        "m or rad per unit modal coordinate (mass-normalised)",
    )?;
    Ok(())
}
