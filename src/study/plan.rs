//! What a study will cost before it runs (`rotorsweep plan`): its varying values, shared models,
//! and rough CPU time, memory and disk, from the scenes alone (no model is built).
//!
//! In: a loaded [`Study`] and the thread count the estimate assumes. Out: a [`Plan`]. Method:
//! - CPU [s]: per run (every job, and every reference run when the study has a `[reference]`
//!   section) steps × (1.5 µs + 1.5 ns × n²), n the coordinates (modal coordinates plus two
//!   per support), from the timing case (45 coordinates, 100 000 steps, 0.46 s); the steps are
//!   t_end / hmax, for explicit rk45 at least its stability limit 3/ω_max with f_max 6 kHz. A
//!   machine of several rolls costs per step 0.63 × the sum of its rolls' steps (the rolls are
//!   coupled only through the nip forces, so their steps add up rather than growing with the
//!   square of all the coordinates), plus 0.21 µs per nip segment, plus 0.28 ns per point of a
//!   viscoelastic cover (`cover_points` per segment). Calibrated on the shipped two-roll nips
//!   (release build, 2 shared cores, 2026-12-03; 10 s simulated in 100 010 steps, `simulate
//!   --json` cpu_time_s): elastic 0.80 / 1.05 / 1.49 / 2.29 s at 10 / 20 / 40 / 80 segments
//!   (a line 0.62 s + 21 ms per segment; the two rolls' own steps sum to 9.08 µs),
//!   viscoelastic with 1024 points per segment 1.11 / 1.50 / 2.68 s at 10 / 20 / 40 (beyond
//!   the elastic ones, 28 ms per 1000 points per 100 000 steps), and with a third roll (the
//!   reference roll again, below, in a 20-segment steel nip) 1.57 s. The estimates: 0.78 /
//!   0.99 / 1.41 / 2.25, 1.07 / 1.57 / 2.56 and 1.70 s, within 6 % of the two-roll runs and 8 %
//!   of the three-roll one (the factor 0.63 between the two-roll line's 0.68 and the three
//!   rolls');
//! - disk [B]: every run's record, samples × (channels + time) × 8 B, before compression; a
//!   machine's channels are every roll's, plus per nip one force and (hertz, cover) one width
//!   per segment;
//! - memory [B]: per thread the largest record or model build (about 90 B per DOF², dense FE
//!   matrices and eigen-solutions: 0.74 GB measured at 2958 DOFs; a machine's rolls are built
//!   one after another, so its largest roll), times the threads, plus about 1.2 KB per job
//!   for the loaded study (its jobs hold their overrides, ids and a few numbers, not their
//!   scenes; measured peak of `plan`: 16.9 MB for 4901 reference-roll jobs, 126 MB for
//!   100 000 Jeffcott jobs, 11.6 MB for one job).

use std::collections::BTreeSet;

use super::Study;
use crate::integrators::IntegratorKind;
use crate::scene::{NipLaw, Scene};

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
        let references = study.references.iter().filter(|_| study.has_reference);
        let facts: Vec<_> = (study.jobs.iter().map(|j| &j.facts))
            .chain(references.map(|r| &r.facts))
            .collect();
        let cpu_s: f64 = facts.iter().map(|f| f.cpu_s).sum();
        let disk_bytes: f64 = facts.iter().map(|f| f.record_bytes).sum();
        let per_thread = facts
            .iter()
            .map(|f| {
                let dofs = 6.0 * f.max_nodes as f64;
                f.record_bytes.max(90.0 * dofs * dofs)
            })
            .fold(0.0, f64::max);
        let memory_bytes = per_thread * threads.max(1) as f64 + 1.2e3 * study.jobs.len() as f64;
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
const SEGMENT_STEP_S: f64 = 0.21e-6;

/// CPU per step and viscoelastic cover point of a machine [s] (module doc).
const COVER_POINT_STEP_S: f64 = 0.28e-9;

/// A machine's CPU per step per the sum of its rolls' own steps (module doc).
const ROLLS_STEP_FACTOR: f64 = 0.63;

/// Rough CPU seconds of one run (module doc).
pub fn run_cpu_s(scene: &Scene) -> f64 {
    let s = &scene.solver;
    let t = scene.simulation.t_end;
    let steps = match s.integrator {
        IntegratorKind::Rk45 => (t / s.hmax).max(t * 2.0 * std::f64::consts::PI * F_MAX_HZ / 3.0),
        _ => t / s.hmax,
    };
    let per_step = match &scene.machine {
        Some(m) => {
            let segments: usize = m.nips.iter().map(|n| n.z.len()).sum();
            let points: usize = (m.nips.iter())
                .map(|n| match &n.law {
                    NipLaw::Viscoelastic { cover } => n.z.len() * cover.points,
                    _ => 0,
                })
                .sum();
            ROLLS_STEP_FACTOR * m.rolls.iter().map(|r| step_s(&r.scene)).sum::<f64>()
                + SEGMENT_STEP_S * segments as f64
                + COVER_POINT_STEP_S * points as f64
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

/// A run's record: samples × (channels + time) × 8 B; a machine's channels are every roll's
/// and its nips' fields (module doc).
pub fn record_bytes(scene: &Scene) -> f64 {
    let channels = match &scene.machine {
        Some(m) => {
            let rolls: usize = m.rolls.iter().map(|r| r.scene.channels()).sum();
            let fields: usize = (m.nips.iter())
                .map(|n| match n.law {
                    NipLaw::Linear { .. } => n.z.len(),
                    _ => 2 * n.z.len(),
                })
                .sum();
            rolls + fields
        }
        None => scene.channels(),
    };
    scene.samples() * (channels + 1) as f64 * 8.0
}

/// The FE nodes of the largest model a run builds: a machine's largest roll.
pub fn max_nodes(scene: &Scene) -> usize {
    match &scene.machine {
        Some(m) => m
            .rolls
            .iter()
            .map(|r| r.scene.max_nodes())
            .max()
            .unwrap_or(0),
        None => scene.max_nodes(),
    }
}
