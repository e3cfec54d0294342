//! The roll builder: `[roll]` → the rotor of a tube roll, journal to journal.
//!
//! In: the `[roll]` table (shell, heads, shafts, journal in mm; sensors and masses on the shell's
//! axis; balancing planes), the scene's materials. Out: the [`RotorSpec`] (segments in m from
//! `z_start`, the shell from z = 0 to its length), its thickness map, sensors and the journals
//! as the default Craig–Bampton boundary; or an [`InputError`] at the key. Method: the shell's
//! wall ([`super::shell`]), then its ends laid out symmetrically (journal, shafts, head, shell,
//! head, shafts, journal); the named points are the journals' centres and the shell's ends; the
//! mesh is bounded before it is built ([`MAX_FE_NODES`](crate::scene::MAX_FE_NODES)) and masses
//! must sit in the material.

use super::body::{in_material, masses, Body};
use super::built::Geometry;
use super::materials::Materials;
use super::shell::{nominal_wall, shell_section, thickness_map};
use crate::error::InputError;
use crate::rotor::fe::{BalancingSpec, Material, RotorSpec, SectionSpec, SegmentSpec};
use crate::rotor::wall::FieldStats;
use crate::scene::check::Check;
use crate::scene::file::*;
use crate::scene::limits::mesh_size;
use crate::scene::position::Frame;

/// The rotor of `[roll]`, its keys checked in the order they are read: the shell, its wall, the
/// ends, the sensors, the mesh size, the masses, the balancing planes.
pub(crate) fn build_roll(
    c: &Check,
    roll: &RollFile,
    materials: &Materials,
) -> Result<Geometry, InputError> {
    let mat = materials.get(c, "roll.material", &roll.material)?;
    let sh = &roll.shell;
    let outer = 1e-3 * c.size_mm("roll.shell.outer_diameter_mm", sh.outer_diameter_mm)?;
    let length = 1e-3 * c.size_mm("roll.shell.length_mm", sh.length_mm)?;
    let elements = c.count("roll.shell.elements", sh.elements, 1, 2000)?;
    let wall = nominal_wall(c, sh, outer)?;
    let map = thickness_map(c, sh, length, outer)?;
    let ends = Ends::new(c, roll, outer, mat, materials)?;
    let outboard = ends.length();
    let z_start = -outboard;
    let z_end = length + outboard;
    let shell = SegmentSpec {
        length,
        section: shell_section(c, outer, &map, wall)?,
        elements,
        material: mat,
    };
    let segments = ends.around(shell);
    let mut named_points = vec![
        (
            "journal_tending".to_string(),
            z_start + 0.5 * ends.journal.length,
        ),
        (
            "journal_drive".to_string(),
            z_end - 0.5 * ends.journal.length,
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
    let sensors = sensors(c, &roll.sensors, length, &shell_frame, &mut named_points)?;
    mesh_size(c, &ends.written(elements), named_points.len())?;
    let body = Body {
        segments: &segments,
        z_start,
        disks: &[],
    };
    let point_masses = masses(c, "roll.masses", &roll.masses, &body, &shell_frame)?;
    let balancing = balancing(
        c,
        roll.balancing.as_ref(),
        (z_start, z_end),
        &shell_frame,
        &body,
    )?;
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
        wall_field: sh
            .random_wall
            .as_ref()
            .and(map.as_deref())
            .map(FieldStats::of),
        thickness_map: map,
        sensors,
        boundary,
        body: None,
    })
}

/// One end of the roll outboard of the shell, from the shell outward: the head, the shafts, the
/// journal (the two ends alike, mirrored).
struct Ends {
    head: SegmentSpec,
    shafts: Vec<SegmentSpec>,
    journal: SegmentSpec,
}

impl Ends {
    /// `roll.heads` (a solid disk of the shell's diameter `outer` [m], of the roll's material
    /// `mat` unless it names its own), `roll.shafts` and `roll.journal`.
    fn new(
        c: &Check,
        roll: &RollFile,
        outer: f64,
        mat: Material,
        materials: &Materials,
    ) -> Result<Self, InputError> {
        let head_t = 1e-3 * c.size_mm("roll.heads.thickness_mm", roll.heads.thickness_mm)?;
        let head_mat = match &roll.heads.material {
            Some(m) => materials.get(c, "roll.heads.material", m)?,
            None => mat,
        };
        let head_el = c.count("roll.heads.elements", roll.heads.elements, 1, 100)?;
        let mut shafts = Vec::new();
        for (i, s) in roll.shafts.iter().enumerate() {
            shafts.push(shaft(c, &format!("roll.shafts[{i}]"), s, outer, mat)?);
        }
        let journal = shaft(c, "roll.journal", &roll.journal, outer, mat)?;
        let head = SegmentSpec {
            length: head_t,
            section: SectionSpec::Tube {
                outer,
                inner: 0.0,
                asymmetry: 0.0,
            },
            elements: head_el,
            material: head_mat,
        };
        Ok(Self {
            head,
            shafts,
            journal,
        })
    }

