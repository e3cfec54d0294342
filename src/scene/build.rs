//! The raw scene file (its schema, [`SceneFile`]) → a validated [`Scene`] in SI.
//!
//! In: the deserialised scene file and its validation context ([`Check`]). Out: the [`Scene`]
//! (units converted once: mm → m, Hz → rad/s, g → kg), or the first [`InputError`] in the order
//! the keys are checked. Method: materials, then the rotor's geometry (the roll builder or a
//! general rotor, [`super::geometry`]), the supports on named nodes ([`super::supports`]), the
//! drive, the reduction's boundary and modes, the speed, run window, damping and solver, and
//! last the record's size.

use super::check::Check;
use super::file::{DriveFile, ReductionFile, SceneFile};
use super::geometry::{build_fe, build_roll, build_rotor, Geometry, Materials};
use super::limits::record_size;
use super::settings;
use super::speed;
use super::supports::build_supports;
use super::types::{Drive, Scene, Support};
use crate::error::InputError;
use crate::rotor::reduction::ModeSelection;

/// The scene of `raw`, its keys checked in the order of the module doc.
pub(super) fn build(c: &Check, raw: SceneFile) -> Result<Scene, InputError> {
    let materials = Materials::new(c, &raw.materials)?;
    let Geometry {
        rotor,
        thickness_map: map,
        wall_field,
        sensors,
        boundary: default_boundary,
        body,
    } = match (&raw.roll, &raw.rotor, &raw.fe) {
        (Some(roll), None, None) => build_roll(c, roll, &materials)?,
        (None, Some(rotor), None) => build_rotor(c, rotor, &materials)?,
        (None, None, Some(fe)) => build_fe(c, fe)?,
        _ => return Err(c.err(
            "roll",
            "a scene needs exactly one of [roll] (the roll builder), [rotor] (a general rotor) \
             or [fe] (an FE body from files)",
        )),
    };
    let named: Vec<&str> = rotor.named_points.iter().map(|(n, _)| n.as_str()).collect();
    let supports = build_supports(c, &raw, &named, &materials)?;
    let drive = drive(c, raw.drive.as_ref(), &named)?;
    let boundary = boundary(c, &raw.reduction, default_boundary, &supports, &named)?;
    let modes =
        ModeSelection::parse(&raw.reduction.modes).map_err(|r| c.err("reduction.modes", r))?;
    let speed = speed::profile(c, &raw.speed)?;
    let simulation = settings::simulation(c, &raw.simulation)?;
    let scene = Scene {
        name: raw.name.clone().unwrap_or_else(|| {
            c.file
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        }),
        description: raw.description.clone().unwrap_or_default(),
        source: c.file.to_path_buf(),
        bases: Vec::new(),
        rotor,
        thickness_map: map,
        wall_field,
        body,
        boundary,
        modes,
        sensors,
        supports,
        drive,
        outputs: settings::outputs(&raw.outputs, &speed, &simulation),
        speed,
        damping: settings::damping(c, &raw.damping)?,
        simulation,
        solver: settings::solver(c, &raw.solver)?,
        machine: None,
    };
    record_size(c, &scene)?;
    Ok(scene)
}

/// The drive's axial spring on a named node (`named`), if `[drive]` is given.
fn drive(c: &Check, d: Option<&DriveFile>, named: &[&str]) -> Result<Option<Drive>, InputError> {
    let Some(d) = d else {
        return Ok(None);
    };
    Ok(Some(Drive {
        node: c.node("drive.node", &d.node, named)?,
        axial_stiffness: c.positive("drive.axial_stiffness_n_per_m", d.axial_stiffness_n_per_m)?,
        axial_damping: c.non_negative("drive.axial_damping_ns_per_m", d.axial_damping_ns_per_m)?,
    }))
}

/// The Craig–Bampton boundary: the named nodes `reduction.boundary` lists, else the geometry's
/// `default` (the roll's journals), else the supports' nodes; never none.
fn boundary(
    c: &Check,
    reduction: &ReductionFile,
    default: Vec<String>,
    supports: &[Support],
    named: &[&str],
) -> Result<Vec<String>, InputError> {
    let boundary = match &reduction.boundary {
        Some(b) => b
            .iter()
            .enumerate()
            .map(|(i, n)| c.node(&format!("reduction.boundary[{i}]"), n, named))
            .collect::<Result<Vec<_>, _>>()?,
        None if !default.is_empty() => default,
        None => supports.iter().map(|s| s.node.clone()).collect(),
    };
    if boundary.is_empty() {
        return Err(c.err(
            "reduction.boundary",
            "no boundary nodes: name them here or add supports",
        ));
    }
    Ok(boundary)
}
