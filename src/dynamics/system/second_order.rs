//! The roll system as the integrators see it ([`SecondOrder`]): size, mass, force, Newton
//! matrix, error weights, and one event per contact roller.
//!
//! In: t [s] and the state q, q̇. Out: what [`SecondOrder`] asks for; the events are the
//! penetrations δ [m] of every contact roller, supports and rollers in scene order (their
//! zeros are lift-off and touch-down). Method: delegation to the system's own force and Newton
//! matrix; the system is linear in the state when no support has contacts.

use nalgebra::{DMatrix, DVector};

use super::roll_system::RollSystem;
use super::supports::Law;
use crate::integrators::SecondOrder;

impl SecondOrder for RollSystem {
    fn n(&self) -> usize {
        self.n
    }

    fn mass(&self) -> &DMatrix<f64> {
        &self.m
    }

    fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        RollSystem::force(self, t, q, v, out);
    }

    fn newton_matrix(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        coef: (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        RollSystem::newton_matrix(self, t, q, v, coef, out);
    }

    fn weights(&self) -> &[f64] {
        &self.weights
    }

    fn linear_in_state(&self) -> bool {
        self.supports
            .iter()
            .all(|s| matches!(s.law, Law::Linear(_)))
    }

    /// One event per contact roller: its penetration δ [m].
    fn n_events(&self) -> usize {
        (self.supports.iter())
            .map(|s| match &s.law {
                Law::Contact(contacts) => contacts.rollers.len(),
                Law::Linear(_) => 0,
            })
            .sum()
    }

    /// The penetration δ [m] of every contact roller, supports and rollers in scene order.
    fn events(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut [f64]) {
        let (theta, omega, _) = self.speed.at(t);
        let (st, ct) = theta.sin_cos();
        let mut slots = out.iter_mut();
        for sup in &self.supports {
            if let Law::Contact(contacts) = &sup.law {
                let (w, _, _) = sup.relative(self.nm, (st, ct), omega, q, v);
                for (r, slot) in contacts.rollers.iter().zip(&mut slots) {
                    *slot = r.penetration(&contacts.journal, (theta, st, ct), w).delta;
                }
            }
        }
    }
}
