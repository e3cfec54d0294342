//! The FE body builder: `[fe]` → a rotor that is an FE body imported from files, with its
//! named nodes, rings and sensors.
//!
//! In: the `[fe]` table: the matrices' `format` (`matrix-market`, `abaqus`, `dmig` or `op4`),
//! the files `mass`, `stiffness`, `nodes`, `dofs` (Matrix Market and OP4) and optionally the
//! `[fe.rotating]` terms, paths relative to the scene file; the names of the matrices in DMIG
//! or OP4 files (`mass_matrix`, `stiffness_matrix`, `stress_stiffness_matrix`; needed when a
//! file holds several); `units` (`SI` or `mm-t-s`); optionally a stress
//! stiffness `stress_stiffness` (a file in the matrices' format), `stress_stiffness_kind`
//! (`increment`: ΔK, or `total`: K + ΔK) and `stress_reference_hz` (the speed [Hz] it was
//! computed at), all three or none; `named` nodes (name → node id), `rings` (ring attachments,
//! [`crate::rotor::import::rings`]) and `sensors` (names among them).
//! Out: a [`Geometry`] whose rotor spec has no segments, only the named points at their z [m],
//! and the [`ImportedBody`]; no default boundary (the supports' nodes are); or an
//! [`InputError`] at the key, or naming the body's file and line
//! ([`crate::rotor::import::body`]). Without rings the body is an axis body (every node on the
//! axis with six DOFs), its points its named nodes; with rings it is a solid or shell body
//! ([`crate::rotor::import::solid`], read sparse with its stress stiffness if given, reduced
//! by [`crate::rotor::solid_reduction`]; `[fe.rotating]` refused), its points the rings' reference points and the named
//! nodes, in ascending z.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;

use super::built::Geometry;
use crate::error::InputError;
use crate::rotor::fe::{FeMatrices, RotorSpec};
use crate::rotor::import::body::{
    self, BodyFiles, Format, ImportedBody, RotatingFiles, StressFiles, StressKind,
};
use crate::rotor::import::files::MatrixNames;
use crate::rotor::import::rings::{self, Ring, RingSpec};
use crate::rotor::import::tables::{Node, Units};
use crate::rotor::import::{solid, sparse_body};
use crate::rotor::solid_reduction::attachment_order;
use crate::scene::check::Check;
use crate::scene::source::Source;

/// `[fe]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FeFile {
    #[serde(default = "matrix_market")]
    pub format: String,
    pub mass: String,
    pub stiffness: String,
    pub nodes: String,
    pub dofs: Option<String>,
    pub mass_matrix: Option<String>,
    pub stiffness_matrix: Option<String>,
    pub stress_stiffness_matrix: Option<String>,
    pub units: String,
    pub rotating: Option<FeRotatingFile>,
    pub stress_stiffness: Option<String>,
    pub stress_stiffness_kind: Option<String>,
    pub stress_reference_hz: Option<f64>,
    pub named: BTreeMap<String, i64>,
    #[serde(default)]
    pub sensors: Vec<String>,
    #[serde(default)]
    pub rings: BTreeMap<String, FeRingFile>,
}

/// `[fe.rings.<name>]` as written: a ring attachment ([`crate::rotor::import::rings`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FeRingFile {
    pub nodes: Option<Vec<i64>>,
    pub z: Option<f64>,
    pub radius: Option<f64>,
    pub tolerance: Option<f64>,
    pub weights: Option<Vec<f64>>,
}

/// `[fe.rotating]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FeRotatingFile {
    pub coriolis: String,
    pub spin_softening: String,
    pub angular_acceleration: String,
    pub gyroscopic: String,
    pub loads: String,
}

fn matrix_market() -> String {
    "matrix-market".to_string()
}

