//! The results file filled while the runs go on: saved runs are written into the working file
//! `OUT.h5.tmp` in plan order by the writer thread, right after their batch is saved, so the
//! assembly after the last run has only the study's own groups, the analysis and the summary
//! left to write.
//!
//! In: the working path; the run's plan order (reference runs it computes, then its jobs; their
//! ids and kinds); where each run is saved (`parts::Saved`), those saved before this run at
//! once, the others as each batch is saved, with the batch's runs in memory. Out:
//! `OUT.h5.tmp` holding `/references/<id>` and `/jobs/<id>` of the plan order's first runs,
//! every one whose predecessors are all saved (written from memory when its batch is the one
//! just saved, else read back from its part file: `parts::OpenParts`), each job's analysis
//! (made on the worker that ran it, `Finished::analysed`, kept here while the job waits for a
//! predecessor; a job without one, saved before a resume, is analysed from its group) written
//! into its group and kept for the study's analysis (`results::job_analysis::Prepared`: means,
//! spectra, lines, order tracking at a constant speed), and the set of runs copied. Plan order, not the order of finishing: small groups list their members
//! in the order they were made, and the analysis reads them in that order, so the file is the
//! same whatever the threads. Memory: where each saved-but-not-yet-written run is (a path and
//! an offset per run) and its analysis (lines and spectra up to the study's cap), not its
//! samples.
//!
//! The part files stay the record of what is saved: a `kill -9` leaves this file unfinished
//! under its working name, and `--resume` starts it again from the parts. The first failed copy
//! (disk full, I/O error) drops the file: the assembly then writes the output whole from the
//! parts, as without a stream, and reports a full disk as it does.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::parts::{Finished, OpenParts, Saved};
use super::work::Kind;
use crate::results::job_analysis::{Analysed, Prepared};

/// The working file being filled (module doc).
pub(super) struct Stream {
    path: PathBuf,
    file: Option<hdf5::File>,
    /// The plan order: each run's id and kind.
    order: Vec<(String, Kind)>,
    /// The first run of `order` not copied yet.
    next: usize,
    /// Saved runs waiting for a predecessor.
    ready: BTreeMap<String, Saved>,
    parts: OpenParts,
    /// The copied jobs, analysed.
    prepared: Prepared,
    /// The analyses (made on the workers) of saved jobs waiting for a predecessor.
    pending: BTreeMap<String, Analysed>,
}

impl Stream {
    /// Creates the working file at `tmp` (checked by the caller: absent or a leftover of ours)
    /// with its `jobs` and `references` groups, for the runs of `order`, and copies the runs
    /// saved `before` this run that lead the order. A file that cannot be created is no stream
    /// (the assembly writes the output whole and reports why).
    pub(super) fn create(
        tmp: &Path,
        order: Vec<(String, Kind)>,
        before: &BTreeMap<String, Saved>,
        prepared: Prepared,
    ) -> Stream {
        let mut s = Stream {
            path: tmp.to_path_buf(),
            file: None,
            order,
            next: 0,
            ready: BTreeMap::new(),
            parts: OpenParts::default(),
            prepared,
            pending: BTreeMap::new(),
        };
        if let Ok(f) = hdf5::File::create(tmp) {
            if f.create_group("jobs").is_ok() && f.create_group("references").is_ok() {
                s.file = Some(f);
            } else {
                s.drop_file();
            }
        }
        let wanted: Vec<(String, Saved)> = s
            .order
            .iter()
            .filter_map(|(id, _)| Some((id.clone(), before.get(id)?.clone())))
            .collect();
        s.add(wanted, &mut []);
        s
    }

    /// Takes the saved runs (id, where saved; those of `fresh`, the batch just saved, in
    /// memory) and writes every run the plan order now allows; the first failure drops the
    /// file (module doc).
    pub(super) fn add(
        &mut self,
        saved: impl IntoIterator<Item = (String, Saved)>,
        fresh: &mut [Finished],
    ) {
        if self.file.is_none() {
            return;
        }
        self.ready.extend(saved);
        for run in fresh.iter_mut() {
            if let Some(a) = run.analysed.take() {
                self.pending.insert(run.id.to_string(), a);
            }
        }
        if let Err(()) = self.copy_ready(fresh) {
            self.drop_file();
        }
    }

    /// Writes the leading runs of the plan order that are saved.
    fn copy_ready(&mut self, fresh: &[Finished]) -> Result<(), ()> {
        let Some(f) = &self.file else {
            return Ok(());
        };
        let (jobs, refs) = (
            f.group("jobs").map_err(drop)?,
            f.group("references").map_err(drop)?,
        );
        while let Some((id, kind)) = self.order.get(self.next) {
            let Some(saved) = self.ready.remove(id) else {
                break;
            };
            let dst = match kind {
                Kind::Job(_) => &jobs,
                Kind::Reference => &refs,
            };
            match fresh.iter().find(|r| r.id == id) {
                Some(run) => run.write(dst).map_err(drop)?,
                None => self.parts.copy_saved(&saved, id, dst).map_err(drop)?,
            }
            if let Kind::Job(_) = kind {
                let g = dst.group(id).map_err(drop)?;
                match self.pending.remove(id) {
                    Some(a) => self.prepared.add_analysed(&g, id, a),
                    None => self.prepared.add(&g, id),
                }
                .map_err(drop)?;
            }
            self.next += 1;
        }
        Ok(())
    }

    /// Closes and removes the file it created (a failed copy, a stopped run): nothing
    /// half-filled is left where the assembly writes.
    pub(super) fn drop_file(&mut self) {
        self.file = None;
        self.parts = OpenParts::default();
        self.pending.clear();
        let _ = std::fs::remove_file(&self.path);
    }

    /// The file, the runs copied into it and the jobs analysed, taken for the assembly to
    /// finish (`None` after a failed copy).
    pub(super) fn take(mut self) -> Option<(hdf5::File, BTreeSet<String>, Prepared)> {
        let f = self.file.take()?;
        let copied = self.order[..self.next]
            .iter()
            .map(|(id, _)| id.clone())
            .collect();
        Some((f, copied, self.prepared))
    }
}
