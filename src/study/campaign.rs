//! Running a study: shared models, pruning pilots, reference runs and jobs on a thread pool, each
//! finished job saved at once, then one HDF5 file assembled.
//!
//! In: a [`Study`] and [`RunOptions`] (output path, threads, resume, shard, overwrite).
//! Out: `OUT.h5` in the layout of `store` plus `/models/<id>`, `/references/<id>` and the
//! `summary` table, and an [`Outcome`] (counts).
//!
//! How results are kept safe:
//! - The output is locked for the whole run (`store::output`: one writer per output); an
//!   existing output is replaced only with `overwrite`, and only if it is a rotorsweep results
//!   file; the new file is renamed over it when complete.
//! - Every finished job is first written to its own file `OUT.h5.parts/<id>.h5` (under a
//!   temporary name, then renamed), so a `kill -9` at any moment loses only the jobs that were
//!   running. Each part file carries the study's digest ([`Identity`]); `resume` reuses a saved
//!   job only when its id and digest match the current study and runs every other job.
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

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};

use rayon::prelude::*;

use super::identity::{compare, describe_mismatch, Identity};
use super::progress::{Progress, RunLog};
use super::{Job, Study};
use crate::dynamics::linear_system::LinearSystem;
use crate::dynamics::model::Model;
use crate::dynamics::simulation::{self, JobResult};
use crate::error::InputError;
use crate::integrators::{Stats, Status};
use crate::rotor::reduction::{ModeKind, ModeSelection};
use crate::scene::Scene;
use crate::store::output::{self, OutputError, OutputLock};
use crate::store::{self, units_of_key, Column, Param};

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

/// Where a run's reference runs come from (module doc).
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
const REFERENCES_SHARD: &str = "references";

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

/// Why a campaign could not run or finish (bad files or I/O; failing jobs are results, not
/// errors).
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// An input file (study, scene, map, or a results file given as input) is wrong.
    #[error("{0}")]
    Input(#[from] InputError),
    /// The output cannot be written (exists, not ours, in use, OS error).
    #[error("{0}")]
    Output(#[from] OutputError),
    /// Writing or reading a file failed: the path and the cause.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed, with the OS error where one is known.
        reason: String,
    },
    /// A usage problem (options that do not fit the files).
    #[error("{0}")]
    Usage(String),
}

impl CampaignError {
    fn io(path: &Path, reason: impl std::fmt::Display) -> Self {
        CampaignError::Io {
            path: path.to_path_buf(),
            reason: reason.to_string(),
        }
    }
}

/// An HDF5 error on `path`, with the OS error behind it when the library's error stack names
/// one (disk full, permissions), and the free space of the folder when it is exhausted.
fn hdf5_at(path: &Path) -> impl Fn(hdf5::Error) -> CampaignError + '_ {
    move |e| CampaignError::io(path, describe_hdf5(path, &e))
}

fn describe_hdf5(path: &Path, e: &hdf5::Error) -> String {
    let full = e.to_string();
    let frames: Vec<String> = e
        .stack()
        .map(|st| st.iter().map(|f| f.desc().to_string()).collect())
        .unwrap_or_default();
    // The OS error as the library's file driver reports it: "errno = 28, error message = '…'".
    let os = std::iter::once(full.as_str())
        .chain(frames.iter().map(String::as_str))
        .find_map(|t| {
            let n = t.split("errno = ").nth(1)?;
            let n: String = n.chars().take_while(char::is_ascii_digit).collect();
            let m = t.split("error message = '").nth(1)?.split('\'').next()?;
            Some(format!("{m} (errno {n})"))
        });
    let cut = [", errno", ": file write failed", " time = "]
        .iter()
        .filter_map(|m| full.find(m))
        .min()
        .unwrap_or(full.len());
    let mut text = match os {
        Some(os) => format!("{os}; HDF5: {}", &full[..cut]),
        None => full[..cut].to_string(),
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if let Some(free) = free_bytes(dir) {
        if free < 1 << 20 {
            text.push_str(&format!(" [{} bytes free in {}]", free, dir.display()));
        }
    }
    text
}

fn free_bytes(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: a valid NUL-terminated path and a zeroed out-struct.
    (unsafe { libc::statvfs(c.as_ptr(), &mut st) } == 0)
        .then(|| st.f_bavail as u64 * st.f_frsize as u64)
}

/// Where a run on `out` keeps its finished jobs until the file is assembled.
pub fn parts_dir(out: &Path) -> PathBuf {
    store::with_suffix(out, ".parts")
}

/// A unit of work for the pool.
struct Work<'a> {
    id: String,
    kind: Kind,
    scene: &'a Scene,
    model_id: &'a str,
    linear_id: Option<&'a str>,
    prune: Option<f64>,
    params: Vec<(String, Param)>,
    /// What the progress lines call it: the job's labels, else its varying values.
    name: String,
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
            }
        }
    }
}

fn failed_result(cause: String) -> JobResult {
    JobResult {
        stats: Stats::failed(cause),
        modes: String::new(),
        coordinates: 0,
        time: Vec::new(),
        channels: Vec::new(),
        lift_off_s: None,
    }
}

