//! Where a rotor's material is, for the masses placed on it: point masses (`masses`) and
//! balancing masses must sit in it.
//!
//! In: the rotor's segments from `z_start` [m] (tubes and mapped shells), its rigid disks, and a
//! mass's radius [m], axial position [m] and angle [rad] (masses in g as written). Out: the
//! [`PointMassSpec`]s in SI (m, rad, kg), or an [`InputError`] saying whether the mass lies in
//! the bore or outside the rotor and where the material spans. Method: the segments holding z
//! (both at a joint) give the radii of material, to 1 nm; a mapped shell's bore at the mass's
//! angle, or its widest at that z when the angle is free.

use std::f64::consts::PI;

use crate::error::InputError;
use crate::rotor::fe::{DiskSpec, PointMassSpec, SectionSpec, SegmentSpec};
use crate::scene::check::Check;
use crate::scene::file::MassFile;
use crate::scene::position::Frame;

/// The rotor's material as far as masses go: its segments from `z_start` on, and the axial
/// positions of its rigid disks.
pub(super) struct Body<'a> {
    pub segments: &'a [SegmentSpec],
    pub z_start: f64,
    pub disks: &'a [DiskSpec],
}

/// A mass at `radius` [m] from the axis at `(z, phi)` (axial position [m], body angle [rad]) must
/// sit in the rotor's material there: between the bore and the outer surface of a segment that
/// holds z (either one at a joint), or on a rigid disk at that z (a disk's radius is not part of
/// the scene: any radius). Without an angle (a balancing mass, placed later at any angle) a
/// mapped shell's bore is its widest at that z.
pub(super) fn in_material(
    c: &Check,
    key: &str,
    what: &str,
    radius: f64,
    (z, phi): (f64, Option<f64>),
    body: &Body,
) -> Result<(), InputError> {
    // Radii compare to 1 nm: a mass on the surface, written in mm, is on it.
    const SLACK_M: f64 = 1e-9;
    if body.disks.iter().any(|d| (d.z - z).abs() <= SLACK_M) {
        return Ok(());
    }
    let mut spans = Vec::new();
    let mut z0 = body.z_start;
    for s in body.segments {
        let z1 = z0 + s.length;
        if z >= z0 - SLACK_M && z <= z1 + SLACK_M {
            spans.push(match &s.section {
                SectionSpec::Tube { outer, inner, .. } => (0.5 * inner, 0.5 * outer),
                SectionSpec::Mapped { outer, map, map_z0 } => {
                    let t = match phi {
                        Some(p) => map.thickness(p, z - map_z0),
                        None => map.min_thickness_at(z - map_z0),
                    };
                    (0.5 * outer - t, 0.5 * outer)
                }
            });
        }
        z0 = z1;
    }
    if spans
        .iter()
        .any(|&(a, b)| radius >= a - SLACK_M && radius <= b + SLACK_M)
    {
        return Ok(());
    }
    let inner = spans.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
    let outer = spans.iter().map(|s| s.1).fold(0.0, f64::max);
    let place = if radius < inner {
        "inside the bore"
    } else {
        "outside the rotor"
    };
    Err(c.err(
        key,
        format!(
            "{what} at radius {} mm (z = {} mm) lies {place}: the material there spans {:.3} \
             ... {:.3} mm from the axis",
            radius * 1e3,
            z * 1e3,
            inner * 1e3,
            outer * 1e3
        ),
    ))
}

/// Point masses on the rotor: each within its length and in its material.
pub(super) fn masses(
    c: &Check,
    key: &str,
    list: &[MassFile],
    body: &Body,
    frame: &Frame,
) -> Result<Vec<PointMassSpec>, InputError> {
    let z_start = body.z_start;
    let z_end = z_start + body.segments.iter().map(|s| s.length).sum::<f64>();
    list.iter()
        .enumerate()
        .map(|(i, m)| {
            let k = format!("{key}[{i}]");
            let zk = format!("{k}.z_mm");
            let z_mm = c.position(&zk, &m.z_mm, frame)?;
            let z = 1e-3 * c.range(&zk, z_mm, z_start * 1e3, z_end * 1e3)?;
            let radius = 1e-3 * c.non_negative(&format!("{k}.radius_mm"), m.radius_mm)?;
            let angle =
                c.range(&format!("{k}.angle_deg"), m.angle_deg, -360.0, 360.0)? * PI / 180.0;
            let rk = format!("{k}.radius_mm");
            in_material(c, &rk, "the mass", radius, (z, Some(angle)), body)?;
            Ok(PointMassSpec {
                z,
                radius,
                angle,
                mass: 1e-3 * c.positive(&format!("{k}.mass_g"), m.mass_g)?,
            })
        })
        .collect()
}
