//! What a simulation records of a state: each support's journal, support-mass and contact
//! state, and the sensors' displacements.
//!
//! In: t [s] and the state q, q̇. Out: per support a [`SupportState`] (journal and support-mass
//! displacement [m], contact force per roller [N]), per sensor plane the centre's lateral
//! displacement [m], all in the inertial frame. Method: R(θ) Φ_j p at the roll angle of the
//! speed profile at t; the contact forces from the support's force law.

use nalgebra::{DVector, Vector2};

use super::roll_system::RollSystem;
use super::supports::{rot, rows_times, SupportState};

impl RollSystem {
    /// Journal, support-mass and contact state of every support at time t.
    pub fn support_states(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> Vec<SupportState> {
        let (theta, omega, _) = self.speed.at(t);
        let (st, ct) = theta.sin_cos();
        self.supports
            .iter()
            .map(|s| {
                let (w, wd, _) = s.relative(self.nm, (st, ct), omega, q, v);
                let stand = s
                    .stand
                    .map(|i| Vector2::new(q[i], q[i + 1]))
                    .unwrap_or_default();
                let mut contact = Vec::new();
                s.local((theta, st, ct), omega, w, wd, Some(&mut contact));
                SupportState {
                    journal: w + stand,
                    stand,
                    contact,
                }
            })
            .collect()
    }

    /// Inertial lateral displacement [m] of each sensor plane's centre at time t.
    pub fn sensor_displacements(&self, t: f64, q: &DVector<f64>) -> Vec<Vector2<f64>> {
        let r = rot(self.speed.at(t).0.sin_cos());
        let p = &q.as_slice()[..self.nm];
        self.sensors
            .iter()
            .map(|(_, rows)| r * rows_times(rows, p))
            .collect()
    }
}