/// Writes one finished job to its own part file, atomically, tagged with the study's digest.
fn save_part(
    dir: &Path,
    w: &Work,
    r: &JobResult,
    integrator: &str,
    id: &Identity,
) -> Result<(), CampaignError> {
    let tmp = dir.join(format!("{}.h5.tmp", w.id));
    let fin = dir.join(format!("{}.h5", w.id));
    output::check_working_file(&tmp)?;
    let write = || -> hdf5::Result<()> {
        let f = hdf5::File::create(&tmp)?;
        store::attr_str(&f, "tool", "rotorsweep")?;
        store::attr_str(&f, "tool_version", env!("CARGO_PKG_VERSION"))?;
        store::attr_str(&f, "study_digest", &id.digest)?;
        let mut params = w.params.clone();
        params.push(("model_id".into(), Param::Text(w.model_id.to_string())));
        if let Some(l) = w.linear_id {
            params.push(("linear_id".into(), Param::Text(l.to_string())));
        }
        // The spin speed over the record, the roll angle's offset and the roller ratios, for
        // the spectral analysis.
        params.extend(crate::results::analyse::job_attrs(w.scene));
        if let Some(p) = w.prune {
            params.push((super::PRUNE_KEY.into(), Param::Number(p)));
        }
        match w.kind {
            Kind::Job(i) => {
                params.push(("job_index".into(), Param::Count(i as u64)));
                params.push(("kind".into(), Param::Text("job".into())));
            }
            Kind::Reference => params.push(("kind".into(), Param::Text("reference".into()))),
        }
        store::write_job(&f, "job", &params, integrator, r)?;
        f.close()
    };
    if let Err(e) = write() {
        let reason = describe_hdf5(&tmp, &e);
        let _ = std::fs::remove_file(&tmp);
        return Err(CampaignError::io(&tmp, reason));
    }
    std::fs::rename(&tmp, &fin).map_err(|e| CampaignError::io(&fin, e))?;
    Ok(())
}

/// The saved parts of a run: ids whose part file carries the study's digest, and the number of
/// parts made from other inputs (or unreadable), which are run again: among them the parts of
/// this study before an edit (the same study file, another digest), whose ids are no longer
/// jobs when the edit changed a scene. A file there that rotorsweep did not write (not HDF5
/// with `tool = rotorsweep` and a `job` group), or a saved job of another study or another
/// shard on the same output, is refused: nothing in the folder is replaced or removed that is
/// not this run's own.
fn saved_parts(
    dir: &Path,
    identity: &Identity,
    wanted: &BTreeSet<&str>,
) -> Result<(BTreeSet<String>, usize), CampaignError> {
    let digest = identity.digest.as_str();
    let study_file = identity.inputs.iter().find(|f| f.role == "study");
    // A part of this study's earlier inputs: the same study file, edited (or what it reads).
    let earlier = |f: &hdf5::File| {
        let d = store::read_str(f, "study_digest").unwrap_or_default();
        let inputs = store::read_str(f, "study_inputs").unwrap_or_default();
        !d.is_empty()
            && d != digest
            && Identity::parse_inputs(&inputs)
                .iter()
                .any(|i| study_file.is_some_and(|s| s.role == i.role && s.path == i.path))
    };
    let mut done = BTreeSet::new();
    let mut stale = 0;
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Ok((done, 0));
    };
    for e in rd.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(id) = name.strip_suffix(".h5") else {
            continue;
        };
        let path = e.path();
        let f = open_part(&path).map_err(|why| {
            OutputError::Refused(
                path.clone(),
                format!("{why}: it is not a saved job of rotorsweep's; move it away"),
            )
        })?;
        if !wanted.contains(id) {
            if earlier(&f) {
                stale += 1;
                continue;
            }
            return Err(CampaignError::Usage(format!(
                "{}: a saved job that is not in this run (another shard's, or another study's, \
                 on the same output): finish that run into this output, or choose another -o, \
                 or run with --overwrite instead of --resume to discard the saved jobs",
                path.display()
            )));
        }
        if store::read_str(&f, "study_digest").is_ok_and(|d| d == digest) {
            done.insert(id.to_string());
        } else {
            stale += 1;
        }
    }
    Ok((done, stale))
}

/// A saved job's part file, opened: a rotorsweep results file with a `job` group.
fn open_part(path: &Path) -> Result<hdf5::File, String> {
    let f = output::open_results_file(path)?;
    match f.group("job") {
        Ok(_) => Ok(f),
        Err(_) => Err("has no `job` group".into()),
    }
}

/// Whether a file in a parts folder is one of rotorsweep's: a part file (a rotorsweep HDF5 file
/// with a `job` group), a part's temporary name (empty or HDF5), or pilot shares (one number a
/// line), judged by content, not only by name. Parts of the `known` ids (saved or checked by
/// this run) are not opened again.
fn is_own_part(path: &Path, known: &BTreeSet<&str>) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.ends_with(".h5.tmp") {
        output::is_own_leftover(path)
    } else if let Some(id) = name.strip_suffix(".h5") {
        known.contains(id) || open_part(path).is_ok()
    } else if name.ends_with(".shares") {
        std::fs::read_to_string(path)
            .is_ok_and(|t| t.lines().all(|l| l.trim().parse::<f64>().is_ok()))
    } else {
        false
    }
}

/// Removes a parts folder: only rotorsweep's own regular files, then the folder; anything
/// else in it is refused (nothing a user put there is removed). `known`: ids whose part files
/// this run saved or checked itself.
pub fn remove_parts(dir: &Path, known: &BTreeSet<&str>) -> Result<(), CampaignError> {
    let meta = std::fs::symlink_metadata(dir).map_err(|e| CampaignError::io(dir, e))?;
    if !meta.is_dir() {
        return Err(OutputError::Refused(
            dir.to_path_buf(),
            "is not a folder, where rotorsweep keeps the saved jobs of a run".into(),
        )
        .into());
    }
    let entries: Vec<std::fs::DirEntry> = std::fs::read_dir(dir)
        .map_err(|e| CampaignError::io(dir, e))?
        .filter_map(|e| e.ok())
        .collect();
    if let Some(bad) = entries
        .iter()
        .find(|e| !e.file_type().is_ok_and(|t| t.is_file()) || !is_own_part(&e.path(), known))
    {
        return Err(OutputError::Refused(
            dir.to_path_buf(),
            format!(
                "holds {}, which rotorsweep did not write",
                bad.path().display()
            ),
        )
        .into());
    }
    for e in entries {
        std::fs::remove_file(e.path()).map_err(|x| CampaignError::io(&e.path(), x))?;
    }
    std::fs::remove_dir(dir).map_err(|e| CampaignError::io(dir, e))
}

