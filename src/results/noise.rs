//! The noise floor of a record's tracked orders: how large an order's tracked amplitude gets
//! from the record's broadband noise alone, so that a "resonance" of noise (a peak of a flat,
//! noise-only order) can be told from one that stands above it (`report --compare`'s
//! `compare_resonances`).
//!
//! In: one job of a results file with a waterfall (`/jobs/<id>/waterfall`: `freq_hz`,
//! `speed_hz` and `map/<sensor>/<dir>` [µm], written by `results::orders` for a job whose speed
//! changes), its `time` [s] and the order tracking's block length B [revolutions] and orders.
//! Out: per channel ("sensor/direction") a [`NoiseFloor`]: the noise's RMS per sample σ [µm]
//! and the floor [µm] at any speed [Hz].
//!
//! Method: white noise of RMS σ per sample, sampled at fs, reads in a Hann-windowed,
//! amplitude-correct spectrum of N samples (the waterfall's bins) and in a Hann-weighted order
//! fit over M samples (a tracked block) alike: a Rayleigh-distributed amplitude with
//! E|A|² = 4σ²Σw²/(Σw)² = 6σ²/M (Σw = M/2, Σw² = 3M/8), i.e. Rayleigh scale s² = 3σ²/M, median
//! s·√(2 ln 2). σ is estimated from the median of the waterfall's bins over all blocks, leaving
//! out the 0 Hz bin and its neighbour (the static part's window residue) and the bins within
//! 2.5 bins of a tracked order's line k·speed in each block (the Hann main lobe ± half a bin):
//! the other bins hold noise and, here and there, untracked lines, which the median ignores.
//! A block of B revolutions at speed f holds M = B·fs/f samples; the floor there is the
//! amplitude that noise alone exceeds in one block with probability [`FALSE_ALARM`],
//! s·√(2 ln(1/p)) = 4.29 s. Coloured noise is taken as white of the median level (a floor that
//! is too low where the noise is above its median, e.g. at low frequencies); a measured
//! record's σ comes out 8–22 % above the 1 µm the shipped synthetic records were made with
//! (untracked lines and a resonant 1×'s leakage in the median, more with fewer orders
//! tracked): the floor errs high.

use std::collections::BTreeMap;

use crate::numerics::median::median;

/// Probability that noise alone lifts one block's order amplitude above the floor (module doc):
/// 1e-4 per block, i.e. about 0.3 % that a noise-only order over 30 blocks has a block above it.
pub const FALSE_ALARM: f64 = 1e-4;

/// Bins either side of a tracked order's line left out of the noise estimate (module doc).
const LINE_BINS: f64 = 2.5;

/// The noise floor of one channel of one record (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseFloor {
    /// The noise's RMS per sample [µm] (white-noise equivalent of the median bin).
    pub sigma_um: f64,
    /// The record's sample rate [Hz].
    pub sample_rate_hz: f64,
    /// The order tracking's block length [revolutions].
    pub revolutions: f64,
}

impl NoiseFloor {
    /// The floor [µm] of an order tracked over one block at `speed_hz` (module doc); NaN for a
    /// speed that is not positive.
    pub fn at(&self, speed_hz: f64) -> f64 {
        if speed_hz.is_nan() || speed_hz <= 0.0 {
            return f64::NAN;
        }
        let m = self.revolutions * self.sample_rate_hz / speed_hz;
        let scale = (3.0 * self.sigma_um * self.sigma_um / m).sqrt();
        scale * (2.0 * (1.0 / FALSE_ALARM).ln()).sqrt()
    }
}

/// σ [µm] from a waterfall `map` (blocks × bins, row-major) with bin frequencies `freq` [Hz],
/// blocks' speeds `speed` [Hz] and the tracked `orders`, for spectra of N = fs/Δf samples
/// (module doc); NaN with no bin left.
pub fn sigma_from_map(map: &[f64], freq: &[f64], speed: &[f64], orders: &[f64], fs: f64) -> f64 {
    let bins = freq.len();
    if bins < 3 || map.len() != bins * speed.len() {
        return f64::NAN;
    }
    let df = freq[1] - freq[0];
    let mut kept = Vec::with_capacity(map.len());
    for (row, v) in map.chunks(bins).zip(speed) {
        for (a, f) in row.iter().zip(freq).skip(2) {
            let on_line = orders.iter().any(|k| (f - k * v).abs() <= LINE_BINS * df);
            if !on_line && a.is_finite() {
                kept.push(*a);
            }
        }
    }
    let s = median(kept) / (2.0 * 2f64.ln()).sqrt();
    let n = fs / df;
    (n * s * s / 3.0).sqrt()
}

