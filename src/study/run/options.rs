//! What a run is asked to do and what it reports.
//!
//! In: [`RunOptions`] (output path, threads, resume, overwrite, shard, where the reference runs
//! come from). Out: the `shard` attribute a run writes (`i/n`, or `references` for a references
//! file) and an [`Outcome`]: the counts of jobs by status, read back from the assembled file.

use std::path::{Path, PathBuf};

use super::error::{hdf5_at, CampaignError};
use crate::integrators::Status;
use crate::store;

/// How to run a study.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The results file.
    pub output: PathBuf,
    /// Worker threads.
    pub threads: usize,
    /// Continue from the saved jobs of an interrupted run.
    pub resume: bool,
    /// Replace an existing results file (and the saved jobs of an interrupted run).
    pub overwrite: bool,
    /// Run only shard i of n.
    pub shard: Option<(usize, usize)>,
    /// The command line, stored in the file.
    pub command: String,
    /// Where the reference runs come from.
    pub references: ReferenceSource,
}

/// Where a run's reference runs come from (module doc of `study::run`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum ReferenceSource {
    /// Computed by the run itself, those its jobs need.
    #[default]
    Run,
    /// Only the study's reference runs, all of them, into the output (a references file).
    Only,
    /// Copied from a references file of the same study (written with `Only`).
    File(PathBuf),
}

/// The `shard` attribute of a references file.
pub(crate) const REFERENCES_SHARD: &str = "references";

impl RunOptions {
    /// The `shard` attribute of the run's output: `i/n` (`0/1` unsharded), or
    /// [`REFERENCES_SHARD`] for a references-only run.
    pub(super) fn shard_text(&self) -> String {
        let (si, sn) = self.shard.unwrap_or((0, 1));
        match self.references {
            ReferenceSource::Only => REFERENCES_SHARD.to_string(),
            _ => format!("{si}/{sn}"),
        }
    }
}

/// What a campaign did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// Jobs in this run (shard).
    pub jobs: usize,
    /// Jobs that ended ok.
    pub ok: usize,
    /// Jobs that reached their end time with an error estimate that did not control the step
    /// (`integrators::review_trust`): their records are complete.
    pub untrusted: usize,
    /// Jobs that ended otherwise.
    pub failed: usize,
    /// Jobs found already done (resume).
    pub resumed: usize,
    /// Saved jobs of other inputs that were run again (resume).
    pub stale: usize,
    /// Reference runs that did not end ok (their jobs have no error columns).
    pub references_failed: usize,
}

impl Outcome {
    /// The outcome of a run of `jobs` jobs whose assembled file is `path`: the job statuses and
    /// the failed reference runs as the file holds them.
    pub(super) fn read(
        path: &Path,
        jobs: usize,
        resumed: usize,
        stale: usize,
    ) -> Result<Outcome, CampaignError> {
        let statuses = read_statuses_in(path, "jobs")?;
        let n = |name: &str| statuses.iter().filter(|s| s.as_str() == name).count();
        let (ok, untrusted) = (n("ok"), n("untrusted"));
        let references_failed = read_statuses_in(path, "references")?
            .iter()
            .filter(|s| !Status::name_completed(s))
            .count();
        Ok(Outcome {
            jobs,
            ok,
            untrusted,
            failed: jobs - ok - untrusted,
            resumed,
            stale,
            references_failed,
        })
    }
}

/// The `status` of every run in a group (`jobs`, `references`) of a results file.
fn read_statuses_in(path: &Path, group: &str) -> Result<Vec<String>, CampaignError> {
    let read = || -> hdf5::Result<Vec<String>> {
        let f = hdf5::File::open(path)?;
        let Ok(g) = f.group(group) else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        for name in g.member_names()? {
            let run = g.group(&name)?;
            out.push(store::read_str(&run, "status")?);
        }
        Ok(out)
    };
    read().map_err(hdf5_at(path))
}