/// A results file's identity attributes: (digest, inputs text, shard).
fn stored_identity(path: &Path) -> Result<(String, Option<String>, String), CampaignError> {
    let f = hdf5::File::open(path).map_err(hdf5_at(path))?;
    Ok((
        store::read_str(&f, "study_digest").unwrap_or_default(),
        store::read_str(&f, "study_inputs").ok(),
        store::read_str(&f, "shard").unwrap_or_default(),
    ))
}

/// Runs a study (module doc).
pub fn run(study: &Study, opts: &RunOptions) -> Result<Outcome, CampaignError> {
    let _lock = OutputLock::acquire(&opts.output)?;
    RunLog::check(&opts.output)?;
    let identity = Identity::of(study)?;
    let dir = parts_dir(&opts.output);
    let only = opts.references == ReferenceSource::Only;
    if opts.references != ReferenceSource::Run && !study.has_reference {
        return Err(CampaignError::Usage(format!(
            "{}: has no [reference] section, so there are no reference runs to compute or share",
            study.path.display()
        )));
    }
    if only && opts.shard.is_some() {
        return Err(CampaignError::Usage(
            "the reference runs are computed for the whole study: no --shard with them".into(),
        ));
    }
    let (si, sn) = opts.shard.unwrap_or((0, 1));
    let shard_text = if only {
        REFERENCES_SHARD.to_string()
    } else {
        format!("{si}/{sn}")
    };
    let jobs: Vec<&Job> = if only {
        Vec::new()
    } else {
        study.shard(si, sn)
    };
    if opts.resume {
        output::check_replace(&opts.output, true)?;
        if opts.output.exists() {
            let (digest, inputs, shard) = stored_identity(&opts.output)?;
            let whole = |t: &str| {
                parse_shards(t).is_some_and(|l| {
                    let n = l.first().map_or(0, |x| x.1);
                    l.iter().all(|x| x.1 == n) && (0..n).all(|i| l.contains(&(i, n)))
                })
            };
            let same_shard = shard == shard_text || (sn == 1 && !only && whole(&shard));
            if digest != identity.digest || !same_shard {
                let what = if digest != identity.digest {
                    describe_mismatch(&identity, &digest, inputs.as_deref())
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
            // Already assembled from these inputs: nothing left to run (a parts folder left by
            // a run killed after assembling is cleared).
            if dir.exists() {
                remove_parts(&dir, &BTreeSet::new())?;
            }
            let n = jobs.len();
            let statuses = read_statuses(&opts.output)?;
            let (ok, untrusted) = count_statuses(&statuses);
            return Ok(Outcome {
                jobs: n,
                ok,
                untrusted,
                failed: n - ok - untrusted,
                resumed: n,
                stale: 0,
                references_failed: failed_references(&opts.output)?,
            });
        }
    } else {
        output::check_replace(&opts.output, opts.overwrite)?;
        if dir.exists() || std::fs::symlink_metadata(&dir).is_ok() {
            if !opts.overwrite {
                return Err(CampaignError::Usage(format!(
                    "{} exists (an interrupted run?): add --resume to finish it, or --overwrite \
                     to start again",
                    dir.display()
                )));
            }
            remove_parts(&dir, &BTreeSet::new())?;
        }
    }
    let refs: Vec<&super::Reference> = if only {
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
    };
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
    output::check_working_file(&store::with_suffix(&opts.output, ".tmp"))?;
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
    // 1. Distinct models, built once each.
    let mut model_scenes: BTreeMap<&str, &Scene> = BTreeMap::new();
    for j in &linear_jobs {
        model_scenes.entry(j.model_id.as_str()).or_insert(&j.scene);
    }
    for r in refs.iter().filter(|_| shared.is_none()) {
        model_scenes.entry(r.model_id.as_str()).or_insert(&r.scene);
    }
    let built: Vec<(&str, Result<Arc<Model>, String>)> = pool.install(|| {
        model_scenes
            .par_iter()
            .map(|(id, sc)| {
                // A model that cannot be built (or whose build panics) fails its jobs alone.
                let built = catch_unwind(AssertUnwindSafe(|| Model::build(sc, None)))
                    .map_err(|e| format!("{}: panic: {}", sc.source.display(), panic_text(&*e)))
                    .and_then(|r| {
                        r.map(Arc::new)
                            .map_err(|e| format!("{}: {e}", sc.source.display()))
                    });
                (*id, built)
            })
            .collect()
    });
    let models: BTreeMap<&str, Result<Arc<Model>, String>> = built.into_iter().collect();
    // 2. Pruning pilots, once per model that a pruned job needs.
    let mut shares: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let pilot_models: BTreeSet<&str> = jobs
        .iter()
        .filter(|j| j.prune.is_some())
        .map(|j| j.model_id.as_str())
        .collect();
    let pilots: Vec<(String, Result<Vec<f64>, String>)> = pool.install(|| {
        pilot_models
            .par_iter()
            .map(|mid| {
                let pilot_key = super::fnv1a(super::pilot_text(&study.pilot_overrides).as_bytes());
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
    let mut pilot_errors: BTreeMap<String, String> = BTreeMap::new();
    for (mid, r) in pilots {
        match r {
            Ok(v) => {
                shares.insert(mid, v);
            }
            Err(e) => {
                pilot_errors.insert(mid, e);
            }
        }
    }
    // 3. The work list: references (unless shared), then jobs; saved ones skipped.
    let mut work: Vec<Work> = Vec::new();
    for r in refs.iter().filter(|_| shared.is_none()) {
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
    for j in &jobs {
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
    let resumed = jobs.iter().filter(|j| done.contains(&j.id)).count();
    work.retain(|w| !done.contains(&w.id));
    let total = work.len();
    let progress = Progress::new(
        total as u64,
        log,
        &format!(
            "{} (shard {shard_text}, {} threads): {total} runs to do, {resumed} saved before",
            opts.command, opts.threads
        ),
    );
    let (tx, rx) = mpsc::channel::<(usize, JobResult)>();
    let mut write_error: Option<CampaignError> = None;
    // Set at the first failed save: no new job starts; running ones finish.
    let stop = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let stop_ref = &stop;
        let work_ref = &work;
        let models_ref = &models;
        let shares_ref = &shares;
        let pilot_errors_ref = &pilot_errors;
        let pool_ref = &pool;
        scope.spawn(move || {
            pool_ref.install(|| {
                work_ref
                    .par_iter()
                    .enumerate()
                    .for_each_with(tx, |tx, (i, w)| {
                        if stop_ref.load(Ordering::SeqCst) {
                            return;
                        }
                        let r = match &models_ref[w.model_id] {
                            Err(e) => failed_result(format!("model: {e}")),
                            Ok(m) => match w.prune {
                                Some(t) if t > 0.0 => match (
                                    shares_ref.get(w.model_id),
                                    pilot_errors_ref.get(w.model_id),
                                ) {
                                    (Some(sh), _) => {
                                        let sel = pruned_selection(m, sh, t);
                                        match m.full.select(&sel) {
                                            Ok(red) => {
                                                let mut pm = (**m).clone();
                                                pm.reduced = red;
                                                run_one(w.scene, &pm)
                                            }
                                            Err(e) => failed_result(format!("pruning: {e}")),
                                        }
                                    }
                                    (None, Some(e)) => failed_result(format!("pruning pilot: {e}")),
                                    (None, None) => failed_result("pruning pilot missing".into()),
                                },
                                _ => run_one(w.scene, m),
                            },
                        };
                        // The receiver lives until every sender is gone.
                        let _ = tx.send((i, r));
                    });
            });
        });
        for (i, r) in rx {
            let w = &work[i];
            let saved = save_part(&dir, w, &r, w.scene.solver.integrator.name(), &identity);
            progress.job_done(
                &w.id,
                &w.name,
                &r.stats,
                saved.as_ref().err().map(|e| e as &dyn std::fmt::Display),
            );
            if let Err(e) = saved {
                stop.store(true, Ordering::SeqCst);
                write_error.get_or_insert(e);
            }
        }
    });
    progress.finish();
    if let Some(e) = write_error {
        let saved = saved_parts(&dir, &identity, &wanted).map_or(0, |p| p.0.len());
        progress.assembled(
            &opts.output,
            Some(&format!("a run could not be saved: {e}")),
        );
        return Err(CampaignError::Io {
            path: match &e {
                CampaignError::Io { path, .. } => path.clone(),
                _ => dir.clone(),
            },
            reason: format!(
                "{}; the campaign stopped: {saved} of {} runs are saved in {}; free space (or fix \
                 the folder), then finish with --resume",
                match &e {
                    CampaignError::Io { reason, .. } => reason.clone(),
                    other => other.to_string(),
                },
                work.len() + resumed,
                dir.display()
            ),
        });
    }
    let sources = Sources {
        dir: &dir,
        linear: &linear_jobs,
        shared: shared.as_ref(),
        models: &models,
        shares: &shares,
    };
    let assembled = assemble(study, opts, &identity, &jobs, &refs, &sources);
    progress.assembled(&opts.output, assembled.as_ref().err().map(|e| e as _));
    assembled?;
    drop(shared);
    let statuses = read_statuses(&opts.output)?;
    let (ok, untrusted) = count_statuses(&statuses);
    let references_failed = failed_references(&opts.output)?;
    // Every part of this run's jobs was checked (saved_parts) or written by it.
    remove_parts(&dir, &wanted)?;
    Ok(Outcome {
        jobs: jobs.len(),
        ok,
        untrusted,
        failed: jobs.len() - ok - untrusted,
        resumed,
        stale,
        references_failed,
    })
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
        .map(|(k, v)| format!("{k}={}", super::value_text(v)))
        .collect();
    over.push("outputs.modal=true".into());
    let scene = Scene::load(&study.scene_path, &over).map_err(|e| e.to_string())?;
    let r = run_one(&scene, &model);
    if !r.stats.status.completed() {
        return Err(format!("{}: {}", r.stats.status.name(), r.stats.cause));
    }
    Ok(strain_energy_shares(&model, &r))
}

/// How many of `statuses` are ok and how many untrusted.
fn count_statuses(statuses: &[String]) -> (usize, usize) {
    let n = |name: &str| statuses.iter().filter(|s| s.as_str() == name).count();
    (n("ok"), n("untrusted"))
}

fn read_statuses(path: &Path) -> Result<Vec<String>, CampaignError> {
    read_statuses_in(path, "jobs")
}

/// How many reference runs of a results file did not end ok.
fn failed_references(path: &Path) -> Result<usize, CampaignError> {
    Ok(read_statuses_in(path, "references")?
        .iter()
        .filter(|s| !Status::name_completed(s))
        .count())
}

/// Whether two paths name one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => (x.dev(), x.ino()) == (y.dev(), y.ino()),
        _ => false,
    }
}

/// A references file for a shard ([`ReferenceSource::File`]): a rotorsweep results file
/// written by a references-only run of the same study digest, holding every run of `refs`.
fn open_references(
    path: &Path,
    identity: &Identity,
    refs: &[&super::Reference],
) -> Result<hdf5::File, CampaignError> {
    let f = output::open_results_file(path).map_err(|why| InputError::new(path, why))?;
    let shard = store::read_str(&f, "shard").unwrap_or_default();
    if shard != REFERENCES_SHARD {
        return Err(InputError::new(
            path,
            format!(
                "is not a references file (its shard is `{shard}`): write one with \
                 `rotorsweep run STUDY --references-only -o FILE`"
            ),
        )
        .into());
    }
    let digest = store::read_str(&f, "study_digest").unwrap_or_default();
    if digest != identity.digest {
        let inputs = store::read_str(&f, "study_inputs").ok();
        return Err(InputError::new(
            path,
            format!(
                "holds the reference runs of other inputs ({}): compute them again with \
                 --references-only",
                describe_mismatch(identity, &digest, inputs.as_deref())
            ),
        )
        .into());
    }
    let g = f.group("references").map_err(hdf5_at(path))?;
    if let Some(r) = refs.iter().find(|r| !g.link_exists(&r.id)) {
        return Err(InputError::new(path, format!("has no reference run {}", r.id)).into());
    }
    Ok(f)
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

/// A job's runout error against its reference [µm] (physics.md §8): the max and RMS of the
/// difference over the common samples, and the error of the peak amplitude (half the
/// peak-to-peak runout).
#[derive(Clone, Copy)]
struct RunoutError {
    max: f64,
    rms: f64,
    peak: f64,
}

impl RunoutError {
    const NONE: Self = Self {
        max: f64::NAN,
        rms: f64::NAN,
        peak: f64::NAN,
    };
}

/// The runout error per channel and the worst over channels; NaN when nothing compares.
fn errors_against(
    job: &hdf5::Group,
    reference: &hdf5::Group,
) -> (RunoutError, Vec<(String, RunoutError)>) {
    let a = store::runout_channels(job);
    let b = store::runout_channels(reference);
    let half_pp = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(*x), h.max(*x))
            });
        0.5 * (hi - lo)
    };
    let mut per = Vec::new();
    for (name, x) in &a {
        if let Some((_, y)) = b.iter().find(|(n, _)| n == name) {
            let n = x.len().min(y.len());
            if n == 0 {
                continue;
            }
            let d: Vec<f64> = (0..n).map(|i| x[i] - y[i]).collect();
            per.push((
                name.clone(),
                RunoutError {
                    max: d.iter().map(|v| v.abs()).fold(0.0, f64::max),
                    rms: (d.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt(),
                    peak: (half_pp(&x[..n]) - half_pp(&y[..n])).abs(),
                },
            ));
        }
    }
    let worst = |f: fn(&RunoutError) -> f64| per.iter().map(|p| f(&p.1)).fold(f64::NAN, f64::max);
    let all = RunoutError {
        max: worst(|e| e.max),
        rms: worst(|e| e.rms),
        peak: worst(|e| e.peak),
    };
    (all, per)
}

/// A job's model on its linearised supports (`/linear/<linear_id>`): the analyses the study's
/// `[linear]` table asks for (damped modes over its speeds always) in the layout of `rotorsweep
/// linear -o` ([`crate::linear::request::Results::write`], without wall times), and the
/// attribute `model_id`; a failure is stored as the attribute `linear_error`.
fn write_linear(
    g: &hdf5::Group,
    req: &crate::linear::request::Request,
    model_id: &str,
    scene: &Scene,
    m: &Model,
) -> hdf5::Result<()> {
    store::attr_str(g, "model_id", model_id)?;
    let results = LinearSystem::of_scene(scene, m)
        .and_then(|sys| crate::linear::request::compute(req, scene, m, &sys));
    match results {
        Ok(r) => r.write(g, false),
        Err(e) => store::attr_str(g, "linear_error", &e.to_string()),
    }
}

fn write_model(
    group: &hdf5::Group,
    id: &str,
    m: &Model,
    shares: Option<&Vec<f64>>,
) -> hdf5::Result<()> {
    let g = group.create_group(id)?;
    let r = &m.full;
    store::attr_str(&g, "modes", &m.reduced.counts_label())?;
    store::attr_u64(&g, "elements", m.rotor.elements.len() as u64)?;
    store::attr_f64(&g, "mass_kg", m.rotor.mass())?;
    store::dataset(&g, "freq_hz", &r.freq_hz, "Hz")?;
    let idx: Vec<f64> = r.index.iter().map(|&i| i as f64).collect();
    store::dataset(&g, "index", &idx, "1")?;
    store::string_dataset(
        &g,
        "labels",
        &r.labels.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
    )?;
    store::string_dataset(
        &g,
        "kinds",
        &r.kinds.iter().map(|k| k.to_string()).collect::<Vec<_>>(),
    )?;
    if let Some(s) = shares {
        // Shares are per mode of the pilot's set; scatter them onto the full set's indices.
        let mut full = vec![f64::NAN; r.len()];
        for (i, &idx) in m.reduced.index.iter().enumerate() {
            if let (Some(slot), Some(v)) = (full.get_mut(idx), s.get(i)) {
                *slot = *v;
            }
        }
        store::dataset(&g, "strain_energy_share", &full, "1")?;
    }
    Ok(())
}

/// What a run assembles its file from: the saved parts, the jobs whose linearised systems it
/// stores, the shared references file (if any), the models it built and the pruning pilots'
/// shares.
struct Sources<'a> {
    dir: &'a Path,
    linear: &'a [&'a Job],
    shared: Option<&'a hdf5::File>,
    models: &'a BTreeMap<&'a str, Result<Arc<Model>, String>>,
    shares: &'a BTreeMap<String, Vec<f64>>,
}

