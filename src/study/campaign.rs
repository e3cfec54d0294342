//! Running a study: shared models, pruning pilots, reference runs and jobs on a thread pool, each
//! finished job saved at once, then one HDF5 file assembled.
//!
//! In: a [`Study`] and [`RunOptions`] (output path, threads, resume, shard).
//! Out: `OUT.h5` in the layout of `store` plus `/models/<id>`, `/references/<id>` and the
//! `summary` table, and an [`Outcome`] (counts). Every finished job is first written to its own
//! file `OUT.h5.parts/<id>.h5` (written under a temporary name, then renamed), so a `kill -9`
//! at any moment loses only the jobs that were running; `--resume` skips the saved ones and
//! assembles again. Each job runs on one thread; results do not depend on the thread count.
//! A job that panics, diverges or exhausts its budget is a result with its status and cause.

use std::collections::{BTreeMap, BTreeSet};
use std::io::IsTerminal;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc};

use rayon::prelude::*;

use super::{Job, Study};
use crate::dynamics::linear::{campbell, LinearSystem};
use crate::integrators::{Stats, Status};
use crate::job::{self, JobResult};
use crate::model::Model;
use crate::reduction::{ModeKind, ModeSelection};
use crate::scene::Scene;
use crate::store::{self, Column, Param};

/// How to run a study.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The results file.
    pub output: PathBuf,
    /// Worker threads.
    pub threads: usize,
    /// Continue from the saved jobs of an interrupted run.
    pub resume: bool,
    /// Run only shard i of n.
    pub shard: Option<(usize, usize)>,
    /// The command line, stored in the file.
    pub command: String,
}

/// What a campaign did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// Jobs in this run (shard).
    pub jobs: usize,
    /// Jobs that ended ok.
    pub ok: usize,
    /// Jobs that ended otherwise.
    pub failed: usize,
    /// Jobs found already done (resume).
    pub resumed: usize,
}

