//! The `orders` and `order_resonances` tables of `rotorsweep report`, from `/analysis/orders`
//! and `/analysis/order_resonances` (written by `results::orders`).

use hdf5::types::VarLenUnicode;
use hdf5::File;

use crate::report::table::{Cell, Table};

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
struct PeakRow {
    job_id: VarLenUnicode,
    sensor: VarLenUnicode,
    direction: VarLenUnicode,
    order: f64,
    rank: u64,
    speed_hz: f64,
    amplitude_um: f64,
}

fn text(s: &VarLenUnicode) -> Cell {
    Cell::Text(s.as_str().to_string())
}

/// The records of the table at `path`; `None` when the file has none.
pub(crate) fn records<T: hdf5::H5Type>(f: &File, path: &str) -> hdf5::Result<Option<Vec<T>>> {
    let Ok(ds) = f.dataset(path) else {
        return Ok(None);
    };
    let r: Vec<T> = ds.read_raw()?;
    Ok((!r.is_empty()).then_some(r))
}

/// The order-tracking table: one row per job, order, block (speed), sensor and direction.
/// Only for a file with a tracked job (one whose speed changes: more than one block); the
/// constant-speed jobs' single rows, equal to the `lines`, then come with it.
pub(crate) fn orders_table(f: &File) -> hdf5::Result<Option<Table>> {
    let Some(rows) = records::<OrderRow>(f, "analysis/orders")? else {
        return Ok(None);
    };
    if rows.iter().all(|r| r.block == 0) {
        return Ok(None);
    }
    let rows = rows
        .iter()
        .map(|r| {
            vec![
                text(&r.job_id),
                Cell::Number(r.order),
                Cell::Count(r.block),
                Cell::Number(r.time_s),
                Cell::Number(r.speed_hz),
                text(&r.sensor),
                text(&r.direction),
                Cell::Number(r.amplitude_um),
                Cell::Number(r.phase_deg),
            ]
        })
        .collect();
    Ok(Some(Table {
        name: "orders".into(),
        title: "Order tracking".into(),
        legend: "Amplitude [µm] and phase [deg] of A cos(kθ + φ) against roll angle 0, per job, \
                 order k, block (mean speed [Hz], mid time [s]), sensor and direction"
            .into(),
        columns: [
            "job_id",
            "order",
            "block",
            "time_s",
            "speed_hz",
            "sensor",
            "direction",
            "amplitude_um",
            "phase_deg",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        markdown: None,
    }))
}

/// The resonance speeds of each tracked job: the highest peaks of each order over speed.
pub(crate) fn order_resonance_table(f: &File) -> hdf5::Result<Option<Table>> {
    let Some(rows) = records::<PeakRow>(f, "analysis/order_resonances")? else {
        return Ok(None);
    };
    let rows = rows
        .iter()
        .map(|r| {
            vec![
                text(&r.job_id),
                Cell::Number(r.order),
                text(&r.sensor),
                text(&r.direction),
                Cell::Count(r.rank),
                Cell::Number(r.speed_hz),
                Cell::Number(r.amplitude_um),
            ]
        })
        .collect();
    Ok(Some(Table {
        name: "order_resonances".into(),
        title: "Resonances of run-ups and coast-downs".into(),
        legend: "Speed [Hz] and amplitude [µm] of the highest interior peaks of each order over \
                 the blocks' speeds, per tracked job, sensor and direction"
            .into(),
        columns: [
            "job_id",
            "order",
            "sensor",
            "direction",
            "rank",
            "speed_hz",
            "amplitude_um",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        markdown: None,
    }))
}