/// Builds the final file from the part files (module doc), written under a temporary name;
/// shared references, their models and the linearised systems are copied from the references
/// file.
fn assemble(
    study: &Study,
    opts: &RunOptions,
    identity: &Identity,
    jobs: &[&Job],
    refs: &[&super::Reference],
    src: &Sources,
) -> Result<(), CampaignError> {
    let (dir, models, shares) = (src.dir, src.models, src.shares);
    let tmp = store::with_suffix(&opts.output, ".tmp");
    let open_part = |id: &str| {
        let p = dir.join(format!("{id}.h5"));
        hdf5::File::open(&p)
            .map_err(|e| hdf5::Error::from(format!("cannot open {}: {e}", p.display()).as_str()))
    };
    let write = || -> hdf5::Result<()> {
        let f = hdf5::File::create(&tmp)?;
        store::provenance(&f, &opts.command)?;
        store::attr_str(&f, "study_digest", &identity.digest)?;
        store::attr_str(&f, "study_inputs", &identity.inputs_text())?;
        store::attr_u64(&f, "threads", opts.threads as u64)?;
        store::attr_str(&f, "study_name", &study.name)?;
        store::attr_str(&f, "study_path", &study.path.display().to_string())?;
        store::attr_str(&f, "study_text", &study.text)?;
        store::attr_str(&f, "varying_keys", &study.varying.join("\n"))?;
        let (si, sn) = opts.shard.unwrap_or((0, 1));
        let shard = match opts.references {
            ReferenceSource::Only => REFERENCES_SHARD.to_string(),
            _ => format!("{si}/{sn}"),
        };
        store::attr_str(&f, "shard", &shard)?;
        let mg = f.create_group("models")?;
        for (id, m) in models {
            if let Ok(m) = m {
                write_model(&mg, id, m, shares.get(*id))?;
            }
        }
        if let Some(shared) = src.shared {
            // The shared references' models this run did not build (a model that failed to
            // build is absent there too).
            let sm = shared.group("models")?;
            let wanted: BTreeSet<&str> = refs.iter().map(|r| r.model_id.as_str()).collect();
            for id in wanted {
                if !models.contains_key(id) && sm.link_exists(id) {
                    store::copy_object(&sm, id, &mg, id)?;
                }
            }
        }
        // One linearised system per distinct model, supports, drive and gravity; copied when
        // the references file holds it.
        let lg = f.create_group("linear")?;
        let mut linear: BTreeMap<&str, &Job> = BTreeMap::new();
        for j in src.linear {
            linear.entry(j.linear_id.as_str()).or_insert(j);
        }
        let shared_linear = src.shared.map(|s| s.group("linear")).transpose()?;
        for (lid, j) in linear {
            if let Some(sl) = shared_linear.as_ref().filter(|g| g.link_exists(lid)) {
                store::copy_object(sl, lid, &lg, lid)?;
            } else if let Some(Ok(m)) = models.get(j.model_id.as_str()) {
                write_linear(
                    &lg.create_group(lid)?,
                    &study.linear,
                    &j.model_id,
                    &j.scene,
                    m,
                )?;
            }
        }
        let rg = f.create_group("references")?;
        for r in refs {
            match src.shared {
                Some(shared) => {
                    let g = shared.group("references")?;
                    store::copy_object(&g, &r.id, &rg, &r.id)?
                }
                None => {
                    let part = open_part(&r.id)?;
                    store::copy_object(&part, "job", &rg, &r.id)?
                }
            }
        }
        let jg = f.create_group("jobs")?;
        for j in jobs {
            let part = open_part(&j.id)?;
            store::copy_object(&part, "job", &jg, &j.id)?;
            let g = jg.group(&j.id)?;
            let (err, per) = match rg.group(&j.reference_id) {
                Ok(rgp) if study.has_reference => {
                    let status = store::read_str(&rgp, "status").unwrap_or_default();
                    if Status::name_completed(&status) {
                        errors_against(&g, &rgp)
                    } else {
                        let cause = store::read_str(&rgp, "cause").unwrap_or_default();
                        store::attr_str(
                            &g,
                            "error_cause",
                            &format!("reference {status}: {cause}"),
                        )?;
                        (RunoutError::NONE, Vec::new())
                    }
                }
                _ => (RunoutError::NONE, Vec::new()),
            };
            store::attr_str(&g, "reference_id", &j.reference_id)?;
            for (suffix, e) in std::iter::once((String::new(), err))
                .chain(per.into_iter().map(|(n, e)| (format!(":{n}"), e)))
            {
                store::attr_f64(&g, &format!("error_max_um{suffix}"), e.max)?;
                store::attr_f64(&g, &format!("error_rms_um{suffix}"), e.rms)?;
                store::attr_f64(&g, &format!("error_peak_um{suffix}"), e.peak)?;
            }
        }
        analyse_or_note(&f, &opts.output);
        write_summary(&f, &study.varying)?;
        f.flush()?;
        f.close()
    };
    finish_output(&tmp, &opts.output, write())
}

