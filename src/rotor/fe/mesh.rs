//! The rotor mesh: nodes along z, beam elements, rigid packets at nodes, named nodes, and the
//! two- or three-plane balancing of the rotor's own unbalance.
//!
//! In: a [`RotorSpec`] (SI). Out: a [`Rotor`] whose nodes carry [`NDOF`] DOFs each (u_x, u_y,
//! u_z, θ_x, θ_y, θ_z), or a [`MeshError`]; its mass [kg], mass centre [m], distributed
//! unbalance [kg m] and rigid-body modes. Method: uniform elements per segment, a node moved
//! onto (or inserted at) every named point, disk and joint; mapped sections averaged over three
//! Gauss–Legendre points per element; balancing masses solved from the static, moment (and
//! half-sine) unbalance conditions and added as point packets.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::{DMatrix, Vector3};

use super::beam::Element;
use super::packet::Packet;
use super::spec::{BalancingSpec, PointMassSpec, RotorSpec, SectionSpec};
use crate::rotor::import::body::ImportedBody;
use crate::rotor::section::Section;

/// Degrees of freedom per node.
pub const NDOF: usize = 6;

/// The mesh: node positions, elements, rigid packets at nodes, named nodes.
#[derive(Debug, Clone)]
pub struct Rotor {
    /// Node z [m], ascending.
    pub node_z: Vec<f64>,
    /// Beam elements.
    pub elements: Vec<Element>,
    /// Rigid packets (disks, point masses) at nodes.
    pub packets: Vec<(usize, Packet)>,
    /// Named nodes.
    pub named: BTreeMap<String, usize>,
    /// The balancing masses computed for this mesh (also among `packets`).
    pub balancing_masses: Vec<PointMassSpec>,
    /// An FE body imported from files ([`crate::rotor::import`]): its matrices replace the
    /// elements' and packets' (both empty then).
    pub imported: Option<Arc<ImportedBody>>,
}

fn nearest_node(node_z: &[f64], z: f64) -> usize {
    node_z
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
        .map(|(i, _)| i)
        .expect("mesh has nodes")
}

/// Why a rotor description cannot be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A named point, disk or mass lies outside the rotor.
    #[error("{what} at z = {z} m lies outside the rotor [{start}, {end}] m")]
    OutsideRotor {
        /// What was being placed.
        what: String,
        /// Its z [m].
        z: f64,
        /// Rotor start [m].
        start: f64,
        /// Rotor end [m].
        end: f64,
    },
    /// The rotor has no segments.
    #[error("the rotor has no segments")]
    Empty,
}

