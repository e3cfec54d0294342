//! The `stability` table: per integrator and other setting, the status, max runout error
//! against the reference [µm], its class ([`error_class`]) and CPU time [s].
//!
//! In: the [`Job`]s and the varying keys (the table is made when the integrator varies beside
//! another key). Out: the long form (one row per job: its identifying columns with the
//! integrator, then status, error, class, CPU time and cause) and the matrix markdown and HTML
//! show: integrators as rows, the other settings as columns, each cell the outcomes of its jobs
//! (`ok 1.2 µm 0.48 s`, `diverged: cause` cut to [`SHORT_CAUSE`] characters, `budget 30 s`;
//! several joined by `; `) and classed by the worst of them (the last in
//! [`CLASS_COLOURS`]'s order), by which HTML colours it.

use std::collections::BTreeMap;

use crate::report::classes::{error_class, CLASS_COLOURS};
use crate::report::jobs::{job_columns, Job, INTEGRATOR_KEY};
use crate::report::table::{position_or_push, Cell, Grid, Table};
use crate::text::significant;

/// Causes longer than this are cut in the stability matrix.
const SHORT_CAUSE: usize = 40;

/// `text` cut to `n` characters with an ellipsis.
fn cut(text: &str, n: usize) -> String {
    if text.chars().count() <= n {
        text.to_string()
    } else {
        format!("{}…", text.chars().take(n).collect::<String>())
    }
}

/// The matrix cell of one job: `ok 1.2 µm 0.48 s`, `diverged: cause`, `budget 30 s`.
fn outcome(j: &Job) -> String {
    match j.status.as_str() {
        "ok" if j.error_max_um.is_finite() => format!(
            "ok {} µm {} s",
            significant(j.error_max_um, 2),
            significant(j.cpu_time_s, 2)
        ),
        "ok" => format!("ok {} s", significant(j.cpu_time_s, 2)),
        "untrusted" => format!(
            "untrusted {} µm {} s",
            significant(j.error_max_um, 2),
            significant(j.cpu_time_s, 2)
        ),
        "budget" => format!("budget {} s", significant(j.cpu_time_s, 2)),
        s => format!("{s}: {}", cut(&j.cause, SHORT_CAUSE)),
    }
}

/// The `stability` table of `jobs` (module doc).
pub(crate) fn stability_table(jobs: &[Job], varying: &[String]) -> Table {
    let mut integrators: Vec<&str> = Vec::new();
    let mut settings: Vec<&str> = Vec::new();
    let mut cells: BTreeMap<(usize, usize), Vec<String>> = BTreeMap::new();
    let mut worst: BTreeMap<(usize, usize), (usize, &str)> = BTreeMap::new();
    let (mut columns, ids) = job_columns(jobs, varying, INTEGRATOR_KEY);
    columns.splice(1..1, ["integrator".to_string()]);
    columns.extend(
        [
            "status",
            "error_max_um",
            "error_class",
            "cpu_time_s",
            "cause",
        ]
        .iter()
        .map(|c| c.to_string()),
    );
    let mut rows = Vec::new();
    for (j, mut row) in jobs.iter().zip(ids) {
        let i = position_or_push(&mut integrators, &j.integrator);
        let s = position_or_push(&mut settings, &j.other);
        cells.entry((i, s)).or_default().push(outcome(j));
        let class = error_class(&j.status, j.error_max_um);
        let rank = CLASS_COLOURS
            .iter()
            .position(|(c, _)| *c == class)
            .unwrap_or(CLASS_COLOURS.len());
        let w = worst.entry((i, s)).or_insert((rank, class));
        if rank > w.0 {
            *w = (rank, class);
        }
        row.insert(1, Cell::Text(j.integrator.clone()));
        row.extend([
            Cell::Text(j.status.clone()),
            Cell::Number(j.error_max_um),
            Cell::Text(error_class(&j.status, j.error_max_um).to_string()),
            Cell::Number(j.cpu_time_s),
            Cell::Text(j.cause.clone()),
        ]);
        rows.push(row);
    }
    let grid = Grid {
        columns: std::iter::once("integrator")
            .chain(settings.iter().copied())
            .map(str::to_string)
            .collect(),
        rows: integrators
            .iter()
            .enumerate()
            .map(|(i, name)| {
                std::iter::once(name.to_string())
                    .chain(
                        (0..settings.len())
                            .map(|s| cells.get(&(i, s)).map(|v| v.join("; ")).unwrap_or_default()),
                    )
                    .collect()
            })
            .collect(),
        classes: (0..integrators.len())
            .map(|i| {
                std::iter::once(String::new())
                    .chain((0..settings.len()).map(|s| {
                        worst
                            .get(&(i, s))
                            .map_or_else(String::new, |w| w.1.to_string())
                    }))
                    .collect()
            })
            .collect(),
    };
    Table {
        name: "stability".into(),
        title: "Stability and accuracy per integrator".into(),
        legend: "Per integrator (rows) and other setting (columns): status, max runout error \
                 against the reference [µm] and CPU time [s]; error class by decade (< 1 µm, \
                 1–10 µm, 10–100 µm, ≥ 100 µm; no reference; or the status of a job that did \
                 not end ok)."
            .into(),
        columns,
        rows,
        markdown: Some(grid),
    }
}
