//! A calibration's evaluations: batches of parameter points run as studies through the campaign
//! engine, each point's target outputs read back.
//!
//! In: a [`Calibration`], the evaluations folder (`OUT.h5.evaluations/`), threads, and batches
//! of points in the fit's coordinates ([`Point`]: log₁₀ of the value on a log scale). Out: per
//! point its residuals √w (model − measured)/σ per target row, and an [`Evaluation`] record
//! each (values in the keys' units, the model's output per row, cost, role, batch file, job
//! ids and whether every job ended ok).
//!
//! Method: the points of a batch not evaluated before (a point is known by the text of its
//! values) become one more `[[axes]]` of the base study — every parameter's keys zipped, one
//! row per point, labelled `eval <n>` — so each point runs every job of the study; the base
//! study's explicit `[[jobs]]` are written once per point, with the point's values added,
//! after the axes' jobs (with no axes, the explicit jobs alone and no axis). The study is
//! written as `batch-NNN.toml` beside its results `batch-NNN.h5` (its scene named by absolute
//! path) and run with `study::run` (resume on): the jobs run in parallel, are saved as they
//! finish, and a calibration run again replays its batches from the saved files — the fit is a
//! function of the evaluations, so it asks for the same points in the same batches and only
//! the missing jobs run. The outputs are the statistics table's (`report::tables::outputs`);
//! a measured record's rows are the job's order amplitudes at the record's speeds
//! (`calibration::record`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::file::Calibration;
use super::record;
use crate::numerics::least_squares::{Evaluate, Point};
use crate::report::tables::outputs::{job_outputs, Outputs};
use crate::store;
use crate::study::run::{self as campaign, CampaignError, ReferenceSource, RunOptions};
use crate::study::Study;

/// One evaluated point.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Parameter values [keys' units].
    pub values: Vec<f64>,
    /// The model's output per target row (NaN where a job gave none).
    pub outputs: Vec<f64>,
    /// ½ Σ residual².
    pub cost: f64,
    /// Why it was evaluated (`start`, `jacobian:<k>`, `step`).
    pub role: String,
    /// The fit iteration.
    pub iteration: usize,
    /// The batch's results file name.
    pub batch: String,
    /// Its jobs' ids, in the base study's job order.
    pub job_ids: Vec<String>,
    /// Whether every job ended ok.
    pub ok: bool,
}

