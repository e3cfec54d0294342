//! Global assembly of the body-frame FE matrices of a meshed rotor.
//!
//! In: a [`Rotor`] mesh. Out: its [`FeMatrices`] in physical DOFs ([`NDOF`] per node): M, K,
//! G_c, E, C, G_s and the loads f_c, f_t, g_x, g_y, SI units (kg, N/m, N per unit of Ω², Ω̇ and
//! acceleration). Method: each element's 12×12 [`ElementTerms`] and each packet's 6×6
//! [`PacketTerms`] added into the global matrices at its nodes' DOFs; an imported body's own
//! matrices as they are.

use nalgebra::{DMatrix, DVector};

use super::beam::ElementTerms;
use super::mesh::{Rotor, NDOF};
use super::packet::PacketTerms;

/// Assembled body-frame matrices and load vectors in physical DOFs (see the `fe` module doc).
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
    /// Stress stiffening per (rad/s)² [N/m per (rad/s)²], K_σ = ΔK/Ω_ref² of a stiffness ΔK
    /// exported at a reference speed Ω_ref: the equations carry +Ω² K_σ (stiffness K + Ω² K_σ).
    /// `None` (the default, and always for the native beam rotor: the `fe` module doc) adds
    /// nothing.
    pub ks: Option<DMatrix<f64>>,
}

impl FeMatrices {
    /// No matrices (0 × 0): a solid body's, which is reduced sparse from its own files.
    pub fn empty() -> Self {
        let z = || DMatrix::zeros(0, 0);
        let v = || DVector::zeros(0);
        Self {
            m: z(),
            k: z(),
            gc: z(),
            e: z(),
            c: z(),
            gs: z(),
            fc: v(),
            ft: v(),
            gx: v(),
            gy: v(),
            ks: None,
        }
    }
}

impl Rotor {
    /// Assembles the body-frame matrices (the `fe` module doc).
    pub fn assemble(&self) -> FeMatrices {
        if let Some(b) = &self.imported {
            return b.matrices.clone();
        }
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
            ks: None,
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
}