/// Ends the writing of an output: on success the temporary file is renamed over the output
/// (checked again: only a results file is ever replaced); on failure it is removed and the
/// error names it with its cause.
fn finish_output(tmp: &Path, out: &Path, written: hdf5::Result<()>) -> Result<(), CampaignError> {
    if let Err(e) = written {
        let reason = describe_hdf5(tmp, &e);
        let _ = std::fs::remove_file(tmp);
        return Err(CampaignError::io(tmp, reason));
    }
    if let Err(why) = output::verify_written(tmp) {
        let _ = std::fs::remove_file(tmp);
        let dir = tmp
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let free = free_bytes(dir).map_or(String::new(), |b| {
            format!("; {b} bytes free in {}", dir.display())
        });
        return Err(CampaignError::io(
            tmp,
            format!("{why}: the write failed (disk full or a file-size limit?){free}"),
        ));
    }
    if let Err(e) = output::check_replace(out, true) {
        let _ = std::fs::remove_file(tmp);
        return Err(e.into());
    }
    std::fs::rename(tmp, out).map_err(|e| CampaignError::io(out, e))
}

/// Analyses the file being assembled (`post`); a failure there costs the analysis, not the
/// finished jobs: it is printed and kept as the file's `analysis_error` attribute.
fn analyse_or_note(f: &hdf5::File, out: &Path) {
    if let Err(e) = crate::results::analyse::analyse(f) {
        let msg = format!("analysing {}: {e}", out.display());
        eprintln!("warning: {msg}");
        if let Err(e2) = store::attr_str(f, "analysis_error", &msg) {
            eprintln!("warning: {}: cannot note it either: {e2}", out.display());
        }
    }
}

