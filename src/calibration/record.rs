//! A measured record as calibration target rows (`[[records]]`), and the model's values of them.
//!
//! In: a `[[records]]` table of the calibration file — `file` (a results file written by
//! `rotorsweep import`, or any results file with `/analysis/orders` of one job; relative to the
//! calibration file), `job` (the study's job, from 0, that simulates the record: the same
//! run-up), optional `orders` (default: every order of the record), `channels`
//! (`"sensor/direction"`, default: every channel), `speed_min_hz` and `speed_max_hz` (the
//! measured blocks kept, by their mean speed [Hz]), `amplitude_std_um` (the standard deviation
//! [µm] of each of the two parts of a block's measured complex order amplitude) and `weight`.
//! Out: two [`Row`]s per kept measured block of `/analysis/orders`: the real and the imaginary
//! part [µm] of the complex amplitude A e^{iφ} (A the order's amplitude [µm], φ its phase
//! against the roll angle), each with an [`OrderPoint`] naming its sensor, direction, order,
//! speed and part; and, for an evaluated batch ([`model_values`]), the model's values of such
//! rows.
//!
//! Method: the model's value of a row is its job's own order rows of the same sensor,
//! direction and order (a run-up's tracked blocks), sorted by speed and interpolated linearly
//! in speed at the measured block's speed through the complex amplitude (the rule of `report
//! --compare`, `report::compare::at_speed`); outside the simulated speeds there is none (NaN,
//! which the fit reports as a point without a value). Two kept blocks of one channel and order
//! at one speed (a record that dwells at a speed or turns back) are an error naming the
//! table, as are an unreadable file, one without order rows or with several jobs, an order or a
//! channel the record lacks, a σ that is not positive, a negative weight and a selection that
//! keeps no block. Fitting both parts fits amplitude and
//! phase together and keeps the residuals linear in the amplitude near a resonance, where the
//! phase turns by 180°. White sensor noise of σ per sample gives each part of a block's tracked
//! amplitude a standard deviation √(3/M) σ for a Hann-weighted fit over M samples
//! (docs/runups-and-balancing.md, the noise floor): that is the `amplitude_std_um` of a record
//! whose sensor noise is known.

use std::collections::BTreeMap;
use std::path::Path;

use rustfft::num_complex::Complex64;
use serde::Deserialize;

use super::row::{Ctx, OrderPoint, Row};
use crate::error::InputError;
use crate::report::compare::{at_speed, Curve};
use crate::report::tables::orders::{records, OrderRow};
use crate::text::number_text;

/// `[[records]]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RecordFile {
    file: String,
    #[serde(default)]
    job: usize,
    orders: Option<Vec<f64>>,
    channels: Option<Vec<String>>,
    speed_min_hz: Option<f64>,
    speed_max_hz: Option<f64>,
    amplitude_std_um: f64,
    weight: Option<f64>,
}

