//! A nip's contact segments between two reduced rolls: geometry, forces and their derivatives.
//!
//! In: a [`Nip`] of the scene (segment centres z [m], direction n from roll_a's axis to roll_b's,
//! gap [m], contact law, damping per length) and both rolls' reduced models and FE meshes; at
//! evaluation both rolls' angles θ [rad], speeds Ω [rad/s] and modal states. Out: per segment
//! the penetration δ [m], its rate [m/s], the force F [N] (pushing the rolls apart along n),
//! its tangent dF/dδ [N/m], and the nip band's width [m]; the generalized forces on both rolls'
//! modal coordinates and their Newton-matrix terms.
//!
//! Method: a segment's centre on each roll moves u = R(θ) Φ(z) p in the inertial frame, with
//! Φ(z) the lateral rows of the mode shapes interpolated linearly between the two nodes around
//! z; its inertial velocity is R(θ)(Φ ṗ + Ω S Φ p), S = [[0, −1], [1, 0]]. The penetration is
//! δ = n·(u_a − u_b) − gap + c(z) (c the rolls' crown at the segment, scene `machine.rs`),
//! so δ = J q − gap + c with the row J = [nᵀR_aΦ_a, −nᵀR_bΦ_b] and
//! δ̇ = J q̇ + J̃ q, J̃ = [Ω_a nᵀR_aSΦ_a, −Ω_b nᵀR_bSΦ_b]. The generalized force is −Jᵀ F.
//! Laws per segment of length L (scene `machine.rs`): linear k L δ (tension too); Hertz
//! k δ^e; a Winkler cover L (4√2/3) k_f √R δ^1.5; the damping c L δ̇ while in contact, the
//! total never adhesive except for the linear law. Width: Hertz 2b of the Roark/Hertz band
//! under the segment's force, cover 2√(2Rδ), none for the linear law. A viscoelastic cover:
//! in the static equilibrium and the linearisation at rest the relaxed Winkler law (k_r); in a
//! run, once [`NipSys::start_covers`] has set each segment's cover points ([`super::cover`]),
//! the force and dF/dδ of its [`CoverTrack`] at the time and the covered roll's angle, its
//! points carried forward by [`NipSys::commit`] after every accepted step; band 2√(2Rδ).
//!
//! Runout: in a run (not in the static equilibrium or the linearisation, which hold round
//! rolls) each roll's outer surface H(ψ) (`Nip::surfaces`: its roundness, and a cover's) adds
//! to every segment's penetration at the body angle ψ of its point facing the other roll,
//! ψ_a of R_aᵀ n and ψ_b of −R_bᵀ n: δ += H_a(ψ_a) + H_b(ψ_b), δ̇ −= Ω_a H_a′(ψ_a) +
//! Ω_b H_b′(ψ_b) (ψ̇ = −Ω). It depends on the angles only, so J is unchanged. H is taken at
//! the nip line, the same over the band: for lobes longer than the band, 2πR/k ≫ 2a.

use std::sync::Mutex;

use nalgebra::{DMatrix, DVector, Matrix2, RowDVector, Vector2};

use super::cover::CoverTrack;
use super::system::Profile;
use crate::dynamics::model::Model;
use crate::rotor::fe::NDOF;
use crate::scene::{Nip, NipLaw};

/// The lateral rows (2 × nm) of the mode shapes at z [m], linear between the nodes around z.
pub fn rows_at(model: &Model, z: f64) -> DMatrix<f64> {
    let nz = &model.rotor.node_z;
    let i = nz.partition_point(|x| *x <= z).clamp(1, nz.len() - 1) - 1;
    let s = ((z - nz[i]) / (nz[i + 1] - nz[i])).clamp(0.0, 1.0);
    let phi = &model.reduced.phi;
    (1.0 - s) * phi.rows(NDOF * i, 2) + s * phi.rows(NDOF * (i + 1), 2)
}

