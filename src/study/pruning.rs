//! Strain-energy pruning in a study: the pseudo-key [`PRUNE_KEY`] and the `[pruning]` table of
//! the pilot runs.
//!
//! In: a job's value of [`PRUNE_KEY`] (a share in [0, 1); 0 means the unpruned pilot), swept
//! like any other key; `[pruning]`: overrides of the pilot runs (no model keys: a pilot runs on
//! its jobs' reduced model). Out: the share, the pilot's (dotted key, value) overrides, and the
//! check that every pruned model's pilot scene loads. Errors: a share out of range, model keys
//! in `[pruning]`, `[pruning]` without a pruned job, a pilot scene that does not load.

use super::context::{override_key, Ctx};
use super::ids::MODEL_TABLES;
use super::jobs::Job;
use super::values::{flatten, value_text};
use crate::error::InputError;
use crate::scene::source::Source;
use crate::scene::Scene;

/// The pseudo-key that asks for strain-energy pruning (not a scene key).
pub const PRUNE_KEY: &str = "reduction.prune_threshold";

/// A value of [`PRUNE_KEY`] as the share it asks for: a number in [0, 1), else `None`.
pub(super) fn share(v: &toml::Value) -> Option<f64> {
    let t = v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    t.filter(|t| (0.0..1.0).contains(t))
}

/// The `[pruning]` table as the pilot's overrides: no materials, roll, rotor or reduction keys.
pub(super) fn pilot(
    c: &Ctx,
    table: &toml::Table,
) -> Result<Vec<(String, toml::Value)>, InputError> {
    let mut pilot = Vec::new();
    flatten("", table, &mut pilot);
    if let Some((k, _)) = pilot
        .iter()
        .find(|(k, _)| MODEL_TABLES.contains(&k.split('.').next().unwrap_or_default()))
    {
        return Err(c.err(
            &format!("pruning.{k}"),
            "the pilot runs on its jobs' reduced model: [pruning] may not change materials, \
             roll, rotor or reduction keys",
        ));
    }
    Ok(pilot)
}

/// Every pruning pilot's scene must load: the jobs' overrides, then `[pruning]`, with the modal
/// coordinates recorded. `[pruning]` without a pruned job is an error, not a silent no-op.
pub(super) fn pilots_load(
    c: &Ctx,
    source: &Source,
    jobs: &[Job],
    pilot: &[(String, toml::Value)],
) -> Result<(), InputError> {
    let pruned: std::collections::BTreeSet<&str> = jobs
        .iter()
        .filter(|j| j.prune.is_some())
        .map(|j| j.model_id.as_str())
        .collect();
    if pruned.is_empty() {
        if let Some((k, _)) = pilot.first() {
            return Err(c.err(
                &format!("pruning.{k}"),
                format!("no job asks for pruning (the pseudo-key `{PRUNE_KEY}`), so [pruning] would be ignored"),
            ));
        }
        return Ok(());
    }
    for j in jobs.iter().filter(|j| pruned.contains(j.model_id.as_str())) {
        let mut over: Vec<String> = j
            .overrides
            .iter()
            .chain(pilot)
            .map(|(k, v)| format!("{k}={}", value_text(v)))
            .collect();
        over.push("outputs.modal=true".into());
        Scene::from_source(source, &over).map_err(|e| {
            let key = override_key(&e, pilot);
            let at = if pilot.iter().any(|(k, _)| *k == key) {
                format!("pruning.{key}")
            } else {
                "pruning".to_string()
            };
            let mut err = c.err(
                &at,
                format!("the pruning pilot of job {}: {}", j.index, e.reason),
            );
            err.key = Some(at);
            err
        })?;
    }
    Ok(())
}
