//! The jobs of a results file as the `solver` and `stability` tables see them.
//!
//! In: `/jobs/<id>` (attributes `status`, `cause`, `integrator`, `label`, `job_index`, the CPU
//! time [s], Newton iterations per step, steps, rejected steps, the max, RMS and peak-amplitude
//! runout errors against the reference [µm], the value of each varying key and each labelled
//! axis's `label:<key>`), the file's varying keys and the study's labelled axes. Out: one
//! [`Job`] per job in job order (`job_index`, then id; a missing number is NaN), each with the
//! setting that tells it from the others (labels, `key=value` of the other varying keys), and
//! the long form's identifying columns ([`job_columns`]).

use hdf5::{File, Group};

use super::table::Cell;
use crate::results::request::LabelledAxis;
use crate::store::{self, Param};
use crate::text::number_text;

/// The key that names the integrator.
pub(crate) const INTEGRATOR_KEY: &str = "solver.integrator";

/// One job as the tables see it.
#[derive(Clone)]
pub(crate) struct Job {
    pub(crate) id: String,
    /// The job's label (its labelled axes' labels), "" without.
    pub(crate) label: String,
    /// One cell per varying key (the file's `varying_keys`, in order).
    pub(crate) params: Vec<Cell>,
    pub(crate) status: String,
    pub(crate) cause: String,
    pub(crate) integrator: String,
    /// The labels and other varying values that tell this job from the others.
    pub(crate) setting: String,
    /// The same without the integrator.
    pub(crate) other: String,
    pub(crate) cpu_time_s: f64,
    pub(crate) iterations_per_step: f64,
    pub(crate) steps: f64,
    pub(crate) rejected_steps: f64,
    pub(crate) error_max_um: f64,
    pub(crate) error_rms_um: f64,
    pub(crate) error_peak_um: f64,
}

/// The labels of the job's labelled axes and `key=value` of its other varying keys, in axis
/// order; without the integrator when `skip_integrator` (the other keys of a labelled axis
/// that holds it then show as `key=value`).
fn setting(g: &Group, varying: &[String], axes: &[LabelledAxis], skip_integrator: bool) -> String {
    let mut parts = Vec::new();
    let mut labelled_done: Vec<usize> = Vec::new();
    for k in varying {
        if skip_integrator && k == INTEGRATOR_KEY {
            continue;
        }
        if let Some(a) = axes.iter().position(|a| a.keys.contains(k)) {
            let with_integrator = axes[a].keys.iter().any(|x| x == INTEGRATOR_KEY);
            if !(skip_integrator && with_integrator) {
                if !labelled_done.contains(&a) {
                    labelled_done.push(a);
                    let attr = format!("label:{}", axes[a].keys[0]);
                    if let Ok(l) = store::read_str(g, &attr) {
                        parts.push(l);
                    }
                }
                continue;
            }
        }
        match store::read_param(g, k) {
            Ok(Param::Number(x)) => parts.push(format!("{k}={}", number_text(x))),
            Ok(Param::Text(t)) => parts.push(format!("{k}={t}")),
            Ok(Param::Count(n)) => parts.push(format!("{k}={n}")),
            Err(_) => {}
        }
    }
    parts.join(", ")
}

/// The jobs in job order.
pub(crate) fn read_jobs(
    f: &File,
    varying: &[String],
    axes: &[LabelledAxis],
) -> hdf5::Result<Vec<Job>> {
    let jobs = f.group("jobs")?;
    let mut out = Vec::new();
    for id in jobs.member_names()? {
        let g = jobs.group(&id)?;
        let num = |name: &str| store::read_num(&g, name).unwrap_or(f64::NAN);
        let text = |name: &str| store::read_str(&g, name).unwrap_or_default();
        let mut all = setting(&g, varying, axes, false);
        if all.is_empty() {
            all = format!("job {id}");
        }
        let params = varying
            .iter()
            .map(|k| match store::read_param(&g, k) {
                Ok(Param::Number(x)) => Cell::Number(x),
                Ok(Param::Count(n)) => Cell::Count(n),
                Ok(Param::Text(t)) => Cell::Text(t),
                Err(_) => Cell::Number(f64::NAN),
            })
            .collect();
        let job = Job {
            id: id.clone(),
            label: text("label"),
            params,
            status: text("status"),
            cause: text("cause"),
            integrator: text("integrator"),
            setting: all,
            other: setting(&g, varying, axes, true),
            cpu_time_s: num("cpu_time_s"),
            iterations_per_step: num("iterations_per_step"),
            steps: num("steps"),
            rejected_steps: num("rejected_steps"),
            error_max_um: num("error_max_um"),
            error_rms_um: num("error_rms_um"),
            error_peak_um: num("error_peak_um"),
        };
        out.push((num("job_index"), id, job));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    Ok(out.into_iter().map(|(_, _, j)| j).collect())
}

/// The long form's identifying columns of every job: `job_id`, `label` (when any job has one)
/// and one per varying key (without `skip`); their names and each job's cells.
pub(crate) fn job_columns(
    jobs: &[Job],
    varying: &[String],
    skip: &str,
) -> (Vec<String>, Vec<Vec<Cell>>) {
    let labelled = jobs.iter().any(|j| !j.label.is_empty());
    let keep: Vec<usize> = (0..varying.len()).filter(|&k| varying[k] != skip).collect();
    let mut names = vec!["job_id".to_string()];
    if labelled {
        names.push("label".into());
    }
    names.extend(keep.iter().map(|&k| varying[k].clone()));
    let cells = jobs
        .iter()
        .map(|j| {
            let mut row = vec![Cell::Text(j.id.clone())];
            if labelled {
                row.push(Cell::Text(j.label.clone()));
            }
            row.extend(
                keep.iter()
                    .map(|&k| j.params.get(k).cloned().unwrap_or(Cell::Number(f64::NAN))),
            );
            row
        })
        .collect();
    (names, cells)
}