/// A segment's force F [N] and tangent dF/dδ [N/m] at penetration δ [m] (no damping).
pub fn law_force(law: &NipLaw, length: f64, delta: f64) -> (f64, f64) {
    match *law {
        NipLaw::Linear { stiffness } => (stiffness * length * delta, stiffness * length),
        _ if delta <= 0.0 => (0.0, 0.0),
        NipLaw::Hertz { fit } => {
            let f = fit.k * delta.powf(fit.exponent);
            (f, fit.exponent * f / delta)
        }
        NipLaw::Cover {
            foundation, radius, ..
        } => winkler(length, foundation, radius, delta),
        NipLaw::Viscoelastic { cover } => winkler(length, cover.relaxed, cover.radius, delta),
    }
}

/// The Winkler cover's (4√2/3) k √R δ^1.5 L and its derivative.
fn winkler(length: f64, foundation: f64, radius: f64, delta: f64) -> (f64, f64) {
    let c = length * 4.0 * std::f64::consts::SQRT_2 / 3.0 * foundation * radius.sqrt();
    let r = delta.sqrt();
    (c * delta * r, 1.5 * c * r)
}

/// The width [m] of a segment's band at penetration δ [m] carrying F [N]; `None` for a law
/// without one (linear).
pub fn band_width(law: &NipLaw, delta: f64, force: f64) -> Option<f64> {
    match *law {
        NipLaw::Linear { .. } => None,
        NipLaw::Hertz { fit } => Some(2.0 * fit.geometry.half_width(force.max(0.0))),
        NipLaw::Cover { radius, .. } => Some(2.0 * (2.0 * radius * delta.max(0.0)).sqrt()),
        NipLaw::Viscoelastic { cover } => Some(2.0 * (2.0 * cover.radius * delta.max(0.0)).sqrt()),
    }
}

/// One segment's state.
#[derive(Debug, Clone, Copy)]
pub struct SegmentState {
    /// Penetration δ [m].
    pub delta: f64,
    /// Its rate [m/s].
    pub rate: f64,
    /// Force F [N] pushing the rolls apart.
    pub force: f64,
    /// ∂F/∂δ [N/m].
    pub stiffness: f64,
    /// ∂F/∂δ̇ [Ns/m].
    pub damping: f64,
}

/// A nip on the two rolls' reduced models.
#[derive(Debug)]
pub struct NipSys {
    /// The scene's nip.
    pub nip: Nip,
    /// Lateral rows (2 × nm) of roll_a and roll_b at each segment.
    rows: Vec<(DMatrix<f64>, DMatrix<f64>)>,
    /// A viscoelastic cover's points per segment, once started.
    covers: Option<Mutex<Vec<CoverTrack>>>,
    /// The outer surfaces of roll_a and roll_b (`Nip::surfaces`).
    surfaces: (Profile, Profile),
}

/// A roll's kinematic state for the nips: R(θ), Ω, modal p and ṗ.
pub struct RollView<'a> {
    /// R(θ) (body → inertial).
    pub rot: Matrix2<f64>,
    /// Ω [rad/s].
    pub omega: f64,
    /// Modal coordinates.
    pub p: &'a [f64],
    /// Their rates.
    pub pd: &'a [f64],
}

/// rows · p over the first `rows.ncols()` entries of p (the column-major storage read in pairs:
/// the same sums, in the same order, as indexing, without the bounds checks).
fn times(rows: &DMatrix<f64>, p: &[f64]) -> Vector2<f64> {
    let mut out = Vector2::zeros();
    for (c, x) in rows.as_slice().chunks_exact(2).zip(p) {
        out.x += c[0] * x;
        out.y += c[1] * x;
    }
    out
}

/// f += rowsᵀ g (rows 2 × n column-major, f of length n at least).
fn add_transposed(f: &mut [f64], rows: &DMatrix<f64>, g: &Vector2<f64>) {
    for (o, c) in f.iter_mut().zip(rows.as_slice().chunks_exact(2)) {
        *o += c[0] * g.x + c[1] * g.y;
    }
}

