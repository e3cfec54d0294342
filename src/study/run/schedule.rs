//! The work of a run in order, on the worker pool, each finished run saved as it arrives.
//!
//! In: the run's reference runs and jobs, the built [`Models`], the parts folder. Out: the work
//! list (reference runs unless shared, then jobs in study order, the saved ones left out), each
//! item run on one thread of the pool and saved by the calling thread in batches as they finish
//! (`saver`, `parts`); the progress line per run. A worker hands its result over only when the
//! saving thread takes it (memory bounded by one batch and one finished run per worker). The
//! first failed save stops
//! new runs from starting; running ones finish and are saved if they can be, and the error says
//! how many are saved. The study's linear systems are computed on the same pool meanwhile.
//! Results do not depend on the thread count or the order in which runs finish.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};

use rayon::prelude::*;

use super::error::CampaignError;
use super::models::Models;
use super::parts::{saved_parts, Saved};
use super::saver::Saver;
use crate::dynamics::simulation::JobResult;
use crate::scene::Scene;
use crate::store::Param;
use crate::study::identity::Identity;
use crate::study::progress::Progress;
use crate::study::{Job, Reference, Study};

/// A unit of work for the pool.
pub(super) struct Work<'a> {
    pub(super) id: String,
    kind: Kind,
    pub(super) scene: &'a Scene,
    model_id: &'a str,
    linear_id: Option<&'a str>,
    prune: Option<f64>,
    params: Vec<(String, Param)>,
    /// What the progress lines call it: the job's labels, else its varying values.
    pub(super) name: String,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Job(usize),
    Reference,
}

fn params_of(overrides: &[(String, toml::Value)]) -> Vec<(String, Param)> {
    overrides
        .iter()
        .map(|(k, v)| (k.clone(), Param::from_toml(v)))
        .collect()
}

/// The work list: the reference runs `refs`, then the jobs.
pub(super) fn work_list<'a>(
    study: &Study,
    jobs: &[&'a Job],
    refs: &[&'a Reference],
) -> Vec<Work<'a>> {
    let mut work: Vec<Work> = Vec::new();
    for r in refs {
        work.push(Work {
            id: r.id.clone(),
            kind: Kind::Reference,
            scene: &r.scene,
            model_id: &r.model_id,
            linear_id: None,
            prune: None,
            params: params_of(&r.overrides),
            name: "reference run".into(),
        });
    }
    for j in jobs {
        let mut params = params_of(&j.overrides);
        // Its labels, then the values of the varying keys no label stands for.
        let name = j
            .labels
            .iter()
            .map(|(_, l)| l.clone())
            .chain(
                study
                    .varying
                    .iter()
                    .filter(|k| !j.labels.iter().any(|(lk, _)| lk == *k))
                    .map(|k| format!("{k}={}", study.value_text(j, k).unwrap_or_default())),
            )
            .collect::<Vec<_>>()
            .join(", ");
        if !j.labels.is_empty() {
            let all: Vec<&str> = j.labels.iter().map(|(_, l)| l.as_str()).collect();
            params.push(("label".into(), Param::Text(all.join(", "))));
            for (k, l) in &j.labels {
                params.push((format!("label:{k}"), Param::Text(l.clone())));
            }
        }
        work.push(Work {
            id: j.id.clone(),
            kind: Kind::Job(j.index),
            scene: &j.scene,
            model_id: &j.model_id,
            linear_id: Some(&j.linear_id),
            prune: j.prune,
            params,
            name,
        });
    }
    work
}

