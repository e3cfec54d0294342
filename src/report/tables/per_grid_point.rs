//! A sampled study with grid axes: its `statistics` and `sensitivity` tables per grid point.
//!
//! In: a results file of a study with `[sample]` beside `[[axes]]` (its stored text), its jobs
//! in job order (label, varying values) and the file's varying keys; a table builder
//! ([`super::statistics`], [`super::sensitivity`]). Out: the builder's table computed over each
//! grid point's jobs alone, the blocks in grid order, each row led by one column per swept key
//! (named by the key, in its unit; the point's value); without grid axes the builder's table
//! as it is. Method: a job's grid point is its values of the varying keys the design does not
//! sample; its design row (`sample 12`, `A 12`, …) the last part of its label, which follows
//! the axes' labels. Explicit `[[jobs]]` beside the design are left out ([`design_jobs`]).

use hdf5::File;

use crate::report::jobs::Job;
use crate::report::table::{md_cell, Cell, Table};
use crate::study::sample::{is_design_job, spec_of_text};

/// A table builder of a sampled study's jobs.
pub(crate) type Builder = fn(&File, &[Job], &str) -> hdf5::Result<Option<Table>>;

/// `build`'s table per grid point (module doc).
pub(crate) fn per_grid_point(
    f: &File,
    jobs: &[Job],
    study_text: &str,
    varying: &[String],
    build: Builder,
) -> hdf5::Result<Option<Table>> {
    let Some(spec) = spec_of_text(study_text) else {
        return Ok(None);
    };
    let (design, swept) = design_jobs(jobs, &spec.keys(), varying);
    if swept.is_empty() {
        return build(f, &design, study_text);
    }
    let mut points: Vec<(Vec<Cell>, Vec<Job>)> = Vec::new();
    for j in &design {
        let at: Vec<Cell> = swept.iter().map(|&i| j.params[i].clone()).collect();
        let mut job = j.clone();
        job.label = j.label.rsplit(", ").next().unwrap_or_default().to_string();
        match points.iter_mut().find(|(p, _)| *p == at) {
            Some((_, list)) => list.push(job),
            None => points.push((at, vec![job])),
        }
    }
    let keys: Vec<String> = swept.iter().map(|&i| varying[i].clone()).collect();
    let mut out: Option<Table> = None;
    for (at, list) in &points {
        let Some(t) = build(f, list, study_text)? else {
            continue;
        };
        let o = out.get_or_insert_with(|| Table {
            legend: format!(
                "{} One block of rows per grid point, led by the swept keys' values ({}).",
                t.legend,
                keys.join(", ")
            ),
            columns: keys.iter().cloned().chain(t.columns.clone()).collect(),
            rows: Vec::new(),
            markdown: t.markdown.as_ref().map(|g| {
                let mut g = g.clone();
                g.columns = keys.iter().cloned().chain(g.columns).collect();
                g.rows.clear();
                g.classes.clear();
                g
            }),
            ..t.clone()
        });
        for r in t.rows {
            o.rows.push(at.iter().cloned().chain(r).collect());
        }
        if let (Some(g), Some(tg)) = (o.markdown.as_mut(), t.markdown) {
            let lead: Vec<String> = at.iter().map(md_cell).collect();
            for r in tg.rows {
                g.rows.push(lead.iter().cloned().chain(r).collect());
            }
        }
    }
    Ok(out)
}

/// The jobs of a sampled study's design (not its explicit `[[jobs]]`, [`is_design_job`]) and
/// the indices in `varying` of its grid axes' keys: the keys not `sampled` that a design job
/// has a value of (an explicit job's own keys have none in the design's jobs).
pub(crate) fn design_jobs(
    jobs: &[Job],
    sampled: &[String],
    varying: &[String],
) -> (Vec<Job>, Vec<usize>) {
    let design: Vec<Job> = jobs
        .iter()
        .filter(|j| is_design_job(&j.label))
        .cloned()
        .collect();
    let unset = |c: &Cell| matches!(c, Cell::Number(x) if x.is_nan());
    let swept = (0..varying.len())
        .filter(|&i| !sampled.contains(&varying[i]))
        .filter(|&i| design.iter().any(|j| !unset(&j.params[i])))
        .collect();
    (design, swept)
}
