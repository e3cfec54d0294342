//! The outputs of every job as numbers, for the `statistics` and `sensitivity` tables.
//!
//! In: a results file: `/jobs/<id>/runout_mean/<sensor>/<dir>` [µm], a random wall's realised
//! statistics (the job attributes `wall_mean_mm`, `wall_std_mm`, `wall_h1_mm`, `wall_h2_mm`), `/analysis/lines` (each
//! job's line amplitude per channel and order [µm]), `/analysis/order_resonances` (the highest
//! peak per job, channel and order: speed [Hz] and amplitude [µm]) and the job's linear system
//! `/linear/<linear_id>` (`critical_speeds_hz` [Hz], `critical_log_dec` (1),
//! `static/sag_vertical_um` and `sag_horizontal_um` per sensor [µm], attributes `vertical_hz`,
//! `horizontal_hz`), and a machine's nips (`/jobs/<id>/nips/<nip>/force` [N], at the study's
//! `[analysis] orders`, from the file's `study_text`; default 1, 2, 3, 4). Out: per output
//! name — its unit in the name, its place after colons, e.g.
//! `runout_mean_um:centre/vertical`, `line_amplitude_um:centre/vertical:2x`,
//! `peak_speed_hz:centre/vertical:2x`, `critical_speed_hz:1`, `critical_log_dec:1` (the log
//! decrement of that critical speed's mode), `nip_static_n:<nip>` and
//! `nip_amplitude_n:<nip>:2x` (the total nip force's static load and its line at the order, as
//! the `nips` table's `total` row) — the value of every job asked for, in their order (NaN
//! where a job has none). Outputs that depend on the machine (CPU
//! time, steps) are not outputs of the physics and are left out.

use std::collections::BTreeMap;

use hdf5::types::VarLenUnicode;
use hdf5::File;

use super::nips::nip_totals;
use super::orders::{records, PeakRow};
use crate::results::request::analysis_of_text;
use crate::store;
use crate::text::number_text;

/// The job attributes of a random wall's realised statistics [mm], outputs under their own names.
const WALL_FIELD: [&str; 4] = ["wall_mean_mm", "wall_std_mm", "wall_h1_mm", "wall_h2_mm"];

/// A row of `/analysis/lines`.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct LineRow {
    job_id: VarLenUnicode,
    channel: VarLenUnicode,
    order: f64,
    speed_hz: f64,
    freq_hz: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

/// Every output by name (module doc): one value per job of `job_ids`, NaN where none.
pub(crate) type Outputs = BTreeMap<String, Vec<f64>>;

/// The outputs of the jobs `job_ids` (module doc).
pub(crate) fn job_outputs(f: &File, job_ids: &[String]) -> hdf5::Result<Outputs> {
    let index: BTreeMap<&str, usize> = job_ids
        .iter()
        .enumerate()
        .map(|(i, id)| (id.as_str(), i))
        .collect();
    let n = job_ids.len();
    let mut out: Outputs = BTreeMap::new();
    let mut put = |name: String, j: usize, v: f64| {
        out.entry(name).or_insert_with(|| vec![f64::NAN; n])[j] = v;
    };
    let jobs = f.group("jobs")?;
    let linear = f.group("linear").ok();
    let text = store::read_str(f, "study_text").unwrap_or_default();
    let orders = analysis_of_text(&text).unwrap_or_default().spec.orders;
    for (j, id) in job_ids.iter().enumerate() {
        let g = jobs.group(id)?;
        for attr in WALL_FIELD {
            if let Ok(v) = store::read_num(&g, attr) {
                put(attr.to_string(), j, v);
            }
        }
        if let Ok(means) = g.group("runout_mean") {
            for sensor in means.member_names()? {
                let sg = means.group(&sensor)?;
                for dir in sg.member_names()? {
                    let v: f64 = sg.dataset(&dir)?.read_scalar()?;
                    put(format!("runout_mean_um:{sensor}/{dir}"), j, v);
                }
            }
        }
        for (nip, stat, amps) in nip_totals(&g, &orders)? {
            put(format!("nip_static_n:{nip}"), j, stat);
            for (k, a) in orders.iter().zip(amps) {
                put(format!("nip_amplitude_n:{nip}:{}x", number_text(*k)), j, a);
            }
        }
        let lid = store::read_str(&g, "linear_id").unwrap_or_default();
        if let Some(lg) = linear.as_ref().and_then(|l| l.group(&lid).ok()) {
            for (attr, name) in [
                ("vertical_hz", "bending_vertical_hz"),
                ("horizontal_hz", "bending_horizontal_hz"),
            ] {
                if let Ok(v) = store::read_num(&lg, attr) {
                    put(name.to_string(), j, v);
                }
            }
            for (dataset, name) in [
                ("critical_speeds_hz", "critical_speed_hz"),
                ("critical_log_dec", "critical_log_dec"),
            ] {
                if let Ok(c) = lg.dataset(dataset).and_then(|d| d.read_raw::<f64>()) {
                    for (k, v) in c.iter().enumerate() {
                        put(format!("{name}:{}", k + 1), j, *v);
                    }
                }
            }
            if let Ok(sensors) = lg
                .dataset("static/sensors")
                .and_then(|d| d.read_raw::<VarLenUnicode>())
            {
                for dir in ["vertical", "horizontal"] {
                    let Ok(sag) = lg
                        .dataset(&format!("static/sag_{dir}_um"))
                        .and_then(|d| d.read_raw::<f64>())
                    else {
                        continue;
                    };
                    for (s, v) in sensors.iter().zip(sag) {
                        put(format!("sag_{dir}_um:{}", s.as_str()), j, v);
                    }
                }
            }
        }
    }
    for r in records::<LineRow>(f, "analysis/lines")?.unwrap_or_default() {
        if let Some(&j) = index.get(r.job_id.as_str()) {
            let name = format!(
                "line_amplitude_um:{}:{}x",
                r.channel.as_str(),
                number_text(r.order)
            );
            put(name, j, r.amplitude_um);
        }
    }
    for r in records::<PeakRow>(f, "analysis/order_resonances")?.unwrap_or_default() {
        if let Some(&j) = index.get(r.job_id.as_str()).filter(|_| r.rank == 1) {
            let at = format!(
                "{}/{}:{}x",
                r.sensor.as_str(),
                r.direction.as_str(),
                number_text(r.order)
            );
            put(format!("peak_speed_hz:{at}"), j, r.speed_hz);
            put(format!("peak_amplitude_um:{at}"), j, r.amplitude_um);
        }
    }
    Ok(out)
}
