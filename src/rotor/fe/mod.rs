//! Rotor FE: a general stepped rotor of 3-D Timoshenko beams, rigid disks and point masses,
//! meshed and assembled into the body-frame matrices of the spinning rotor.
//!
//! In: a [`RotorSpec`] (segments along z with sections, disks, point masses, named nodes).
//! Out: a [`Rotor`] mesh and its [`FeMatrices`] in physical DOFs, 6 per node in the order
//! (u_x, u_y, u_z, θ_x, θ_y, θ_z), SI units (m, rad, kg, N).
//!
//! Every mass — a beam slice at a Gauss point or a rigid body at a node — is a *mass packet*
//! (mass m, first moment h = ∫ρ d, second moment P = ∫ρ d dᵀ of the offsets d from its axis
//! point) that moves with its point's six DOFs: u_p = u + φ×d + ½ φ×(φ×d). Expanding the kinetic
//! energy ½∫ρ|u̇_p + Ω ẑ×(s₀+u_p)|² to second order and applying Lagrange's equations gives
//! (physics.md §4)
//!
//! ```text
//! M q̈ + (D + 2Ω G_c) q̇ + (K − Ω² E + Ω̇ C) q = Ω² f_c − Ω̇ f_t + f_gravity,B + f_ext,B
//! ```
//!
//! where E = M_c + K_r collects spin softening (translations) and the section rotary-inertia
//! stiffening (tilts), and C = G_c + C_r the angular-acceleration terms. The second-order kinematic
//! term ½φ×(φ×d) is what produces the rotary-inertia terms; their gyroscopic part cancels in
//! the body frame for a thin slice, as it must (a thin disk has no body-frame gyroscopic
//! coupling because I_p = 2 I_d).

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector, Vector3};

use crate::rotor::section::Section;
use crate::rotor::wall::ThicknessMap;

type M6 = SMatrix<f64, 6, 6>;
type V6 = SVector<f64, 6>;
type M12 = SMatrix<f64, 12, 12>;
type V12 = SVector<f64, 12>;
type N6x12 = SMatrix<f64, 6, 12>;

/// Degrees of freedom per node.
pub const NDOF: usize = 6;

/// An isotropic linear-elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
}

impl Material {
    /// Shear modulus G = E / (2(1+ν)) [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson))
    }
}

/// How a segment's cross-section is given.
#[derive(Debug, Clone)]
pub enum SectionSpec {
    /// A uniform tube (inner diameter 0 for a solid shaft), diameters in m.
    Tube { outer: f64, inner: f64 },
    /// A tube of outer diameter `outer` whose wall thickness follows a map; `map_z0` is the
    /// rotor z [m] of the map's z = 0 (the tending end of the shell).
    Mapped {
        outer: f64,
        map: Arc<ThicknessMap>,
        map_z0: f64,
    },
}

/// A rotor segment along z, meshed into `elements` beam elements (at least).
#[derive(Debug, Clone)]
pub struct SegmentSpec {
    /// Length [m].
    pub length: f64,
    /// Cross-section.
    pub section: SectionSpec,
    /// Number of elements (more are added where nodes must sit at named points).
    pub elements: usize,
    /// Material.
    pub material: Material,
}

/// A rigid disk centred on the axis.
#[derive(Debug, Clone, Copy)]
pub struct DiskSpec {
    /// Axial position [m].
    pub z: f64,
    /// Mass [kg].
    pub mass: f64,
    /// Polar moment of inertia [kg m²].
    pub polar: f64,
    /// Diametral moment of inertia about its centre [kg m²].
    pub diametral: f64,
}

/// A point mass (balancing or trial mass) on the rotor.
#[derive(Debug, Clone, Copy)]
pub struct PointMassSpec {
    /// Axial position [m].
    pub z: f64,
    /// Radius from the axis [m].
    pub radius: f64,
    /// Body-frame angle [rad], positive about +z (clockwise seen from the tending end), 0 = +x.
    pub angle: f64,
    /// Mass [kg].
    pub mass: f64,
}