/// Why a campaign could not run (bad files or I/O; failing jobs are results, not errors).
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// HDF5 failure.
    #[error("HDF5: {0}")]
    Hdf5(#[from] hdf5::Error),
    /// File-system failure.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A usage problem.
    #[error("{0}")]
    Usage(String),
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
    match catch_unwind(AssertUnwindSafe(|| job::run(scene, model))) {
        Ok(r) => r,
        Err(e) => {
            let msg = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
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

/// Writes one finished job to its own part file, atomically.
fn save_part(dir: &Path, w: &Work, r: &JobResult, integrator: &str) -> Result<(), CampaignError> {
    let tmp = dir.join(format!("{}.h5.tmp", w.id));
    let fin = dir.join(format!("{}.h5", w.id));
    {
        let f = hdf5::File::create(&tmp)?;
        let mut params = w.params.clone();
        params.push(("model_id".into(), Param::Text(w.model_id.to_string())));
        if let Some(l) = w.linear_id {
            params.push(("linear_id".into(), Param::Text(l.to_string())));
        }
        // The spin speed over the record and the roll angle's offset from Ω·t, for the
        // spectral analysis (NaN when the speed changes while recording).
        let sim = &w.scene.simulation;
        let (speed, offset) = w
            .scene
            .speed
            .constant_over(sim.settle, sim.t_end)
            .map_or((f64::NAN, f64::NAN), |(omega, d)| {
                (omega / std::f64::consts::TAU, d)
            });
        params.push(("speed_hz".into(), Param::Number(speed)));
        params.push(("roll_angle_offset_rad".into(), Param::Number(offset)));
        if let Some(p) = w.prune {
            params.push((super::PRUNE_KEY.into(), Param::Number(p)));
        }
        match w.kind {
            Kind::Job(i) => {
                params.push(("job_index".into(), Param::Number(i as f64)));
                params.push(("kind".into(), Param::Text("job".into())));
            }
            Kind::Reference => params.push(("kind".into(), Param::Text("reference".into()))),
        }
        store::write_job(&f, "job", &params, integrator, r)?;
        f.close()?;
    }
    std::fs::rename(&tmp, &fin)?;
    Ok(())
}

fn done_ids(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter_map(|e| {
                    let name = e.file_name().to_string_lossy().into_owned();
                    name.strip_suffix(".h5").map(|s| s.to_string())
                })
                .collect()
        })
        .unwrap_or_default()
}

/// Runs a study (module doc).
pub fn run(study: &Study, opts: &RunOptions) -> Result<Outcome, CampaignError> {
    let dir = parts_dir(&opts.output);
    let (si, sn) = opts.shard.unwrap_or((0, 1));
    if opts.resume && opts.output.exists() && !dir.exists() {
        // Already assembled: nothing left to run.
        let n = study.shard(si, sn).len();
        let statuses = read_statuses(&opts.output)?;
        let ok = statuses.iter().filter(|s| s.as_str() == "ok").count();
        return Ok(Outcome {
            jobs: n,
            ok,
            failed: n - ok,
            resumed: n,
        });
    }
    if dir.exists() && !opts.resume {
        return Err(CampaignError::Usage(format!(
            "{} exists (an interrupted run?): add --resume to finish it, or remove it",
            dir.display()
        )));
    }
    if opts.output.exists() && !opts.resume {
        return Err(CampaignError::Usage(format!(
            "{} exists: choose another -o or remove it",
            opts.output.display()
        )));
    }
    std::fs::create_dir_all(&dir)?;
    let jobs: Vec<&Job> = study.shard(si, sn);
    let refs: Vec<&super::Reference> = if study.has_reference {
        let needed: BTreeSet<&str> = jobs.iter().map(|j| j.reference_id.as_str()).collect();
        study
            .references
            .iter()
            .filter(|r| needed.contains(r.id.as_str()))
            .collect()
    } else {
        Vec::new()
    };
    let done = done_ids(&dir);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.max(1))
        .build()
        .map_err(|e| CampaignError::Usage(e.to_string()))?;
    // 1. Distinct models, built once each.
    let mut model_scenes: BTreeMap<&str, &Scene> = BTreeMap::new();
    for j in &jobs {
        model_scenes.entry(j.model_id.as_str()).or_insert(&j.scene);
    }
    for r in &refs {
        model_scenes.entry(r.model_id.as_str()).or_insert(&r.scene);
    }
    let built: Vec<(&str, Result<Arc<Model>, String>)> = pool.install(|| {
        model_scenes
            .par_iter()
            .map(|(id, sc)| {
                (
                    *id,
                    Model::build(sc, None)
                        .map(Arc::new)
                        .map_err(|e| e.to_string()),
                )
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
    // 3. The work list: references, then jobs; saved ones skipped.
    let mut work: Vec<Work> = Vec::new();
    for r in &refs {
        work.push(Work {
            id: r.id.clone(),
            kind: Kind::Reference,
            scene: &r.scene,
            model_id: &r.model_id,
            linear_id: None,
            prune: None,
            params: params_of(&r.overrides),
        });
    }
    for j in &jobs {
        let mut params = params_of(&j.overrides);
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
        });
    }
    let resumed = jobs.iter().filter(|j| done.contains(&j.id)).count();
    work.retain(|w| !done.contains(&w.id));
    let total = work.len();
    let progress = Progress::new(total as u64);
    let (tx, rx) = mpsc::channel::<(usize, JobResult)>();
    let mut write_error: Option<CampaignError> = None;
    std::thread::scope(|scope| {
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
            let ok = r.stats.status == Status::Ok;
            if let Err(e) = save_part(&dir, w, &r, w.scene.solver.integrator.name()) {
                write_error.get_or_insert(e);
            }
            progress.job_done(&w.id, &r, ok);
        }
    });
    progress.finish();
    if let Some(e) = write_error {
        return Err(e);
    }
    assemble(study, opts, &dir, &jobs, &refs, &models, &shares)?;
    let statuses = read_statuses(&opts.output)?;
    let ok = statuses.iter().filter(|s| s.as_str() == "ok").count();
    std::fs::remove_dir_all(&dir)?;
    Ok(Outcome {
        jobs: jobs.len(),
        ok,
        failed: jobs.len() - ok,
        resumed,
    })
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
    let text = std::fs::read_to_string(&study.scene_path).map_err(|e| e.to_string())?;
    let scene = Scene::from_text(&study.scene_path, &text, &over).map_err(|e| e.to_string())?;
    let r = run_one(&scene, &model);
    if r.stats.status != Status::Ok {
        return Err(format!("{}: {}", r.stats.status.name(), r.stats.cause));
    }
    Ok(strain_energy_shares(&model, &r))
}

fn read_statuses(path: &Path) -> Result<Vec<String>, CampaignError> {
    let f = hdf5::File::open(path)?;
    let jobs = f.group("jobs")?;
    let mut out = Vec::new();
    for name in jobs.member_names()? {
        let g = jobs.group(&name)?;
        out.push(store::read_str(&g, "status")?);
    }
    Ok(out)
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

/// Campbell data of each linearised system: spin speeds 0 … this [Hz] (the `modes` command's
/// default range), in this many steps.
const CAMPBELL_MAX_HZ: f64 = 100.0;
const CAMPBELL_SPEEDS: usize = 201;

/// A job's model on its linearised supports (`/linear/<linear_id>`): `campbell/speed_hz` [Hz],
/// `campbell/whirl_hz` [speeds × branches, Hz], `critical_speeds_hz`, and as attributes the
/// `model_id` and the first bending frequencies at standstill (`vertical_hz`, `horizontal_hz`);
/// a failure is stored as the attribute `linear_error`.
fn write_linear(g: &hdf5::Group, model_id: &str, scene: &Scene, m: &Model) -> hdf5::Result<()> {
    store::attr_str(g, "model_id", model_id)?;
    let sys = match LinearSystem::of_scene(scene, m) {
        Ok(s) => s,
        Err(e) => return store::attr_str(g, "linear_error", &e.to_string()),
    };
    let standstill = sys.standstill_modes().unwrap_or_default();
    let first = |k: ModeKind| -> f64 {
        standstill
            .iter()
            .find(|x| x.kind == k && x.freq_hz > 1e-6)
            .map_or(f64::NAN, |x| x.freq_hz)
    };
    store::attr_f64(g, "vertical_hz", first(ModeKind::BendingY))?;
    store::attr_f64(g, "horizontal_hz", first(ModeKind::BendingX))?;
    match campbell(&sys, CAMPBELL_MAX_HZ, CAMPBELL_SPEEDS) {
        Ok(c) => {
            store::dataset(g, "campbell/speed_hz", &c.speeds_hz, "Hz")?;
            let branches = c.whirl_hz.iter().map(Vec::len).min().unwrap_or(0);
            let flat: Vec<f64> = c
                .whirl_hz
                .iter()
                .flat_map(|w| w[..branches].iter().copied())
                .collect();
            store::dataset_2d(
                g,
                "campbell/whirl_hz",
                (c.speeds_hz.len(), branches),
                &flat,
                "Hz",
            )?;
            store::dataset(g, "critical_speeds_hz", &c.critical_hz, "Hz")
        }
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

/// Builds the final file from the part files (module doc), written under a temporary name.
#[allow(clippy::too_many_arguments)]
fn assemble(
    study: &Study,
    opts: &RunOptions,
    dir: &Path,
    jobs: &[&Job],
    refs: &[&super::Reference],
    models: &BTreeMap<&str, Result<Arc<Model>, String>>,
    shares: &BTreeMap<String, Vec<f64>>,
) -> Result<(), CampaignError> {
    let tmp = store::with_suffix(&opts.output, ".tmp");
    {
        let f = hdf5::File::create(&tmp)?;
        store::provenance(&f, &opts.command)?;
        store::attr_u64(&f, "threads", opts.threads as u64)?;
        store::attr_str(&f, "study_name", &study.name)?;
        store::attr_str(&f, "study_path", &study.path.display().to_string())?;
        store::attr_str(&f, "study_text", &study.text)?;
        store::attr_str(&f, "varying_keys", &study.varying.join("\n"))?;
        let (si, sn) = opts.shard.unwrap_or((0, 1));
        store::attr_str(&f, "shard", &format!("{si}/{sn}"))?;
        let mg = f.create_group("models")?;
        for (id, m) in models {
            if let Ok(m) = m {
                write_model(&mg, id, m, shares.get(*id))?;
            }
        }
        // One linearised system per distinct model, supports, drive and gravity.
        let lg = f.create_group("linear")?;
        let mut linear: BTreeMap<&str, &Job> = BTreeMap::new();
        for j in jobs {
            linear.entry(j.linear_id.as_str()).or_insert(j);
        }
        for (lid, j) in linear {
            if let Some(Ok(m)) = models.get(j.model_id.as_str()) {
                write_linear(&lg.create_group(lid)?, &j.model_id, &j.scene, m)?;
            }
        }
        let rg = f.create_group("references")?;
        for r in refs {
            let part = hdf5::File::open(dir.join(format!("{}.h5", r.id)))?;
            store::copy_object(&part, "job", &rg, &r.id)?;
        }
        let jg = f.create_group("jobs")?;
        for j in jobs {
            let part = hdf5::File::open(dir.join(format!("{}.h5", j.id)))?;
            store::copy_object(&part, "job", &jg, &j.id)?;
            let g = jg.group(&j.id)?;
            let (err, per) = match rg.group(&j.reference_id) {
                Ok(rgp) if study.has_reference => {
                    let status = store::read_str(&rgp, "status").unwrap_or_default();
                    if status == "ok" {
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
        f.close()?;
    }
    std::fs::rename(&tmp, &opts.output)?;
    Ok(())
}

/// Analyses the file being assembled (`post`); a failure there costs the analysis, not the
/// finished jobs: it is printed and kept as the file's `analysis_error` attribute.
fn analyse_or_note(f: &hdf5::File, out: &Path) {
    if let Err(e) = super::post::analyse(f) {
        let msg = format!("analysing {}: {e}", out.display());
        eprintln!("warning: {msg}");
        if let Err(e2) = store::attr_str(f, "analysis_error", &msg) {
            eprintln!("warning: {}: cannot note it either: {e2}", out.display());
        }
    }
}

/// The numeric statistics every summary row carries, in order.
const STAT_COLUMNS: [&str; 12] = [
    "cpu_time_s",
    "wall_time_s",
    "steps",
    "rejected_steps",
    "newton_iterations",
    "iterations_per_step",
    "jacobian_evals",
    "rhs_evals",
    "t_end_s",
    "error_max_um",
    "error_rms_um",
    "error_peak_um",
];

/// (Re)writes `/summary` from the job groups' attributes, ordered by job index.
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
    let text = |name: &str, w: usize, get: &dyn Fn(&hdf5::Group) -> String| {
        Column::Text(
            name.to_string(),
            w,
            rows.iter().map(|r| get(&r.1)).collect(),
        )
    };
    let mut cols = vec![
        text("job_id", 17, &|g| {
            g.name().rsplit('/').next().unwrap_or("").to_string()
        }),
        Column::Number("job_index".into(), rows.iter().map(|r| r.0).collect()),
        text("status", 8, &|g| {
            store::read_str(g, "status").unwrap_or_default()
        }),
        text("cause", 96, &|g| {
            store::read_str(g, "cause").unwrap_or_default()
        }),
        text("integrator", 12, &|g| {
            store::read_str(g, "integrator").unwrap_or_default()
        }),
        text("modes", 32, &|g| {
            store::read_str(g, "modes").unwrap_or_default()
        }),
        text("label", 128, &|g| {
            store::read_str(g, "label").unwrap_or_default()
        }),
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
            cols.push(Column::Number(
                key.clone(),
                vals.iter()
                    .map(|v| match v {
                        Some(Param::Number(x)) => *x,
                        _ => f64::NAN,
                    })
                    .collect(),
            ));
        } else {
            cols.push(Column::Text(
                key.clone(),
                32,
                vals.iter()
                    .map(|v| v.as_ref().map(Param::to_string).unwrap_or_default())
                    .collect(),
            ));
        }
    }
    for key in STAT_COLUMNS {
        cols.push(Column::Number(
            key.to_string(),
            rows.iter()
                .map(|r| store::read_num(&r.1, key).unwrap_or(f64::NAN))
                .collect(),
        ));
    }
    store::compound_table(f, "summary", &cols)
}

/// Progress: an indicatif bar on a terminal, plain lines otherwise.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    total: u64,
    done: std::cell::Cell<u64>,
    failed: std::cell::Cell<u64>,
}

impl Progress {
    fn new(total: u64) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = indicatif::ProgressBar::new(total);
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} jobs, {msg} failed, {elapsed} elapsed, ETA {eta}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            b.set_message("0");
            b
        });
        Self {
            bar,
            total,
            done: 0.into(),
            failed: 0.into(),
        }
    }

    fn job_done(&self, id: &str, r: &JobResult, ok: bool) {
        self.done.set(self.done.get() + 1);
        if !ok {
            self.failed.set(self.failed.get() + 1);
        }
        match &self.bar {
            Some(b) => {
                b.inc(1);
                b.set_message(self.failed.get().to_string());
            }
            None => eprintln!(
                "[{}/{}] {id} {} cpu {:.3} s{}",
                self.done.get(),
                self.total,
                r.stats.status.name(),
                r.stats.cpu_time_s,
                if r.stats.cause.is_empty() {
                    String::new()
                } else {
                    format!(": {}", r.stats.cause)
                }
            ),
        }
    }

    fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish();
        }
    }
}

