//! [`run`]: a study's run from its output's lock to its [`Outcome`], step by step (the module
//! doc of `study::run` says what each step keeps safe).
//!
//! In: a [`Study`] and [`RunOptions`]. Out: the assembled `OUT.h5` and the [`Outcome`]. The
//! steps, in order: lock the output and check the options; either find the output already
//! assembled from these inputs (resume: nothing to do) or clear the way for a new run; choose
//! the reference runs and open a shared references file; reuse the saved parts; build the
//! models and run the pruning pilots; run and save the rest (`schedule`), filling the results
//! file meanwhile (`stream`); assemble; count; remove the parts folder.

use std::collections::BTreeSet;
use std::path::Path;

use super::assemble::{assemble, Sources};
use super::error::CampaignError;
use super::linear;
use super::models::Models;
use super::options::{Outcome, ReferenceSource, RunOptions};
use super::parts::{parts_dir, remove_parts, saved_parts};
use super::references::{open_references, same_file, stored_identity};
use super::saver::Sink;
use super::schedule::{run_all, stopped};
use super::stream::Stream;
use super::work::work_list;
use crate::results::job_analysis::{Analyser, Prepared};
use crate::store;
use crate::store::output::{self, OutputLock};
use crate::study::identity::{describe_mismatch, Identity};
use crate::study::merge::parse_shards;
use crate::study::progress::{Progress, RunLog};
use crate::study::{Job, Reference, Study};

/// Runs a study (module doc).
pub fn run(study: &Study, opts: &RunOptions) -> Result<Outcome, CampaignError> {
    let _lock = OutputLock::acquire(&opts.output)?;
    RunLog::check(&opts.output)?;
    let identity = Identity::of(study)?;
    let dir = parts_dir(&opts.output);
    let only = opts.references == ReferenceSource::Only;
    check_options(study, opts)?;
    let (si, sn) = opts.shard.unwrap_or((0, 1));
    let jobs: Vec<&Job> = if only {
        Vec::new()
    } else {
        study.shard(si, sn)
    };
    if opts.resume {
        if let Some(done) = already_assembled(opts, &identity, &dir, jobs.len())? {
            return Ok(done);
        }
    } else {
        clear_for_new_run(opts, &dir)?;
    }
    let refs = references_of(study, &jobs, only);
    // The shared references, checked before anything runs.
    let shared = match &opts.references {
        ReferenceSource::File(p) => {
            if same_file(p, &opts.output) {
                return Err(CampaignError::Usage(format!(
                    "{}: is the output too; the references file is an input of the run",
                    p.display()
                )));
            }
            Some(open_references(p, &identity, &refs)?)
        }
        _ => None,
    };
    let tmp = store::with_suffix(&opts.output, ".tmp");
    output::check_working_file(&tmp)?;
    let log = RunLog::open(&opts.output)?;
    std::fs::create_dir_all(&dir).map_err(|e| CampaignError::io(&dir, e))?;
    let wanted: BTreeSet<&str> = jobs
        .iter()
        .map(|j| j.id.as_str())
        .chain(refs.iter().map(|r| r.id.as_str()))
        .collect();
    let (done, stale) = saved_parts(&dir, &identity, &wanted)?;
    if stale > 0 {
        eprintln!(
            "{}: {stale} saved job(s) were made from other inputs or are unreadable; they run again",
            dir.display()
        );
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.max(1))
        .build()
        .map_err(|e| CampaignError::Usage(e.to_string()))?;
    // The jobs whose linearised systems this run stores: a references file holds the whole
    // study's, for the shards to copy.
    let linear_jobs: Vec<&Job> = if only {
        study.jobs.iter().collect()
    } else {
        jobs.clone()
    };
    // The reference runs this run computes itself: none when they are shared.
    let own_refs: &[&Reference] = if shared.is_none() { &refs } else { &[] };
    let models = Models::prepare(&pool, study, &linear_jobs, &jobs, own_refs, &dir);
    let mut work = work_list(&jobs, own_refs);
    // The plan order, the saved runs among them: the order the results file lists them in.
    let order: Vec<_> = work.iter().map(|w| (w.id.to_string(), w.kind)).collect();
    let resumed = jobs.iter().filter(|j| done.contains_key(&j.id)).count();
    work.retain(|w| !done.contains_key(w.id));
    let total = work.len();
    let mut progress = Progress::new(
        total as u64,
        log,
        &format!(
            "{} (shard {}, {} threads): {total} runs to do, {resumed} saved before",
            opts.command,
            opts.shard_text(),
            opts.threads
        ),
    );
    let in_shared = shared_linear_ids(shared.as_ref())?;
    let systems_to_compute = linear::distinct(&linear_jobs, &in_shared);
    let top_speed_hz = jobs
        .iter()
        .filter_map(|j| j.facts.record_omega)
        .map(|w| w / std::f64::consts::TAU)
        .filter(|s| s.is_finite())
        .fold(0.0, f64::max);
    let analyser = Analyser::new(&study.text, &study.varying, top_speed_hz);
    let prepared = Prepared::new(&study.text, &analyser);
    let mut stream = Stream::create(&tmp, order, &done, prepared);
    let sink = Sink {
        dir: &dir,
        identity: &identity,
        progress: &mut progress,
        stream: &mut stream,
    };
    let ran = run_all(&pool, study, &work, (&models, &analyser), sink, || {
        linear::compute_all(study, &study.linear, &systems_to_compute, &models)
    });
    progress.finish();
    if let Some(e) = ran.error {
        stream.drop_file();
        progress.assembled(
            &opts.output,
            Some(&format!("a run could not be saved: {e}")),
        );
        return Err(stopped(e, &dir, &identity, &wanted, work.len() + resumed));
    }
    let mut saved = done;
    saved.extend(ran.saved);
    let sources = Sources {
        linear: &linear_jobs,
        shared: shared.as_ref(),
        models: &models,
        systems: &ran.beside,
        saved: &saved,
    };
    let assembled = assemble(study, opts, &identity, &jobs, &refs, &sources, stream);
    progress.assembled(&opts.output, assembled.as_ref().err().map(|e| e as _));
    assembled?;
    drop(shared);
    let outcome = Outcome::read(&opts.output, jobs.len(), resumed, stale)?;
    // Every part of this run's jobs was checked (saved_parts) or written by it.
    remove_parts(&dir, &wanted)?;
    Ok(outcome)
}

