//! The saving side of a run: finished runs gathered into batches, and batches written to one
//! part file at a time on a writer thread, so the runs go on while a batch is written.
//!
//! In: finished runs as the workers hand them over ([`Finished`]).
//! Out: the part files (`parts::save_batch`), each batch's runs written into the results file
//! being filled (`stream`), where each run is saved, one progress line per
//! run when its batch is written (ok, or NOT SAVED with the cause: nothing unsaved is reported
//! ok), and the first failed save, which raises the run's stop flag. [`Saver`] gathers a batch
//! and hands it to [`write_batches`] when it holds `parts::BATCH_RUNS` runs or
//! `parts::BATCH_SAMPLES` samples, when `parts::BATCH_SECONDS` have passed since its first run
//! arrived ([`Saver::due_in`] says how long the thread may wait for the next run), and at the
//! end. Memory: the batch being written and the one being gathered (the hand-over waits while
//! the writer is busy).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, SyncSender};
use std::time::{Duration, Instant};

use super::error::CampaignError;
use super::parts::{save_batch, Finished, Saved, BATCH_RUNS, BATCH_SAMPLES, BATCH_SECONDS};
use super::stream::Stream;
use crate::study::identity::Identity;
use crate::study::progress::Progress;

/// A batch: what each of its runs left.
pub(super) type Batch<'a> = Vec<Finished<'a>>;

/// The batch being gathered (module doc).
pub(super) struct Saver<'a> {
    batch: Batch<'a>,
    samples: usize,
    since: Option<Instant>,
    writer: SyncSender<Batch<'a>>,
}

impl<'a> Saver<'a> {
    /// Gathers runs and hands each batch to `writer` ([`write_batches`]).
    pub(super) fn new(writer: SyncSender<Batch<'a>>) -> Self {
        Saver {
            batch: Vec::new(),
            samples: 0,
            since: None,
            writer,
        }
    }

    /// How long the next run may be waited for before the batch is due (`None`: no batch).
    pub(super) fn due_in(&self) -> Option<Duration> {
        self.since
            .map(|t| Duration::from_secs_f64(BATCH_SECONDS).saturating_sub(t.elapsed()))
    }

    /// Adds a finished run; hands the batch over when it is full.
    pub(super) fn add(&mut self, finished: Finished<'a>) {
        let result = &finished.result;
        self.samples += result.time.len() * (result.channels.len() + 1);
        self.since.get_or_insert_with(Instant::now);
        self.batch.push(finished);
        if self.batch.len() >= BATCH_RUNS || self.samples >= BATCH_SAMPLES {
            self.flush();
        }
    }

    /// Hands the batch (if any) to the writer, waiting while it writes the one before.
    pub(super) fn flush(&mut self) {
        if self.batch.is_empty() {
            return;
        }
        self.samples = 0;
        self.since = None;
        // The writer lives until this sender is dropped (it ends only by a panic, which the
        // run's scope passes on).
        let _ = self.writer.send(std::mem::take(&mut self.batch));
    }
}

/// Where finished runs go: the parts folder and the study's digest its part files carry, the
/// progress lines, and the results file being filled.
pub(super) struct Sink<'a> {
    pub(super) dir: &'a Path,
    pub(super) identity: &'a Identity,
    pub(super) progress: &'a mut Progress,
    pub(super) stream: &'a mut Stream,
}

/// What the writer leaves: where each run is saved, and the first failed save.
pub(super) struct Written {
    pub(super) saved: BTreeMap<String, Saved>,
    pub(super) error: Option<CampaignError>,
}

/// Writes each batch from `batches` to its part file in the sink's folder, copies its runs
/// into the results file being filled (its `stream`) and reports each of its runs (module doc); the first
/// failed save raises `stop`. Ends when the [`Saver`] is dropped.
pub(super) fn write_batches(batches: Receiver<Batch>, sink: Sink, stop: &AtomicBool) -> Written {
    let mut out = Written {
        saved: BTreeMap::new(),
        error: None,
    };
    for batch in batches {
        let mut runs = batch;
        let written = save_batch(sink.dir, &runs, sink.identity);
        for r in &runs {
            sink.progress.job_done(
                r.id,
                &r.name,
                &r.result.stats,
                written.as_ref().err().map(|e| e as &dyn std::fmt::Display),
            );
        }
        match written {
            Ok(places) => {
                let ids: Vec<(String, Saved)> = (runs.iter().zip(&places))
                    .map(|(r, place)| (r.id.to_string(), place.clone()))
                    .collect();
                sink.stream.add(ids, &mut runs);
                for (r, place) in runs.iter().zip(places) {
                    out.saved.insert(r.id.to_string(), place);
                }
            }
            Err(e) => {
                stop.store(true, Ordering::SeqCst);
                out.error.get_or_insert(e);
            }
        }
    }
    out
}
