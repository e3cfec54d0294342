//! The `orders` and `order_resonances` tables of `rotorsweep report`, from `/analysis/orders`
//! and `/analysis/order_resonances` (written by `results::orders`).
//!
//! Each job is named as in the other tables: in the long form (CSV, JSON) by `job_id`, `label`
//! (when an axis has labels) and one column per varying key ([`job_columns`]); in markdown and
//! HTML by its setting (the study's axis labels, `key=value` of the other varying keys) in a
//! column `job`.

use std::collections::BTreeMap;

use hdf5::types::VarLenUnicode;
use hdf5::File;

use crate::report::jobs::{job_columns, Job};
use crate::report::table::{md_cell, text_cell, Cell, Grid, Table};

/// A row of `/analysis/orders` (HDF5 converts records member by member by name).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
pub(crate) struct OrderRow {
    pub(crate) job_id: VarLenUnicode,
    pub(crate) sensor: VarLenUnicode,
    pub(crate) direction: VarLenUnicode,
    pub(crate) order: f64,
    pub(crate) block: u64,
    pub(crate) time_s: f64,
    pub(crate) speed_hz: f64,
    pub(crate) amplitude_um: f64,
    pub(crate) phase_deg: f64,
}

/// A row of `/analysis/order_resonances`.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
pub(crate) struct PeakRow {
    pub(crate) job_id: VarLenUnicode,
    pub(crate) sensor: VarLenUnicode,
    pub(crate) direction: VarLenUnicode,
    pub(crate) order: f64,
    pub(crate) rank: u64,
    pub(crate) speed_hz: f64,
    pub(crate) amplitude_um: f64,
}

/// The records of the table at `path`; `None` when the file has none.
pub(crate) fn records<T: hdf5::H5Type>(f: &File, path: &str) -> hdf5::Result<Option<Vec<T>>> {
    let Ok(ds) = f.dataset(path) else {
        return Ok(None);
    };
    let r: Vec<T> = ds.read_raw()?;
    Ok((!r.is_empty()).then_some(r))
}

/// How the jobs are named in a table (module doc): the long form's identifying columns and
/// cells per job id, and each job's setting.
struct Names {
    columns: Vec<String>,
    cells: BTreeMap<String, (Vec<Cell>, String)>,
}

impl Names {
    fn new(jobs: &[Job], varying: &[String]) -> Self {
        let (columns, cells) = job_columns(jobs, varying, "");
        let cells = jobs
            .iter()
            .zip(cells)
            .map(|(j, c)| (j.id.clone(), (c, j.setting.clone())))
            .collect();
        Self { columns, cells }
    }

    /// The table of `rest` columns and rows (one per `ids` entry): the long form with the
    /// jobs' identifying columns first, the markdown grid with their settings.
    fn table(
        &self,
        ids: &[&str],
        rest: &[&str],
        rows: Vec<Vec<Cell>>,
    ) -> (Vec<String>, Vec<Vec<Cell>>, Grid) {
        let mut columns = self.columns.clone();
        columns.extend(rest.iter().map(|c| c.to_string()));
        let mut md_columns = vec!["job".to_string()];
        md_columns.extend(rest.iter().map(|c| c.to_string()));
        let mut long = Vec::with_capacity(rows.len());
        let mut md = Vec::with_capacity(rows.len());
        for (id, row) in ids.iter().zip(rows) {
            let (cells, setting) = self.cells.get(*id).cloned().unwrap_or_else(|| {
                let mut c = vec![Cell::Text(id.to_string())];
                c.resize(self.columns.len(), Cell::Text(String::new()));
                (c, format!("job {id}"))
            });
            let mut text = vec![setting];
            text.extend(row.iter().map(md_cell));
            md.push(text);
            long.push(cells.into_iter().chain(row).collect());
        }
        let grid = Grid {
            columns: md_columns,
            rows: md,
            classes: Vec::new(),
        };
        (columns, long, grid)
    }
}

/// The order-tracking table: one row per job, order, block (speed), sensor and direction.
/// Only for a file with a tracked job (one whose speed changes: more than one block); the
/// constant-speed jobs' single rows, equal to the `lines`, then come with it. `jobs` and
/// `varying` name the jobs (module doc).
pub(crate) fn orders_table(
    f: &File,
    jobs: &[Job],
    varying: &[String],
) -> hdf5::Result<Option<Table>> {
    let Some(rows) = records::<OrderRow>(f, "analysis/orders")? else {
        return Ok(None);
    };
    if rows.iter().all(|r| r.block == 0) {
        return Ok(None);
    }
    let ids: Vec<&str> = rows.iter().map(|r| r.job_id.as_str()).collect();
    let cells = rows
        .iter()
        .map(|r| {
            vec![
                Cell::Number(r.order),
                Cell::Count(r.block),
                Cell::Number(r.time_s),
                Cell::Number(r.speed_hz),
                text_cell(&r.sensor),
                text_cell(&r.direction),
                Cell::Number(r.amplitude_um),
                Cell::Number(r.phase_deg),
            ]
        })
        .collect();
    let rest = [
        "order",
        "block",
        "time_s",
        "speed_hz",
        "sensor",
        "direction",
        "amplitude_um",
        "phase_deg",
    ];
    let (columns, rows, grid) = Names::new(jobs, varying).table(&ids, &rest, cells);
    Ok(Some(Table {
        name: "orders".into(),
        title: "Order tracking".into(),
        legend: "Amplitude [µm] and phase [deg] of A cos(kθ + φ) against roll angle 0, per job, \
                 order k, block (mean speed [Hz], mid time [s]), sensor and direction"
            .into(),
        columns,
        rows,
        markdown: Some(grid),
    }))
}

/// The resonance speeds of each tracked job: the highest peaks of each order over speed; `jobs`
/// and `varying` name the jobs (module doc).
pub(crate) fn order_resonance_table(
    f: &File,
    jobs: &[Job],
    varying: &[String],
) -> hdf5::Result<Option<Table>> {
    let Some(rows) = records::<PeakRow>(f, "analysis/order_resonances")? else {
        return Ok(None);
    };
    let ids: Vec<&str> = rows.iter().map(|r| r.job_id.as_str()).collect();
    let cells = rows
        .iter()
        .map(|r| {
            vec![
                Cell::Number(r.order),
                text_cell(&r.sensor),
                text_cell(&r.direction),
                Cell::Count(r.rank),
                Cell::Number(r.speed_hz),
                Cell::Number(r.amplitude_um),
            ]
        })
        .collect();
    let rest = [
        "order",
        "sensor",
        "direction",
        "rank",
        "speed_hz",
        "amplitude_um",
    ];
    let (columns, rows, grid) = Names::new(jobs, varying).table(&ids, &rest, cells);
    Ok(Some(Table {
        name: "order_resonances".into(),
        title: "Resonances of run-ups and coast-downs".into(),
        legend: "Speed [Hz] and amplitude [µm] of the highest interior peaks of each order over \
                 the blocks' speeds, per tracked job, sensor and direction"
            .into(),
        columns,
        rows,
        markdown: Some(grid),
    }))
}
