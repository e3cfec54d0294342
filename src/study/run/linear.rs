//! The study's linearised systems, computed on the worker pool beside the jobs.
//!
//! In: the jobs whose linearised systems a run stores, the built [`Models`], the ids already
//! in a shared references file (copied there, not computed), and the study's `[linear]`
//! request. Out: [`Systems`]: per distinct linear id (`/linear/<id>`), its model's id and either
//! the analyses the request asks for ([`crate::linear::request::compute`]: damped modes over
//! its speeds always) or why they failed (stored as `linear_error`). Each system is one task of
//! the pool and its Campbell sweep solves its speeds in parallel, so a run's linear analysis
//! overlaps its jobs instead of following the last one (on a study of 200 0.1 s Jeffcott jobs
//! the one Campbell sweep was 30 % of all instructions, serial after the jobs). Cost: one
//! damped eigen-solve per speed and system, plus what `[linear]` adds. The results do not
//! depend on the thread count: each system is computed alone and kept by id.

use std::collections::{BTreeMap, BTreeSet};

use rayon::prelude::*;

use super::models::Models;
use crate::dynamics::linear_system::LinearSystem;
use crate::linear::request::{compute, Request, Results};
use crate::study::{Job, Study};

/// The computed systems by linear id: (model id, results or the cause of their failure).
pub(super) type Systems = BTreeMap<String, (String, Result<Results, String>)>;

/// The distinct linear systems of `jobs` (the first job of each id stands for it), without
/// those in `shared` (copied from the references file).
pub(super) fn distinct<'a>(jobs: &[&'a Job], shared: &BTreeSet<String>) -> Vec<&'a Job> {
    let mut first: BTreeMap<&str, &Job> = BTreeMap::new();
    for j in jobs {
        first.entry(j.linear_id.as_str()).or_insert(j);
    }
    first
        .into_values()
        .filter(|j| !shared.contains(&j.linear_id))
        .collect()
}

/// Computes the systems of `jobs` (from [`distinct`]) on the current rayon pool. A job whose
/// model failed to build has no system (its jobs fail with that cause).
pub(super) fn compute_all(study: &Study, req: &Request, jobs: &[&Job], models: &Models) -> Systems {
    jobs.par_iter()
        .filter_map(|j| {
            let Some(Ok(m)) = models.built.get(j.model_id.as_str()) else {
                return None;
            };
            let results =
                (study.scene_of(&j.overrides).map_err(|e| e.to_string())).and_then(|scene| {
                    LinearSystem::of_scene(&scene, m)
                        .and_then(|sys| compute(req, &scene, m, &sys))
                        .map_err(|e| e.to_string())
                });
            Some((j.linear_id.clone(), (j.model_id.clone(), results)))
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect()
}
