//! The 3-D Timoshenko beam element: one element's 12×12 body-frame matrices and 12-vectors of
//! loads over the six DOFs of its two nodes.
//!
//! In: an [`Element`] (length [m], constant [`Section`], [`Material`]). Out: its
//! [`ElementTerms`]: stiffness K from axial, bending (with the section's centroid and product
//! moments), shear (Timoshenko factor) and torsion strain energy, and the mass, Coriolis,
//! spin-softening, angular-acceleration and stationary gyroscopic matrices and loads of its
//! slices ([`PacketTerms`] per unit length), SI units. Method: the interdependent interpolation
//! of Friedman & Kosmatka (1993), exact for a uniform Timoshenko beam, integrated with a
//! four-point Gauss–Legendre rule.

use nalgebra::{Matrix3, SMatrix, SVector};

use super::packet::{Packet, PacketTerms};
use super::spec::Material;
use crate::rotor::section::Section;

type M12 = SMatrix<f64, 12, 12>;
type V12 = SVector<f64, 12>;
type N6x12 = SMatrix<f64, 6, 12>;

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

/// The 12×12 matrices and loads of one element (the terms of [`PacketTerms`], integrated over
/// the element, and the stiffness K).
pub(super) struct ElementTerms {
    pub(super) k: M12,
    pub(super) m: M12,
    pub(super) gc: M12,
    pub(super) e: M12,
    pub(super) c: M12,
    pub(super) gs: M12,
    pub(super) fc: V12,
    pub(super) ft: V12,
    pub(super) gx: V12,
    pub(super) gy: V12,
}

impl ElementTerms {
    pub(super) fn new(el: &Element) -> Self {
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
