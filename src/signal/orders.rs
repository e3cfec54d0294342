//! Order tracking: the amplitude and phase of orders k of the spin (integer or fractional,
//! e.g. 0.92 for a roller line) against speed, from a record with a roll angle (keyphasor).
//!
//! In: sample times t [s], the roll angle θ at each sample [rad, unwrapped, non-decreasing; 0
//! at the keyphasor mark], one or more signals sampled at those times (any unit; runout in µm),
//! the orders, and the block length B [revolutions] and hop [revolutions].
//! Out: per block its start revolution, mid time [s], mean speed [Hz] (Δθ / 2πΔt over the
//! block's samples) and per signal and order the complex amplitude A e^{iφ} with
//! x ≈ m + Σ_k A_k cos(k θ + φ_k): modulus in the signal's unit, phase against roll angle 0 —
//! the convention of the constant-speed lines (`signal::lines`) and of the linear unbalance
//! response (x(t) = Re(X e^{iθ})).
//!
//! Method: computed order tracking in the angle domain without interpolation. A block is the
//! samples whose roll angle lies in [θ_s, θ_s + 2πB]; the orders are fitted together with the
//! mean by Hann-in-angle weighted least squares, w = ½(1 − cos(2π(θ − θ_s)/2πB))
//! ([`crate::signal::weighted_lines`] with the angle in revolutions as abscissa). On samples
//! uniform in angle and orders at multiples of 1/B this is the per-block Hann DFT of
//! angle-domain resampled data; on samples uniform in time during a speed change it needs no
//! resampling, so no interpolation error. A record at constant speed is one block over the
//! whole record, which is exactly the constant-speed line fit.
//!
//! Resolution limits: (1) orders fitted together are separated exactly once they differ by
//! more than about 1/B (the fit's conditioning), content at orders not fitted leaks in through
//! the Hann sidelobes (−31 dB at 1.5/B, falling as 1/Δk³), so B ≥ 2/Δk for lines Δk apart that
//! are not all fitted; (2) a block averages over B revolutions, B/f seconds: its speed is the
//! mean, and a response that changes faster than that (a fast ramp through a sharp resonance,
//! half-power width 2ζf_n) is smoothed — keep the speed change per block, rate·B/f, well below
//! 2ζf_n; (3) an order needs more than 2k samples per revolution (angle-domain Nyquist): an
//! order at or above half the block's samples per revolution is NaN.

use rustfft::num_complex::Complex64;

use super::weighted_lines;

/// One tracked block.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// The block's first revolution (θ_s / 2π, from the record's first angle).
    pub revolution: f64,
    /// Mid time of its samples [s].
    pub time_s: f64,
    /// Mean speed over the block [Hz].
    pub speed_hz: f64,
    /// Per signal, per order: A e^{iφ} (module doc); NaN above the angle-domain Nyquist order.
    pub amplitudes: Vec<Vec<Complex64>>,
}

/// Checks the roll angle: as many samples as times, finite, non-decreasing.
fn check_angle(t: &[f64], theta: &[f64]) -> Result<(), String> {
    if theta.len() != t.len() {
        return Err(format!(
            "{} roll-angle samples for {} times",
            theta.len(),
            t.len()
        ));
    }
    if let Some(i) = theta.iter().position(|x| !x.is_finite()) {
        return Err(format!("roll angle not finite at sample {i}"));
    }
    if let Some(i) = theta.windows(2).position(|w| w[1] < w[0]) {
        return Err(format!(
            "roll angle decreases at sample {} ({} → {} rad): it must be unwrapped and the roll \
             must not turn backward",
            i + 1,
            theta[i],
            theta[i + 1]
        ));
    }
    if let Some(i) = t
        .windows(2)
        .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(format!("sample times not ascending at sample {}", i + 1));
    }
    Ok(())
}

/// Fits the orders over the samples `range` with the Hann-in-angle weight over [θ_s, θ_e].
fn fit_block(
    (t, theta): (&[f64], &[f64]),
    signals: &[&[f64]],
    orders: &[f64],
    range: std::ops::Range<usize>,
    (theta_s, theta_e): (f64, f64),
    origin: f64,
) -> Option<Block> {
    let (i0, i1) = (range.start, range.end);
    if i1 < i0 + 3 {
        return None;
    }
    let tau = std::f64::consts::TAU;
    let span = theta_e - theta_s;
    let w: Vec<f64> = theta[i0..i1]
        .iter()
        .map(|a| 0.5 * (1.0 - (tau * (a - theta_s) / span).cos()))
        .collect();
    let revs: Vec<f64> = theta[i0..i1].iter().map(|a| a / tau).collect();
    let dt = t[i1 - 1] - t[i0];
    let dtheta = theta[i1 - 1] - theta[i0];
    if !(dt > 0.0 && dtheta > 0.0) {
        return None;
    }
    let per_rev = (i1 - i0 - 1) as f64 * tau / dtheta;
    let amplitudes = signals
        .iter()
        .map(|x| {
            let mut z = weighted_lines(&x[i0..i1], &revs, &w, orders);
            for (zk, k) in z.iter_mut().zip(orders) {
                if *k >= 0.5 * per_rev {
                    *zk = Complex64::new(f64::NAN, f64::NAN);
                }
            }
            z
        })
        .collect();
    Some(Block {
        revolution: (theta_s - origin) / tau,
        time_s: 0.5 * (t[i0] + t[i1 - 1]),
        speed_hz: dtheta / (tau * dt),
        amplitudes,
    })
}