/// The statistics every summary row carries, in order: (name, units, is a count).
const STAT_COLUMNS: [(&str, &str, bool); 14] = [
    ("cpu_time_s", "s", false),
    ("wall_time_s", "s", false),
    ("steps", "1", true),
    ("rejected_steps", "1", true),
    ("newton_iterations", "1", true),
    ("iterations_per_step", "1", false),
    ("jacobian_evals", "1", true),
    ("rhs_evals", "1", true),
    ("factorizations", "1", true),
    ("events", "1", true),
    ("t_end_s", "s", false),
    ("error_max_um", "um", false),
    ("error_rms_um", "um", false),
    ("error_peak_um", "um", false),
];

/// (Re)writes `/summary` from the job groups' attributes, ordered by job index: text columns
/// (job_id, status, cause, error_cause, integrator, modes, label), job_index as a count, every
/// varying key as its own column (numbers where every value is a number, else each value's
/// full text; table-valued parameters as their canonical TOML), then the statistics (counts
/// as integers), each with its units (`store::table`).
pub fn write_summary(f: &hdf5::File, varying: &[String]) -> hdf5::Result<()> {
    if let Ok(old) = f.dataset("summary") {
        drop(old);
        f.unlink("summary")?;
    }
    let jobs = f.group("jobs")?;
    let mut rows: Vec<(f64, hdf5::Group, String)> = Vec::new();
    for name in jobs.member_names()? {
        let g = jobs.group(&name)?;
        let idx = store::read_num(&g, "job_index").unwrap_or(f64::NAN);
        rows.push((idx, g, name));
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let text = |name: &str| {
        Column::text(
            name,
            rows.iter()
                .map(|r| store::read_str(&r.1, name).unwrap_or_default())
                .collect(),
        )
    };
    let mut cols = vec![
        Column::text("job_id", rows.iter().map(|r| r.2.clone()).collect()),
        Column::count(
            "job_index",
            rows.iter()
                .map(|r| {
                    if r.0.is_finite() {
                        r.0 as u64
                    } else {
                        u64::MAX
                    }
                })
                .collect(),
        ),
        text("status"),
        text("cause"),
        text("error_cause"),
        text("integrator"),
        text("modes"),
        text("label"),
    ];
    for key in varying {
        if key == "solver.integrator" {
            continue;
        }
        let vals: Vec<Option<Param>> = rows
            .iter()
            .map(|r| store::read_param(&r.1, key).ok())
            .collect();
        if vals.iter().flatten().all(|v| matches!(v, Param::Number(_))) {
            cols.push(Column::number(
                key,
                units_of_key(key),
                vals.iter()
                    .map(|v| match v {
                        Some(Param::Number(x)) => *x,
                        _ => f64::NAN,
                    })
                    .collect(),
            ));
        } else {
            cols.push(Column::text(
                key,
                vals.iter()
                    .map(|v| v.as_ref().map(Param::to_string).unwrap_or_default())
                    .collect(),
            ));
        }
    }
    for (key, units, count) in STAT_COLUMNS {
        let v = rows
            .iter()
            .map(|r| store::read_num(&r.1, key).unwrap_or(f64::NAN));
        cols.push(if count {
            Column::count(key, v.map(|x| x as u64).collect())
        } else {
            Column::number(key, units, v.collect())
        });
    }
    store::compound_table(f, "summary", &cols)
}

/// How to merge shard files.
#[derive(Debug, Clone, Default)]
pub struct MergeOptions {
    /// Replace an existing output (only a rotorsweep results file).
    pub overwrite: bool,
    /// Merge an incomplete set of shards (the merged file records it).
    pub partial: bool,
}

/// What a merge did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MergeOutcome {
    /// Jobs in the merged file.
    pub jobs: usize,
    /// The shards it holds, `i/n`.
    pub shards: Vec<String>,
    /// The shards of the split it lacks (only with `partial`).
    pub missing: Vec<String>,
}