/// The target rows of `records[i]` (module doc); errors name the file, key and line.
pub(super) fn record_rows(c: &Ctx, i: usize, r: &RecordFile) -> Result<Vec<Row>, InputError> {
    let at = format!("records[{i}]");
    let line = c.line(&at);
    if !(r.amplitude_std_um.is_finite() && r.amplitude_std_um > 0.0) {
        return Err(c.err(
            &format!("{at}.amplitude_std_um"),
            format!(
                "{}: a standard deviation must be positive",
                r.amplitude_std_um
            ),
        ));
    }
    let weight = r.weight.unwrap_or(1.0);
    if !(weight.is_finite() && weight >= 0.0) {
        return Err(c.err(
            &format!("{at}.weight"),
            format!("{weight}: a weight must be ≥ 0"),
        ));
    }
    let lo = r.speed_min_hz.unwrap_or(f64::NEG_INFINITY);
    let hi = r.speed_max_hz.unwrap_or(f64::INFINITY);
    if lo.is_nan() || hi.is_nan() || lo >= hi {
        return Err(c.err(
            &format!("{at}.speed_max_hz"),
            format!("speed_min_hz {lo} must be below speed_max_hz {hi}"),
        ));
    }
    let path = c.path.parent().unwrap_or(Path::new(".")).join(&r.file);
    let file_err = |why: String| c.err(&format!("{at}.file"), format!("{}: {why}", path.display()));
    let f = crate::store::output::open_results_file(&path).map_err(file_err)?;
    let rows: Vec<OrderRow> = records(&f, "analysis/orders")
        .map_err(|e| file_err(e.to_string()))?
        .ok_or_else(|| {
            file_err(
                "no `/analysis/orders` table (import the record with `rotorsweep import`)".into(),
            )
        })?;
    let jobs: std::collections::BTreeSet<String> =
        rows.iter().map(|o| o.job_id.to_string()).collect();
    if jobs.len() != 1 {
        return Err(file_err(format!(
            "holds {} jobs' order rows; a record is one job (as `rotorsweep import` writes)",
            jobs.len()
        )));
    }
    let channel = |o: &OrderRow| format!("{}/{}", o.sensor, o.direction);
    if let Some(list) = &r.orders {
        if let Some(o) = list.iter().find(|o| !rows.iter().any(|x| x.order == **o)) {
            return Err(c.err(
                &format!("{at}.orders"),
                format!(
                    "order {o} is not in {} (import it with --orders)",
                    path.display()
                ),
            ));
        }
    }
    if let Some(list) = &r.channels {
        if let Some(ch) = list
            .iter()
            .find(|ch| !rows.iter().any(|x| channel(x) == **ch))
        {
            return Err(c.err(
                &format!("{at}.channels"),
                format!(
                    "channel `{ch}` is not in {} (`sensor/direction`)",
                    path.display()
                ),
            ));
        }
    }
    let keep = |o: &&OrderRow| {
        r.orders.as_ref().is_none_or(|l| l.contains(&o.order))
            && r.channels.as_ref().is_none_or(|l| l.contains(&channel(o)))
            && (lo..=hi).contains(&o.speed_hz)
            && o.amplitude_um.is_finite()
    };
    let mut out = Vec::new();
    for o in rows.iter().filter(keep) {
        let v = Complex64::from_polar(o.amplitude_um, o.phase_deg.to_radians());
        for (imaginary, value, part) in [(false, v.re, "re"), (true, v.im, "im")] {
            out.push(Row {
                at: format!(
                    "{at}.block[{}].{}:{}x.{part}",
                    o.block,
                    channel(o),
                    number_text(o.order)
                ),
                line,
                output: format!(
                    "order_{part}_um:{}:{}x@{}Hz",
                    channel(o),
                    number_text(o.order),
                    number_text(o.speed_hz)
                ),
                job: r.job,
                value,
                std: r.amplitude_std_um,
                weight,
                point: Some(OrderPoint {
                    sensor: o.sensor.to_string(),
                    direction: o.direction.to_string(),
                    order: o.order,
                    speed_hz: o.speed_hz,
                    imaginary,
                }),
            });
        }
    }
    // Rows are matched to the model by speed: two kept blocks of one channel and order at one
    // speed (a record that dwells at a speed, or turns back) would take one model value.
    let mut seen: BTreeMap<(String, u64, u64), u64> = BTreeMap::new();
    for o in rows.iter().filter(keep) {
        let key = (channel(o), o.order.to_bits(), o.speed_hz.to_bits());
        if let Some(b) = seen.insert(key, o.block) {
            return Err(c.err(
                &at,
                format!(
                    "blocks {b} and {} of {} at {} ({}x) both lie at {} Hz: the record's rows \
                     are matched to the model by speed, so keep one ramp (`speed_min_hz`, \
                     `speed_max_hz`) without its dwell at a constant speed",
                    o.block,
                    path.display(),
                    channel(o),
                    number_text(o.order),
                    number_text(o.speed_hz)
                ),
            ));
        }
    }
    if out.is_empty() {
        return Err(c.err(
            &at,
            format!(
                "no order rows of {} are left by `orders`, `channels` and the speeds",
                path.display()
            ),
        ));
    }
    Ok(out)
}

/// The model's value of every record row (NaN for the others and where the job's curve does not
/// reach the row's speed), from a batch's results file: `job_of(row)` is the id of the job
/// that simulates the row at the evaluated point (module doc).
pub(super) fn model_values(
    f: &hdf5::File,
    rows: &[Row],
    job_of: impl Fn(&Row) -> String,
) -> hdf5::Result<Vec<f64>> {
    let mut out = vec![f64::NAN; rows.len()];
    if rows.iter().all(|r| r.point.is_none()) {
        return Ok(out);
    }
    let table: Vec<OrderRow> = records(f, "analysis/orders")?.unwrap_or_default();
    let mut curves: BTreeMap<(String, String, String, u64), Curve> = BTreeMap::new();
    for o in &table {
        let key = (
            o.job_id.to_string(),
            o.sensor.to_string(),
            o.direction.to_string(),
            o.order.to_bits(),
        );
        let v = Complex64::from_polar(o.amplitude_um, o.phase_deg.to_radians());
        curves.entry(key).or_default().push((o.speed_hz, v));
    }
    for c in curves.values_mut() {
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    for (k, r) in rows.iter().enumerate() {
        let Some(p) = &r.point else { continue };
        let key = (
            job_of(r),
            p.sensor.clone(),
            p.direction.clone(),
            p.order.to_bits(),
        );
        if let Some(v) = curves.get(&key).and_then(|c| at_speed(c, p.speed_hz)) {
            out[k] = if p.imaginary { v.im } else { v.re };
        }
    }
    Ok(out)
}
