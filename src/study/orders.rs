//! Order tracking of an assembled results file (part of the post-processing, `post::analyse`).
//!
//! In: `/jobs/<id>` groups that ended ok with runout channels [µm] and a roll angle: the
//! `speed/roll_angle` channel [rad] (recorded when the speed changes, or imported from a
//! measurement), else — at a constant speed — θ = Ω t + δ from the `speed_hz` and
//! `roll_angle_offset_rad` attributes; the study's `[analysis] orders` and `order_revolutions`.
//! Out, in the same file:
//! - `/analysis/orders`: table job_id, sensor, direction, order, block, time_s, speed_hz,
//!   freq_hz, amplitude_um, phase_deg (phase of A cos(kθ + φ) against roll angle 0, as
//!   `/analysis/lines` and `rotorsweep linear`'s unbalance response): one row per block of
//!   `order_revolutions` revolutions (half overlapping) for a job whose speed changes, one row
//!   for the whole record at a constant speed (`analysis::orders`, method and limits there);
//! - `/analysis/order_resonances`: table job_id, sensor, direction, order, rank, speed_hz,
//!   amplitude_um — the three highest interior peaks of each order's amplitude over the blocks'
//!   speeds of one job (the resonance speeds of a run-up or coast-down; jobs of ≥ 3 blocks);
//! - `/jobs/<id>/waterfall` for a job whose speed changes: `time_s`, `speed_hz` (mean over each
//!   block), `freq_hz` and `map/<sensor>/<dir>` [blocks × frequencies, µm]: amplitude-correct
//!   Hanning spectra of time blocks of 2^⌊log₂ fs⌋ samples (about 1 s), half overlapping, up to
//!   `max_freq_hz` (default 8 × the highest speed).

use rustfft::num_complex::Complex64;

use super::AnalysisSpec;
use crate::analysis::{self, orders as track};
use crate::integrators::Status;
use crate::store::{self, Column};

/// Peaks kept per job, order and channel in the order-resonance table.
const RANKS: usize = 3;

/// The table rows being built.
#[derive(Default)]
struct Rows {
    job: Vec<String>,
    sensor: Vec<String>,
    direction: Vec<String>,
    order: Vec<f64>,
    block: Vec<u64>,
    time: Vec<f64>,
    speed: Vec<f64>,
    freq: Vec<f64>,
    amp: Vec<f64>,
    phase: Vec<f64>,
}

#[derive(Default)]
struct Peaks {
    job: Vec<String>,
    sensor: Vec<String>,
    direction: Vec<String>,
    order: Vec<f64>,
    rank: Vec<u64>,
    speed: Vec<f64>,
    amp: Vec<f64>,
}

/// "sensor/direction" split at its last '/'.
fn split(name: &str) -> (String, String) {
    match name.rsplit_once('/') {
        Some((s, d)) => (s.to_string(), d.to_string()),
        None => (name.to_string(), String::new()),
    }
}

/// The roll angle of a job's samples and whether its speed is constant; `None` when it has no
/// angle to track with.
fn roll_angle(g: &hdf5::Group, time: &[f64]) -> Option<(Vec<f64>, bool)> {
    if let Ok(ds) = g.dataset("speed/roll_angle") {
        let theta = ds.read_raw::<f64>().ok()?;
        let constant = store::read_num(g, "speed_hz").is_ok_and(|s| s.is_finite() && s > 0.0);
        return Some((theta, constant));
    }
    let speed = store::read_num(g, "speed_hz").ok()?;
    let delta = store::read_num(g, "roll_angle_offset_rad").unwrap_or(0.0);
    (speed.is_finite() && speed > 0.0).then(|| {
        let w = std::f64::consts::TAU * speed;
        (time.iter().map(|t| w * t + delta).collect(), true)
    })
}

/// The waterfall of one job (module doc).
fn waterfall(
    g: &hdf5::Group,
    time: &[f64],
    theta: &[f64],
    channels: &[(String, Vec<f64>)],
    max_freq_hz: Option<f64>,
) -> hdf5::Result<()> {
    let n = time.len();
    if n < 2 || time[n - 1] <= time[0] {
        return Ok(());
    }
    let fs = (n - 1) as f64 / (time[n - 1] - time[0]);
    let len = (1usize << (fs.max(64.0).log2().floor() as u32)).min(n);
    let hop = (len / 2).max(1);
    let starts: Vec<usize> = (0..)
        .map(|i| i * hop)
        .take_while(|s| s + len <= n)
        .collect();
    if starts.is_empty() {
        return Ok(());
    }
    let tau = std::f64::consts::TAU;
    let speeds: Vec<f64> = starts
        .iter()
        .map(|&s| (theta[s + len - 1] - theta[s]) / (tau * (time[s + len - 1] - time[s])))
        .collect();
    let mids: Vec<f64> = starts
        .iter()
        .map(|&s| 0.5 * (time[s] + time[s + len - 1]))
        .collect();
    let cap = max_freq_hz.unwrap_or(8.0 * speeds.iter().copied().fold(0.0, f64::max));
    if g.link_exists("waterfall") {
        g.unlink("waterfall")?;
    }
    let wg = g.create_group("waterfall")?;
    store::dataset(&wg, "time_s", &mids, "s")?;
    store::dataset(&wg, "speed_hz", &speeds, "Hz")?;
    let mut bins = 0;
    for (c, (name, x)) in channels.iter().enumerate() {
        let mut map = Vec::new();
        for &s in &starts {
            let sp = analysis::spectrum(&x[s..s + len], fs);
            if bins == 0 {
                bins = sp.freq_hz.iter().take_while(|f| **f <= cap + 1e-9).count();
            }
            if c == 0 && s == 0 {
                store::dataset(&wg, "freq_hz", &sp.freq_hz[..bins], "Hz")?;
            }
            map.extend_from_slice(&sp.amplitude[..bins]);
        }
        store::dataset_2d(
            &wg,
            &format!("map/{name}"),
            (starts.len(), bins),
            &map,
            "um",
        )?;
    }
    Ok(())
}