/// Runs batches of points (module doc).
pub struct Evaluator<'a> {
    cal: &'a Calibration,
    dir: PathBuf,
    threads: usize,
    command: String,
    base: toml::Table,
    batches: usize,
    known: BTreeMap<String, usize>,
    /// Every evaluation, in order.
    pub evaluations: Vec<Evaluation>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator writing into `dir` (created).
    pub fn new(
        cal: &'a Calibration,
        dir: &Path,
        threads: usize,
        command: &str,
    ) -> Result<Self, CampaignError> {
        std::fs::create_dir_all(dir).map_err(|e| CampaignError::io(dir, e))?;
        let study = &cal.study;
        let mut base: toml::Table = toml::from_str(&study.text).map_err(|e| {
            CampaignError::io(&study.path, format!("cannot parse the study again: {e}"))
        })?;
        let scene = std::path::absolute(&study.scene_path)
            .map_err(|e| CampaignError::io(&study.scene_path, e))?;
        base.insert(
            "scene".into(),
            toml::Value::String(scene.to_string_lossy().into_owned()),
        );
        Ok(Self {
            cal,
            dir: dir.to_path_buf(),
            threads,
            command: command.to_string(),
            base,
            batches: 0,
            known: BTreeMap::new(),
            evaluations: Vec::new(),
        })
    }

    /// The parameter values of fit coordinates.
    pub fn values(&self, x: &[f64]) -> Vec<f64> {
        self.cal
            .parameters
            .iter()
            .zip(x)
            .map(|(p, u)| p.scale.to_value(*u))
            .collect()
    }

    /// The index of the evaluation of fit coordinates `x`, if evaluated.
    pub fn find(&self, x: &[f64]) -> Option<usize> {
        self.known.get(&point_key(&self.values(x))).copied()
    }

    /// Residuals of an evaluation.
    pub fn residuals(&self, e: &Evaluation) -> Vec<f64> {
        self.cal
            .rows
            .iter()
            .zip(&e.outputs)
            .map(|(r, m)| r.weight.sqrt() * (m - r.value) / r.std)
            .collect()
    }

    /// Runs one batch of new points; returns nothing when every point is known.
    fn run_batch(&mut self, points: &[Point]) -> Result<(), CampaignError> {
        let mut new: Vec<(Vec<f64>, &Point)> = Vec::new();
        for p in points {
            let v = self.values(&p.x);
            let k = point_key(&v);
            if !self.known.contains_key(&k) && !new.iter().any(|(w, _)| point_key(w) == k) {
                new.push((v, p));
            }
        }
        if new.is_empty() {
            return Ok(());
        }
        let name = format!("batch-{:03}", self.batches);
        self.batches += 1;
        let first = self.evaluations.len();
        let keys: Vec<String> = self
            .cal
            .parameters
            .iter()
            .flat_map(|p| p.keys.iter().cloned())
            .collect();
        let rows: Vec<toml::Value> = new
            .iter()
            .map(|(v, _)| {
                let row: Vec<toml::Value> = self
                    .cal
                    .parameters
                    .iter()
                    .zip(v)
                    .flat_map(|(p, x)| p.keys.iter().map(move |_| toml::Value::Float(*x)))
                    .collect();
                if row.len() == 1 {
                    row[0].clone()
                } else {
                    toml::Value::Array(row)
                }
            })
            .collect();
        let labels: Vec<toml::Value> = (0..new.len())
            .map(|i| toml::Value::String(format!("eval {}", first + i)))
            .collect();
        let mut axis = toml::Table::new();
        if keys.len() == 1 {
            axis.insert("key".into(), toml::Value::String(keys[0].clone()));
        } else {
            axis.insert(
                "keys".into(),
                toml::Value::Array(keys.iter().cloned().map(toml::Value::String).collect()),
            );
        }
        axis.insert("values".into(), toml::Value::Array(rows));
        axis.insert("labels".into(), toml::Value::Array(labels));
        let mut t = self.base.clone();
        t.insert(
            "name".into(),
            toml::Value::String(format!("{} {name}", self.cal.name)),
        );
        let explicit = explicit_jobs(&mut t);
        match t.get_mut("axes") {
            Some(toml::Value::Array(a)) => a.push(toml::Value::Table(axis)),
            // Explicit jobs alone: no axis, or the axis's points would run the base scene too.
            _ if !explicit.is_empty() => {}
            _ => {
                t.insert(
                    "axes".into(),
                    toml::Value::Array(vec![toml::Value::Table(axis)]),
                );
            }
        }
        if !explicit.is_empty() {
            // Each point runs every explicit job once, after the axes' jobs, point by point.
            let mut jobs = Vec::with_capacity(explicit.len() * new.len());
            for (v, _) in &new {
                for job in &explicit {
                    let mut job = job.clone();
                    for (p, x) in self.cal.parameters.iter().zip(v) {
                        for k in &p.keys {
                            job.insert(k.clone(), toml::Value::Float(*x));
                        }
                    }
                    jobs.push(toml::Value::Table(job));
                }
            }
            t.insert("jobs".into(), toml::Value::Array(jobs));
        }
        let study_path = self.dir.join(format!("{name}.toml"));
        let out = self.dir.join(format!("{name}.h5"));
        let text = toml::to_string(&t)
            .map_err(|e| CampaignError::io(&study_path, format!("cannot write: {e}")))?;
        let header = format!(
            "# Written by `rotorsweep calibrate {}`: the study {} at {} parameter point(s).\n",
            self.cal.path.display(),
            self.cal.study.path.display(),
            new.len()
        );
        std::fs::write(&study_path, header + &text)
            .map_err(|e| CampaignError::io(&study_path, e))?;
        let study = Study::load(&study_path)?;
        campaign::run(
            &study,
            &RunOptions {
                output: out.clone(),
                threads: self.threads,
                resume: true,
                overwrite: false,
                shard: None,
                command: self.command.clone(),
                references: ReferenceSource::Run,
            },
        )?;
        let per_point = self.cal.study.jobs.len();
        let mut jobs_of: Vec<Vec<String>> = vec![Vec::new(); new.len()];
        let mut explicit_seen = 0;
        for j in &study.jobs {
            let i = j
                .labels
                .iter()
                .find_map(|(_, l)| l.strip_prefix("eval ")?.parse::<usize>().ok());
            match i {
                Some(i) if (first..first + new.len()).contains(&i) => {
                    jobs_of[i - first].push(j.id.clone())
                }
                Some(_) => {}
                // An explicit job: the point's copies follow each other (above).
                None if !explicit.is_empty() => {
                    if let Some(js) = jobs_of.get_mut(explicit_seen / explicit.len()) {
                        js.push(j.id.clone());
                    }
                    explicit_seen += 1;
                }
                None => {}
            }
        }
        if jobs_of.iter().any(|j| j.len() != per_point) {
            return Err(CampaignError::Usage(format!(
                "{}: every point should run the study's {per_point} job(s)",
                study_path.display()
            )));
        }
        type Read = (Outputs, Vec<Vec<f64>>, Vec<bool>);
        let read = || -> hdf5::Result<Read> {
            let f = hdf5::File::open(&out)?;
            let ids: Vec<String> = jobs_of.iter().flatten().cloned().collect();
            let outputs = job_outputs(&f, &ids)?;
            let rows = &self.cal.rows;
            let records = (0..new.len())
                .map(|i| record::model_values(&f, rows, |r| jobs_of[i][r.job].clone()))
                .collect::<hdf5::Result<Vec<_>>>()?;
            let jobs = f.group("jobs")?;
            let mut ok = Vec::new();
            for id in &ids {
                let g = jobs.group(id)?;
                let s = store::read_str(&g, "status")?;
                ok.push(s == "ok" || s == "untrusted");
            }
            Ok((outputs, records, ok))
        };
        let (outputs, records, ok) = read().map_err(|e| CampaignError::io(&out, e))?;
        for (i, (v, p)) in new.iter().enumerate() {
            let model: Vec<f64> = self
                .cal
                .rows
                .iter()
                .zip(&records[i])
                .map(|(r, record)| match r.point {
                    Some(_) => *record,
                    None => outputs
                        .get(&r.output)
                        .map_or(f64::NAN, |vals| vals[i * per_point + r.job]),
                })
                .collect();
            let mut e = Evaluation {
                values: v.clone(),
                outputs: model,
                cost: 0.0,
                role: p.role.text(),
                iteration: p.iteration,
                batch: format!("{name}.h5"),
                job_ids: jobs_of[i].clone(),
                ok: ok[i * per_point..(i + 1) * per_point].iter().all(|o| *o),
            };
            let r = self.residuals(&e);
            e.cost = if r.iter().all(|x| x.is_finite()) {
                0.5 * r.iter().map(|x| x * x).sum::<f64>()
            } else {
                f64::INFINITY
            };
            self.known.insert(point_key(v), self.evaluations.len());
            self.evaluations.push(e);
        }
        Ok(())
    }
}

impl Evaluate for Evaluator<'_> {
    type Error = CampaignError;

    fn evaluate(&mut self, points: &[Point]) -> Result<Vec<Vec<f64>>, CampaignError> {
        self.run_batch(points)?;
        Ok(points
            .iter()
            .map(|p| {
                let i = self
                    .find(&p.x)
                    .expect("every point of the batch was evaluated");
                self.residuals(&self.evaluations[i])
            })
            .collect())
    }
}

/// Takes the base study's explicit `[[jobs]]` tables out of `t` (none: empty).
fn explicit_jobs(t: &mut toml::Table) -> Vec<toml::Table> {
    match t.remove("jobs") {
        Some(toml::Value::Array(a)) => a
            .into_iter()
            .filter_map(|v| match v {
                toml::Value::Table(job) => Some(job),
                _ => None,
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// A point's identity: its values as exact text.
fn point_key(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{:e}", v))
        .collect::<Vec<_>>()
        .join(",")
}
