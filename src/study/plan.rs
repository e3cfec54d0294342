//! What a study will cost before it runs (`rotorsweep plan`): its varying values, shared models,
//! and rough CPU time, memory and disk, from the scenes alone (no model is built).
//!
//! In: a loaded [`Study`] and the thread count the estimate assumes. Out: a [`Plan`]. Method:
//! - CPU [s]: per run (every job, and every reference run when the study has a `[reference]`
//!   section) steps × (1.5 µs + 1.5 ns × n²), n the coordinates (modal coordinates plus two
//!   per support), from the timing case (45 coordinates, 100 000 steps, 0.46 s); the steps are
//!   t_end / hmax, for explicit rk45 at least its stability limit 3/ω_max with f_max 6 kHz. A
//!   machine of several rolls costs the sum of its rolls' steps plus 0.16 µs per step and nip
//!   segment (measured: two rolls of 30n+12st, 10 s simulated in 100 100 steps, 0.62 / 0.83 /
//!   1.12 / 1.78 s at 10 / 20 / 40 / 80 segments, 16 ms per segment; the rolls are coupled only
//!   through the nip forces, so their steps add up rather than growing with the square of all
//!   the coordinates);
//! - disk [B]: every run's record, samples × (channels + time) × 8 B, before compression;
//! - memory [B]: per thread the largest record or model build (about 90 B per DOF², dense FE
//!   matrices and eigen-solutions: 0.74 GB measured at 2958 DOFs), times the threads, plus
//!   about 60 KB per job for the loaded study (measured: 274 MB for 4901 jobs).

use std::collections::BTreeSet;

use super::Study;
use crate::integrators::IntegratorKind;
use crate::scene::Scene;

/// The highest frequency an explicit integrator's step must resolve [Hz].
const F_MAX_HZ: f64 = 6000.0;

/// A study's plan (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Each varying key with its distinct values as text, numbers in numeric order.
    pub varying: Vec<(String, Vec<String>)>,
    /// Distinct reduced models.
    pub models: usize,
    /// Pruning pilots (models that a pruned job needs).
    pub pilots: usize,
    /// Jobs on pruned mode sets.
    pub pruned: usize,
    /// CPU time of every run [s].
    pub cpu_s: f64,
    /// Memory on the assumed threads [B].
    pub memory_bytes: f64,
    /// Samples written, before compression [B].
    pub disk_bytes: f64,
}

impl Plan {
    /// The plan of `study` on `threads` threads (at least 1 in the estimates).
    pub fn of(study: &Study, threads: usize) -> Plan {
        let varying = study
            .varying
            .iter()
            .map(|k| {
                let vals: BTreeSet<String> = study
                    .jobs
                    .iter()
                    .filter_map(|j| study.value_text(j, k))
                    .collect();
                let mut vals: Vec<String> = vals.into_iter().collect();
                // Numbers in numeric order (10 after 9, not after 1), text as text.
                vals.sort_by(|a, b| match (a.parse::<f64>(), b.parse::<f64>()) {
                    (Ok(x), Ok(y)) => x.total_cmp(&y),
                    _ => a.cmp(b),
                });
                (k.clone(), vals)
            })
            .collect();
        let models: BTreeSet<&str> = study.jobs.iter().map(|j| j.model_id.as_str()).collect();
        let pilots: BTreeSet<&str> = study
            .jobs
            .iter()
            .filter(|j| j.prune.is_some())
            .map(|j| j.model_id.as_str())
            .collect();
        let pruned = study.jobs.iter().filter(|j| j.prune.is_some()).count();
        let mut cpu_s = 0.0;
        for j in &study.jobs {
            cpu_s += run_cpu_s(&j.scene);
        }
        if study.has_reference {
            for r in &study.references {
                cpu_s += run_cpu_s(&r.scene);
            }
        }
        let scenes: Vec<&Scene> = study
            .jobs
            .iter()
            .map(|j| &j.scene)
            .chain(
                study
                    .references
                    .iter()
                    .filter(|_| study.has_reference)
                    .map(|r| &r.scene),
            )
            .collect();
        let disk_bytes: f64 = scenes.iter().map(|sc| record_bytes(sc)).sum();
        let per_thread = scenes
            .iter()
            .map(|sc| {
                let dofs = 6.0 * sc.max_nodes() as f64;
                record_bytes(sc).max(90.0 * dofs * dofs)
            })
            .fold(0.0, f64::max);
        let memory_bytes = per_thread * threads.max(1) as f64 + 60e3 * study.jobs.len() as f64;
        Plan {
            varying,
            models: models.len(),
            pilots: pilots.len(),
            pruned,
            cpu_s,
            memory_bytes,
            disk_bytes,
        }
    }
}

/// CPU per step and nip segment of a machine [s] (module doc).
const SEGMENT_STEP_S: f64 = 0.16e-6;

/// Rough CPU seconds of one run (module doc).
fn run_cpu_s(scene: &Scene) -> f64 {
    let s = &scene.solver;
    let t = scene.simulation.t_end;
    let steps = match s.integrator {
        IntegratorKind::Rk45 => (t / s.hmax).max(t * 2.0 * std::f64::consts::PI * F_MAX_HZ / 3.0),
        _ => t / s.hmax,
    };
    let per_step = match &scene.machine {
        Some(m) => {
            let segments: usize = m.nips.iter().map(|n| n.z.len()).sum();
            m.rolls.iter().map(|r| step_s(&r.scene)).sum::<f64>() + SEGMENT_STEP_S * segments as f64
        }
        None => step_s(scene),
    };
    steps * per_step
}

/// CPU of one step of one body [s] (module doc).
fn step_s(scene: &Scene) -> f64 {
    let coords = scene.modal_coordinates() + 2 * scene.supports.len();
    1.5e-6 + 1.5e-9 * (coords * coords) as f64
}

/// A run's record: samples × (channels + time) × 8 B.
fn record_bytes(scene: &Scene) -> f64 {
    scene.samples() * (scene.channels() + 1) as f64 * 8.0
}
