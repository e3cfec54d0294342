//! The general rotor builder: `[rotor]` → a rotor of tube segments with named nodes, sensors,
//! rigid disks and point masses.
//!
//! In: the `[rotor]` table (segments in mm, positions on the rotor's axis, disks in kg and
//! kg m², masses in g), the scene's materials. Out: the [`RotorSpec`] in SI (m, kg, kg m²), its
//! sensors and no default boundary (the supports' nodes are); or an [`InputError`] at the key.
//! Method: segments laid end to end from `z_start_mm`; every named point, sensor and disk within
//! the rotor; disks' inertias those of a body; the mesh bounded before it is built; masses in
//! the material.

use super::body::{masses, Body};
use super::built::Geometry;
use super::materials::Materials;
use crate::error::InputError;
use crate::rotor::fe::{DiskSpec, RotorSpec, SectionSpec, SegmentSpec};
use crate::scene::check::Check;
use crate::scene::file::*;
use crate::scene::limits::mesh_size;
use crate::scene::position::{Frame, Position};

pub(crate) fn build_rotor(
    c: &Check,
    r: &RotorFile,
    materials: &Materials,
) -> Result<Geometry, InputError> {
    let mut segments = Vec::new();
    for (i, s) in r.segments.iter().enumerate() {
        let k = format!("rotor.segments[{i}]");
        let outer = 1e-3 * c.size_mm(&format!("{k}.outer_diameter_mm"), s.outer_diameter_mm)?;
        let inner =
            1e-3 * c.non_negative(&format!("{k}.inner_diameter_mm"), s.inner_diameter_mm)?;
        if inner >= outer {
            return Err(c.err(
                &format!("{k}.inner_diameter_mm"),
                "the inner diameter must be smaller than the outer one",
            ));
        }
        segments.push(SegmentSpec {
            length: 1e-3 * c.size_mm(&format!("{k}.length_mm"), s.length_mm)?,
            section: SectionSpec::Tube {
                outer,
                inner,
                asymmetry: c.range(
                    &format!("{k}.bending_asymmetry"),
                    s.bending_asymmetry,
                    -0.9,
                    0.9,
                )?,
            },
            elements: c.count(&format!("{k}.elements"), s.elements, 1, 2000)?,
            material: materials.get(c, &format!("{k}.material"), &s.material)?,
        });
    }
    if segments.is_empty() {
        return Err(c.err("rotor.segments", "a rotor needs at least one segment"));
    }
    let z0 = 1e-3 * c.finite("rotor.z_start_mm", r.z_start_mm)?;
    let z1 = z0 + segments.iter().map(|s| s.length).sum::<f64>();
    let frame = Frame {
        start_mm: z0 * 1e3,
        length_mm: (z1 - z0) * 1e3,
        ends: ("start", "end"),
        what: "the rotor",
    };
    let in_rotor = |key: &str, z: &Position| {
        let z_mm = c.position(key, z, &frame)?;
        c.range(key, z_mm, z0 * 1e3, z1 * 1e3).map(|z| z * 1e-3)
    };
    let mut named_points = Vec::new();
    for (name, z) in &r.nodes {
        named_points.push((name.clone(), in_rotor(&format!("rotor.nodes.{name}"), z)?));
    }
    let mut sensors = Vec::new();
    for (i, s) in r.sensors.iter().enumerate() {
        let k = format!("rotor.sensors[{i}]");
        crate::error::safe_name(&s.name).map_err(|r| c.err(&format!("{k}.name"), r))?;
        if named_points.iter().any(|(n, _)| n == &s.name) {
            return Err(c.err(
                &format!("{k}.name"),
                format!("duplicate node name `{}`", s.name),
            ));
        }
        named_points.push((s.name.clone(), in_rotor(&format!("{k}.z_mm"), &s.z_mm)?));
        sensors.push(s.name.clone());
    }
    let mut disks = Vec::new();
    for (i, d) in r.disks.iter().enumerate() {
        let k = format!("rotor.disks[{i}]");
        let disk = DiskSpec {
            z: in_rotor(&format!("{k}.z_mm"), &d.z_mm)?,
            mass: c.positive(&format!("{k}.mass_kg"), d.mass_kg)?,
            polar: c.non_negative(&format!("{k}.polar_kg_m2"), d.polar_kg_m2)?,
            diametral: c.non_negative(&format!("{k}.diametral_kg_m2"), d.diametral_kg_m2)?,
        };
        disk_inertia(c, &k, &disk, z1 - z0)?;
        disks.push(disk);
    }
    let written: Vec<(String, usize)> = segments
        .iter()
        .enumerate()
        .map(|(i, s)| (format!("rotor.segments[{i}].elements"), s.elements))
        .collect();
    mesh_size(c, &written, named_points.len() + disks.len())?;
    let body = Body {
        segments: &segments,
        z_start: z0,
        disks: &disks,
    };
    let point_masses = masses(c, "rotor.masses", &r.masses, &body, &frame)?;
    Ok(Geometry {
        rotor: RotorSpec {
            z_start: z0,
            segments,
            disks,
            point_masses,
            named_points,
            balancing: None,
        },
        thickness_map: None,
        wall_field: None,
        sensors,
        boundary: Vec::new(),
        body: None,
    })
}

/// A rigid disk's inertias must be those of a body: the polar moment at most twice the diametral
/// one (an axisymmetric body: I_p = ∫r² dm ≤ 2 I_d = ∫r² dm + 2∫z² dm), and its size, the radius
/// √(2 I_p / m) of a uniform disk with these values, at most ten rotor lengths (a mass of
/// 1e-308 kg with the inertia of a 12 kg disk makes the eigen-solvers fail).
fn disk_inertia(c: &Check, key: &str, d: &DiskSpec, length: f64) -> Result<(), InputError> {
    if d.polar > 2.0 * d.diametral * (1.0 + 1e-9) {
        return Err(c.err(
            &format!("{key}.polar_kg_m2"),
            format!(
                "a polar moment of {} kg m² cannot exceed twice the diametral one ({} kg m²)",
                d.polar, d.diametral
            ),
        ));
    }
    let radius = (2.0 * d.polar.max(d.diametral) / d.mass).sqrt();
    if radius > 10.0 * length {
        return Err(c.err(
            &format!("{key}.mass_kg"),
            format!(
                "{:e} kg with these inertias is a disk of radius {radius:.3e} m (√(2 I / m)), \
                 more than ten times the rotor's {:.1} mm length",
                d.mass,
                length * 1e3
            ),
        ));
    }
    Ok(())
}
