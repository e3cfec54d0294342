//! The roll builder: `[roll]` → the rotor of a tube roll, journal to journal.
//!
//! In: the `[roll]` table (shell, heads, shafts, journal in mm; sensors and masses on the shell's
//! axis; balancing planes), the scene's materials. Out: the [`RotorSpec`] (segments in m from
//! `z_start`, the shell from z = 0 to its length), its thickness map, sensors and the journals
//! as the default Craig–Bampton boundary; or an [`InputError`] at the key. Method: the segments
//! are laid out symmetrically (journal, shafts, head, shell, head, shafts, journal); the named
//! points are the journals' centres and the shell's ends; the mesh is bounded before it is built
//! ([`MAX_FE_NODES`](crate::scene::MAX_FE_NODES)) and masses must sit in the material.

use std::path::Path;
use std::sync::Arc;

use super::body::{in_material, masses, Body};
use super::built::Geometry;
use super::shell::synthetic_spec;
use crate::error::InputError;
use crate::rotor::fe::{BalancingSpec, Material, RotorSpec, SectionSpec, SegmentSpec};
use crate::rotor::wall::ThicknessMap;
use crate::scene::check::Check;
use crate::scene::file::*;
use crate::scene::limits::mesh_size;
use crate::scene::position::Frame;

pub(crate) fn build_roll(
    c: &Check,
    roll: &RollFile,
    find_mat: &dyn Fn(&str, &str) -> Result<Material, InputError>,
) -> Result<Geometry, InputError> {
    let mat = find_mat("roll.material", &roll.material)?;
    let sh = &roll.shell;
    let outer = 1e-3 * c.positive("roll.shell.outer_diameter_mm", sh.outer_diameter_mm)?;
    let length = 1e-3 * c.positive("roll.shell.length_mm", sh.length_mm)?;
    let elements = c.count("roll.shell.elements", sh.elements, 1, 2000)?;
    // The wall is either nominal (uniform) or a map, never both: with a map, a nominal wall would
    // be ignored in favour of the map's, a silent change of the roll's mass and stiffness.
    let wall = match (sh.wall_thickness_mm, &sh.thickness_map, &sh.synthetic_map) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(c.err(
                "roll.shell.wall_thickness_mm",
                "give either a nominal wall (wall_thickness_mm) or a thickness map \
                 (thickness_map or synthetic_map), not both: with a map the wall, and so the \
                 shell's mass and stiffness, come from the map",
            ))
        }
        (Some(w), None, None) => {
            let wall = 1e-3 * c.positive("roll.shell.wall_thickness_mm", w)?;
            if 2.0 * wall >= outer {
                return Err(c.err(
                    "roll.shell.wall_thickness_mm",
                    format!(
                        "a wall of {} mm does not fit in a {} mm tube",
                        wall * 1e3,
                        outer * 1e3
                    ),
                ));
            }
            Some(wall)
        }
        (None, _, _) => None,
    };
    let map = match (&sh.thickness_map, &sh.synthetic_map) {
        (Some(_), Some(_)) => {
            return Err(c.err(
                "roll.shell.synthetic_map",
                "give either thickness_map (a CSV file) or synthetic_map, not both",
            ))
        }
        (Some(csv), None) => {
            let p = c.file.parent().unwrap_or(Path::new(".")).join(csv);
            // Errors inside the CSV name the CSV and its line, and where the scene names it; an
            // unreadable file is reported where the scene names it.
            let key = "roll.shell.thickness_map";
            let map = ThicknessMap::from_csv(&p, length).map_err(|mut e| match e.line {
                Some(_) => {
                    let at = c.err(key, "");
                    let line = at.line.map(|l| format!(":{l}")).unwrap_or_default();
                    e.reason += &format!(" (the map of `{key}`, {}{line})", at.file.display());
                    e
                }
                None => c.err(key, format!("{}: {}", p.display(), e.reason)),
            })?;
            Some(map)
        }
        (None, Some(s)) => {
            let spec = synthetic_spec(c, s)?;
            spec.validate(length)
                .map_err(|r| c.err("roll.shell.synthetic_map", r))?;
            Some(ThicknessMap::synthetic(&spec, length))
        }
        (None, None) => None,
    };
    if let Some(m) = &map {
        let st = m.stats();
        if st.min_m <= 0.0 || st.max_m >= 0.5 * outer {
            let source = match &sh.thickness_map {
                Some(csv) => format!(
                    " ({})",
                    c.file
                        .parent()
                        .unwrap_or(Path::new("."))
                        .join(csv)
                        .display()
                ),
                None => String::new(),
            };
            return Err(c.err(
                "roll.shell.thickness_map",
                format!(
                    "map thickness {:.3}..{:.3} mm{source} does not fit a {} mm tube",
                    st.min_m * 1e3,
                    st.max_m * 1e3,
                    outer * 1e3
                ),
            ));
        }
    }
    let map = map.map(Arc::new);
    let head_t = 1e-3 * c.positive("roll.heads.thickness_mm", roll.heads.thickness_mm)?;
    let head_mat = match &roll.heads.material {
        Some(m) => find_mat("roll.heads.material", m)?,
        None => mat,
    };
    let head_el = c.count("roll.heads.elements", roll.heads.elements, 1, 100)?;
    let mut shafts = Vec::new();
    for (i, s) in roll.shafts.iter().enumerate() {
        shafts.push(shaft(c, &format!("roll.shafts[{i}]"), s, outer, mat)?);
    }
    let journal = shaft(c, "roll.journal", &roll.journal, outer, mat)?;
    let outboard: f64 = head_t + shafts.iter().map(|s| s.length).sum::<f64>() + journal.length;
    let z_start = -outboard;
    let head = SegmentSpec {
        length: head_t,
        section: SectionSpec::Tube { outer, inner: 0.0 },
        elements: head_el,
        material: head_mat,
    };
    let shell = SegmentSpec {
        length,
        section: match (&map, wall) {
            (Some(m), _) => SectionSpec::Mapped {
                outer,
                map: Arc::clone(m),
                map_z0: 0.0,
            },
            (None, Some(w)) => SectionSpec::Tube {
                outer,
                inner: outer - 2.0 * w,
            },
            (None, None) => {
                return Err(c.err(
                    "roll.shell",
                    "the shell needs its wall: wall_thickness_mm (uniform) or a thickness map \
                     (thickness_map or synthetic_map)",
                ))
            }
        },
        elements,
        material: mat,
    };
    let mut segments = vec![journal.clone()];
    segments.extend(shafts.iter().rev().cloned());
    segments.push(head.clone());
    segments.push(shell);
    segments.push(head);
    segments.extend(shafts.iter().cloned());
    segments.push(journal.clone());
    let mut named_points = vec![
        (
            "journal_tending".to_string(),
            z_start + 0.5 * journal.length,
        ),
        (
            "journal_drive".to_string(),
            length + outboard - 0.5 * journal.length,
        ),
        ("shell_tending_end".to_string(), 0.0),
        ("shell_drive_end".to_string(), length),
    ];
    let shell_frame = Frame {
        start_mm: 0.0,
        length_mm: length * 1e3,
        ends: ("tending", "drive"),
        what: "the shell",
    };
    let mut sensors = Vec::new();
    for (i, s) in roll.sensors.iter().enumerate() {
        let key = format!("roll.sensors[{i}]");
        let zk = format!("{key}.z_mm");
        let z = 1e-3
            * c.range(
                &zk,
                c.position(&zk, &s.z_mm, &shell_frame)?,
                0.0,
                length * 1e3,
            )?;
        if named_points.iter().any(|(n, _)| n == &s.name) {
            return Err(c.err(
                &format!("{key}.name"),
                format!("duplicate node name `{}`", s.name),
            ));
        }
        named_points.push((s.name.clone(), z));
        sensors.push(s.name.clone());
    }
    let mut written = vec![("roll.shell.elements".to_string(), elements)];
    for (i, s) in shafts.iter().enumerate() {
        written.push((format!("roll.shafts[{i}].elements"), 2 * s.elements));
    }
    written.push(("roll.heads.elements".to_string(), 2 * head_el));
    written.push(("roll.journal.elements".to_string(), 2 * journal.elements));
    mesh_size(c, &written, named_points.len())?;
    let body = Body {
        segments: &segments,
        z_start,
        disks: &[],
    };
    let point_masses = masses(c, "roll.masses", &roll.masses, &body, &shell_frame)?;
    let balancing = match &roll.balancing {
        // No planes: no balancing masses (the roll with its own unbalance, as trial-mass
        // balancing starts from).
        Some(b) if b.planes_mm.is_empty() => None,
        Some(b) => {
            let key = "roll.balancing.planes_mm";
            if !(2..=3).contains(&b.planes_mm.len()) {
                return Err(c.err(
                    key,
                    "two planes (rigid balancing) or three (modal) are needed (or none: no balancing)",
                ));
            }
            let mut planes = Vec::new();
            for (i, z) in b.planes_mm.iter().enumerate() {
                let lo = z_start * 1e3;
                let hi = (length + outboard) * 1e3;
                let k = format!("{key}[{i}]");
                let z = c.position(&k, z, &shell_frame)?;
                planes.push(1e-3 * c.range(&k, z, lo, hi)?);
            }
            let mut sorted = planes.clone();
            sorted.sort_by(f64::total_cmp);
            if sorted.windows(2).any(|w| w[1] - w[0] < 1e-3) {
                return Err(c.err(key, "the planes must be at least 1 mm apart"));
            }
            let rk = "roll.balancing.radius_mm";
            let radius = 1e-3 * c.positive(rk, b.radius_mm)?;
            for (i, &z) in planes.iter().enumerate() {
                let what = format!("the balancing mass of plane {}", i + 1);
                in_material(c, rk, &what, radius, (z, None), &body)?;
            }
            Some(BalancingSpec { planes, radius })
        }
        None => None,
    };
    let rotor = RotorSpec {
        z_start,
        segments,
        disks: Vec::new(),
        point_masses,
        named_points,
        balancing,
    };
    let boundary = vec!["journal_tending".to_string(), "journal_drive".to_string()];
    Ok(Geometry {
        rotor,
        thickness_map: map,
        sensors,
        boundary,
    })
}

fn shaft(
    c: &Check,
    key: &str,
    s: &ShaftFile,
    shell_outer: f64,
    mat: Material,
) -> Result<SegmentSpec, InputError> {
    let d = 1e-3 * c.positive(&format!("{key}.diameter_mm"), s.diameter_mm)?;
    if d > shell_outer {
        return Err(c.err(
            &format!("{key}.diameter_mm"),
            "a shaft cannot be thicker than the shell",
        ));
    }
    Ok(SegmentSpec {
        length: 1e-3 * c.positive(&format!("{key}.length_mm"), s.length_mm)?,
        section: SectionSpec::Tube {
            outer: d,
            inner: 0.0,
        },
        elements: c.count(&format!("{key}.elements"), s.elements, 1, 1000)?,
        material: mat,
    })
}
