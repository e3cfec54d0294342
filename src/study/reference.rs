//! A study's reference runs: every job's physics run again with the `[reference]` solver
//! setting, so that each job's error can be computed against it.
//!
//! In: `[reference]` (only `solver.*` keys and `reduction.modes`: the same physics), then per
//! job its overrides, the text of its scene's files and its merged scene. Out: the job's
//! reference id, and (when the study has a `[reference]`) one [`Reference`] per distinct id,
//! its scene validated. The study's
//! `[budget]` is among the job's overrides, so it binds the reference too, unless `[reference]`
//! sets `solver.cpu_budget_s` / `solver.max_steps` itself. With its own mode set the reference
//! is shared by jobs that differ only in their modes (their error then includes the
//! truncation); otherwise each mode set has its own.

use std::collections::BTreeMap;

use super::context::{override_key, Ctx};
use super::ids::{model_id, reference_id, Inputs};
use super::job_table::{BaseTable, JobTable};
use super::jobs::{Reference, SceneFacts};
use super::values::{flatten, Override};
use crate::error::InputError;
use crate::scene::source::Source;
use crate::scene::Scene;

/// The `[reference]` setting and the references built from it so far.
pub(super) struct References<'a> {
    c: &'a Ctx<'a>,
    source: &'a Source,
    /// The `[reference]` keys (dotted key, value).
    pub(super) keys: Vec<(String, toml::Value)>,
    /// Whether `[reference]` sets its own mode set.
    sets_modes: bool,
    /// The references by id.
    built: BTreeMap<String, Reference>,
}

impl<'a> References<'a> {
    /// The `[reference]` table of a study on the base scene `source`, its keys checked.
    pub(super) fn new(
        c: &'a Ctx<'a>,
        source: &'a Source,
        table: &toml::Table,
    ) -> Result<Self, InputError> {
        let mut keys = Vec::new();
        flatten("", table, &mut keys);
        if let Some((k, _)) = keys
            .iter()
            .find(|(k, _)| !k.starts_with("solver.") && k != "reduction.modes")
        {
            return Err(c.err(
                &format!("reference.{k}"),
                "the reference may only change solver.* keys and reduction.modes (same physics)",
            ));
        }
        let sets_modes = keys.iter().any(|(k, _)| k == "reduction.modes");
        Ok(References {
            c,
            source,
            keys,
            sets_modes,
            built: BTreeMap::new(),
        })
    }

    /// Job `overrides` with the `[reference]` keys set after them: its reference's overrides.
    pub(super) fn overrides_of(&self, overrides: &[Override]) -> Vec<Override> {
        let mut ref_over = overrides.to_vec();
        for (k, v) in &self.keys {
            ref_over.retain(|(ok, _)| ok != k);
            ref_over.push((k.clone(), v.clone()));
        }
        ref_over
    }

    /// The reference's scene table of a job whose reference overrides are `ref_over`.
    fn table<'t>(
        &self,
        base: &'t BaseTable<'t>,
        ref_over: &[Override],
    ) -> Result<JobTable<'t>, InputError> {
        JobTable::new(base, ref_over, |_, r| self.c.err("reference", r))
    }

    /// The reference id of a job (the text of its scene's files `inputs`, its scene table
    /// `job`, its reference overrides `ref_over`).
    pub(super) fn id_of(
        &self,
        base: &BaseTable,
        inputs: Inputs,
        job: &JobTable,
        ref_over: &[Override],
    ) -> Result<String, InputError> {
        let reference = self.table(base, ref_over)?;
        Ok(reference_id(inputs, job, &reference, self.sets_modes))
    }

    /// Job `index`'s reference, of id `id` and overrides `ref_over`: built and its scene
    /// validated the first time its id comes up.
    pub(super) fn add(
        &mut self,
        index: usize,
        id: &str,
        ref_over: Vec<Override>,
        inputs: Inputs,
        base: &BaseTable,
    ) -> Result<(), InputError> {
        if !self.built.contains_key(id) {
            let facts = SceneFacts::of(&self.scene(index, &ref_over)?);
            let model_id = model_id(inputs, &self.table(base, &ref_over)?);
            self.built.insert(
                id.to_string(),
                Reference {
                    id: id.to_string(),
                    overrides: ref_over,
                    model_id,
                    facts,
                },
            );
        }
        Ok(())
    }

    /// The validated scene of job `index`'s reference; errors point at the `[reference]` key
    /// the scene refuses, or at `[reference]`.
    fn scene(&self, index: usize, ref_over: &[(String, toml::Value)]) -> Result<Scene, InputError> {
        Scene::from_source_values(self.source, ref_over).map_err(|e| {
            let key = override_key(&e, ref_over);
            let at = if self.keys.iter().any(|(k, _)| *k == key) {
                format!("reference.{key}")
            } else {
                "reference".to_string()
            };
            let mut err = self
                .c
                .err(&at, format!("the reference of job {index}: {}", e.reason));
            err.key = Some(at);
            err
        })
    }

    /// Whether the study names a reference setting.
    pub(super) fn named(&self) -> bool {
        !self.keys.is_empty()
    }

    /// The references, by id.
    pub(super) fn into_list(self) -> Vec<Reference> {
        self.built.into_values().collect()
    }
}
