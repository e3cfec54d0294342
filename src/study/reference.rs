//! A study's reference runs: every job's physics run again with the `[reference]` solver
//! setting, so that each job's error can be computed against it.
//!
//! In: `[reference]` (only `solver.*` keys and `reduction.modes`: the same physics), then per
//! job its overrides, the text of its scene's files and its merged scene. Out: the job's
//! reference id, and one [`Reference`] per distinct id with its validated scene. The study's
//! `[budget]` is among the job's overrides, so it binds the reference too, unless `[reference]`
//! sets `solver.cpu_budget_s` / `solver.max_steps` itself. With its own mode set the reference
//! is shared by jobs that differ only in their modes (their error then includes the
//! truncation); otherwise each mode set has its own.

use std::collections::BTreeMap;

use super::context::{override_key, Ctx};
use super::ids::{merged, model_id, reference_id, Inputs};
use super::jobs::Reference;
use super::values::{flatten, value_text};
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

    /// The reference id of job `index` (its `overrides`, the text of its scene's files
    /// `inputs`, its merged scene); the reference is built and its scene validated the first
    /// time its id comes up.
    pub(super) fn add(
        &mut self,
        index: usize,
        overrides: &[(String, toml::Value)],
        inputs: Inputs,
        job_merged: &toml::Value,
    ) -> Result<String, InputError> {
        let mut ref_over = overrides.to_vec();
        for (k, v) in &self.keys {
            ref_over.retain(|(ok, _)| ok != k);
            ref_over.push((k.clone(), v.clone()));
        }
        let ref_merged = merged(&self.source.table, &ref_over, |_, r| {
            self.c.err("reference", r)
        })?;
        let id = reference_id(inputs, job_merged, &ref_merged, self.sets_modes);
        if !self.built.contains_key(&id) {
            let scene = self.scene(index, &ref_over)?;
            self.built.insert(
                id.clone(),
                Reference {
                    id: id.clone(),
                    overrides: ref_over,
                    model_id: model_id(inputs, &ref_merged),
                    scene,
                },
            );
        }
        Ok(id)
    }

    /// The validated scene of job `index`'s reference; errors point at the `[reference]` key
    /// the scene refuses, or at `[reference]`.
    fn scene(&self, index: usize, ref_over: &[(String, toml::Value)]) -> Result<Scene, InputError> {
        let rs: Vec<String> = ref_over
            .iter()
            .map(|(k, v)| format!("{k}={}", value_text(v)))
            .collect();
        Scene::from_source(self.source, &rs).map_err(|e| {
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