/// A general stepped rotor: segments laid end to end from `z_start`.
#[derive(Debug, Clone)]
pub struct RotorSpec {
    /// z of the first segment's left end [m].
    pub z_start: f64,
    /// Segments, from the tending end to the drive end.
    pub segments: Vec<SegmentSpec>,
    /// Rigid disks.
    pub disks: Vec<DiskSpec>,
    /// Point masses.
    pub point_masses: Vec<PointMassSpec>,
    /// Named points where a node must sit (supports, sensors), name → z [m].
    pub named_points: Vec<(String, f64)>,
    /// Two-plane balancing of the rotor's own unbalance, if asked for.
    pub balancing: Option<BalancingSpec>,
}

/// Balancing of the rotor's own unbalance (its sections' centroid offsets; trial and other point
/// masses stay as given) with
/// masses at the given planes and radius: two planes cancel the static and the couple
/// unbalance (rigid-rotor balancing); a third plane also cancels the unbalance weighted by a
/// half-sine over the rotor's length, the first bending mode's (modal balancing).
#[derive(Debug, Clone, PartialEq)]
pub struct BalancingSpec {
    /// Axial positions of the two or three correction planes [m], distinct.
    pub planes: Vec<f64>,
    /// Radius of the correction masses [m].
    pub radius: f64,
}

/// One beam element between nodes `node` and `node + 1`.
#[derive(Debug, Clone, Copy)]
pub struct Element {
    /// Left node index.
    pub node: usize,
    /// Length [m].
    pub length: f64,
    /// Constant cross-section over the element.
    pub section: Section,
    /// Material.
    pub material: Material,
}

/// A rigid mass packet attached to a node: mass, first and second moments of its offsets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Packet {
    /// Mass [kg].
    pub mass: f64,
    /// First moment ∫ρ d [kg m].
    pub h: Vector3<f64>,
    /// Second moment ∫ρ d dᵀ [kg m²].
    pub p: Matrix3<f64>,
}

impl Packet {
    /// An axisymmetric rigid body with polar and diametral inertia about its centre.
    pub fn disk(mass: f64, polar: f64, diametral: f64) -> Self {
        let pxx = 0.5 * polar;
        let pzz = diametral - 0.5 * polar;
        Self {
            mass,
            h: Vector3::zeros(),
            p: Matrix3::from_diagonal(&Vector3::new(pxx, pxx, pzz)),
        }
    }

    /// A point mass at offset `d` from its node.
    pub fn point(mass: f64, d: Vector3<f64>) -> Self {
        Self {
            mass,
            h: mass * d,
            p: mass * d * d.transpose(),
        }
    }

    /// The per-length packet of a beam slice with density ρ and section `s`.
    fn slice(rho: f64, s: &Section) -> Self {
        Self {
            mass: rho * s.area,
            h: Vector3::new(rho * s.qx, rho * s.qy, 0.0),
            p: rho * Matrix3::new(s.sxx, s.sxy, 0.0, s.sxy, s.syy, 0.0, 0.0, 0.0, 0.0),
        }
    }
}

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
}

fn nearest_node(node_z: &[f64], z: f64) -> usize {
    node_z
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
        .map(|(i, _)| i)
        .expect("mesh has nodes")
}

/// Assembled body-frame matrices and load vectors in physical DOFs (see the module doc).
#[derive(Debug, Clone)]
pub struct FeMatrices {
    /// Mass M.
    pub m: DMatrix<f64>,
    /// Elastic stiffness K.
    pub k: DMatrix<f64>,
    /// Coriolis matrix G_c (skew); the equations carry 2Ω G_c.
    pub gc: DMatrix<f64>,
    /// Spin-softening and rotary-inertia matrix E; the equations carry −Ω² E.
    pub e: DMatrix<f64>,
    /// Angular-acceleration stiffness C; the equations carry Ω̇ C.
    pub c: DMatrix<f64>,
    /// Stationary-frame gyroscopic matrix (polar inertia on the tilts), for Campbell diagrams
    /// of a rotor treated as axisymmetric; the stationary-frame equations carry Ω G_s.
    pub gs: DMatrix<f64>,
    /// Centrifugal load of the undeformed mass per Ω² (the unbalance) [N/(rad/s)²].
    pub fc: DVector<f64>,
    /// Angular-acceleration load per Ω̇ [N/(rad/s²)]; the equations carry −Ω̇ f_t.
    pub ft: DVector<f64>,
    /// Load of a unit acceleration field along body x [N/(m/s²)].
    pub gx: DVector<f64>,
    /// Load of a unit acceleration field along body y [N/(m/s²)].
    pub gy: DVector<f64>,
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// S = skew(ẑ): S r = ẑ × r.
fn s_mat() -> Matrix3<f64> {
    skew(&Vector3::z())
}

/// Z = SᵀS = diag(1, 1, 0): the projection on the plane of the section.
fn z_mat() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0))
}

