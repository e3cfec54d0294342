//! Mass packets: every mass of the rotor — a beam slice at a Gauss point, a rigid disk or a
//! point mass at a node — as mass m, first moment h = ∫ρ d and second moment P = ∫ρ d dᵀ of the
//! offsets d from its axis point, and the 6×6 body-frame terms such a packet contributes.
//!
//! In: a [`Packet`] (kg, kg m, kg m²). Out: its [`PacketTerms`]: the mass, Coriolis G_c,
//! spin-softening and rotary-inertia E, angular-acceleration C and stationary gyroscopic G_s
//! matrices over the six DOFs (u_x, u_y, u_z, θ_x, θ_y, θ_z) of its point, and its loads per
//! Ω² [N/(rad/s)²], per Ω̇ [N/(rad/s²)] and per unit acceleration along body x and y
//! [N/(m/s²)]. Method: the second-order expansion of the kinetic energy of the packet moving as
//! u_p = u + φ×d + ½ φ×(φ×d) in the body frame spinning about z (the module doc of
//! [`fe`](super); physics.md §4).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::rotor::section::Section;

type M6 = SMatrix<f64, 6, 6>;
type V6 = SVector<f64, 6>;

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
    pub(super) fn slice(rho: f64, s: &Section) -> Self {
        Self {
            mass: rho * s.area,
            h: Vector3::new(rho * s.qx, rho * s.qy, 0.0),
            p: rho * Matrix3::new(s.sxx, s.sxy, 0.0, s.sxy, s.syy, 0.0, 0.0, 0.0, 0.0),
        }
    }
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

/// The 6×6 matrices and loads of one packet (the `fe` module doc has the derivation).
pub(super) struct PacketTerms {
    pub(super) m: M6,
    pub(super) gc: M6,
    pub(super) e: M6,
    pub(super) c: M6,
    pub(super) gs: M6,
    pub(super) fc: V6,
    pub(super) ft: V6,
    pub(super) gx: V6,
    pub(super) gy: V6,
}

impl PacketTerms {
    pub(super) fn new(pk: &Packet) -> Self {
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
