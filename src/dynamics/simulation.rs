//! One job: a scene on its reduced model, started from static equilibrium and integrated in time,
//! with the outputs the scene asks for sampled at a fixed rate.
//!
//! In: a validated [`Scene`] and its [`Model`]; a machine (several rolls in nips) runs on its
//! own path, [`super::bodies`].
//! Out: a [`JobResult`]: solver statistics (status, cause, counts, times) and sampled channels
//! (runout and journal/stand motion in µm, contact forces in N, modal coordinates, and the spin
//! speed [Hz] and roll angle [rad] when the scene records them), each with its units. A failure at any stage is a result with status `diverged` and its cause, never a panic.

pub use super::job::{Channel, Field, JobResult};

use super::job::{failed, start, Recorder};
use crate::dynamics::model::Model;
use crate::dynamics::system::RollSystem;
use crate::integrators::{integrate, StepView};
use crate::scene::Scene;

/// Runs one job (module doc): a machine of several rolls in nips on its own path.
pub fn run(scene: &Scene, model: &Model) -> JobResult {
    if let Some(machine) = &scene.machine {
        return super::bodies::run(machine, model);
    }
    let sys = RollSystem::new(scene, model);
    let n = sys.n;
    let q0 = match start(scene, model, &sys) {
        Ok(q) => q,
        Err(e) => return failed(e, model, n),
    };
    let mut rec = Recorder::new(&sys, scene);
    let bound = scene.simulation.runout_bound;
    let weights = sys.weights.clone();
    let mut observer = |s: &StepView| -> Result<(), String> {
        let size: f64 = (s.q1.as_slice().iter())
            .zip(&weights)
            .map(|(q, w)| (q * w).abs())
            .sum();
        if size > bound {
            let worst = sys
                .sensor_displacements(s.t1, s.q1)
                .iter()
                .chain(
                    sys.support_states(s.t1, s.q1, s.v1)
                        .iter()
                        .map(|x| &x.journal),
                )
                .map(|d| d.norm())
                .fold(0.0, f64::max);
            if worst > bound {
                return Err(format!(
                    "displacement {:.3} mm beyond the bound of {:.3} mm at t = {:.6} s",
                    worst * 1e3,
                    bound * 1e3,
                    s.t1
                ));
            }
        }
        rec.step(s);
        Ok(())
    };
    // The spin jumps to Ω(0) with the static deflection at rest in space.
    let v0 = sys.quiescent_velocity(&q0, scene.speed.at(0.0).1);
    let (_, _, stats) = integrate(
        &sys,
        &scene.solver,
        0.0,
        scene.simulation.t_end,
        q0,
        v0,
        &mut observer,
    );
    JobResult {
        stats,
        modes: model.reduced.counts_label(),
        coordinates: n,
        time: rec.time,
        channels: rec.channels,
        lift_off_s: rec.lift_off,
        fields: Vec::new(),
    }
}
