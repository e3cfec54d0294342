//! The `trial_mass` table: per trial-mass job, the vertical 1× amplitude change and vector
//! change against the baseline [µm] at each sensor.
//!
//! In: `/analysis/trial_mass` (one record per job and channel: `job_id`, `label`, `channel`,
//! `speed_hz`, `amplitude_change_um`, `vector_change_um`; only the vertical channels are
//! shown) and the jobs' `label:<label_key>` and `job_index` attributes. Out: one row per job,
//! the labels in the study's order (that of their first job), each by speed; the sensors centre
//! first, then by name; none when the file has no trial-mass records.

use std::collections::BTreeMap;

use hdf5::types::VarLenUnicode;
use hdf5::File;

use crate::report::table::{position_or_push, sensor_rank, Cell, Table};
use crate::store;

/// The columns of `/analysis/trial_mass` the table uses (HDF5 converts records member by member
/// by name).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct TrialRow {
    job_id: VarLenUnicode,
    label: VarLenUnicode,
    channel: VarLenUnicode,
    speed_hz: f64,
    amplitude_change_um: f64,
    vector_change_um: f64,
}

/// The trial-mass table; the labels come from the jobs' `label:<label_key>` attributes when
/// there, else from the table.
pub(crate) fn trial_mass_table(f: &File, label_key: Option<&str>) -> hdf5::Result<Option<Table>> {
    let Ok(ds) = f.dataset("analysis/trial_mass") else {
        return Ok(None);
    };
    let records: Vec<TrialRow> = ds.read_raw()?;
    let mut sensors: Vec<&str> = Vec::new();
    // Job → (label, speed, job index, sensor index → (amplitude change, vector change)).
    type Changes = BTreeMap<usize, (f64, f64)>;
    let mut per_job: BTreeMap<&str, (String, f64, f64, Changes, String)> = BTreeMap::new();
    for r in &records {
        let Some(sensor) = r.channel.as_str().strip_suffix("/vertical") else {
            continue;
        };
        let s = position_or_push(&mut sensors, sensor);
        per_job
            .entry(r.job_id.as_str())
            .or_insert_with(|| {
                let g = f.group(&format!("jobs/{}", r.job_id.as_str())).ok();
                let label = label_key
                    .and_then(|k| store::read_str(g.as_ref()?, &format!("label:{k}")).ok())
                    .unwrap_or_else(|| r.label.as_str().to_string());
                let index = g
                    .and_then(|g| store::read_num(&g, "job_index").ok())
                    .unwrap_or(f64::NAN);
                (
                    label,
                    r.speed_hz,
                    index,
                    BTreeMap::new(),
                    r.job_id.as_str().to_string(),
                )
            })
            .3
            .insert(s, (r.amplitude_change_um, r.vector_change_um));
    }
    if per_job.is_empty() {
        return Ok(None);
    }
    let mut jobs: Vec<_> = per_job.into_values().collect();
    // The labels in the study's order (that of their first job), each by speed.
    let mut first: BTreeMap<String, f64> = BTreeMap::new();
    for j in &jobs {
        let e = first.entry(j.0.clone()).or_insert(j.2);
        *e = e.min(j.2);
    }
    jobs.sort_by(|a, b| {
        first[&a.0]
            .total_cmp(&first[&b.0])
            .then(a.1.total_cmp(&b.1))
    });
    let mut shown: Vec<usize> = (0..sensors.len()).collect();
    shown.sort_by(|a, b| sensor_rank(sensors[*a]).cmp(&sensor_rank(sensors[*b])));
    let mut columns = vec![
        "job_id".to_string(),
        "label".to_string(),
        "speed_hz".to_string(),
    ];
    for s in &shown {
        columns.push(format!("{}_amplitude_change_um", sensors[*s]));
        columns.push(format!("{}_vector_change_um", sensors[*s]));
    }
    let rows = jobs
        .iter()
        .map(|(label, speed, _, ch, id)| {
            let mut row = vec![
                Cell::Text(id.clone()),
                Cell::Text(label.clone()),
                Cell::Number(*speed),
            ];
            for s in &shown {
                let (a, v) = ch.get(s).copied().unwrap_or((f64::NAN, f64::NAN));
                row.extend([Cell::Number(a), Cell::Number(v)]);
            }
            row
        })
        .collect();
    Ok(Some(Table {
        name: "trial_mass".into(),
        title: "Trial-mass response".into(),
        legend: "Per trial-mass job: the vertical 1× runout against the baseline job's at the \
                 same speed [µm]: amplitude change |A|−|A₀| and vector change |A−A₀| per sensor."
            .into(),
        columns,
        rows,
        markdown: None,
    }))
}
