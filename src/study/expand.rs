//! A study's jobs, expanded: every job of the grid becomes its overrides, its validated scene,
//! its ids and its reference.
//!
//! In: the grid's jobs as overrides ([`super::grid`]), the base scene, `[set]`, the `[budget]`
//! overrides, the pruning pilot's overrides and the `[reference]` setting. Out: the [`Job`]s in
//! grid order, each job's overrides being `[set]`, then the budget, then its own keys (a key set
//! again replaces the earlier value; the pruning pseudo-key becomes the job's share), and the
//! references they need. Errors point at the axis, `[set]` key or explicit job that set the
//! offending key, or (for an error in the scene or its map) say which job of which study read
//! it. Two jobs of the same inputs are an error, whether written alike or not (`10` and
//! `10.0`).

use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, HashMap};
use std::sync::Mutex;

use rayon::prelude::*;

use super::context::{override_key, Ctx};
use super::grid::Combo;
use super::ids::{fnv1a, job_id, linear_id, map_of, map_text, model_id, scene_inputs, Inputs};
use super::job_table::{BaseTable, JobTable};
use super::jobs::{Job, SceneFacts};
use super::pruning::{share, PRUNE_KEY};
use super::reference::References;
use super::values::{normal_text, Override};
use crate::error::InputError;
use crate::scene::source::Source;
use crate::scene::{Scene, COMMAND_LINE};

/// Jobs checked on the pool at a time.
const CHUNK: usize = 1 << 16;

/// A job after its own checks (`Expansion::check`), with its ids.
struct Checked {
    overrides: Vec<Override>,
    prune: Option<f64>,
    labels: Vec<(String, String)>,
    facts: SceneFacts,
    /// Its inputs as normalised text (two jobs of the same text are one physics).
    written: String,
    inputs: Inputs,
    id: String,
    model_id: String,
    linear_id: String,
    reference_id: String,
    /// Its reference's overrides, when the study has a `[reference]`.
    reference_overrides: Option<Vec<Override>>,
}

/// What every job of a study is made from.
pub(super) struct Expansion<'a> {
    /// The study file, for errors.
    pub(super) c: &'a Ctx<'a>,
    /// The base scene.
    pub(super) source: &'a Source,
    /// The `[set]` overrides.
    pub(super) base: &'a [Override],
    /// The `[budget]` overrides.
    pub(super) budget: &'a [Override],
    /// The pruning pilot's overrides.
    pub(super) pilot: &'a [Override],
    /// The axis that sets each swept key.
    pub(super) axis_of_key: &'a BTreeMap<String, usize>,
    /// How many jobs come from the axes (the explicit jobs follow).
    pub(super) axis_combos: usize,
}