impl NipSys {
    /// The nip on roll_a's and roll_b's models.
    pub fn new(nip: &Nip, a: &Model, b: &Model) -> Self {
        let rows = nip
            .z
            .iter()
            .map(|z| (rows_at(a, *z), rows_at(b, *z)))
            .collect();
        Self {
            nip: nip.clone(),
            rows,
            covers: None,
            surfaces: (Profile::new(&nip.surfaces.0), Profile::new(&nip.surfaces.1)),
        }
    }

    /// The runout at the nip (module doc): H_a(ψ_a) + H_b(ψ_b) [m] and its rate [m/s]; `None`
    /// for round rolls.
    fn runout(&self, a: &RollView, b: &RollView) -> Option<(f64, f64)> {
        let (ha, hb) = &self.surfaces;
        if ha.is_round() && hb.is_round() {
            return None;
        }
        let n = Vector2::new(self.nip.normal[0], self.nip.normal[1]);
        let (da, db) = (a.rot.transpose() * n, b.rot.transpose() * -n);
        let (va, sa) = ha.eval((da.y, da.x));
        let (vb, sb) = hb.eval((db.y, db.x));
        Some((va + vb, -(a.omega * sa + b.omega * sb)))
    }

    /// The body-frame angle [rad] of the nip line on the covered roll (a viscoelastic cover).
    fn cover_angle(&self, a: &RollView, b: &RollView, on_b: bool) -> f64 {
        let n = Vector2::new(self.nip.normal[0], self.nip.normal[1]);
        let d = if on_b {
            b.rot.transpose() * -n
        } else {
            a.rot.transpose() * n
        };
        d.y.atan2(d.x)
    }

    /// Every segment's penetration δ [m] and its rate [m/s], with the rolls' runout in a run
    /// (`runout`; module doc).
    fn penetrations(&self, a: &RollView, b: &RollView, runout: bool) -> Vec<(f64, f64)> {
        let n = Vector2::new(self.nip.normal[0], self.nip.normal[1]);
        let s = Matrix2::new(0.0, -1.0, 1.0, 0.0);
        let surface = if runout { self.runout(a, b) } else { None };
        self.rows
            .iter()
            .enumerate()
            .map(|(j, (ra, rb))| {
                let (ua, ub) = (times(ra, a.p), times(rb, b.p));
                let va = a.rot * (times(ra, a.pd) + a.omega * s * ua);
                let vb = b.rot * (times(rb, b.pd) + b.omega * s * ub);
                let mut delta = n.dot(&(a.rot * ua - b.rot * ub)) - self.nip.gap;
                if let Some(c) = self.nip.crown.get(j) {
                    delta += c;
                }
                let rate = n.dot(&(va - vb));
                match surface {
                    Some((h, dh)) => (delta + h, rate + dh),
                    None => (delta, rate),
                }
            })
            .collect()
    }

    /// A viscoelastic cover's points set at time `t` [s] (module doc of [`super::cover`]: those
    /// in the band relaxed at their penetration); nothing for another law.
    pub fn start_covers(&mut self, t: f64, a: &RollView, b: &RollView) {
        let NipLaw::Viscoelastic { cover } = self.nip.law else {
            return;
        };
        let psi = self.cover_angle(a, b, cover.on_b);
        let tracks = (self.penetrations(a, b, true).iter())
            .map(|(delta, _)| {
                let mut track = CoverTrack::new(&cover, self.nip.segment_length);
                track.start(t, psi, *delta);
                track
            })
            .collect();
        self.covers = Some(Mutex::new(tracks));
    }

    /// Carries a started viscoelastic cover's points to the accepted time `t` [s].
    pub fn commit(&self, t: f64, a: &RollView, b: &RollView) {
        let (Some(covers), NipLaw::Viscoelastic { cover }) = (&self.covers, &self.nip.law) else {
            return;
        };
        let psi = self.cover_angle(a, b, cover.on_b);
        let mut tracks = covers.lock().unwrap_or_else(|e| e.into_inner());
        for (track, (delta, _)) in tracks.iter_mut().zip(self.penetrations(a, b, true)) {
            track.commit(t, psi, delta);
        }
    }