/// ∫ρ [d] X [d] = Σ P_ij [e_i] X [e_j].
fn bilinear(p: &Matrix3<f64>, x: &Matrix3<f64>) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..3 {
            if p[(i, j)] != 0.0 {
                out += p[(i, j)] * skew(&Vector3::ith(i, 1.0)) * x * skew(&Vector3::ith(j, 1.0));
            }
        }
    }
    out
}

/// ∫ρ d × (X d) = Σ P_ij e_i × (X e_j).
fn cross_moment(p: &Matrix3<f64>, x: &Matrix3<f64>) -> Vector3<f64> {
    let mut out = Vector3::zeros();
    for i in 0..3 {
        for j in 0..3 {
            if p[(i, j)] != 0.0 {
                out += p[(i, j)] * Vector3::ith(i, 1.0).cross(&(x * Vector3::ith(j, 1.0)));
            }
        }
    }
    out
}

fn blocks(a: Matrix3<f64>, b: Matrix3<f64>, c: Matrix3<f64>, d: Matrix3<f64>) -> M6 {
    let mut m = M6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&a);
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&b);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&c);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&d);
    m
}

fn stack(a: Vector3<f64>, b: Vector3<f64>) -> V6 {
    V6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

/// The 6×6 matrices and loads of one packet (see the module doc for the derivation).
struct PacketTerms {
    m: M6,
    gc: M6,
    e: M6,
    c: M6,
    gs: M6,
    fc: V6,
    ft: V6,
    gx: V6,
    gy: V6,
}

impl PacketTerms {
    fn new(pk: &Packet) -> Self {
        let (m, h, p) = (pk.mass, pk.h, pk.p);
        let s = s_mat();
        let z = z_mat();
        let hx = skew(&h);
        let inertia = Matrix3::identity() * p.trace() - p;
        let mass = blocks(Matrix3::identity() * m, -hx, hx, inertia);
        let gc = blocks(s * m, -s * hx, hx * s, -bilinear(&p, &s));
        let zp = z * p;
        let k_rot = 0.5 * (zp + zp.transpose()) - Matrix3::identity() * zp.trace();
        let e = blocks(z * m, -z * hx, hx * z, -bilinear(&p, &z) + k_rot);
        let c = gc
            + blocks(
                Matrix3::zeros(),
                Matrix3::zeros(),
                Matrix3::zeros(),
                0.5 * (s * p - p * s),
            );
        let jp = zp.trace();
        let mut gs = M6::zeros();
        gs[(3, 4)] = jp;
        gs[(4, 3)] = -jp;
        let load = |g: Vector3<f64>| stack(m * g, h.cross(&g));
        Self {
            m: mass,
            gc,
            e,
            c,
            gs,
            fc: stack(z * h, cross_moment(&p, &z)),
            ft: stack(s * h, cross_moment(&p, &s)),
            gx: load(Vector3::x()),
            gy: load(Vector3::y()),
        }
    }
}

/// Four-point Gauss–Legendre rule on [0, 1]: exact for polynomials up to degree 7.
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// Interdependent Timoshenko interpolation (Friedman & Kosmatka 1993) at ξ ∈ [0, 1]:
/// the 6×12 map from element DOFs to (u, φ) at ξ, and its z-derivative.
fn interpolation(xi: f64, l: f64, phi: f64) -> (N6x12, N6x12) {
    let d = 1.0 + phi;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    // displacement w and section rotation ψ in one bending plane, for (w1, ψ1, w2, ψ2)
    let n = [
        (2.0 * x3 - 3.0 * x2 - phi * xi + d) / d,
        l * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * xi) / d,
        (-2.0 * x3 + 3.0 * x2 + phi * xi) / d,
        l * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * xi) / d,
    ];
    let dn = [
        (6.0 * x2 - 6.0 * xi - phi) / (d * l),
        (3.0 * x2 - (4.0 + phi) * xi + 1.0 + 0.5 * phi) / d,
        (-6.0 * x2 + 6.0 * xi + phi) / (d * l),
        (3.0 * x2 - (2.0 - phi) * xi - 0.5 * phi) / d,
    ];
    let p = [
        6.0 * (x2 - xi) / (d * l),
        (3.0 * x2 - (4.0 + phi) * xi + d) / d,
        -6.0 * (x2 - xi) / (d * l),
        (3.0 * x2 - (2.0 - phi) * xi) / d,
    ];
    let dp = [
        6.0 * (2.0 * xi - 1.0) / (d * l * l),
        (6.0 * xi - 4.0 - phi) / (d * l),
        -6.0 * (2.0 * xi - 1.0) / (d * l * l),
        (6.0 * xi - 2.0 + phi) / (d * l),
    ];
    let mut nn = N6x12::zeros();
    let mut dd = N6x12::zeros();
    for (node, off) in [(0usize, 0usize), (1, 6)] {
        let (a, b) = (2 * node, 2 * node + 1);
        // x–z plane: u_x with θ_y = ψ
        nn[(0, off)] = n[a];
        nn[(0, off + 4)] = n[b];
        nn[(4, off)] = p[a];
        nn[(4, off + 4)] = p[b];
        dd[(0, off)] = dn[a];
        dd[(0, off + 4)] = dn[b];
        dd[(4, off)] = dp[a];
        dd[(4, off + 4)] = dp[b];
        // y–z plane: u_y with θ_x = −ψ
        nn[(1, off + 1)] = n[a];
        nn[(1, off + 3)] = -n[b];
        nn[(3, off + 1)] = -p[a];
        nn[(3, off + 3)] = p[b];
        dd[(1, off + 1)] = dn[a];
        dd[(1, off + 3)] = -dn[b];
        dd[(3, off + 1)] = -dp[a];
        dd[(3, off + 3)] = dp[b];
        // axial and torsion: linear
        let (lin, dlin) = if node == 0 {
            (1.0 - xi, -1.0 / l)
        } else {
            (xi, 1.0 / l)
        };
        nn[(2, off + 2)] = lin;
        nn[(5, off + 5)] = lin;
        dd[(2, off + 2)] = dlin;
        dd[(5, off + 5)] = dlin;
    }
    (nn, dd)
}