/// The files of `[fe]`, paths relative to the scene file (module doc).
fn files_of(c: &Check, fe: &FeFile) -> Result<BodyFiles, InputError> {
    let dir = c.file.parent().unwrap_or(Path::new("."));
    let path = |p: &str| -> PathBuf { dir.join(p) };
    let format = match fe.format.as_str() {
        "matrix-market" => Format::MatrixMarket,
        "abaqus" => Format::Abaqus,
        "dmig" => Format::Dmig,
        "op4" => Format::Op4,
        f => {
            return Err(c.err(
                "fe.format",
                format!("`{f}`: expected `matrix-market`, `abaqus`, `dmig` or `op4`"),
            ))
        }
    };
    match format {
        Format::MatrixMarket | Format::Op4 if fe.dofs.is_none() => {
            return Err(c.err(
                "fe.dofs",
                if format == Format::Op4 {
                    "an OP4 body needs its DOF table"
                } else {
                    "a Matrix Market body needs its DOF table"
                },
            ))
        }
        Format::Dmig if fe.dofs.is_some() => {
            return Err(c.err(
                "fe.dofs",
                "a DMIG body's cards name each entry's GRID and component: leave out the DOF table",
            ))
        }
        _ => {}
    }
    if !format.named_matrices() {
        for (key, v) in [
            ("fe.mass_matrix", &fe.mass_matrix),
            ("fe.stiffness_matrix", &fe.stiffness_matrix),
            ("fe.stress_stiffness_matrix", &fe.stress_stiffness_matrix),
        ] {
            if v.is_some() {
                return Err(c.err(
                    key,
                    format!(
                        "a matrix name is for `dmig` or `op4` files, not `{}`",
                        fe.format
                    ),
                ));
            }
        }
    }
    if fe.stress_stiffness_matrix.is_some() && fe.stress_stiffness.is_none() {
        return Err(c.err(
            "fe.stress_stiffness_matrix",
            "names a matrix of fe.stress_stiffness, which is not given",
        ));
    }
    let units = Units::parse(&fe.units).map_err(|r| c.err("fe.units", r))?;
    let stress = match (
        &fe.stress_stiffness,
        &fe.stress_stiffness_kind,
        fe.stress_reference_hz,
    ) {
        (None, None, None) => None,
        (Some(file), Some(kind), Some(hz)) => {
            let kind = match kind.as_str() {
                "increment" => StressKind::Increment,
                "total" => StressKind::Total,
                k => {
                    return Err(c.err(
                        "fe.stress_stiffness_kind",
                        format!("`{k}`: expected `increment` (ΔK) or `total` (K + ΔK)"),
                    ))
                }
            };
            if !(hz.is_finite() && hz > 0.0) {
                return Err(c.err(
                    "fe.stress_reference_hz",
                    format!("{hz}: the reference speed must be a positive number of Hz"),
                ));
            }
            Some(StressFiles {
                stiffness: path(file),
                kind,
                reference_hz: hz,
            })
        }
        (file, kind, hz) => {
            let keys = [
                ("fe.stress_stiffness", file.is_some()),
                ("fe.stress_stiffness_kind", kind.is_some()),
                ("fe.stress_reference_hz", hz.is_some()),
            ];
            let given = keys.iter().find(|(_, g)| *g).map_or(keys[0].0, |k| k.0);
            let missing: Vec<&str> = keys.iter().filter(|(_, g)| !g).map(|k| k.0).collect();
            return Err(c.err(
                given,
                format!(
                    "stress stiffening needs fe.stress_stiffness, fe.stress_stiffness_kind and \
                     fe.stress_reference_hz together; missing: {}",
                    missing.join(", ")
                ),
            ));
        }
    };
    Ok(BodyFiles {
        format,
        mass: path(&fe.mass),
        stiffness: path(&fe.stiffness),
        nodes: path(&fe.nodes),
        dofs: fe.dofs.as_deref().map(path),
        names: MatrixNames {
            mass: fe.mass_matrix.clone(),
            stiffness: fe.stiffness_matrix.clone(),
            stress: fe.stress_stiffness_matrix.clone(),
        },
        units,
        rotating: fe.rotating.as_ref().map(|r| RotatingFiles {
            coriolis: path(&r.coriolis),
            spin_softening: path(&r.spin_softening),
            angular_acceleration: path(&r.angular_acceleration),
            gyroscopic: path(&r.gyroscopic),
            loads: path(&r.loads),
        }),
        stress,
    })
}

/// The files and named nodes (name → node id) of the `[fe]` body of the scene file `scene`
/// (after `extends`), without reading the body: the sparse reduction reads it itself.
pub fn fe_body_files(scene: &Path) -> Result<(BodyFiles, BTreeMap<String, i64>), InputError> {
    with_fe_table(scene, |c, fe| Ok((files_of(c, &fe)?, fe.named)))
}

/// Reads the scene file `scene` (after `extends`) and hands its `[fe]` table to `read`.
fn with_fe_table<T>(
    scene: &Path,
    read: impl FnOnce(&Check, FeFile) -> Result<T, InputError>,
) -> Result<T, InputError> {
    let source = Source::load(scene)?;
    let c = Check {
        file: scene,
        source: &source,
        overridden: &[],
    };
    let fe = fe_table(&c)?;
    read(&c, fe)
}

/// The scene's `[fe]` table as written (an error names the scene and the key).
fn fe_table(c: &Check) -> Result<FeFile, InputError> {
    let table = c
        .source
        .table
        .get("fe")
        .ok_or_else(|| InputError::new(c.file, "the scene has no [fe] body"))?;
    table.clone().try_into().map_err(|e: toml::de::Error| {
        c.err("fe", crate::scene::locate::plain_type_error(e.message()))
    })
}

/// The ring attachments `[fe.rings]` of the scene file `scene` on the body's node table
/// `nodes` (SI), the rings' lengths in the body's `units`; an error names the scene's line and
/// the ring's key.
pub fn fe_body_rings(
    scene: &Path,
    nodes: &[Node],
    units: Units,
) -> Result<BTreeMap<String, Ring>, InputError> {
    with_fe_table(scene, |c, fe| rings_of(c, &fe, nodes, units))
}

