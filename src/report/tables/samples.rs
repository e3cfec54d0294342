//! The `samples` table of a sampled study: each job's sampled inputs and its outputs, the data
//! of the histograms and scatter plots.
//!
//! In: a results file of a study with `[sample]` (its stored text names the parameters), its
//! jobs (status, label, values of the varying keys), the file's varying keys and the jobs'
//! outputs ([`super::outputs`]). Out: one row per job of the design (not an explicit
//! `[[jobs]]` entry beside it) that ended `ok`, in job order: `job_id`,
//! `label` (its labelled axes' labels, then its design row), on grid axes each swept key's
//! value (column: the key; the varying keys the design does not sample, as in
//! [`super::per_grid_point`]), each parameter's value (column: its first key; the job
//! attribute of that key, NaN when it is not a number) and each output (its unit in its name;
//! NaN where the job has none). `None` for a study without `[sample]`.

use hdf5::File;

use super::outputs::job_outputs;
use super::per_grid_point::design_jobs;
use crate::report::jobs::Job;
use crate::report::table::{Cell, Table};
use crate::store;
use crate::study::sample::spec_of_text;

/// The `samples` table (module doc).
pub(crate) fn samples_table(
    f: &File,
    jobs: &[Job],
    study_text: &str,
    varying: &[String],
) -> hdf5::Result<Option<Table>> {
    let Some(spec) = spec_of_text(study_text) else {
        return Ok(None);
    };
    let (design, swept) = design_jobs(jobs, &spec.keys(), varying);
    let ok: Vec<&Job> = design.iter().filter(|j| j.status == "ok").collect();
    if ok.is_empty() {
        return Ok(None);
    }
    let ids: Vec<String> = ok.iter().map(|j| j.id.clone()).collect();
    let outputs = job_outputs(f, &ids)?;
    let keys: Vec<&str> = spec.parameters.iter().map(|p| p.keys[0].as_str()).collect();
    let mut columns = vec!["job_id".to_string(), "label".to_string()];
    columns.extend(swept.iter().map(|&i| varying[i].clone()));
    columns.extend(keys.iter().map(|k| k.to_string()));
    columns.extend(outputs.keys().cloned());
    let group = f.group("jobs")?;
    let mut rows = Vec::with_capacity(ok.len());
    for (i, j) in ok.iter().enumerate() {
        let g = group.group(&j.id)?;
        let mut row = vec![Cell::Text(j.id.clone()), Cell::Text(j.label.clone())];
        row.extend(swept.iter().map(|&i| j.params[i].clone()));
        row.extend(
            keys.iter()
                .map(|k| Cell::Number(store::read_num(&g, k).unwrap_or(f64::NAN))),
        );
        row.extend(outputs.values().map(|v| Cell::Number(v[i])));
        rows.push(row);
    }
    Ok(Some(Table {
        name: "samples".into(),
        title: "Sampled inputs and outputs of every job".into(),
        legend: "One row per job that ended ok: its id, its label (on grid axes the axes' labels, \
                 then its design row), on grid axes the value of each swept key, the value of \
                 each sampled parameter (named by its first key, in its unit) and each output \
                 (its unit in its name: _um µm, _hz Hz, _mm mm; empty where the job has none)."
            .into(),
        columns,
        rows,
        markdown: None,
    }))
}