struct ElementTerms {
    k: M12,
    m: M12,
    gc: M12,
    e: M12,
    c: M12,
    gs: M12,
    fc: V12,
    ft: V12,
    gx: V12,
    gy: V12,
}

impl ElementTerms {
    fn new(el: &Element) -> Self {
        let (l, s, mat) = (el.length, &el.section, &el.material);
        let (e_mod, g_mod) = (mat.youngs_modulus, mat.shear_modulus());
        let kga = s.shear_factor * g_mod * s.area;
        let phi = 12.0 * e_mod * s.mean_centroidal_inertia() / (kga * l * l);
        // Axial/bending stiffness over (u_z', θ_x', θ_y'): ε = u_z' + y θ_x' − x θ_y'.
        let db = e_mod
            * Matrix3::new(
                s.area, s.qy, -s.qx, s.qy, s.syy, -s.sxy, -s.qx, -s.sxy, s.sxx,
            );
        let slice = PacketTerms::new(&Packet::slice(mat.density, s));
        let mut t = Self {
            k: M12::zeros(),
            m: M12::zeros(),
            gc: M12::zeros(),
            e: M12::zeros(),
            c: M12::zeros(),
            gs: M12::zeros(),
            fc: V12::zeros(),
            ft: V12::zeros(),
            gx: V12::zeros(),
            gy: V12::zeros(),
        };
        for &(xi, w) in &GAUSS4 {
            let wl = w * l;
            let (n, dn) = interpolation(xi, l, phi);
            let mut bb = SMatrix::<f64, 3, 12>::zeros();
            bb.row_mut(0).copy_from(&dn.row(2));
            bb.row_mut(1).copy_from(&dn.row(3));
            bb.row_mut(2).copy_from(&dn.row(4));
            let mut bs = SMatrix::<f64, 2, 12>::zeros();
            bs.row_mut(0).copy_from(&(dn.row(0) - n.row(4)));
            bs.row_mut(1).copy_from(&(dn.row(1) + n.row(3)));
            let bt = dn.row(5);
            t.k += wl
                * (bb.transpose() * db * bb
                    + kga * bs.transpose() * bs
                    + g_mod * s.torsion * bt.transpose() * bt);
            let nt = n.transpose();
            t.m += wl * nt * slice.m * n;
            t.gc += wl * nt * slice.gc * n;
            t.e += wl * nt * slice.e * n;
            t.c += wl * nt * slice.c * n;
            t.gs += wl * nt * slice.gs * n;
            t.fc += wl * nt * slice.fc;
            t.ft += wl * nt * slice.ft;
            t.gx += wl * nt * slice.gx;
            t.gy += wl * nt * slice.gy;
        }
        t
    }
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