/// Tracks `orders` in `signals` over blocks of `revolutions` revolutions, `hop` revolutions
/// apart (module doc). Blocks that hold fewer than three samples are left out (a stopped roll).
pub fn track(
    t: &[f64],
    theta: &[f64],
    signals: &[&[f64]],
    orders: &[f64],
    revolutions: f64,
    hop: f64,
) -> Result<Vec<Block>, String> {
    check_angle(t, theta)?;
    if let Some(x) = signals.iter().find(|x| x.len() != t.len()) {
        return Err(format!(
            "a signal has {} samples for {} times",
            x.len(),
            t.len()
        ));
    }
    if !(revolutions > 0.0 && hop > 0.0) {
        return Err("block length and hop must be positive".into());
    }
    let mut out = Vec::new();
    let Some((&first, &last)) = theta.first().zip(theta.last()) else {
        return Ok(out);
    };
    let span = std::f64::consts::TAU * revolutions;
    let mut j = 0u64;
    loop {
        let theta_s = first + j as f64 * std::f64::consts::TAU * hop;
        let theta_e = theta_s + span;
        if theta_e > last {
            break;
        }
        let i0 = theta.partition_point(|a| *a < theta_s);
        let i1 = theta.partition_point(|a| *a <= theta_e);
        out.extend(fit_block(
            (t, theta),
            signals,
            orders,
            i0..i1,
            (theta_s, theta_e),
            first,
        ));
        j += 1;
    }
    Ok(out)
}

/// The orders over the whole record as one block (a record at constant speed, module doc).
pub fn whole(
    t: &[f64],
    theta: &[f64],
    signals: &[&[f64]],
    orders: &[f64],
) -> Result<Option<Block>, String> {
    check_angle(t, theta)?;
    let n = t.len();
    if n < 3 {
        return Ok(None);
    }
    // The Hann weight over the record's span in angle (the first and last sample get weight
    // zero, as the periodic window of `signal::lines` gives the first).
    Ok(fit_block(
        (t, theta),
        signals,
        orders,
        0..n,
        (theta[0], theta[n - 1]),
        theta[0],
    ))
}

/// The roll angle of a keyphasor pulse train: θ = 2π n at the n-th pulse time (ascending,
/// [s]), linear in time between pulses (the speed constant within a revolution), and the first
/// and last revolutions' speeds extrapolated to the record's ends. At least two pulses.
pub fn angle_from_pulses(t: &[f64], pulses: &[f64]) -> Result<Vec<f64>, String> {
    if pulses.len() < 2 {
        return Err(format!(
            "{} keyphasor pulses: at least two are needed",
            pulses.len()
        ));
    }
    if let Some(i) = pulses
        .windows(2)
        .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(format!(
            "keyphasor pulse times not ascending at pulse {}",
            i + 1
        ));
    }
    let tau = std::f64::consts::TAU;
    let last = pulses.len() - 1;
    Ok(t.iter()
        .map(|&x| {
            // The pulse interval holding x (the first or last one outside the pulses).
            let i = pulses.partition_point(|p| *p <= x).clamp(1, last) - 1;
            let frac = (x - pulses[i]) / (pulses[i + 1] - pulses[i]);
            tau * (i as f64 + frac)
        })
        .collect())
}