    /// The end's axial length [m]: head, shafts and journal.
    fn length(&self) -> f64 {
        self.head.length + self.shafts.iter().map(|s| s.length).sum::<f64>() + self.journal.length
    }

    /// The roll's segments from the tending journal to the drive one, `shell` between the heads.
    fn around(&self, shell: SegmentSpec) -> Vec<SegmentSpec> {
        let mut segments = vec![self.journal.clone()];
        segments.extend(self.shafts.iter().rev().cloned());
        segments.push(self.head.clone());
        segments.push(shell);
        segments.push(self.head.clone());
        segments.extend(self.shafts.iter().cloned());
        segments.push(self.journal.clone());
        segments
    }

    /// The roll's elements keys as written, each with the elements it adds (an end's parts
    /// twice), the shell's `shell_elements` first: what [`mesh_size`] bounds.
    fn written(&self, shell_elements: usize) -> Vec<(String, usize)> {
        let mut written = vec![("roll.shell.elements".to_string(), shell_elements)];
        for (i, s) in self.shafts.iter().enumerate() {
            written.push((format!("roll.shafts[{i}].elements"), 2 * s.elements));
        }
        written.push(("roll.heads.elements".to_string(), 2 * self.head.elements));
        written.push((
            "roll.journal.elements".to_string(),
            2 * self.journal.elements,
        ));
        written
    }
}

/// `roll.sensors`: each on the shell (z within its `length` [m], on `frame`), its name new among
/// `named_points`, to which it is added. The sensors' names, in order.
fn sensors(
    c: &Check,
    list: &[SensorFile],
    length: f64,
    frame: &Frame,
    named_points: &mut Vec<(String, f64)>,
) -> Result<Vec<String>, InputError> {
    let mut sensors = Vec::new();
    for (i, s) in list.iter().enumerate() {
        let key = format!("roll.sensors[{i}]");
        let zk = format!("{key}.z_mm");
        let z = 1e-3 * c.range(&zk, c.position(&zk, &s.z_mm, frame)?, 0.0, length * 1e3)?;
        crate::error::safe_name(&s.name).map_err(|r| c.err(&format!("{key}.name"), r))?;
        if named_points.iter().any(|(n, _)| n == &s.name) {
            return Err(c.err(
                &format!("{key}.name"),
                format!("duplicate node name `{}`", s.name),
            ));
        }
        named_points.push((s.name.clone(), z));
        sensors.push(s.name.clone());
    }
    Ok(sensors)
}

/// `roll.balancing`: two or three planes (positions on `frame`) within the roll
/// (`z_start`..`z_end` [m]), at least 1 mm apart, and a radius in the material at every plane.
fn balancing(
    c: &Check,
    balancing: Option<&BalancingFile>,
    (z_start, z_end): (f64, f64),
    frame: &Frame,
    body: &Body,
) -> Result<Option<BalancingSpec>, InputError> {
    // No planes: no balancing masses (the roll with its own unbalance, as trial-mass balancing
    // starts from).
    let Some(b) = balancing.filter(|b| !b.planes_mm.is_empty()) else {
        return Ok(None);
    };
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
        let hi = z_end * 1e3;
        let k = format!("{key}[{i}]");
        let z = c.position(&k, z, frame)?;
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
        in_material(c, rk, &what, radius, (z, None), body)?;
    }
    Ok(Some(BalancingSpec { planes, radius }))
}

/// A shaft or the journal: a solid tube no thicker than the shell (`shell_outer` [m]).
fn shaft(
    c: &Check,
    key: &str,
    s: &ShaftFile,
    shell_outer: f64,
    mat: Material,
) -> Result<SegmentSpec, InputError> {
    let d = 1e-3 * c.size_mm(&format!("{key}.diameter_mm"), s.diameter_mm)?;
    if d > shell_outer {
        return Err(c.err_among(
            &[
                &format!("{key}.diameter_mm"),
                "roll.shell.outer_diameter_mm",
            ],
            "a shaft cannot be thicker than the shell",
        ));
    }
    Ok(SegmentSpec {
        length: 1e-3 * c.size_mm(&format!("{key}.length_mm"), s.length_mm)?,
        section: SectionSpec::Tube {
            outer: d,
            inner: 0.0,
            asymmetry: 0.0,
        },
        elements: c.count(&format!("{key}.elements"), s.elements, 1, 1000)?,
        material: mat,
    })
}
