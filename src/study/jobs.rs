//! What a study expands to: its jobs and the reference runs they are compared with.
//!
//! A [`Job`] is the scene's key=value overrides (the base `[set]` first), its pruning share,
//! its ids (module doc of [`super::ids`]) and the few numbers of its validated scene that
//! `plan`, the study's checks and a run's preparation read ([`SceneFacts`]); a [`Reference`]
//! is a job's physics with the study's `[reference]` solver setting, one per distinct physics.
//! Neither holds its scene (about 9 kB each; a study of 10⁶ jobs could not hold them): where a
//! run needs it, [`Study::scene_of`](super::Study::scene_of) builds it again from the overrides.

use super::plan::{max_nodes, record_bytes, run_cpu_s};
use crate::results::analyse::record_spin;
use crate::scene::Scene;

/// One job: the overrides that make it, and its identities.
#[derive(Debug, Clone)]
pub struct Job {
    /// Position in the study's job list (shards split on it).
    pub index: usize,
    /// Stable id: hash of the scene files and all resolved overrides.
    pub id: String,
    /// Scene overrides (dotted key, value), base `[set]` first; without the prune pseudo-key.
    pub overrides: Vec<(String, toml::Value)>,
    /// Strain-energy pruning threshold, if this job asks for pruning (0 = the pilot's full set).
    pub prune: Option<f64>,
    /// Id of the unpruned reduced model this job starts from.
    pub model_id: String,
    /// Id of the reference run this job is compared with.
    pub reference_id: String,
    /// Id of the job's linearised system (its model on its supports, drive and gravity): the
    /// Campbell data and critical speeds stored under `/linear/<id>`.
    pub linear_id: String,
    /// Labels of the job's rows on labelled axes: (the axis's first key, label).
    pub labels: Vec<(String, String)>,
    /// What is read of its validated scene before it runs.
    pub facts: SceneFacts,
}

/// A reference run: the job's physics with the study's reference solver setting.
#[derive(Debug, Clone)]
pub struct Reference {
    /// Stable id.
    pub id: String,
    /// Scene overrides.
    pub overrides: Vec<(String, toml::Value)>,
    /// Id of the (unpruned) model it runs on.
    pub model_id: String,
    /// What is read of its validated scene before it runs.
    pub facts: SceneFacts,
}

/// The numbers of a run's validated scene that are read before it runs: `plan`'s estimates
/// (module doc of [`super::plan`]), the record's speed for the Nyquist check of the study's
/// orders and for the results file's frequency axis, and its integrator's name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneFacts {
    /// Rough CPU time of the run [s].
    pub cpu_s: f64,
    /// Its record, before compression [B].
    pub record_bytes: f64,
    /// FE nodes of the largest model it builds.
    pub max_nodes: usize,
    /// The spin speed over the record [rad/s]; `None` when it changes while recording.
    pub record_omega: Option<f64>,
    /// The record's sample rate [Hz].
    pub sample_rate_hz: f64,
    /// The name of its integrator (`solver.integrator`).
    pub integrator: &'static str,
}

impl SceneFacts {
    /// The facts of `scene`.
    pub fn of(scene: &Scene) -> SceneFacts {
        SceneFacts {
            cpu_s: run_cpu_s(scene),
            record_bytes: record_bytes(scene),
            max_nodes: max_nodes(scene),
            record_omega: record_spin(scene).map(|(omega, _)| omega),
            sample_rate_hz: scene.simulation.sample_rate,
            integrator: scene.solver.integrator.name(),
        }
    }
}
