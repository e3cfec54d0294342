//! The work of a run in order, on the worker pool, each finished run saved as it arrives.
//!
//! In: the run's work list (`work`: reference runs unless shared, then jobs in study order, the
//! saved ones left out), the built [`Models`], the parts folder. Out: each item run on one
//! thread of the pool (its scene built there, and what its part file records beside the
//! result: `Work::run`) and saved by the calling thread in batches as they finish (`saver`,
//! `parts`); the progress line per run. A worker hands its result over only when the saving
//! thread takes it (memory bounded by one batch and one finished run per worker). The first
//! failed save stops new runs from starting; running ones finish and are saved if they can be,
//! and the error says how many are saved. The study's linear systems are computed on the same
//! pool meanwhile. Results do not depend on the thread count or the order in which runs finish.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};

use rayon::prelude::*;

use super::error::CampaignError;
use super::models::Models;
use super::parts::{saved_parts, Finished, Saved};
use super::saver::{write_batches, Batch, Saver, Sink};
use super::work::Work;
use crate::results::job_analysis::Analyser;
use crate::study::identity::Identity;
use crate::study::Study;

/// What [`run_all`] leaves: where each run it saved is, the first failed save, and what the
/// work beside the jobs returned.
pub(super) struct Ran<T> {
    pub(super) saved: BTreeMap<String, Saved>,
    pub(super) error: Option<CampaignError>,
    pub(super) beside: T,
}

/// Runs `work` on `pool` and saves the results in batches as they arrive, into the `sink`'s
/// parts folder and the results file it fills (module doc, `saver`), with `beside` (the study's linear systems) on the same pool at the same time.
pub(super) fn run_all<T: Send>(
    pool: &rayon::ThreadPool,
    study: &Study,
    work: &[Work],
    (models, analyser): (&Models, &Analyser),
    sink: Sink,
    beside: impl FnOnce() -> T + Send,
) -> Ran<T> {
    // A rendezvous channel: a worker hands its result over only when this thread takes it, so
    // finished runs never pile up in memory beyond the batches while saves are slower than the
    // runs, and after a failed save each worker has started at most the run it is handing over.
    let (tx, rx) = mpsc::sync_channel::<Finished>(0);
    let (to_writer, batches) = mpsc::sync_channel::<Batch>(0);
    // Set at the first failed save: no new job starts; running ones finish.
    let stop = AtomicBool::new(false);
    let (beside, written) = std::thread::scope(|scope| {
        let stop_ref = &stop;
        // Its tasks share the pool's threads with the jobs' (work stealing).
        let beside = scope.spawn(|| pool.install(beside));
        scope.spawn(move || {
            pool.install(|| {
                work.par_iter().for_each_with(tx, |tx, w| {
                    if stop_ref.load(Ordering::SeqCst) {
                        return;
                    }
                    let r = w.run(study, models, analyser);
                    // The receiver lives until every sender is gone.
                    let _ = tx.send(r);
                });
            });
        });
        let writer = scope.spawn(move || write_batches(batches, sink, stop_ref));
        let mut saver = Saver::new(to_writer);
        loop {
            let next = match saver.due_in() {
                None => rx.recv().map_err(|_| RecvTimeoutError::Disconnected),
                Some(left) => rx.recv_timeout(left),
            };
            match next {
                Ok(r) => saver.add(r),
                Err(RecvTimeoutError::Timeout) => saver.flush(),
                Err(RecvTimeoutError::Disconnected) => {
                    saver.flush();
                    break;
                }
            }
        }
        // The writer ends when the saver's sender is gone.
        drop(saver);
        (joined(beside), joined(writer))
    });
    Ran {
        saved: written.saved,
        error: written.error,
        beside,
    }
}

/// A scoped thread's value, its panic passed on.
fn joined<T>(h: std::thread::ScopedJoinHandle<'_, T>) -> T {
    match h.join() {
        Ok(t) => t,
        Err(panic) => std::panic::resume_unwind(panic),
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