/// The times of the pulses in a keyphasor signal: each rising crossing of half its range,
/// refined linearly between the two samples around it.
pub fn pulse_times(t: &[f64], signal: &[f64]) -> Vec<f64> {
    let n = t.len().min(signal.len());
    let (lo, hi) = signal[..n]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    let level = 0.5 * (lo + hi);
    let mut out = Vec::new();
    for i in 1..n {
        let (a, b) = (signal[i - 1], signal[i]);
        if a < level && b >= level {
            out.push(t[i - 1] + (level - a) / (b - a) * (t[i] - t[i - 1]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// A ramp f(t) = f0 + r t sampled at fs: times and θ = 2π(f0 t + r t²/2).
    fn ramp(f0: f64, r: f64, fs: f64, secs: f64) -> (Vec<f64>, Vec<f64>) {
        let n = (secs * fs) as usize + 1;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let th = t.iter().map(|t| TAU * (f0 * t + 0.5 * r * t * t)).collect();
        (t, th)
    }

    #[test]
    fn orders_of_a_ramp_are_exact_for_signals_made_of_orders() {
        // 10 → 30 Hz at 4 Hz/s, 1 kHz: x = 40 cos(θ + 0.3) + 7 cos(2θ − 1) + 3 cos(0.92θ + 2)
        // + 5 (constant amplitudes in the angle domain): every block reads them to rounding,
        // the 0.92 line 0.08 orders from 1× included (fitted together; B = 25 > 1/0.08).
        let (t, th) = ramp(10.0, 4.0, 1000.0, 5.0);
        let x: Vec<f64> = th
            .iter()
            .map(|a| {
                40.0 * (a + 0.3).cos()
                    + 7.0 * (2.0 * a - 1.0).cos()
                    + 3.0 * (0.92 * a + 2.0).cos()
                    + 5.0
            })
            .collect();
        let blocks = track(&t, &th, &[&x], &[1.0, 2.0, 0.92], 25.0, 12.5).unwrap();
        assert!(blocks.len() > 5);
        for b in &blocks {
            let z = &b.amplitudes[0];
            assert!((z[0].norm() - 40.0).abs() < 1e-7 && (z[0].arg() - 0.3).abs() < 1e-9);
            assert!((z[1].norm() - 7.0).abs() < 1e-7 && (z[1].arg() + 1.0).abs() < 1e-8);
            assert!((z[2].norm() - 3.0).abs() < 1e-7 && (z[2].arg() - 2.0).abs() < 1e-8);
            // The mean speed of a linear ramp over the block is the speed at its mid time to
            // within the sampling (the block ends on samples, not on the exact angles).
            assert!((b.speed_hz - (10.0 + 4.0 * b.time_s)).abs() < 1e-2, "{b:?}");
        }
    }

    #[test]
    fn whole_record_at_constant_speed_equals_the_line_fit() {
        // 16.4 Hz over 8192 samples at 1 kHz, a 1× and a 2× line and a tone at 0.7× not fitted:
        // the angle-domain fit over the whole record is `signal::lines` to rounding (the same
        // Hann window up to the last sample's weight).
        let fs = 1000.0;
        let t: Vec<f64> = (0..8192).map(|i| i as f64 / fs).collect();
        let th: Vec<f64> = t.iter().map(|t| TAU * 16.4 * t).collect();
        let x: Vec<f64> = th
            .iter()
            .map(|a| 12.0 * (a - 0.4).cos() + 3.0 * (2.0 * a).cos() + 2.0 * (0.7 * a).cos())
            .collect();
        let b = whole(&t, &th, &[&x], &[1.0, 2.0]).unwrap().unwrap();
        let l = crate::signal::lines(&x, &t, &[16.4, 32.8]);
        for (z, e) in b.amplitudes[0].iter().zip(&l) {
            assert!((z - e).norm() < 1e-3, "{z} {e}");
        }
        assert!((b.amplitudes[0][0].norm() - 12.0).abs() < 5e-3);
        assert!((b.speed_hz - 16.4).abs() < 1e-9);
    }

    #[test]
    fn orders_above_the_angle_nyquist_are_nan_and_a_backward_angle_is_refused() {
        // 100 Hz at 1 kHz: 10 samples per revolution, so order 5 and above cannot be told.
        let (t, th) = ramp(100.0, 0.0, 1000.0, 1.0);
        let x: Vec<f64> = th.iter().map(|a| a.cos()).collect();
        let b = track(&t, &th, &[&x], &[1.0, 4.0, 5.0], 8.0, 8.0).unwrap();
        assert!(b[0].amplitudes[0][1].norm().is_finite());
        assert!(b[0].amplitudes[0][2].norm().is_nan());
        let mut back = th.clone();
        back[10] = back[9] - 0.1;
        assert!(track(&t, &back, &[&x], &[1.0], 8.0, 8.0)
            .unwrap_err()
            .contains("decreases at sample 10"));
    }

    #[test]
    fn keyphasor_pulses_give_the_roll_angle() {
        // A ramp 5 → 7.05 Hz over 2.05 s: the pulses at θ = 2πn found in a once-per-revolution
        // signal (a pulse 0.02 rev wide), and the angle rebuilt from them lies within the
        // sampling of the true angle (speed change within a revolution: linear between pulses).
        let (t, th) = ramp(5.0, 1.0, 1000.0, 2.05);
        let sig: Vec<f64> = th
            .iter()
            .map(|a| if (a / TAU).fract() < 0.02 { 1.0 } else { 0.0 })
            .collect();
        let p = pulse_times(&t, &sig);
        // θ(2.05) = 2π·12.35: pulses at n = 1 … 12 (n = 0 at t = 0 is no rising edge).
        assert_eq!(p.len(), 12, "{p:?}");
        let angle = angle_from_pulses(&t, &p).unwrap();
        // θ from pulses counts from the first pulse (n = 1 there).
        for (a, b) in angle.iter().zip(&th).skip(250).step_by(97) {
            assert!((a + TAU - b).abs() < 0.05, "{a} {b}");
        }
        assert!(angle_from_pulses(&t, &p[..1]).is_err());
    }
}