/// The noise floors of every runout channel ("sensor/direction") of `job`, a job with a
/// waterfall, tracked in blocks of `revolutions` at `orders` (module doc); empty without a
/// waterfall or a usable time axis.
pub fn noise_floors(
    job: &hdf5::Group,
    orders: &[f64],
    revolutions: f64,
) -> BTreeMap<String, NoiseFloor> {
    let mut out = BTreeMap::new();
    let read = |name: &str| job.dataset(name).and_then(|d| d.read_raw::<f64>()).ok();
    let (Some(time), Some(freq), Some(speed)) = (
        read("time"),
        read("waterfall/freq_hz"),
        read("waterfall/speed_hz"),
    ) else {
        return out;
    };
    let n = time.len();
    if n < 2 || time[n - 1] <= time[0] {
        return out;
    }
    let fs = (n - 1) as f64 / (time[n - 1] - time[0]);
    let Ok(maps) = job.group("waterfall/map") else {
        return out;
    };
    for sensor in maps.member_names().unwrap_or_default() {
        let Ok(sg) = maps.group(&sensor) else {
            continue;
        };
        for dir in sg.member_names().unwrap_or_default() {
            let Some(map) = read(&format!("waterfall/map/{sensor}/{dir}")) else {
                continue;
            };
            let sigma = sigma_from_map(&map, &freq, &speed, orders, fs);
            if sigma.is_finite() {
                out.insert(
                    format!("{sensor}/{dir}"),
                    NoiseFloor {
                        sigma_um: sigma,
                        sample_rate_hz: fs,
                        revolutions,
                    },
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::{self, orders};

    /// Gaussian samples of RMS `sigma` from a fixed linear congruential sequence (Box–Muller).
    fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut state = seed;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let (u, v) = (uniform(), uniform());
                sigma * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
            })
            .collect()
    }

    #[test]
    fn white_noise_reads_its_sigma_and_its_tracked_orders_stay_under_the_floor() {
        // 20 s at 1 kHz of σ = 1 µm noise plus a 30 µm 1× and a 3 µm 2× on a run-up 30 → 38 Hz,
        // tracked at orders 1–4 in blocks of 8 revolutions: the waterfall's median gives σ
        // within 10 %, and the noise-only 4× stays below the floor in every block.
        let (fs, n, sigma) = (1000.0, 20_000, 1.0);
        let tau = std::f64::consts::TAU;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let theta: Vec<f64> = t.iter().map(|t| tau * (30.0 * t + 0.2 * t * t)).collect();
        let e = noise(n, sigma, 7);
        let x: Vec<f64> = theta
            .iter()
            .zip(&e)
            .map(|(q, e)| 30.0 * q.cos() + 3.0 * (2.0 * q + 1.0).cos() + e)
            .collect();
        let ks = [1.0, 2.0, 3.0, 4.0];
        // The waterfall as results::orders writes it: 1024-sample Hann spectra, half overlapping.
        let len = 1024;
        let (mut map, mut speed) = (Vec::new(), Vec::new());
        let mut freq = Vec::new();
        for s in (0..).map(|i| i * len / 2).take_while(|s| s + len <= n) {
            let b = &x[s..s + len];
            let mean = b.iter().sum::<f64>() / len as f64;
            let centred: Vec<f64> = b.iter().map(|v| v - mean).collect();
            let sp = signal::spectrum(&centred, fs);
            let bins = sp.freq_hz.iter().take_while(|f| **f <= 200.0).count();
            freq = sp.freq_hz[..bins].to_vec();
            map.extend_from_slice(&sp.amplitude[..bins]);
            speed.push((theta[s + len - 1] - theta[s]) / (tau * (t[s + len - 1] - t[s])));
        }
        let est = sigma_from_map(&map, &freq, &speed, &ks, fs);
        assert!((est / sigma - 1.0).abs() < 0.1, "{est}");
        let floor = NoiseFloor {
            sigma_um: est,
            sample_rate_hz: fs,
            revolutions: 8.0,
        };
        let blocks = orders::track(&t, &theta, &[&x], &ks, 8.0, 4.0).unwrap();
        let mut top: f64 = 0.0;
        for b in &blocks {
            let a4 = b.amplitudes[0][3].norm();
            top = top.max(a4 / floor.at(b.speed_hz));
            // The 2× line stands far above it.
            assert!(b.amplitudes[0][1].norm() > 4.0 * floor.at(b.speed_hz));
        }
        assert!(top < 1.0, "{top}");
        // 4.29 Rayleigh scales: at 34 Hz, M = 8 · 1000 / 34 = 235 samples, s = √(3/235).
        let s = (3.0f64 / (8000.0 / 34.0)).sqrt();
        let exact = NoiseFloor {
            sigma_um: 1.0,
            ..floor
        };
        assert!((exact.at(34.0) / s - 4.2919).abs() < 1e-3);
        assert!(exact.at(0.0).is_nan());
    }
}
