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
//!   for the whole record at a constant speed (`signal::orders`, method and limits there);
//! - `/analysis/order_resonances`: table job_id, sensor, direction, order, rank, speed_hz,
//!   amplitude_um — the three highest interior peaks of each order's amplitude over the blocks'
//!   speeds of one job (the resonance speeds of a run-up or coast-down; jobs of ≥ 3 blocks);
//! - `/jobs/<id>/waterfall` for a job whose speed changes: `time_s`, `speed_hz` (mean over each
//!   block), `freq_hz`, `map/<sensor>/<dir>` [blocks × frequencies, µm]: amplitude-correct
//!   Hanning spectra of the fluctuating part of time blocks of 2^⌊log₂ fs⌋ samples (about 1 s),
//!   half overlapping, up to `max_freq_hz` (default [`ORDER_MARGIN`] × the highest
//!   order × the highest speed, as the constant-speed spectra), and `mean/<sensor>/<dir>`
//!   [blocks, µm]: the static part (sag, offset) removed from each block before its spectrum.
//!
//! The static part of a block is the mean m of the Hann-weighted least-squares fit x ≈ m +
//! Σ_k A_k cos(kθ + φ_k) over the block with the tracked orders k (`signal::weighted_fit`).
//! The plain mean is not it at low speed: a block of T seconds holds d = f·T periods of a line
//! at f, and its plain mean keeps A·sin(πd)/(πd)·cos(πd + φ) of it (up to A/(πd): 21 % of the
//! 1× amplitude at d = 1.5, the 3 Hz start of a run-up in 0.512 s blocks, which a static part
//! removed that way leaves at 0 Hz: the 17 % that failed a "0 Hz below 5 % of the peak" check
//! in such blocks).
//! The fitted mean leaves the 0 Hz bin with the fluctuation's own window leakage only, a line
//! d bins away reading A·|sinc d/(1 − d²)|·|cos φ| there: below 5 % of A from d = 1.9 bins on,
//! up to A inside the Hann main lobe (d < 2: speeds below 2/T, the lowest block or two of a
//! run-up from a few Hz), a resolution limit of the block length, not a static part.

use rustfft::num_complex::Complex64;

use super::job_analysis::Tracked;
use super::request::{AnalysisSpec, DEFAULT_ORDER_REVOLUTIONS, ORDER_MARGIN};
use crate::integrators::Status;
use crate::signal::{self, orders as track};
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

/// The static part of the block `x` (samples at roll angles `theta` [rad], the Hann weight `w`
/// in time) and its fluctuation: the mean of the fit with the `orders` below the block's
/// angle-domain Nyquist order (module doc).
fn fluctuation(x: &[f64], theta: &[f64], w: &[f64], orders: &[f64]) -> (f64, Vec<f64>) {
    let tau = std::f64::consts::TAU;
    let n = x.len().min(theta.len());
    let per_rev = match (theta.first(), theta.last()) {
        (Some(a), Some(b)) if b > a => (n.saturating_sub(1)) as f64 * tau / (b - a),
        _ => 0.0,
    };
    let fitted: Vec<f64> = orders
        .iter()
        .copied()
        .filter(|k| *k < 0.5 * per_rev)
        .collect();
    let revs: Vec<f64> = theta[..n].iter().map(|a| a / tau).collect();
    let m = signal::weighted_fit(&x[..n], &revs, w, &fitted).0;
    (m, x[..n].iter().map(|v| v - m).collect())
}