impl Rotor {
    /// Meshes a rotor description: uniform elements per segment, with a node moved onto (or
    /// inserted at) every named point, disk and segment joint.
    pub fn mesh(spec: &RotorSpec) -> Result<Self, MeshError> {
        if spec.segments.is_empty() {
            return Err(MeshError::Empty);
        }
        let start = spec.z_start;
        let end = start + spec.segments.iter().map(|s| s.length).sum::<f64>();
        let check = |what: &str, z: f64| {
            if z < start - 1e-9 || z > end + 1e-9 {
                Err(MeshError::OutsideRotor {
                    what: what.to_string(),
                    z,
                    start,
                    end,
                })
            } else {
                Ok(z.clamp(start, end))
            }
        };
        let mut required = Vec::new();
        for (name, z) in &spec.named_points {
            required.push(check(&format!("named point `{name}`"), *z)?);
        }
        for d in &spec.disks {
            required.push(check("disk", d.z)?);
        }
        for p in &spec.point_masses {
            check("point mass", p.z)?;
        }
        let mut node_z = vec![start];
        let mut elements = Vec::new();
        let mut z0 = start;
        for seg in &spec.segments {
            let z1 = z0 + seg.length;
            let n = seg.elements.max(1);
            let h = seg.length / n as f64;
            let mut pts: Vec<f64> = (1..n).map(|i| z0 + i as f64 * h).collect();
            let mut claimed = vec![false; pts.len()];
            let mut extra = Vec::new();
            for &r in required.iter().filter(|&&r| r > z0 + 1e-9 && r < z1 - 1e-9) {
                let nearest = pts
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| !claimed[*i])
                    .min_by(|a, b| (a.1 - r).abs().total_cmp(&(b.1 - r).abs()));
                match nearest {
                    Some((i, &p)) if (p - r).abs() < 0.5 * h => {
                        pts[i] = r;
                        claimed[i] = true;
                    }
                    _ => extra.push(r),
                }
            }
            pts.extend(extra);
            pts.push(z1);
            pts.sort_by(f64::total_cmp);
            pts.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            for &z in &pts {
                let za = *node_z.last().expect("node list starts non-empty");
                let length = z - za;
                let section = element_section(&seg.section, za, z, seg.material.poisson);
                elements.push(Element {
                    node: node_z.len() - 1,
                    length,
                    section,
                    material: seg.material,
                });
                node_z.push(z);
            }
            z0 = z1;
        }
        let nearest = |z: f64| nearest_node(&node_z, z);
        let named = spec
            .named_points
            .iter()
            .map(|(n, z)| (n.clone(), nearest(*z)))
            .collect();
        let mut packets = Vec::new();
        for d in &spec.disks {
            packets.push((nearest(d.z), Packet::disk(d.mass, d.polar, d.diametral)));
        }
        for p in &spec.point_masses {
            let node = nearest(p.z);
            let d = Vector3::new(
                p.radius * p.angle.cos(),
                p.radius * p.angle.sin(),
                p.z - node_z[node],
            );
            packets.push((node, Packet::point(p.mass, d)));
        }
        let mut rotor = Self {
            node_z,
            elements,
            packets,
            named,
            balancing_masses: Vec::new(),
            imported: None,
        };
        if let Some(b) = &spec.balancing {
            for (i, &z) in b.planes.iter().enumerate() {
                check(&format!("balancing plane {}", i + 1), z)?;
            }
            rotor.balance(b);
        }
        Ok(rotor)
    }

    /// The rotor's own (distributed) unbalance weighted along z, ∫ w(z) ρ(q_x, q_y) dz [kg m],
    /// from the sections' centroid offsets; point masses (trial masses) are not part of it.
    /// w = 1 is the static unbalance, w = z its moment.
    pub fn distributed_unbalance(&self, w: impl Fn(f64) -> f64) -> (f64, f64) {
        let mut u = (0.0, 0.0);
        for e in &self.elements {
            let rho = e.material.density;
            let zm = self.node_z[e.node] + 0.5 * e.length;
            let k = w(zm) * rho * e.length;
            u = (u.0 + k * e.section.qx, u.1 + k * e.section.qy);
        }
        u
    }

    /// The weights of the balancing conditions: static, moment, and with a third plane the
    /// half-sine over the rotor's length (the first bending mode of a roll on its journals).
    fn balancing_weights(&self, planes: usize) -> Vec<Box<dyn Fn(f64) -> f64>> {
        let (z0, z1) = (self.node_z[0], self.node_z[self.node_z.len() - 1]);
        let mut w: Vec<Box<dyn Fn(f64) -> f64>> = vec![Box::new(|_| 1.0), Box::new(|z| z)];
        if planes == 3 {
            w.push(Box::new(move |z| {
                (std::f64::consts::PI * (z - z0) / (z1 - z0)).sin()
            }));
        }
        w
    }

    fn balance(&mut self, b: &BalancingSpec) {
        let n = b.planes.len();
        let weights = self.balancing_weights(n);
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| weights[i](b.planes[j]));
        let (mut rx, mut ry) = (nalgebra::DVector::zeros(n), nalgebra::DVector::zeros(n));
        for (i, w) in weights.iter().enumerate() {
            let (ux, uy) = self.distributed_unbalance(w);
            rx[i] = -ux;
            ry[i] = -uy;
        }
        let lu = a.lu();
        let (Some(ux), Some(uy)) = (lu.solve(&rx), lu.solve(&ry)) else {
            return;
        };
        for (k, &z) in b.planes.iter().enumerate() {
            let mag = ux[k].hypot(uy[k]);
            if mag == 0.0 {
                continue;
            }
            let mass = mag / b.radius;
            let angle = uy[k].atan2(ux[k]);
            let node = nearest_node(&self.node_z, z);
            let d = Vector3::new(
                b.radius * angle.cos(),
                b.radius * angle.sin(),
                z - self.node_z[node],
            );
            self.packets.push((node, Packet::point(mass, d)));
            self.balancing_masses.push(PointMassSpec {
                z,
                radius: b.radius,
                angle,
                mass,
            });
        }
    }

    /// The rotor of an imported body, with its named nodes.
    pub fn from_body(body: Arc<ImportedBody>) -> Self {
        Self {
            node_z: body.node_z.clone(),
            elements: Vec::new(),
            packets: Vec::new(),
            named: body.named.clone(),
            balancing_masses: Vec::new(),
            imported: Some(body),
        }
    }

    /// Number of physical DOFs (a solid body's: its matrices' size).
    pub fn ndof(&self) -> usize {
        if let Some(s) = self.imported.as_ref().and_then(|b| b.solid.as_ref()) {
            return s.body.dofs.len();
        }
        NDOF * self.node_z.len()
    }

    /// Total mass [kg].
    pub fn mass(&self) -> f64 {
        if let Some(b) = &self.imported {
            return b.invariants.mass;
        }
        let beams: f64 = self
            .elements
            .iter()
            .map(|e| e.material.density * e.section.area * e.length)
            .sum();
        beams + self.packets.iter().map(|(_, p)| p.mass).sum::<f64>()
    }

    /// Axial position of the mass centre [m].
    pub fn mass_center_z(&self) -> f64 {
        if let Some(b) = &self.imported {
            return b.invariants.centre.z;
        }
        let beams: f64 = self
            .elements
            .iter()
            .map(|e| {
                let zm = self.node_z[e.node] + 0.5 * e.length;
                e.material.density * e.section.area * e.length * zm
            })
            .sum();
        let bodies: f64 = self
            .packets
            .iter()
            .map(|(n, p)| p.mass * self.node_z[*n] + p.h.z)
            .sum();
        (beams + bodies) / self.mass()
    }

    /// The six rigid-body motions (translations x, y, z; rotations about x, y, z through the
    /// origin) as columns in physical DOFs.
    pub fn rigid_body_modes(&self) -> DMatrix<f64> {
        let mut r = DMatrix::zeros(self.ndof(), 6);
        for (i, &z) in self.node_z.iter().enumerate() {
            let o = NDOF * i;
            for k in 0..3 {
                r[(o + k, k)] = 1.0;
                r[(o + 3 + k, 3 + k)] = 1.0;
            }
            // u = ω × (0, 0, z): rotation about x moves y by −z, about y moves x by +z.
            r[(o + 1, 3)] = -z;
            r[(o, 4)] = z;
        }
        r
    }
}

/// The constant section of the element spanning [za, zb]: uniform tubes directly, mapped
/// tubes as the mean of the sections at the element's three Gauss–Legendre points.
fn element_section(spec: &SectionSpec, za: f64, zb: f64, nu: f64) -> Section {
    match spec {
        SectionSpec::Tube {
            outer,
            inner,
            asymmetry,
        } => Section::tube(*outer, *inner, nu).with_asymmetry(*asymmetry),
        SectionSpec::Mapped { outer, map, map_z0 } => {
            let ro = 0.5 * outer;
            // Gauss–Legendre points and weights on [0, 1].
            let g = 0.5 * (3.0f64 / 5.0).sqrt();
            let items: Vec<(f64, Section)> = [(0.5 - g, 5.0), (0.5, 8.0), (0.5 + g, 5.0)]
                .iter()
                .map(|&(xi, w)| {
                    let zm = za + xi * (zb - za) - map_z0;
                    let s = Section::from_inner_radius(ro, |p| ro - map.thickness(p, zm), 72, nu);
                    (w / 18.0, s)
                })
                .collect();
            Section::weighted_mean(&items)
        }
    }
}