    /// Number of physical DOFs.
    pub fn ndof(&self) -> usize {
        NDOF * self.node_z.len()
    }

    /// Total mass [kg].
    pub fn mass(&self) -> f64 {
        let beams: f64 = self
            .elements
            .iter()
            .map(|e| e.material.density * e.section.area * e.length)
            .sum();
        beams + self.packets.iter().map(|(_, p)| p.mass).sum::<f64>()
    }

    /// Axial position of the mass centre [m].
    pub fn mass_center_z(&self) -> f64 {
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

    /// Assembles the body-frame matrices (module doc).
    pub fn assemble(&self) -> FeMatrices {
        let n = self.ndof();
        let mut f = FeMatrices {
            m: DMatrix::zeros(n, n),
            k: DMatrix::zeros(n, n),
            gc: DMatrix::zeros(n, n),
            e: DMatrix::zeros(n, n),
            c: DMatrix::zeros(n, n),
            gs: DMatrix::zeros(n, n),
            fc: DVector::zeros(n),
            ft: DVector::zeros(n),
            gx: DVector::zeros(n),
            gy: DVector::zeros(n),
        };
        for el in &self.elements {
            let t = ElementTerms::new(el);
            let o = NDOF * el.node;
            for (dst, src) in [
                (&mut f.k, &t.k),
                (&mut f.m, &t.m),
                (&mut f.gc, &t.gc),
                (&mut f.e, &t.e),
                (&mut f.c, &t.c),
                (&mut f.gs, &t.gs),
            ] {
                let mut v = dst.view_mut((o, o), (12, 12));
                v += src;
            }
            for (dst, src) in [
                (&mut f.fc, &t.fc),
                (&mut f.ft, &t.ft),
                (&mut f.gx, &t.gx),
                (&mut f.gy, &t.gy),
            ] {
                let mut v = dst.rows_mut(o, 12);
                v += src;
            }
        }
        for (node, pk) in &self.packets {
            let t = PacketTerms::new(pk);
            let o = NDOF * node;
            for (dst, src) in [
                (&mut f.m, &t.m),
                (&mut f.gc, &t.gc),
                (&mut f.e, &t.e),
                (&mut f.c, &t.c),
                (&mut f.gs, &t.gs),
            ] {
                let mut v = dst.view_mut((o, o), (6, 6));
                v += src;
            }
            for (dst, src) in [
                (&mut f.fc, &t.fc),
                (&mut f.ft, &t.ft),
                (&mut f.gx, &t.gx),
                (&mut f.gy, &t.gy),
            ] {
                let mut v = dst.rows_mut(o, 6);
                v += src;
            }
        }
        f
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
        SectionSpec::Tube { outer, inner } => Section::tube(*outer, *inner, nu),
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