impl Expansion<'_> {
    /// The jobs of `combos`, in order; their references are added to `references`.
    ///
    /// Each job's scene is validated and its ids are hashed on rayon's pool, the jobs split
    /// among its threads; the ids hash the base scene's text, serialised once, with only the
    /// entries a job's overrides touch serialised again ([`JobTable`]). The checks that compare
    /// jobs (the same inputs twice) and the references follow in job order. The first error in
    /// job order is reported, each job's own checks in the order: overrides, scene, merged
    /// scene and ids, repeated inputs, reference.
    pub(super) fn jobs(
        &self,
        combos: Vec<Combo>,
        references: &mut References,
    ) -> Result<Vec<Job>, InputError> {
        let base = BaseTable::new(&self.source.table);
        // The inputs' hash by thickness map: each map read and hashed once.
        let inputs_of: Mutex<BTreeMap<Option<String>, Inputs>> = Mutex::default();
        let mut physics_of = HashMap::new();
        let mut jobs = Vec::with_capacity(combos.len());
        let mut combos = combos.into_iter().enumerate();
        // A chunk at a time, so that what a job's checks leave besides the job is held for one
        // chunk only.
        loop {
            let chunk: Vec<(usize, Combo)> = combos.by_ref().take(CHUNK).collect();
            if chunk.is_empty() {
                break;
            }
            let checked: Vec<Result<Checked, InputError>> = chunk
                .into_par_iter()
                .map(|(index, (combo, labels))| {
                    self.check(index, combo, labels, &base, references, &inputs_of)
                })
                .collect();
            for c in checked {
                let c = c?;
                let index = jobs.len();
                self.new_physics(index, &c.written, &jobs, &mut physics_of)?;
                // Without `[reference]` a reference is its job's own physics, never run:
                // nothing to build (its id is still the job's).
                if let Some(ref_over) = c.reference_overrides {
                    references.add(index, &c.reference_id, ref_over, c.inputs, &base)?;
                }
                jobs.push(Job {
                    index,
                    id: c.id,
                    model_id: c.model_id,
                    linear_id: c.linear_id,
                    overrides: c.overrides,
                    prune: c.prune,
                    reference_id: c.reference_id,
                    labels: c.labels,
                    facts: c.facts,
                });
            }
        }
        Ok(jobs)
    }

    /// Job `index`'s own checks, which need no other job (its overrides, its validated scene,
    /// its scene table), and its ids.
    fn check(
        &self,
        index: usize,
        combo: Vec<Override>,
        labels: Vec<(String, String)>,
        base: &BaseTable,
        references: &References,
        inputs_of: &Mutex<BTreeMap<Option<String>, Inputs>>,
    ) -> Result<Checked, InputError> {
        let (overrides, prune) = self.overrides(index, combo)?;
        // The scene is validated and only its facts kept (module doc of `jobs`).
        let facts = SceneFacts::of(&self.scene(index, &overrides)?);
        let merged = JobTable::new(base, &overrides, |k, r| {
            self.c.err(&self.locate_key(index, k), r)
        })?;
        let map = map_of(&merged).map(str::to_string);
        let inputs = {
            let mut known = inputs_of.lock().unwrap_or_else(|e| e.into_inner());
            *known.entry(map).or_insert_with_key(|m| {
                let text = m.as_deref().map(|csv| map_text(self.source, csv));
                scene_inputs(self.source, text.as_deref())
            })
        };
        let reference_overrides = references.overrides_of(&overrides);
        let reference_id = references.id_of(base, inputs, &merged, &reference_overrides)?;
        let reference_overrides = references.named().then_some(reference_overrides);
        Ok(Checked {
            written: written_text(&overrides, prune),
            id: job_id(inputs, &merged, prune, self.pilot),
            model_id: model_id(inputs, &merged),
            linear_id: linear_id(inputs, &merged),
            inputs,
            reference_id,
            reference_overrides,
            overrides,
            prune,
            labels,
            facts,
        })
    }

    /// Where to point errors about key `k` of job `index`: the axis (or explicit job) that set
    /// it.
    fn locate_key(&self, index: usize, k: &str) -> String {
        match self.axis_of_key.get(k) {
            Some(i) => format!("axes[{i}].values"),
            None if self.base.iter().any(|(b, _)| b == k) => format!("set.{k}"),
            None => match index.checked_sub(self.axis_combos) {
                Some(j) => format!("jobs[{j}].{k}"),
                None => "jobs".to_string(),
            },
        }
    }

    /// Job `index`'s overrides (`[set]`, the budget, then its own keys) and its pruning share.
    fn overrides(
        &self,
        index: usize,
        combo: Vec<Override>,
    ) -> Result<(Vec<Override>, Option<f64>), InputError> {
        let mut overrides: Vec<Override> = self.base.to_vec();
        overrides.extend(self.budget.iter().cloned());
        let mut prune = None;
        for (k, v) in combo {
            if k == PRUNE_KEY {
                match share(&v) {
                    Some(t) => prune = Some(t),
                    None => {
                        return Err(self.c.err(
                            &self.locate_key(index, &k),
                            format!("`{PRUNE_KEY}` must be a share in [0, 1), got {v}"),
                        ))
                    }
                }
            } else {
                overrides.retain(|(ok, _)| ok != &k);
                overrides.push((k, v));
            }
        }
        // Held by the job for the whole study: no spare room.
        overrides.shrink_to_fit();
        Ok((overrides, prune))
    }

    /// Job `index`'s validated scene.
    fn scene(&self, index: usize, overrides: &[Override]) -> Result<Scene, InputError> {
        Scene::from_source_values(self.source, overrides).map_err(|mut e| {
            let key = override_key(&e, overrides);
            if e.file.as_os_str() == COMMAND_LINE {
                let mut err = self.c.err(
                    &self.locate_key(index, &key),
                    format!("job {index}: {}", e.reason),
                );
                err.key = Some(key);
                err
            } else {
                // In the scene or its map: say which study and job read it.
                e.reason += &format!(" (job {index} of {})", self.c.path.display());
                e
            }
        })
    }

    /// The same physics written twice (`10` and `10.0`): one job. `physics_of` holds the
    /// jobs before `index` (`jobs`) by the hash of their normalised inputs; `written` is job
    /// `index`'s. A hash seen before is checked against the texts of the earlier jobs (two
    /// texts of one hash, 2⁻⁶⁴ per pair, are not the same inputs).
    fn new_physics(
        &self,
        index: usize,
        written: &str,
        jobs: &[Job],
        physics_of: &mut HashMap<u64, usize>,
    ) -> Result<(), InputError> {
        let first = match physics_of.entry(fnv1a(written.as_bytes())) {
            Entry::Vacant(e) => {
                e.insert(index);
                return Ok(());
            }
            Entry::Occupied(_) => jobs
                .iter()
                .find(|j| written_text(&j.overrides, j.prune) == written),
        };
        let Some(first) = first else {
            return Ok(());
        };
        let at = match index.checked_sub(self.axis_combos) {
            Some(j) => format!("jobs[{j}]"),
            None => "axes".to_string(),
        };
        Err(self.c.err(
            &at,
            format!(
                "jobs {} and {index} have the same inputs (values that differ only in how they \
                 are written, such as 10 and 10.0, are the same)",
                first.index
            ),
        ))
    }
}

/// A job's inputs as normalised text: its overrides and its pruning share.
fn written_text(overrides: &[Override], prune: Option<f64>) -> String {
    normal_text(overrides) + &format!("|{prune:?}")
}

/// No two jobs may have the same id (the same inputs).
pub(super) fn distinct_ids(c: &Ctx, jobs: &[Job]) -> Result<(), InputError> {
    let mut seen = HashMap::with_capacity(jobs.len());
    for j in jobs {
        if let Some(first) = seen.insert(j.id.as_str(), j.index) {
            return Err(c.err(
                "axes",
                format!("jobs {first} and {} are identical (same inputs)", j.index),
            ));
        }
    }
    Ok(())
}
