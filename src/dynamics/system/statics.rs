//! The system at rest: the gravity load, the static equilibrium the simulation starts from, and
//! the velocity that keeps a deflected shape at rest when the spin starts.
//!
//! In: a state q [modal coordinates, m] and a speed Ω [rad/s]. Out: the gravity load at θ = 0
//! [N]; the static equilibrium q under gravity at standstill; the body-frame velocity
//! M⁻¹(−Ω G_c q). Method: Newton on F(q, 0) = 0 with the analytic Newton matrix, open contacts
//! given the stiffness of a 1 µm penetration (in the matrix only) so the iteration can close
//! them; converged when the weighted step is below 1e-13 m.

use nalgebra::{DMatrix, DVector, Matrix2};

use super::roll_system::RollSystem;
use super::supports::Law;
use crate::numerics::newton;

impl RollSystem {
    /// The body-frame velocity that keeps a deflected shape q at rest in the inertial frame when
    /// the spin jumps to Ω: material velocity u̇ = −Ω ẑ×u, projected on the modes, M v = −Ω G_c q.
    /// (Zero body velocity would make the static sag turn with the roll and throw it sideways.)
    pub fn quiescent_velocity(&self, q: &DVector<f64>, omega: f64) -> DVector<f64> {
        let rhs = -omega * (&self.g * q);
        self.m
            .clone()
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| DVector::zeros(self.n))
    }

    /// The gravity load at rest (θ = 0): rotor and support masses.
    pub fn gravity_at_rest(&self) -> DVector<f64> {
        -self.gravity * &self.gy + &self.f_stand
    }

    /// Static equilibrium under gravity at standstill (θ = 0): Newton on F(q, 0) = 0 from `q0`.
    /// Open contacts get the stiffness of a 1 µm penetration in the Newton matrix (not in F) so
    /// the iteration can close them.
    pub fn static_equilibrium(&self, q0: &DVector<f64>) -> Result<DVector<f64>, String> {
        let v = DVector::zeros(self.n);
        let state = (0.0, 0.0, 0.0);
        let floor = self.contact_floor();
        let eval = |q: &DVector<f64>, f: &mut DVector<f64>, jac: &mut DMatrix<f64>| {
            self.force_at(state, q, &v, f);
            self.newton_matrix_at(state, q, &v, (0.0, 1.0, 0.0), jac);
            for (sup, kf) in self.supports.iter().zip(&floor) {
                if let (Law::Contact(_), Some(kf)) = (&sup.law, kf) {
                    let tq = sup.connection(self.n, self.nm, &sup.rows);
                    jac.gemm(1.0, &tq.transpose(), &(kf * &tq), 1.0);
                }
            }
        };
        newton::solve(
            q0.clone(),
            &self.weights,
            eval,
            "static equilibrium",
            "is every rigid mode supported?",
        )
    }

    /// A small regularising contact stiffness per contact support (1 µm penetration, all rollers).
    fn contact_floor(&self) -> Vec<Option<Matrix2<f64>>> {
        self.supports
            .iter()
            .map(|s| match &s.law {
                Law::Contact(contacts) => Some(
                    contacts
                        .rollers
                        .iter()
                        .map(|r| 1e-3 * contacts.law.tangent(1e-6) * r.e * r.e.transpose())
                        .sum(),
                ),
                Law::Linear(_) => None,
            })
            .collect()
    }
}
