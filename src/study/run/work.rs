//! The work list of a run: what each unit of work on the pool runs and how it is named.
//!
//! In: the study, the jobs and reference runs still to run. Out: one [`Work`] per run, the
//! reference runs first, then the jobs in study order: its id, scene, model and linearised
//! system, pruning threshold, the parameters its part file records ([`Work::part_params`]: a
//! random wall's realised statistics `wall_mean_mm`, `wall_std_mm`, `wall_h1_mm`, `wall_h2_mm`
//! among them) and
//! the name its progress line gives it (its labels, else its varying values).

use crate::scene::Scene;
use crate::store::Param;
use crate::study::{Job, Reference, Study};

/// A unit of work for the pool.
pub(super) struct Work<'a> {
    pub(super) id: String,
    pub(super) kind: Kind,
    pub(super) scene: &'a Scene,
    pub(super) model_id: &'a str,
    pub(super) linear_id: Option<&'a str>,
    pub(super) prune: Option<f64>,
    pub(super) params: Vec<(String, Param)>,
    /// What the progress lines call it: the job's labels, else its varying values.
    pub(super) name: String,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Job(usize),
    Reference,
}

fn params_of(overrides: &[(String, toml::Value)]) -> Vec<(String, Param)> {
    overrides
        .iter()
        .map(|(k, v)| (k.clone(), Param::from_toml(v)))
        .collect()
}

/// The work list: the reference runs `refs`, then the jobs.
pub(super) fn work_list<'a>(
    study: &Study,
    jobs: &[&'a Job],
    refs: &[&'a Reference],
) -> Vec<Work<'a>> {
    let mut work: Vec<Work> = Vec::new();
    for r in refs {
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
    for j in jobs {
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
    work
}

impl Work<'_> {
    /// The attributes of its part file's `job` group besides the result: its overrides (and
    /// labels), the ids of its model and linearised system, what the analysis reads of its
    /// scene, its pruning threshold, and its kind (and job index).
    pub(super) fn part_params(&self) -> Vec<(String, Param)> {
        let mut params = self.params.clone();
        params.push(("model_id".into(), Param::Text(self.model_id.to_string())));
        if let Some(l) = self.linear_id {
            params.push(("linear_id".into(), Param::Text(l.to_string())));
        }
        // The spin speed over the record, the roll angle's offset and the roller ratios, for
        // the spectral analysis.
        params.extend(crate::results::analyse::job_attrs(self.scene));
        // A random wall's realised statistics (outputs of the statistics and sensitivity tables).
        if let Some(w) = &self.scene.wall_field {
            for (name, v) in [
                ("wall_mean_mm", w.mean_mm),
                ("wall_std_mm", w.std_mm),
                ("wall_h1_mm", w.h1_mm),
                ("wall_h2_mm", w.h2_mm),
            ] {
                params.push((name.into(), Param::Number(v)));
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
