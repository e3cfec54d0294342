//! The work list of a run, and one unit of it run on a worker.
//!
//! In: the study, the jobs and reference runs still to run. Out: one [`Work`] per run, the
//! reference runs first, then the jobs in study order: references into the study (its id,
//! overrides, model, linearised system, pruning threshold), so the list costs a few words per
//! run. [`Work::run`] is what a worker does with one: the run's scene built again from its
//! overrides ([`Study::scene_of`]), run on its model, and what its part file records besides
//! the result ([`Finished`]): its overrides and labels, the ids of its model and linearised
//! system, what the analysis reads of its scene, a random wall's realised statistics
//! `wall_mean_mm`, `wall_std_mm`, `wall_h1_mm`, `wall_h2_mm`, its pruning threshold and
//! kind, and the name its progress line gives it (its labels, else its varying values); and a
//! job analysed from its result in memory (`results::job_analysis::Analyser`: lines, means,
//! spectra, order tracking at a constant speed), so the thread that writes the results file
//! only writes.

use super::models::{failed_result, Models};
use super::parts::Finished;
use crate::results::job_analysis::Analyser;
use crate::scene::Scene;
use crate::store::Param;
use crate::study::{Job, Reference, SceneFacts, Study};

/// A unit of work for the pool.
pub(super) struct Work<'a> {
    pub(super) id: &'a str,
    pub(super) kind: Kind,
    overrides: &'a [(String, toml::Value)],
    facts: &'a SceneFacts,
    pub(super) model_id: &'a str,
    linear_id: Option<&'a str>,
    prune: Option<f64>,
    /// The job's labels (none for a reference run).
    labels: &'a [(String, String)],
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Job(usize),
    Reference,
}

/// The work list: the reference runs `refs`, then the jobs.
pub(super) fn work_list<'a>(jobs: &[&'a Job], refs: &[&'a Reference]) -> Vec<Work<'a>> {
    let refs = refs.iter().map(|r| Work {
        id: &r.id,
        kind: Kind::Reference,
        overrides: &r.overrides,
        facts: &r.facts,
        model_id: &r.model_id,
        linear_id: None,
        prune: None,
        labels: &[],
    });
    let jobs = jobs.iter().map(|j| Work {
        id: &j.id,
        kind: Kind::Job(j.index),
        overrides: &j.overrides,
        facts: &j.facts,
        model_id: &j.model_id,
        linear_id: Some(&j.linear_id),
        prune: j.prune,
        labels: &j.labels,
    });
    refs.chain(jobs).collect()
}

impl<'a> Work<'a> {
    /// Runs it on its model (module doc). Its scene was validated when the study was loaded;
    /// should building it again fail (a thickness map changed since), the run fails with
    /// that cause.
    pub(super) fn run(&self, study: &Study, models: &Models, analyser: &Analyser) -> Finished<'a> {
        let (result, scene) = match study.scene_of(self.overrides) {
            Ok(scene) => (
                models.simulate(&scene, self.model_id, self.prune),
                Some(scene),
            ),
            Err(e) => (failed_result(format!("scene: {e}")), None),
        };
        let params = self.part_params(scene.as_ref());
        let analysed = match self.kind {
            Kind::Job(_) => {
                let status = result.stats.status.name();
                analyser.run(self.id, &params, status, (&result.time, &result.channels))
            }
            Kind::Reference => None,
        };
        Finished {
            id: self.id,
            params,
            integrator: self.facts.integrator,
            name: self.name(study),
            result,
            analysed,
        }
    }

    /// What the progress lines call it: its labels, then the values of the varying keys no
    /// label stands for; "reference run" for a reference run.
    fn name(&self, study: &Study) -> String {
        let Kind::Job(index) = self.kind else {
            return "reference run".into();
        };
        let job = &study.jobs[index];
        (self.labels.iter().map(|(_, l)| l.clone()))
            .chain(
                (study.varying.iter())
                    .filter(|k| !self.labels.iter().any(|(lk, _)| lk == *k))
                    .map(|k| format!("{k}={}", study.value_text(job, k).unwrap_or_default())),
            )
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The attributes of its part file's `job` group besides the result (module doc); what
    /// the analysis reads of its scene only when there is one.
    fn part_params(&self, scene: Option<&Scene>) -> Vec<(String, Param)> {
        let mut params: Vec<(String, Param)> = (self.overrides.iter())
            .map(|(k, v)| (k.clone(), Param::from_toml(v)))
            .collect();
        if !self.labels.is_empty() {
            let all: Vec<&str> = self.labels.iter().map(|(_, l)| l.as_str()).collect();
            params.push(("label".into(), Param::Text(all.join(", "))));
            for (k, l) in self.labels {
                params.push((format!("label:{k}"), Param::Text(l.clone())));
            }
        }
        params.push(("model_id".into(), Param::Text(self.model_id.to_string())));
        if let Some(l) = self.linear_id {
            params.push(("linear_id".into(), Param::Text(l.to_string())));
        }
        if let Some(scene) = scene {
            // The spin speed over the record, the roll angle's offset and the roller ratios,
            // for the spectral analysis.
            params.extend(crate::results::analyse::job_attrs(scene));
            // A random wall's realised statistics (outputs of the statistics and sensitivity
            // tables).
            if let Some(w) = &scene.wall_field {
                for (name, v) in [
                    ("wall_mean_mm", w.mean_mm),
                    ("wall_std_mm", w.std_mm),
                    ("wall_h1_mm", w.h1_mm),
                    ("wall_h2_mm", w.h2_mm),
                ] {
                    params.push((name.into(), Param::Number(v)));
                }
            }
        }
        if let Some(p) = self.prune {
            params.push((crate::study::PRUNE_KEY.into(), Param::Number(p)));
        }
        match self.kind {
            Kind::Job(i) => {
                params.push(("job_index".into(), Param::Count(i as u64)));
                params.push(("kind".into(), Param::Text("job".into())));
            }
            Kind::Reference => params.push(("kind".into(), Param::Text("reference".into()))),
        }
        params
    }
}