/// Tracks every job it can and writes the tables into `analysis` (module doc).
pub fn write(f: &hdf5::File, analysis: &hdf5::Group, spec: &AnalysisSpec) -> hdf5::Result<()> {
    let revs = spec
        .order_revolutions
        .unwrap_or(super::DEFAULT_ORDER_REVOLUTIONS);
    let jobs = f.group("jobs")?;
    let mut rows = Rows::default();
    let mut peaks = Peaks::default();
    for id in jobs.member_names()? {
        let g = jobs.group(&id)?;
        if !store::read_str(&g, "status").is_ok_and(|s| Status::name_completed(&s)) {
            continue;
        }
        let channels = store::runout_channels(&g);
        let time = g
            .dataset("time")
            .and_then(|d| d.read_raw::<f64>())
            .unwrap_or_default();
        if channels.is_empty() || time.len() < 3 {
            continue;
        }
        let Some((theta, constant)) = roll_angle(&g, &time) else {
            continue;
        };
        let signals: Vec<&[f64]> = channels.iter().map(|(_, x)| x.as_slice()).collect();
        let blocks = if constant {
            track::whole(&time, &theta, &signals, &spec.orders).map(|b| b.into_iter().collect())
        } else {
            track::track(&time, &theta, &signals, &spec.orders, revs, 0.5 * revs)
        };
        // A job whose angle cannot be tracked (it never is in a simulated job; an imported one
        // is checked at import) is left out of the tables.
        let Ok(blocks) = blocks else { continue };
        if !constant {
            waterfall(&g, &time, &theta, &channels, spec.max_freq_hz)?;
        }
        for (c, (name, _)) in channels.iter().enumerate() {
            let (sensor, direction) = split(name);
            for (k, order) in spec.orders.iter().enumerate() {
                for (b, blk) in blocks.iter().enumerate() {
                    let z: Complex64 = blk.amplitudes[c][k];
                    rows.job.push(id.clone());
                    rows.sensor.push(sensor.clone());
                    rows.direction.push(direction.clone());
                    rows.order.push(*order);
                    rows.block.push(b as u64);
                    rows.time.push(blk.time_s);
                    rows.speed.push(blk.speed_hz);
                    rows.freq.push(order * blk.speed_hz);
                    rows.amp.push(z.norm());
                    rows.phase.push(z.arg().to_degrees());
                }
                if blocks.len() < 3 {
                    continue;
                }
                // Peaks over speed: blocks in speed order (a coast-down runs backward).
                let mut by_speed: Vec<(f64, f64)> = blocks
                    .iter()
                    .map(|b| (b.speed_hz, b.amplitudes[c][k].norm()))
                    .filter(|(_, a)| a.is_finite())
                    .collect();
                by_speed.sort_by(|a, b| a.0.total_cmp(&b.0));
                // Blocks at one speed (a hold before or after the ramp) count once, at their
                // highest amplitude: a peak lies between distinct speeds.
                by_speed.dedup_by(|later, kept| {
                    let same = (later.0 - kept.0).abs() <= 1e-9 * kept.0.abs().max(1.0);
                    if same {
                        kept.1 = kept.1.max(later.1);
                    }
                    same
                });
                let (s, a): (Vec<f64>, Vec<f64>) = by_speed.into_iter().unzip();
                for (r, p) in analysis::peaks(&s, &a).into_iter().take(RANKS).enumerate() {
                    peaks.job.push(id.clone());
                    peaks.sensor.push(sensor.clone());
                    peaks.direction.push(direction.clone());
                    peaks.order.push(*order);
                    peaks.rank.push(r as u64 + 1);
                    peaks.speed.push(p.speed_hz);
                    peaks.amp.push(p.amplitude);
                }
            }
        }
    }
    store::compound_table(
        analysis,
        "orders",
        &[
            Column::text("job_id", rows.job),
            Column::text("sensor", rows.sensor),
            Column::text("direction", rows.direction),
            Column::number("order", "1", rows.order),
            Column::count("block", rows.block),
            Column::number("time_s", "s", rows.time),
            Column::number("speed_hz", "Hz", rows.speed),
            Column::number("freq_hz", "Hz", rows.freq),
            Column::number("amplitude_um", "um", rows.amp),
            Column::number("phase_deg", "deg", rows.phase),
        ],
    )?;
    store::compound_table(
        analysis,
        "order_resonances",
        &[
            Column::text("job_id", peaks.job),
            Column::text("sensor", peaks.sensor),
            Column::text("direction", peaks.direction),
            Column::number("order", "1", peaks.order),
            Column::count("rank", peaks.rank),
            Column::number("speed_hz", "Hz", peaks.speed),
            Column::number("amplitude_um", "um", peaks.amp),
        ],
    )
}
