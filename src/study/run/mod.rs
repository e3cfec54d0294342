//! Running a study: shared models, pruning pilots, reference runs and jobs on a thread pool,
//! finished jobs saved in batches within a second, then one HDF5 file assembled.
//!
//! In: a [`Study`](crate::study::Study) and [`RunOptions`] (output path, threads, resume, shard, overwrite).
//! Out: `OUT.h5` in the layout of `store` plus `/models/<id>`, `/references/<id>` and the
//! `summary` table, and an [`Outcome`] (counts).
//!
//! How results are kept safe:
//! - The output is locked for the whole run (`store::output`: one writer per output); an
//!   existing output is replaced only with `overwrite`, and only if it is a rotorsweep results
//!   file; the new file is renamed over it when complete.
//! - Finished jobs are first written, in batches, to part files `OUT.h5.parts/batch-….journal` (under
//!   a temporary name, then renamed; at least once a second, on a writer thread), so a `kill -9`
//!   at any moment loses only the jobs that were running or finished in the last second. Each
//!   part file carries the study's digest ([`Identity`](crate::study::identity::Identity));
//!   `resume` reuses a saved job only when its id and digest match the current study and runs every other job.
//! - An assembled output is resumed only when its digest and shard match (then there is
//!   nothing to do); one made from other inputs is refused, naming what changed.
//! - The first failed save (disk full, read-only folder, I/O error) stops scheduling new jobs;
//!   running jobs finish and are saved if they can be; nothing unsaved is reported ok, and the
//!   error names the path and the OS error. `resume` then completes the study.
//!
//! References shared by shards: [`ReferenceSource::Only`] runs just the study's reference runs
//! into a references file (its `shard` attribute is `references`), with the linearised systems
//! of every job; a shard run with [`ReferenceSource::File`] copies the references (and their
//! models) and the linearised systems its jobs need from that file instead of computing them,
//! after checking its study digest, so a campaign of n shards computes each once. The shard
//! files are the same either way.
//!
//! Progress goes to stderr (a bar on a terminal) and is appended to `OUT.h5.log` (`progress`).
//!
//! Each job runs on one thread; results do not depend on the thread count. A job that panics,
//! diverges, exhausts its budget, or whose model cannot be built is a result with its status
//! and cause.
//!
//! The files, in the order a run uses them: `options` (what is asked, what is reported),
//! `error` (why a run stops), `campaign` ([`run`], step by step), `parts` (the saved runs) and
//! `journal` (their file format),
//! `references` (the shared references file, errors against reference runs), `models`
//! (models, pruning pilots, one run on its model), `linear` (the study's linearised systems,
//! beside the jobs), `work` (the work list), `schedule` (the work list on the pool), `saver`
//! (the batches of finished runs and their writer), `stream` (the results file filled as they
//! are saved), `assemble` (the results file completed). Merging shard files is `study::merge`.

mod assemble;
mod campaign;
mod error;
mod journal;
mod linear;
mod models;
mod options;
mod parts;
mod references;
mod saver;
mod schedule;
mod stream;
mod work;

pub(crate) use assemble::finish_output;
pub use campaign::run;
pub use error::CampaignError;
pub use models::{pruned_selection, strain_energy_shares};
pub(crate) use options::REFERENCES_SHARD;
pub use options::{Outcome, ReferenceSource, RunOptions};
pub use parts::{parts_dir, remove_parts};
pub(crate) use references::stored_identity;
