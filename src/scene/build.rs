//! The raw scene file (its schema, [`SceneFile`]) → a validated [`Scene`] in SI.
//!
//! In: the deserialised scene file and its validation context ([`Check`]). Out: the [`Scene`]
//! (units converted once: mm → m, Hz → rad/s, g → kg), or the first [`InputError`] in the order
//! the keys are checked. Method: materials, then the rotor's geometry (the roll builder or a
//! general rotor, [`super::geometry`]), the supports on named nodes, the drive, the reduction's
//! boundary and modes, the speed, run window, damping and solver, and last the record's size.

use std::collections::BTreeMap;

use super::check::Check;
use super::file::*;
use super::geometry::{build_roll, build_rotor, material, Geometry};
use super::limits::record_size;
use super::settings;
use super::speed;
use super::supports::support_model;
use super::types::{Drive, Scene, Support};
use crate::error::InputError;
use crate::rotor::reduction::ModeSelection;

pub(super) fn build(c: &Check, raw: SceneFile) -> Result<Scene, InputError> {
    let mut materials = BTreeMap::new();
    for (name, m) in &raw.materials {
        materials.insert(name.clone(), material(c, &format!("materials.{name}"), m)?);
    }
    let find_mat = |key: &str, name: &str| {
        materials.get(name).copied().ok_or_else(|| {
            c.err(
                key,
                format!(
                    "unknown material `{name}` (defined: {})",
                    materials.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            )
        })
    };
    let Geometry {
        rotor,
        thickness_map: map,
        sensors,
        boundary: default_boundary,
    } = match (&raw.roll, &raw.rotor) {
        (Some(roll), None) => build_roll(c, roll, &find_mat)?,
        (None, Some(rotor)) => build_rotor(c, rotor, &find_mat)?,
        _ => return Err(c.err(
            "roll",
            "a scene needs exactly one of [roll] (the roll builder) or [rotor] (a general rotor)",
        )),
    };
    let named: Vec<&str> = rotor.named_points.iter().map(|(n, _)| n.as_str()).collect();
    let node_exists = |key: &str, n: &str| {
        if named.contains(&n) {
            Ok(n.to_string())
        } else {
            Err(c.err(
                key,
                format!("unknown node `{n}` (named nodes: {})", named.join(", ")),
            ))
        }
    };
    if raw.supports.is_empty() {
        return Err(c.err(
            "supports",
            "a scene needs at least one support ([[supports]]): without supports the rotor falls",
        ));
    }
    let mut supports = Vec::new();
    for (i, s) in raw.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        let node = node_exists(&format!("{key}.node"), &s.node)?;
        if supports.iter().any(|x: &Support| x.node == node) {
            return Err(c.err(
                &format!("{key}.node"),
                format!("node `{node}` already has a support"),
            ));
        }
        let model = support_model(c, &key, s, roll_journal(&raw))?;
        supports.push(Support { node, model });
    }
    let drive = match &raw.drive {
        Some(d) => Some(Drive {
            node: node_exists("drive.node", &d.node)?,
            axial_stiffness: c
                .positive("drive.axial_stiffness_n_per_m", d.axial_stiffness_n_per_m)?,
            axial_damping: c
                .non_negative("drive.axial_damping_ns_per_m", d.axial_damping_ns_per_m)?,
        }),
        None => None,
    };
    let boundary = match &raw.reduction.boundary {
        Some(b) => b
            .iter()
            .enumerate()
            .map(|(i, n)| node_exists(&format!("reduction.boundary[{i}]"), n))
            .collect::<Result<Vec<_>, _>>()?,
        None if !default_boundary.is_empty() => default_boundary,
        None => supports.iter().map(|s| s.node.clone()).collect(),
    };
    if boundary.is_empty() {
        return Err(c.err(
            "reduction.boundary",
            "no boundary nodes: name them here or add supports",
        ));
    }
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
    };
    record_size(c, &scene)?;
    Ok(scene)
}

fn roll_journal(raw: &SceneFile) -> Option<f64> {
    raw.roll.as_ref().map(|r| r.journal.diameter_mm * 1e-3)
}