/// The shards a results file holds: its `shard` attribute, `i/n` or a comma-separated list.
fn parse_shards(text: &str) -> Option<Vec<(usize, usize)>> {
    text.split(',')
        .map(|s| {
            let (i, n) = s.trim().split_once('/')?;
            let (i, n): (usize, usize) = (i.parse().ok()?, n.parse().ok()?);
            (n > 0 && i < n).then_some((i, n))
        })
        .collect()
}

/// Joins shard files of one study: jobs, references and models (each once), file attributes of
/// the first file, and a new summary. The inputs must be distinct rotorsweep results files of
/// the same study digest and of one split into n shards, all of them unless `partial`; the
/// merged file's `shard` attribute lists the shards it holds, and `partial` (0/1) says
/// whether that is fewer than the split has.
pub fn merge(
    inputs: &[PathBuf],
    output: &Path,
    opts: &MergeOptions,
) -> Result<MergeOutcome, CampaignError> {
    use std::os::unix::fs::MetadataExt;
    if inputs.is_empty() {
        return Err(CampaignError::Usage(
            "merge needs at least one input file".into(),
        ));
    }
    let _lock = OutputLock::acquire(output)?;
    // Distinct regular results files, none of them the output.
    let out_inode = std::fs::metadata(output).ok().map(|m| (m.dev(), m.ino()));
    let mut seen: BTreeMap<(u64, u64), &PathBuf> = BTreeMap::new();
    for p in inputs {
        let m = std::fs::metadata(p)
            .map_err(|e| InputError::new(p, format!("cannot read this input: {e}")))?;
        if !m.is_file() {
            return Err(InputError::new(p, "is not a regular file").into());
        }
        let key = (m.dev(), m.ino());
        if let Some(first) = seen.insert(key, p) {
            return Err(CampaignError::Usage(format!(
                "{} is given twice (also as {}): each shard once",
                p.display(),
                first.display()
            )));
        }
        if Some(key) == out_inode {
            return Err(CampaignError::Usage(format!(
                "{}: is the output too; merge into a new file",
                p.display()
            )));
        }
        output::is_results_file(p).map_err(|why| InputError::new(p, why))?;
    }
    output::check_replace(output, opts.overwrite)?;
    output::check_working_file(&store::with_suffix(output, ".tmp"))?;
    // One study digest and one split.
    let mut shards: BTreeMap<(usize, usize), &PathBuf> = BTreeMap::new();
    let (digest0, inputs0, _) = stored_identity(&inputs[0])?;
    for p in inputs {
        let (digest, inputs_text, shard) = stored_identity(p)?;
        if digest.is_empty() {
            return Err(InputError::new(
                p,
                "has no study digest: not a study's results file (a `simulate` or `linear` \
                 file?), or written by an older rotorsweep (run its shard again)",
            )
            .into());
        }
        if digest != digest0 {
            let mine = Identity::parse_inputs(inputs_text.as_deref().unwrap_or_default());
            let theirs = Identity::parse_inputs(inputs0.as_deref().unwrap_or_default());
            let first_only = format!("read only by {}", inputs[0].display());
            let what = compare(&mine, &theirs, ["differs", "read only by it", &first_only]);
            return Err(InputError::new(
                p,
                format!(
                    "comes from other inputs than {} ({})",
                    inputs[0].display(),
                    if what.is_empty() {
                        "its study digest differs".into()
                    } else {
                        what.join(", ")
                    }
                ),
            )
            .into());
        }
        if shard == REFERENCES_SHARD {
            return Err(InputError::new(
                p,
                "is a references file (run --references-only), not a shard: merge the shard files",
            )
            .into());
        }
        let list = parse_shards(&shard).ok_or_else(|| {
            CampaignError::Usage(format!(
                "{}: its shard attribute `{shard}` is not i/n",
                p.display()
            ))
        })?;
        for s in list {
            if let Some(other) = shards.insert(s, p) {
                return Err(CampaignError::Usage(format!(
                    "shard {}/{} is in both {} and {}",
                    s.0,
                    s.1,
                    other.display(),
                    p.display()
                )));
            }
        }
    }
    let splits: BTreeSet<usize> = shards.keys().map(|s| s.1).collect();
    if splits.len() > 1 {
        let list: Vec<String> = shards
            .iter()
            .map(|(s, p)| format!("{} is shard {}/{}", p.display(), s.0, s.1))
            .collect();
        return Err(InputError::new(
            &inputs[0],
            format!("the inputs come from different splits: {}", list.join(", ")),
        )
        .into());
    }
    let n = *splits.iter().next().expect("at least one input");
    let missing: Vec<String> = (0..n)
        .filter(|i| !shards.contains_key(&(*i, n)))
        .map(|i| format!("{i}/{n}"))
        .collect();
    if !missing.is_empty() && !opts.partial {
        return Err(CampaignError::Usage(format!(
            "shards missing: {} (of {n}); add them, or --partial to merge without them",
            missing.join(", ")
        )));
    }
    let present: Vec<String> = shards.keys().map(|(i, n)| format!("{i}/{n}")).collect();
    let tmp = store::with_suffix(output, ".tmp");
    let mut jobs_n = 0;
    let mut write = || -> hdf5::Result<()> {
        let first = hdf5::File::open(&inputs[0])?;
        let f = hdf5::File::create(&tmp)?;
        let keys = store::varying_keys(&first);
        for name in first.attr_names()? {
            if matches!(
                name.as_str(),
                "shard" | "threads" | "partial" | "merged_from"
            ) {
                continue;
            }
            store::attr_str(
                &f,
                &name,
                &store::read_str(&first, &name).unwrap_or_default(),
            )?;
        }
        store::attr_str(&f, "shard", &present.join(","))?;
        store::attr_u64(&f, "partial", u64::from(!missing.is_empty()))?;
        let sources: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
        store::attr_str(&f, "merged_from", &sources.join("\n"))?;
        for group in ["models", "linear", "references", "jobs"] {
            let dst = f.create_group(group)?;
            let mut seen = BTreeSet::new();
            for p in inputs {
                let src = hdf5::File::open(p)?;
                // Files from before /linear existed have none to copy.
                let Ok(sg) = src.group(group) else { continue };
                for name in sg.member_names()? {
                    if seen.insert(name.clone()) {
                        store::copy_object(&sg, &name, &dst, &name).map_err(|e| {
                            hdf5::Error::from(format!("{}: {e}", p.display()).as_str())
                        })?;
                    }
                }
            }
            if group == "jobs" {
                jobs_n = seen.len();
            }
        }
        analyse_or_note(&f, output);
        write_summary(&f, &keys)?;
        f.flush()?;
        f.close()
    };
    let written = write();
    finish_output(&tmp, output, written)?;
    Ok(MergeOutcome {
        jobs: jobs_n,
        shards: present,
        missing,
    })
}
