//! The models a run shares between its jobs, the pruning pilots, and one run on its model.
//!
//! In: the jobs and reference runs of a run, on the worker pool. Out: [`Models`]: each distinct
//! reduced model built once (a model that cannot be built, or whose build panics, fails its
//! jobs alone, with the cause), and for pruned jobs the strain-energy shares of the modes
//! from one pilot run per model (kept in the parts folder as `pilot-<model>-<key>.shares`,
//! one number a line, and reused when present). [`Models::simulate`] runs one scene on its
//! model, pruned at its threshold; a panic is a failed result, not a crash.

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::Arc;

use rayon::prelude::*;

use crate::dynamics::model::Model;
use crate::dynamics::simulation::{self, JobResult};
use crate::integrators::Stats;
use crate::rotor::reduction::{ModeKind, ModeSelection};
use crate::scene::Scene;
use crate::study::{Job, Reference, Study};

/// The built models of a run by model id, and the pruning pilots' shares (or why a pilot
/// failed) by model id.
pub(super) struct Models<'a> {
    pub(super) built: BTreeMap<&'a str, Result<Arc<Model>, String>>,
    pub(super) shares: BTreeMap<String, Vec<f64>>,
    pub(super) pilot_errors: BTreeMap<String, String>,
}

impl<'a> Models<'a> {
    /// Builds the distinct models of the `linear` jobs and of `refs`, then runs the pruning
    /// pilots of the pruned `jobs`, both on `pool`; pilot shares are kept in `dir`.
    pub(super) fn prepare(
        pool: &rayon::ThreadPool,
        study: &Study,
        linear: &[&'a Job],
        jobs: &[&'a Job],
        refs: &[&'a Reference],
        dir: &Path,
    ) -> Models<'a> {
        // Each model's scene is the first run's that needs it (all of them describe it alike).
        let mut model_runs: BTreeMap<&str, &[(String, toml::Value)]> = BTreeMap::new();
        for j in linear {
            model_runs
                .entry(j.model_id.as_str())
                .or_insert(&j.overrides);
        }
        for r in refs {
            model_runs
                .entry(r.model_id.as_str())
                .or_insert(&r.overrides);
        }
        let built: Vec<(&str, Result<Arc<Model>, String>)> = pool.install(|| {
            model_runs
                .par_iter()
                .map(|(id, overrides)| {
                    let sc = match study.scene_of(overrides) {
                        Ok(sc) => sc,
                        Err(e) => return (*id, Err(e.to_string())),
                    };
                    // A model that cannot be built (or whose build panics) fails its jobs alone.
                    let built = catch_unwind(AssertUnwindSafe(|| Model::build(&sc, None)))
                        .map_err(|e| format!("{}: panic: {}", sc.source.display(), panic_text(&*e)))
                        .and_then(|r| {
                            r.map(Arc::new)
                                .map_err(|e| format!("{}: {e}", sc.source.display()))
                        });
                    (*id, built)
                })
                .collect()
        });
        let mut models = Models {
            built: built.into_iter().collect(),
            shares: BTreeMap::new(),
            pilot_errors: BTreeMap::new(),
        };
        models.run_pilots(pool, study, jobs, dir);
        models
    }

    /// Pruning pilots, once per model that a pruned job needs.
    fn run_pilots(&mut self, pool: &rayon::ThreadPool, study: &Study, jobs: &[&Job], dir: &Path) {
        let pilot_models: BTreeSet<&str> = jobs
            .iter()
            .filter(|j| j.prune.is_some())
            .map(|j| j.model_id.as_str())
            .collect();
        let models = &self.built;
        let pilots: Vec<(String, Result<Vec<f64>, String>)> = pool.install(|| {
            pilot_models
                .par_iter()
                .map(|mid| {
                    let pilot_key = crate::study::fnv1a(
                        crate::study::pilot_text(&study.pilot_overrides).as_bytes(),
                    );
                    let id = format!("pilot-{mid}-{pilot_key:016x}");
                    let path = dir.join(format!("{id}.shares"));
                    if let Ok(text) = std::fs::read_to_string(&path) {
                        let v: Result<Vec<f64>, _> = text.lines().map(str::parse).collect();
                        if let Ok(v) = v {
                            return (mid.to_string(), Ok(v));
                        }
                    }
                    let job = jobs
                        .iter()
                        .find(|j| j.model_id == *mid)
                        .expect("a job uses it");
                    let res = pilot_run(study, job, models[mid].clone()).and_then(|v| {
                        let text: String = v.iter().map(|x| format!("{x:e}\n")).collect();
                        std::fs::write(&path, text).map_err(|e| e.to_string())?;
                        Ok(v)
                    });
                    (mid.to_string(), res)
                })
                .collect()
        });
        for (mid, r) in pilots {
            match r {
                Ok(v) => {
                    self.shares.insert(mid, v);
                }
                Err(e) => {
                    self.pilot_errors.insert(mid, e);
                }
            }
        }
    }

    /// Runs `scene` on the model `model_id`, on the modes kept at `prune` when it is above 0;
    /// a model or pilot that failed is the result's cause.
    pub(super) fn simulate(&self, scene: &Scene, model_id: &str, prune: Option<f64>) -> JobResult {
        match &self.built[model_id] {
            Err(e) => failed_result(format!("model: {e}")),
            Ok(m) => match prune {
                Some(t) if t > 0.0 => {
                    match (self.shares.get(model_id), self.pilot_errors.get(model_id)) {
                        (Some(sh), _) => {
                            let sel = pruned_selection(m, sh, t);
                            match m.full.select(&sel) {
                                Ok(red) => {
                                    let mut pm = (**m).clone();
                                    pm.reduced = red;
                                    run_one(scene, &pm)
                                }
                                Err(e) => failed_result(format!("pruning: {e}")),
                            }
                        }
                        (None, Some(e)) => failed_result(format!("pruning pilot: {e}")),
                        (None, None) => failed_result("pruning pilot missing".into()),
                    }
                }
                _ => run_one(scene, m),
            },
        }
    }
}

/// Strain-energy shares of the modes in a pilot run: E_i = ½ ω_i² p_i², averaged over the
/// recorded window (time average, physics.md §3), normalised to sum 1. Rigid modes get 0.
pub fn strain_energy_shares(model: &Model, r: &JobResult) -> Vec<f64> {
    let red = &model.reduced;
    let mut e = vec![0.0; red.len()];
    for (i, ei) in e.iter_mut().enumerate() {
        let name = format!("modal/{i:03}");
        if let Some(c) = r.channels.iter().find(|c| c.name == name) {
            let w2 = red.k[(i, i)].max(0.0);
            let n = c.data.len().max(1) as f64;
            *ei = 0.5 * w2 * c.data.iter().map(|p| p * p).sum::<f64>() / n;
        }
    }
    let total: f64 = e.iter().sum();
    if total > 0.0 {
        e.iter_mut().for_each(|x| *x /= total);
    }
    e
}

/// The modes kept at a threshold: rigid modes always, the others with a share above it.
pub fn pruned_selection(model: &Model, shares: &[f64], threshold: f64) -> ModeSelection {
    let red = &model.reduced;
    ModeSelection::List(
        (0..red.len())
            .filter(|&i| red.kinds[i] == ModeKind::Rigid || shares[i] > threshold)
            .map(|i| red.index[i])
            .collect(),
    )
}

fn run_one(scene: &Scene, model: &Model) -> JobResult {
    match catch_unwind(AssertUnwindSafe(|| simulation::run(scene, model))) {
        Ok(r) => r,
        Err(e) => {
            let msg = panic_text(&*e);
            JobResult {
                stats: Stats::failed(format!("panic: {msg}")),
                modes: model.reduced.counts_label(),
                coordinates: 0,
                time: Vec::new(),
                channels: Vec::new(),
                lift_off_s: None,
                fields: Vec::new(),
            }
        }
    }
}

pub(super) fn failed_result(cause: String) -> JobResult {
    JobResult {
        stats: Stats::failed(cause),
        modes: String::new(),
        coordinates: 0,
        time: Vec::new(),
        channels: Vec::new(),
        lift_off_s: None,
        fields: Vec::new(),
    }
}

/// The message of a caught panic.
fn panic_text(e: &(dyn std::any::Any + Send)) -> String {
    e.downcast_ref::<String>()
        .cloned()
        .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into())
}

fn pilot_run(
    study: &Study,
    job: &Job,
    model: Result<Arc<Model>, String>,
) -> Result<Vec<f64>, String> {
    let model = model?;
    let mut over: Vec<String> = job
        .overrides
        .iter()
        .chain(study.pilot_overrides.iter())
        .map(|(k, v)| format!("{k}={}", crate::study::value_text(v)))
        .collect();
    over.push("outputs.modal=true".into());
    let scene = Scene::load(&study.scene_path, &over).map_err(|e| e.to_string())?;
    let r = run_one(&scene, &model);
    if !r.stats.status.completed() {
        return Err(format!("{}: {}", r.stats.status.name(), r.stats.cause));
    }
    Ok(strain_energy_shares(&model, &r))
}