/// The linear ids the shared references file holds (copied from it, not computed).
fn shared_linear_ids(shared: Option<&hdf5::File>) -> Result<BTreeSet<String>, CampaignError> {
    let Some(f) = shared else {
        return Ok(BTreeSet::new());
    };
    let names = f
        .group("linear")
        .and_then(|g| g.member_names())
        .map_err(|e| CampaignError::io(Path::new(&f.filename()), e.to_string()))?;
    Ok(names.into_iter().collect())
}

/// The options that do not fit the study: shared or only references without a `[reference]`
/// section, references only with a shard.
fn check_options(study: &Study, opts: &RunOptions) -> Result<(), CampaignError> {
    if opts.references != ReferenceSource::Run && !study.has_reference {
        return Err(CampaignError::Usage(format!(
            "{}: has no [reference] section, so there are no reference runs to compute or share",
            study.path.display()
        )));
    }
    if opts.references == ReferenceSource::Only && opts.shard.is_some() {
        return Err(CampaignError::Usage(
            "the reference runs are computed for the whole study: no --shard with them".into(),
        ));
    }
    Ok(())
}

/// On resume: the outcome when the output is already assembled from these inputs and this
/// shard (a parts folder left by a run killed after assembling is cleared), `None` when there
/// is no output yet; an output made from other inputs or another shard is refused.
fn already_assembled(
    opts: &RunOptions,
    identity: &Identity,
    dir: &Path,
    jobs: usize,
) -> Result<Option<Outcome>, CampaignError> {
    output::check_replace(&opts.output, true)?;
    if !opts.output.exists() {
        return Ok(None);
    }
    let only = opts.references == ReferenceSource::Only;
    let (_, sn) = opts.shard.unwrap_or((0, 1));
    let shard_text = opts.shard_text();
    let (digest, inputs, shard) = stored_identity(&opts.output)?;
    // A merge of every shard of a split is the whole study.
    let whole = |t: &str| {
        parse_shards(t).is_some_and(|l| {
            let n = l.first().map_or(0, |x| x.1);
            l.iter().all(|x| x.1 == n) && (0..n).all(|i| l.contains(&(i, n)))
        })
    };
    let same_shard = shard == shard_text || (sn == 1 && !only && whole(&shard));
    if digest != identity.digest || !same_shard {
        let what = if digest != identity.digest {
            describe_mismatch(identity, &digest, inputs.as_deref())
        } else {
            format!("it is shard {shard}, this run is shard {shard_text}")
        };
        return Err(CampaignError::Usage(format!(
            "{}: already assembled from other inputs ({what}); nothing was changed. \
             Run with --overwrite instead of --resume to compute the study again into it, \
             or choose another -o",
            opts.output.display()
        )));
    }
    if dir.exists() {
        remove_parts(dir, &BTreeSet::new())?;
    }
    Outcome::read(&opts.output, jobs, jobs, 0).map(Some)
}

/// A new run (no resume): the output may be replaced, and a parts folder of an interrupted run
/// is removed with `overwrite`, else refused.
fn clear_for_new_run(opts: &RunOptions, dir: &Path) -> Result<(), CampaignError> {
    output::check_replace(&opts.output, opts.overwrite)?;
    if dir.exists() || std::fs::symlink_metadata(dir).is_ok() {
        if !opts.overwrite {
            return Err(CampaignError::Usage(format!(
                "{} exists (an interrupted run?): add --resume to finish it, or --overwrite \
                 to start again",
                dir.display()
            )));
        }
        remove_parts(dir, &BTreeSet::new())?;
    }
    Ok(())
}

/// The reference runs of a run: all of the study's for a references file, else those its
/// jobs need (none without a `[reference]` section).
fn references_of<'a>(study: &'a Study, jobs: &[&Job], only: bool) -> Vec<&'a Reference> {
    if only {
        study.references.iter().collect()
    } else if study.has_reference {
        let needed: BTreeSet<&str> = jobs.iter().map(|j| j.reference_id.as_str()).collect();
        study
            .references
            .iter()
            .filter(|r| needed.contains(r.id.as_str()))
            .collect()
    } else {
        Vec::new()
    }
}