/// The waterfall of one job (module doc).
fn waterfall(
    g: &hdf5::Group,
    (time, theta): (&[f64], &[f64]),
    channels: &[(String, Vec<f64>)],
    orders: &[f64],
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
    let top_order = orders.iter().copied().fold(1.0, f64::max);
    let cap = max_freq_hz
        .unwrap_or(ORDER_MARGIN * top_order * speeds.iter().copied().fold(0.0, f64::max));
    let w = signal::hanning(len);
    if g.link_exists("waterfall") {
        g.unlink("waterfall")?;
    }
    let wg = g.create_group("waterfall")?;
    store::dataset(&wg, "time_s", &mids, "s")?;
    store::dataset(&wg, "speed_hz", &speeds, "Hz")?;
    let mut bins = 0;
    for (c, (name, x)) in channels.iter().enumerate() {
        let mut map = Vec::new();
        let mut means = Vec::with_capacity(starts.len());
        for &s in &starts {
            let (m, fluct) = fluctuation(&x[s..s + len], &theta[s..s + len], &w, orders);
            means.push(m);
            let sp = signal::spectrum(&fluct, fs);
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
        store::dataset(&wg, &format!("mean/{name}"), &means, "um")?;
    }
    Ok(())
}

/// The order tracking of the job in group `g` (module doc), its waterfall written there when
/// its speed changes; `None` when it is left out of the tables.
fn track_from_file(
    g: &hdf5::Group,
    spec: &AnalysisSpec,
    revs: f64,
) -> hdf5::Result<Option<Tracked>> {
    if !store::read_str(g, "status").is_ok_and(|s| Status::name_completed(&s)) {
        return Ok(None);
    }
    let channels = store::runout_channels(g);
    let time = g
        .dataset("time")
        .and_then(|d| d.read_raw::<f64>())
        .unwrap_or_default();
    if channels.is_empty() || time.len() < 3 {
        return Ok(None);
    }
    let Some((theta, constant)) = roll_angle(g, &time) else {
        return Ok(None);
    };
    let signals: Vec<&[f64]> = channels.iter().map(|(_, x)| x.as_slice()).collect();
    let blocks = if constant {
        track::whole(&time, &theta, &signals, &spec.orders).map(|b| b.into_iter().collect())
    } else {
        track::track(&time, &theta, &signals, &spec.orders, revs, 0.5 * revs)
    };
    // A job whose angle cannot be tracked (it never is in a simulated job; an imported one
    // is checked at import) is left out of the tables.
    let Ok(blocks) = blocks else { return Ok(None) };
    if !constant {
        waterfall(
            g,
            (&time, &theta),
            &channels,
            &spec.orders,
            spec.max_freq_hz,
        )?;
    }
    Ok(Some(Tracked {
        names: channels.into_iter().map(|(n, _)| n).collect(),
        blocks,
    }))
}

/// Tracks every job it can and writes the tables into `analysis` (module doc); the jobs in
/// `prepared` (tracked in memory at their constant speed) are taken as they are, the others
/// read from the file.
pub fn write(
    f: &hdf5::File,
    analysis: &hdf5::Group,
    spec: &AnalysisSpec,
    mut prepared: std::collections::BTreeMap<String, Option<Tracked>>,
) -> hdf5::Result<()> {
    let revs = spec.order_revolutions.unwrap_or(DEFAULT_ORDER_REVOLUTIONS);
    let jobs = f.group("jobs")?;
    let mut rows = Rows::default();
    let mut peaks = Peaks::default();
    for id in jobs.member_names()? {
        let tracked = match prepared.remove(&id) {
            Some(t) => t,
            None => track_from_file(&jobs.group(&id)?, spec, revs)?,
        };
        let Some(Tracked { names, blocks }) = tracked else {
            continue;
        };
        for (c, name) in names.iter().enumerate() {
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
                // Peaks over speed (a coast-down runs backward; a hold counts once).
                let points = blocks
                    .iter()
                    .map(|b| (b.speed_hz, b.amplitudes[c][k].norm()))
                    .collect();
                for (r, p) in signal::curve_peaks(points)
                    .into_iter()
                    .take(RANKS)
                    .enumerate()
                {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_static_part_of_a_short_block_is_the_fitted_mean() {
        // A 0.512 s block (256 samples at 500 Hz, the waterfall's block at that rate) at a
        // constant 3.3 Hz, d = 1.69 periods: 306 µm of sag, 30 µm at 1× and 4 µm at 2×.
        let (n, fs, f, a, phi) = (256usize, 500.0, 3.3, 30.0, 0.4);
        let tau = std::f64::consts::TAU;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let theta: Vec<f64> = t.iter().map(|t| tau * f * t).collect();
        let line: Vec<f64> = theta
            .iter()
            .map(|q| a * (q + phi).cos() + 4.0 * (2.0 * q - 1.0).cos())
            .collect();
        let x: Vec<f64> = line.iter().map(|v| v + 306.0).collect();
        let w = signal::hanning(n);
        let (m, fluct) = fluctuation(&x, &theta, &w, &[1.0, 2.0]);
        // The fit models the block exactly: the sag to rounding.
        assert!((m - 306.0).abs() < 1e-9, "{m}");
        // The plain mean keeps the closed-form share of the lines, A sin(πd)/(πd) cos(πd + φ)
        // per line of d periods (the mean of A cos(2πd s + φ) over s in [0, 1), sampled at
        // n points: the sum of the geometric series, exact for the sampled record).
        let d = f * n as f64 / fs;
        let sampled_mean = |amp: f64, d: f64, p: f64| {
            let z: rustfft::num_complex::Complex64 = (0..n)
                .map(|i| Complex64::from_polar(1.0, tau * d * i as f64 / n as f64 + p))
                .sum();
            amp * z.re / n as f64
        };
        let share = sampled_mean(a, d, phi) + sampled_mean(4.0, 2.0 * d, -1.0);
        let plain = x.iter().sum::<f64>() / n as f64;
        assert!((plain - 306.0 - share).abs() < 1e-9, "{plain} {share}");
        // −3.5 µm here, 12 % of A, left at 0 Hz by a plain-mean removal.
        assert!(share.abs() > 0.05 * a, "{share}");
        // After the fitted mean the bins are those of the lines alone (the sag is gone), and
        // 0 Hz reads only their Hann leakage, at most A |sinc d / (1 − d²)| per line.
        let s = signal::spectrum(&fluct, fs);
        let lone = signal::spectrum(&line, fs);
        for (u, v) in s.amplitude.iter().zip(&lone.amplitude).skip(1) {
            assert!((u - v).abs() < 1e-9, "{u} {v}");
        }
        let hann = |d: f64| {
            ((std::f64::consts::PI * d).sin() / (std::f64::consts::PI * d) / (1.0 - d * d)).abs()
        };
        let bound = a * hann(d) + 4.0 * hann(2.0 * d);
        assert!(s.amplitude[0] <= bound + 1e-9, "{} {bound}", s.amplitude[0]);
    }
}
