//! What a study expands to: its jobs and the reference runs they are compared with.
//!
//! A [`Job`] is the scene's key=value overrides (the base `[set]` first), its validated
//! [`Scene`], its pruning share and its ids (module doc of [`super::ids`]); a [`Reference`] is
//! a job's physics with the study's `[reference]` solver setting, one per distinct physics.

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
    /// The validated scene.
    pub scene: Scene,
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
    /// The validated scene.
    pub scene: Scene,
}