/// Joins shard files of one study: jobs, references and models (each once), file attributes of
/// the first file, and a new summary. Returns the number of jobs.
pub fn merge(inputs: &[PathBuf], output: &Path) -> Result<usize, CampaignError> {
    let tmp = store::with_suffix(output, ".tmp");
    let mut jobs_n = 0;
    {
        let open = |p: &PathBuf| {
            hdf5::File::open(p).map_err(|e| CampaignError::Usage(format!("{}: {e}", p.display())))
        };
        let first = open(&inputs[0])?;
        let study_text = store::read_str(&first, "study_text").unwrap_or_default();
        for p in &inputs[1..] {
            let other = open(p)?;
            if store::read_str(&other, "study_text").unwrap_or_default() != study_text {
                return Err(CampaignError::Usage(format!(
                    "{} comes from another study than {} (study_text differs)",
                    p.display(),
                    inputs[0].display()
                )));
            }
        }
        let f = hdf5::File::create(&tmp)?;
        let keys = store::varying_keys(&first);
        for name in first.attr_names()? {
            if name == "shard" || name == "threads" {
                continue;
            }
            store::attr_str(
                &f,
                &name,
                &store::read_str(&first, &name).unwrap_or_default(),
            )?;
        }
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
                        store::copy_object(&sg, &name, &dst, &name)?;
                    }
                }
            }
            if group == "jobs" {
                jobs_n = seen.len();
            }
        }
        analyse_or_note(&f, output);
        write_summary(&f, &keys)?;
        f.close()?;
    }
    std::fs::rename(&tmp, output)?;
    Ok(jobs_n)
}
