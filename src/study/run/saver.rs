//! The saving thread's batches: finished runs gathered and written to one part file at a time.
//!
//! In: finished runs as the workers hand them over (their index in the work list and result).
//! Out: the part files (`parts::save_batch`), where each run is saved, one progress line per
//! run when its batch is written (ok, or NOT SAVED with the cause: nothing unsaved is reported
//! ok), and the first failed save. A batch is written when it holds `parts::BATCH_RUNS` runs or
//! `parts::BATCH_SAMPLES` samples, when `parts::BATCH_SECONDS` have passed since its first
//! run arrived ([`Saver::due_in`] says how long the thread may wait for the next run), and at
//! the end. Memory: at most one batch of results.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use super::error::CampaignError;
use super::parts::{save_batch, Finished, Saved, BATCH_RUNS, BATCH_SAMPLES, BATCH_SECONDS};
use super::work::Work;
use crate::dynamics::simulation::JobResult;
use crate::study::identity::Identity;
use crate::study::progress::Progress;

/// The batch being gathered and what the saves so far left (module doc).
pub(super) struct Saver<'a> {
    dir: &'a Path,
    identity: &'a Identity,
    progress: &'a Progress,
    work: &'a [Work<'a>],
    batch: Vec<(usize, Finished<'a>)>,
    samples: usize,
    since: Option<Instant>,
    /// Where each run of this run is saved.
    pub(super) saved: BTreeMap<String, Saved>,
    /// The first failed save.
    pub(super) error: Option<CampaignError>,
}

impl<'a> Saver<'a> {
    pub(super) fn new(
        dir: &'a Path,
        identity: &'a Identity,
        progress: &'a Progress,
        work: &'a [Work<'a>],
    ) -> Self {
        Saver {
            dir,
            identity,
            progress,
            work,
            batch: Vec::new(),
            samples: 0,
            since: None,
            saved: BTreeMap::new(),
            error: None,
        }
    }

    /// How long the next run may be waited for before the batch is due (`None`: no batch).
    pub(super) fn due_in(&self) -> Option<Duration> {
        self.since
            .map(|t| Duration::from_secs_f64(BATCH_SECONDS).saturating_sub(t.elapsed()))
    }

    /// Adds the finished run `i` of the work list; writes the batch when it is full.
    pub(super) fn add(&mut self, i: usize, result: JobResult) {
        let w = &self.work[i];
        self.samples += result.time.len() * (result.channels.len() + 1);
        self.since.get_or_insert_with(Instant::now);
        self.batch.push((
            i,
            Finished {
                id: &w.id,
                params: w.part_params(),
                integrator: w.scene.solver.integrator.name(),
                result,
            },
        ));
        if self.batch.len() >= BATCH_RUNS || self.samples >= BATCH_SAMPLES {
            self.flush();
        }
    }

    /// Writes the batch (if any) and reports each of its runs.
    pub(super) fn flush(&mut self) {
        if self.batch.is_empty() {
            return;
        }
        let batch = std::mem::take(&mut self.batch);
        self.samples = 0;
        self.since = None;
        let (index, runs): (Vec<usize>, Vec<Finished>) = batch.into_iter().unzip();
        let written = save_batch(self.dir, &runs, self.identity);
        for (i, r) in index.iter().zip(&runs) {
            self.progress.job_done(
                r.id,
                &self.work[*i].name,
                &r.result.stats,
                written.as_ref().err().map(|e| e as &dyn std::fmt::Display),
            );
        }
        match written {
            Ok(places) => {
                for (r, place) in runs.iter().zip(places) {
                    self.saved.insert(r.id.to_string(), place);
                }
            }
            Err(e) => {
                self.error.get_or_insert(e);
            }
        }
    }
}