    /// The rows of segment `j` on each roll: (nᵀ R_a Φ_a, nᵀ R_b Φ_b), 1 × nm.
    pub fn normal_rows(
        &self,
        j: usize,
        a: &Matrix2<f64>,
        b: &Matrix2<f64>,
    ) -> (RowDVector<f64>, RowDVector<f64>) {
        let n = Vector2::new(self.nip.normal[0], self.nip.normal[1]);
        let na = (a.transpose() * n).transpose();
        let nb = (b.transpose() * n).transpose();
        (na * &self.rows[j].0, nb * &self.rows[j].1)
    }

    /// The state of every segment at time `t` [s] (read by a started viscoelastic cover only),
    /// with the rolls' runout in a run (`runout`; module doc).
    pub fn segments(&self, t: f64, a: &RollView, b: &RollView, runout: bool) -> Vec<SegmentState> {
        let nip = &self.nip;
        let tracks = self
            .covers
            .as_ref()
            .map(|c| c.lock().unwrap_or_else(|e| e.into_inner()));
        let psi = match nip.law {
            NipLaw::Viscoelastic { cover } => self.cover_angle(a, b, cover.on_b),
            _ => 0.0,
        };
        self.penetrations(a, b, runout)
            .into_iter()
            .enumerate()
            .map(|(j, (delta, rate))| {
                let (f, k) = match &tracks {
                    Some(tr) => tr[j].force(t, psi, delta),
                    None => law_force(&nip.law, nip.segment_length, delta),
                };
                let linear = matches!(nip.law, NipLaw::Linear { .. });
                let c = if linear || delta > 0.0 {
                    nip.damping * nip.segment_length
                } else {
                    0.0
                };
                let total = f + c * rate;
                let (force, stiffness, damping) = if linear || total > 0.0 {
                    (total, k, c)
                } else {
                    (0.0, 0.0, 0.0)
                };
                SegmentState {
                    delta,
                    rate,
                    force,
                    stiffness,
                    damping,
                }
            })
            .collect()
    }

    /// Adds the generalized forces −Jᵀ F of the segments to roll_a's and roll_b's modal parts.
    pub fn add_forces(
        &self,
        seg: &[SegmentState],
        (a, b): (&Matrix2<f64>, &Matrix2<f64>),
        out_a: &mut [f64],
        out_b: &mut [f64],
    ) {
        let n = Vector2::new(self.nip.normal[0], self.nip.normal[1]);
        // Summed over the segments first, then added (the order of the sums kept).
        let mut fa = vec![0.0; out_a.len()];
        let mut fb = vec![0.0; out_b.len()];
        for ((ra, rb), s) in self.rows.iter().zip(seg) {
            // On roll_a −F n, on roll_b +F n (inertial), into the body frame by Rᵀ.
            let ga = a.transpose() * (-s.force * n);
            let gb = b.transpose() * (s.force * n);
            add_transposed(&mut fa, ra, &ga);
            add_transposed(&mut fb, rb, &gb);
        }
        for (o, f) in out_a.iter_mut().zip(&fa) {
            *o += f;
        }
        for (o, f) in out_b.iter_mut().zip(&fb) {
            *o += f;
        }
    }

    /// The segment rows J (1 × n, roll_a's modal block at `oa`, roll_b's at `ob`) and J̃.
    pub fn jacobian_rows(
        &self,
        j: usize,
        a: &RollView,
        b: &RollView,
        (oa, ob, n): (usize, usize, usize),
    ) -> (DVector<f64>, DVector<f64>) {
        let s = Matrix2::new(0.0, -1.0, 1.0, 0.0);
        let (ja, jb) = self.normal_rows(j, &a.rot, &b.rot);
        let (sa, sb) = self.normal_rows(j, &(a.rot * s), &(b.rot * s));
        let mut row = DVector::zeros(n);
        let mut rate = DVector::zeros(n);
        for k in 0..ja.len() {
            row[oa + k] = ja[k];
            rate[oa + k] = a.omega * sa[k];
        }
        for k in 0..jb.len() {
            row[ob + k] = -jb[k];
            rate[ob + k] = -b.omega * sb[k];
        }
        (row, rate)
    }
}
