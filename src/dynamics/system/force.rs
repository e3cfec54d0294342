//! The force F(t, q, q̇) of the equations of motion M q̈ = F, the integrators' hot path (called
//! once per corrector iteration).
//!
//! In: the state q, q̇ (modal coordinates, support masses [m, m/s]) and the roll angle θ
//! [rad], speed Ω [rad/s] and acceleration Ω̇ [rad/s²] (from the speed profile at t [s]). Out:
//! F [N] over the n coordinates. Method (physics.md §4): −(K − Ω²E + Ω̇C) q − (D + 2ΩG) q̇
//! (for a constant speed one SIMD product with the pre-combined matrices,
//! `crate::numerics::dense::Padded`), plus Ω² f_c − Ω̇ f_t, the gravity g_B(θ) and the support
//! masses' weight, the supports' forces Φ_jᵀ R(θ)ᵀ F_j on the rotor (−F_j on their support
//! mass) and the axial drive spring; one `sin_cos` of θ serves R(θ), g_B and the roundness.

use nalgebra::DVector;

use super::roll_system::RollSystem;

impl RollSystem {
    /// F(q, q̇) at roll angle θ, speed Ω and acceleration Ω̇, into `out`.
    pub fn force_at(
        &self,
        (theta, omega, alpha): (f64, f64, f64),
        q: &DVector<f64>,
        v: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        match &self.lin_padded {
            Some(lin) if alpha == 0.0 && Some(omega) == self.constant_speed() => {
                // [K − Ω²E | D + 2ΩG] [q; v] in one SIMD product (`crate::numerics::dense`): the force's
                // largest cost in the timing case.
                lin.matvec(out.as_mut_slice(), false, q.as_slice(), v.as_slice(), -1.0);
            }
            _ => {
                out.gemv(-1.0, &self.k, q, 0.0);
                out.gemv(omega * omega, &self.e, q, 1.0);
                out.gemv(-1.0, &self.d, v, 1.0);
                out.gemv(-2.0 * omega, &self.g, v, 1.0);
                if alpha != 0.0 {
                    out.gemv(-alpha, &self.c, q, 1.0);
                }
            }
        }
        // The one transcendental call of the force (with roller roundness on the roll angle).
        let (s, c) = theta.sin_cos();
        let (w2, gs, gc) = (omega * omega, -self.gravity * s, -self.gravity * c);
        let loads = (self.fc.as_slice().iter())
            .zip(self.gx.as_slice())
            .zip(self.gy.as_slice())
            .zip(self.f_stand.as_slice());
        for (o, (((fc, gx), gy), fs)) in out.as_mut_slice().iter_mut().zip(loads) {
            *o += w2 * fc + gs * gx + gc * gy + fs;
        }
        if alpha != 0.0 {
            out.axpy(-alpha, &self.ft, 1.0);
        }
        for sup in &self.supports {
            let (w, wd, r) = sup.relative(self.nm, (s, c), omega, q, v);
            let loc = sup.local((theta, s, c), omega, w, wd, None);
            let fb = r.transpose() * loc.f;
            let rows = sup.rows.as_slice().chunks_exact(2);
            for (o, rj) in out.as_mut_slice()[..self.nm].iter_mut().zip(rows) {
                *o += rj[0] * fb.x + rj[1] * fb.y;
            }
            if let Some(i) = sup.stand {
                out[i] -= loc.f.x;
                out[i + 1] -= loc.f.y;
            }
        }
        if let Some((row, ka, ca)) = &self.drive {
            let uz = row.dot(q);
            let vz = row.dot(v);
            out.axpy(-(ka * uz + ca * vz), row, 1.0);
        }
    }

    /// F(t, q, q̇).
    pub fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.force_at(self.speed.at(t), q, v, out);
    }
}