/// The rings of `fe` on the node table `nodes` (SI), lengths in `units` ([`fe_body_rings`]).
fn rings_of(
    c: &Check,
    fe: &FeFile,
    nodes: &[Node],
    units: Units,
) -> Result<BTreeMap<String, Ring>, InputError> {
    let mut out = BTreeMap::new();
    for (name, r) in &fe.rings {
        let key = format!("fe.rings.{name}");
        crate::error::safe_name(name).map_err(|e| c.err(&key, e))?;
        if fe.named.contains_key(name) {
            return Err(c.err(&key, format!("`{name}` is also a name in fe.named")));
        }
        let spec = RingSpec {
            nodes: r.nodes.clone(),
            z: r.z,
            radius: r.radius,
            tolerance: r.tolerance,
            weights: r.weights.clone(),
        };
        let ring = rings::ring(&spec, nodes, units.length()).map_err(|e| c.err(&key, e))?;
        out.insert(name.clone(), ring);
    }
    Ok(out)
}

/// The body of `[fe]` (module doc).
pub(crate) fn build_fe(c: &Check, fe: &FeFile) -> Result<Geometry, InputError> {
    let files = files_of(c, fe)?;
    if !fe.rings.is_empty() {
        return build_solid(c, fe, &files);
    }
    let mut body: ImportedBody = body::load(&files)?;
    let mut named_points = Vec::new();
    for (name, id) in &fe.named {
        let key = format!("fe.named.{name}");
        crate::error::safe_name(name).map_err(|r| c.err(&key, r))?;
        let at = body.node_ids.iter().position(|n| n == id).ok_or_else(|| {
            c.err(
                &key,
                format!("node {id} does not exist in {}", files.nodes.display()),
            )
        })?;
        named_points.push((name.clone(), body.node_z[at]));
        body.named.insert(name.clone(), at);
    }
    Ok(geometry(named_points, sensors_of(c, fe)?, body))
}

/// The geometry of an FE body: a rotor spec with no segments, only the named points [m], from
/// the body's first point; no default boundary.
fn geometry(
    named_points: Vec<(String, f64)>,
    sensors: Vec<String>,
    body: ImportedBody,
) -> Geometry {
    Geometry {
        rotor: RotorSpec {
            z_start: body.node_z[0],
            segments: Vec::new(),
            disks: Vec::new(),
            point_masses: Vec::new(),
            named_points,
            balancing: None,
        },
        thickness_map: None,
        wall_field: None,
        sensors,
        boundary: Vec::new(),
        body: Some(Arc::new(body)),
    }
}

/// `fe.sensors`, each a name of `fe.named` or `fe.rings`.
fn sensors_of(c: &Check, fe: &FeFile) -> Result<Vec<String>, InputError> {
    let mut sensors = Vec::new();
    for (i, s) in fe.sensors.iter().enumerate() {
        if !fe.named.contains_key(s) && !fe.rings.contains_key(s) {
            return Err(c.err(
                &format!("fe.sensors[{i}]"),
                format!("`{s}` is not a node named in fe.named nor a ring of fe.rings"),
            ));
        }
        sensors.push(s.clone());
    }
    Ok(sensors)
}

/// A solid or shell body (`[fe.rings]` given): read sparse, attached at its named nodes and
/// rings ([`crate::rotor::import::solid`]), the rotor's points the attachments' reference
/// points in ascending z (module doc).
fn build_solid(c: &Check, fe: &FeFile, files: &BodyFiles) -> Result<Geometry, InputError> {
    if files.rotating.is_some() {
        return Err(c.err(
            "fe.rotating",
            "a solid or shell body (fe.rings) has its rotating terms from its mass matrix and \
             node coordinates",
        ));
    }
    let read = sparse_body::load(files)?;
    let rings = rings_of(c, fe, &read.nodes, files.units)?;
    let solid = solid::attach(read, &fe.named, &rings, &files.dofs_file())
        .map_err(|(key, reason)| c.err(&key, reason))?;
    let order = attachment_order(&solid);
    let z: Vec<f64> = order
        .iter()
        .map(|(name, _)| {
            let a = solid.attachments.iter().find(|a| &a.name == name);
            a.expect("an attachment").centre[2]
        })
        .collect();
    let body = ImportedBody {
        node_ids: (1..=order.len() as i64).collect(),
        node_z: z.clone(),
        named: order.iter().cloned().collect(),
        matrices: FeMatrices::empty(),
        invariants: solid.invariants.clone(),
        axisymmetric: false,
        solid: Some(Arc::new(solid)),
    };
    let named_points = order.iter().map(|(n, p)| (n.clone(), z[*p])).collect();
    Ok(geometry(named_points, sensors_of(c, fe)?, body))
}
