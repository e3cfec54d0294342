//! The `solver` table: per job, CPU time [s], CPU time relative to the cheapest ok job, Newton
//! iterations per step, steps, rejected steps, max, RMS and peak-amplitude runout error against
//! the reference [µm] and the cause of a job that did not end ok (the thesis's Tables 5.2–5.4).
//!
//! In: the [`Job`]s and the varying keys. Out: the long form (the jobs' identifying columns,
//! then the measured ones) and the markdown grid: transposed (one column per job, by its
//! setting) up to [`TRANSPOSE_MAX`] jobs, else one row per job; without the error rows when no
//! job has a reference, with the cause when some job did not end ok.

use crate::integrators::Status;
use crate::report::jobs::{job_columns, Job};
use crate::report::table::{md_cell, Cell, Grid, Table};

/// Up to this many jobs, markdown shows the solver table transposed (one column per job).
const TRANSPOSE_MAX: usize = 8;

/// The long form's measured columns, after the jobs' identifying ones.
const MEASURED: [&str; 10] = [
    "status",
    "cpu_time_s",
    "relative",
    "iterations_per_step",
    "steps",
    "rejected_steps",
    "error_max_um",
    "error_rms_um",
    "error_peak_um",
    "cause",
];

/// A count stored as a float attribute; NaN (missing) reads as a missing number.
fn count(x: f64) -> Cell {
    if x.is_finite() && x >= 0.0 {
        Cell::Count(x as u64)
    } else {
        Cell::Number(f64::NAN)
    }
}

/// The long form's rows: the identifying cells, then one per [`MEASURED`] column.
fn long_rows(jobs: &[Job], ids: Vec<Vec<Cell>>) -> Vec<Vec<Cell>> {
    let cheapest = jobs
        .iter()
        .filter(|j| Status::name_completed(&j.status) && j.cpu_time_s > 0.0)
        .map(|j| j.cpu_time_s)
        .fold(f64::NAN, f64::min);
    jobs.iter()
        .zip(ids)
        .map(|(j, mut row)| {
            row.extend([
                Cell::Text(j.status.clone()),
                Cell::Number(j.cpu_time_s),
                Cell::Number(j.cpu_time_s / cheapest),
                Cell::Number(j.iterations_per_step),
                count(j.steps),
                count(j.rejected_steps),
                Cell::Number(j.error_max_um),
                Cell::Number(j.error_rms_um),
                Cell::Number(j.error_peak_um),
                Cell::Text(if j.status == "ok" {
                    String::new()
                } else {
                    j.cause.clone()
                }),
            ]);
            row
        })
        .collect()
}

/// The (heading, column) pairs markdown shows: no errors without a reference run, the cause
/// when some job did not end ok.
fn shown(jobs: &[Job]) -> Vec<(&'static str, &'static str)> {
    let mut shown = vec![
        ("CPU time [s]", "cpu_time_s"),
        ("relative", "relative"),
        ("iterations/step", "iterations_per_step"),
        ("max error [µm]", "error_max_um"),
        ("RMS error [µm]", "error_rms_um"),
        ("peak amplitude error [µm]", "error_peak_um"),
        ("status", "status"),
    ];
    if !jobs.iter().any(|j| j.error_max_um.is_finite()) {
        // No reference run: no errors to show.
        shown.retain(|(_, name)| !name.starts_with("error_"));
    }
    if jobs.iter().any(|j| j.status != "ok") {
        shown.push(("cause", "cause"));
    }
    shown
}

/// The markdown grid of the `shown` columns of `rows`, whose measured columns start at `first`:
/// transposed up to [`TRANSPOSE_MAX`] jobs, else one row per job.
fn grid(jobs: &[Job], rows: &[Vec<Cell>], shown: &[(&str, &str)], first: usize) -> Grid {
    let at = |name: &str| first + MEASURED.iter().position(|x| *x == name).unwrap_or(0);
    if jobs.len() <= TRANSPOSE_MAX {
        Grid {
            columns: std::iter::once("setting".to_string())
                .chain(jobs.iter().map(|j| j.setting.clone()))
                .collect(),
            rows: shown
                .iter()
                .map(|(heading, name)| {
                    std::iter::once(heading.to_string())
                        .chain(rows.iter().map(|r| md_cell(&r[at(name)])))
                        .collect()
                })
                .collect(),
            classes: Vec::new(),
        }
    } else {
        Grid {
            columns: std::iter::once("setting")
                .chain(shown.iter().map(|(h, _)| *h))
                .map(str::to_string)
                .collect(),
            rows: jobs
                .iter()
                .zip(rows)
                .map(|(j, r)| {
                    std::iter::once(j.setting.clone())
                        .chain(shown.iter().map(|(_, name)| md_cell(&r[at(name)])))
                        .collect()
                })
                .collect(),
            classes: Vec::new(),
        }
    }
}

/// The `solver` table of `jobs` (module doc).
pub(crate) fn solver_table(jobs: &[Job], varying: &[String]) -> Table {
    let (mut columns, ids) = job_columns(jobs, varying, "");
    let first = columns.len();
    columns.extend(MEASURED.iter().map(|c| c.to_string()));
    let rows = long_rows(jobs, ids);
    let markdown = grid(jobs, &rows, &shown(jobs), first);
    Table {
        name: "solver".into(),
        title: "Solver cost and accuracy".into(),
        legend: "Per job (thesis Tables 5.2–5.4): CPU time [s]; relative: CPU time over the \
                 cheapest ok job's; Newton iterations per step; steps and rejected steps; max, \
                 RMS and peak-amplitude runout error against the reference run [µm] (– without \
                 a reference); cause of a job that did not end ok."
            .into(),
        columns,
        rows,
        markdown: Some(markdown),
    }
}
