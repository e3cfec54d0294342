//! The Newton matrix a M − b ∂F/∂q − c ∂F/∂q̇ that the implicit integrators factor, analytic.
//!
//! In: the state q, q̇, the roll angle θ [rad], speed Ω [rad/s] and acceleration Ω̇ [rad/s²]
//! (from the speed profile at t [s]) and the integrator's coefficients (a, b, c). Out: the
//! n × n matrix. Method: a M + b (K − Ω²E + Ω̇C) + c (D + 2ΩG) (for a constant speed in one
//! pass over the pre-combined matrices), plus per support T_qᵀ [(b K_c + c C_c) T_q +
//! b C_c T_Ω] with T_q the map from q to the relative journal displacement and T_Ω its part
//! through the rotation of the journal velocity, plus the axial drive's rank-1 term. Only the
//! contacts change from one call to the next.

use nalgebra::{DMatrix, DVector, Matrix2};

use super::roll_system::RollSystem;

impl RollSystem {
    /// out = a M − b ∂F/∂q − c ∂F/∂q̇ at (θ, Ω, Ω̇).
    pub fn newton_matrix_at(
        &self,
        (theta, omega, alpha): (f64, f64, f64),
        q: &DVector<f64>,
        v: &DVector<f64>,
        (a, b, c): (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        let n = self.n;
        match &self.lin {
            Some(lin) if alpha == 0.0 && Some(omega) == self.constant_speed() => {
                // a M + b (K − Ω²E) + c (D + 2ΩG) in one pass (nalgebra's scaled sums make an
                // n × n temporary each).
                let (kq, cv) = lin.as_slice().split_at(n * n);
                let terms = self.m.as_slice().iter().zip(kq).zip(cv);
                for (o, ((m, k), d)) in out.as_mut_slice().iter_mut().zip(terms) {
                    *o = a * m + b * k + c * d;
                }
            }
            _ => {
                out.copy_from(&self.m);
                *out *= a;
                *out += b * &self.k;
                *out -= (b * omega * omega) * &self.e;
                if alpha != 0.0 {
                    *out += (b * alpha) * &self.c;
                }
                *out += c * &self.d;
                *out += (2.0 * c * omega) * &self.g;
            }
        }
        let (st, ct) = theta.sin_cos();
        for sup in &self.supports {
            let (w, wd, r) = sup.relative(self.nm, (st, ct), omega, q, v);
            let loc = sup.local((theta, st, ct), omega, w, wd, None);
            // T_q (2 × n): w = R Φ_j p − s; T_Ω = Ω S R Φ_j (the rotation of the journal velocity).
            let rp = DMatrix::from_column_slice(2, self.nm, (r * &sup.rows).as_slice());
            let tq = sup.connection(n, self.nm, &rp);
            let s_mat = Matrix2::new(0.0, -omega, omega, 0.0);
            let mut tw = DMatrix::zeros(2, n);
            tw.view_mut((0, 0), (2, self.nm)).copy_from(&(s_mat * rp));
            let kk = b * loc.kc + c * loc.cc;
            let inner = kk * &tq + (b * loc.cc) * tw;
            // out += T_qᵀ inner, a rank-2 update (nalgebra's gemm packs for a general product).
            let (tq, inner) = (tq.as_slice(), inner.as_slice());
            for (col, ij) in out
                .as_mut_slice()
                .chunks_exact_mut(n)
                .zip(inner.chunks_exact(2))
            {
                for (o, ti) in col.iter_mut().zip(tq.chunks_exact(2)) {
                    *o += ti[0] * ij[0] + ti[1] * ij[1];
                }
            }
        }
        if let Some((row, ka, ca)) = &self.drive {
            out.ger(b * ka + c * ca, row, row, 1.0);
        }
    }

    /// The Newton matrix at time t.
    pub fn newton_matrix(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        coef: (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        self.newton_matrix_at(self.speed.at(t), q, v, coef, out);
    }
}