impl Work<'_> {
    /// The attributes of its part file's `job` group besides the result: its overrides (and
    /// labels), the ids of its model and linearised system, what the analysis reads of its
    /// scene, its pruning threshold, and its kind (and job index).
    pub(super) fn part_params(&self) -> Vec<(String, Param)> {
        let mut params = self.params.clone();
        params.push(("model_id".into(), Param::Text(self.model_id.to_string())));
        if let Some(l) = self.linear_id {
            params.push(("linear_id".into(), Param::Text(l.to_string())));
        }
        // The spin speed over the record, the roll angle's offset and the roller ratios, for
        // the spectral analysis.
        params.extend(crate::results::analyse::job_attrs(self.scene));
        if let Some(p) = self.prune {
            params.push((crate::study::PRUNE_KEY.into(), Param::Number(p)));
        }
        match self.kind {
            Kind::Job(i) => {
                params.push(("job_index".into(), Param::Count(i as u64)));
                params.push(("kind".into(), Param::Text("job".into())));
            }
            Kind::Reference => params.push(("kind".into(), Param::Text("reference".into()))),
        }
        params
    }
}

/// What [`run_all`] leaves: where each run it saved is, the first failed save, and what the
/// work beside the jobs returned.
pub(super) struct Ran<T> {
    pub(super) saved: BTreeMap<String, Saved>,
    pub(super) error: Option<CampaignError>,
    pub(super) beside: T,
}

/// Runs `work` on `pool` and saves the results in `dir` in batches as they arrive (module doc,
/// `saver`), with `beside` (the study's linear systems) on the same pool at the same time.
pub(super) fn run_all<T: Send>(
    pool: &rayon::ThreadPool,
    work: &[Work],
    models: &Models,
    dir: &Path,
    identity: &Identity,
    progress: &Progress,
    beside: impl FnOnce() -> T + Send,
) -> Ran<T> {
    // A rendezvous channel: a worker hands its result over only when this thread takes it, so
    // finished runs never pile up in memory beyond one batch while saves are slower than the
    // runs, and after a failed save each worker has started at most the run it is handing over.
    let (tx, rx) = mpsc::sync_channel::<(usize, JobResult)>(0);
    let mut saver = Saver::new(dir, identity, progress, work);
    // Set at the first failed save: no new job starts; running ones finish.
    let stop = AtomicBool::new(false);
    let beside = std::thread::scope(|scope| {
        let stop_ref = &stop;
        // Its tasks share the pool's threads with the jobs' (work stealing).
        let beside = scope.spawn(|| pool.install(beside));
        scope.spawn(move || {
            pool.install(|| {
                work.par_iter().enumerate().for_each_with(tx, |tx, (i, w)| {
                    if stop_ref.load(Ordering::SeqCst) {
                        return;
                    }
                    let r = models.simulate(w.scene, w.model_id, w.prune);
                    // The receiver lives until every sender is gone.
                    let _ = tx.send((i, r));
                });
            });
        });
        loop {
            let next = match saver.due_in() {
                None => rx.recv().map_err(|_| RecvTimeoutError::Disconnected),
                Some(left) => rx.recv_timeout(left),
            };
            match next {
                Ok((i, r)) => saver.add(i, r),
                Err(RecvTimeoutError::Timeout) => saver.flush(),
                Err(RecvTimeoutError::Disconnected) => {
                    saver.flush();
                    break;
                }
            }
            if saver.error.is_some() {
                stop.store(true, Ordering::SeqCst);
            }
        }
        match beside.join() {
            Ok(t) => t,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    });
    Ran {
        saved: saver.saved,
        error: saver.error,
        beside,
    }
}

/// The error of a run stopped by the failed save `e`: its path and cause, how many of the
/// `runs` are saved in `dir` (of the `wanted` ids), and how to finish.
pub(super) fn stopped(
    e: CampaignError,
    dir: &Path,
    identity: &Identity,
    wanted: &BTreeSet<&str>,
    runs: usize,
) -> CampaignError {
    let saved = saved_parts(dir, identity, wanted).map_or(0, |p| p.0.len());
    CampaignError::Io {
        path: match &e {
            CampaignError::Io { path, .. } => path.clone(),
            _ => dir.to_path_buf(),
        },
        reason: format!(
            "{}; the campaign stopped: {saved} of {} runs are saved in {}; free space (or fix \
             the folder), then finish with --resume",
            match &e {
                CampaignError::Io { reason, .. } => reason.clone(),
                other => other.to_string(),
            },
            runs,
            dir.display()
        ),
    }
}
