//! Signal analysis of sampled runout (physics.md §8): amplitude-correct Hanning spectra of a
//! record's fluctuating part (its mean, the static sag, apart), the complex amplitudes of chosen
//! lines (harmonics k·Ω, roller lines), resonance peaks over a speed sweep with how well the
//! sweep resolves them, and the trial-mass 1× response against a baseline.
//!
//! In: uniformly sampled signals (any unit; runout in µm) with their sample rate [Hz] or their
//! sample times [s], and amplitude curves over speed [Hz].
//! Out: spectra (frequency [Hz], amplitude in the signal's unit), complex line amplitudes
//! (modulus in the signal's unit, phase [rad] relative to t = 0, i.e. to roll angle 0 for a
//! constant speed), peaks (speed [Hz], amplitude). Pure functions, no I/O.

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

use crate::numerics::svd::bounded_svd;

/// The periodic (DFT-even) Hanning window of length n: w_i = ½(1 − cos 2πi/n), Σw = n/2.
pub fn hanning(n: usize) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    (0..n)
        .map(|i| 0.5 * (1.0 - (tau * i as f64 / n as f64).cos()))
        .collect()
}

/// A one-sided amplitude spectrum.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Bin frequencies [Hz], 0 … fs/2 in steps of fs/n.
    pub freq_hz: Vec<f64>,
    /// Amplitude per bin, in the signal's unit: a cosine of amplitude A exactly on a bin reads A
    /// there; the mean reads at 0 Hz.
    pub amplitude: Vec<f64>,
}

/// The amplitude-correct Hanning spectrum of `x` sampled at `fs` [Hz]: |X_k|·2/Σw for 0 < k < n/2,
/// |X_k|/Σw at 0 and at n/2. Empty for fewer than two samples.
pub fn spectrum(x: &[f64], fs: f64) -> Spectrum {
    let n = x.len();
    if n < 2 {
        return Spectrum {
            freq_hz: Vec::new(),
            amplitude: Vec::new(),
        };
    }
    let w = hanning(n);
    let sw: f64 = w.iter().sum();
    let mut buf: Vec<Complex64> = x
        .iter()
        .zip(&w)
        .map(|(a, b)| Complex64::new(a * b, 0.0))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let half = n / 2;
    let amplitude = (0..=half)
        .map(|k| {
            let one_sided = if k == 0 || (n.is_multiple_of(2) && k == half) {
                1.0
            } else {
                2.0
            };
            one_sided * buf[k].norm() / sw
        })
        .collect();
    let freq_hz = (0..=half).map(|k| k as f64 * fs / n as f64).collect();
    Spectrum { freq_hz, amplitude }
}

/// The mean of `x` and the amplitude-correct Hanning spectrum of `x` minus that mean: the static
/// part of a runout record (sag, offset) apart from its fluctuation, so that a large mean does
/// not leak into the lowest bins through the window (otherwise a 306 µm sag reads 306 µm at the first
/// bin too: the Hann window's neighbour bin holds half of the 0 Hz value, and the one-sided
/// spectrum doubles it). The spectrum's 0 Hz bin is then the window's residue of the fluctuation only.
pub fn mean_and_spectrum(x: &[f64], fs: f64) -> (f64, Spectrum) {
    if x.is_empty() {
        return (f64::NAN, spectrum(x, fs));
    }
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let fluct: Vec<f64> = x.iter().map(|v| v - mean).collect();
    (mean, spectrum(&fluct, fs))
}

/// The complex amplitudes of the lines at `freqs_hz` in `x` sampled at times `t` [s], fitted
/// together with the mean by Hann-weighted least squares: x ≈ m + Σ_k A_k cos(2π f_k t + φ_k),
/// returned as A_k e^{iφ_k} (phase relative to t = 0). A signal made of these lines is recovered
/// exactly however close they lie (a roller line at 0.92 × the spin frequency next to 1×);
/// other content leaks in through the window's sidelobes only. Lines the record cannot tell
/// apart (the same frequency twice, 0 Hz, the Nyquist sine) share the minimum-norm solution.
/// Zeros for fewer than two samples.
pub fn lines(x: &[f64], t: &[f64], freqs_hz: &[f64]) -> Vec<Complex64> {
    let n = x.len().min(t.len());
    weighted_lines(&x[..n], &t[..n], &hanning(n), freqs_hz)
}

/// The weighted least-squares fit behind [`lines`], for any abscissa: x ≈ m + Σ_k A_k cos(2π f_k
/// s + φ_k) with weights `w` (one per sample), returned as A_k e^{iφ_k}. With s the time [s] and
/// f_k in Hz it is [`lines`]; with s the roll angle in revolutions and f_k orders it fits orders
/// in the angle domain (`orders`). Zeros for fewer than two samples.
pub fn weighted_lines(x: &[f64], s: &[f64], w: &[f64], freqs: &[f64]) -> Vec<Complex64> {
    weighted_fit(x, s, w, freqs).1
}

/// The fit of [`weighted_lines`] with its mean: (m, [A_k e^{iφ_k}]). The mean fitted together
/// with the lines is the record's static part even over a few periods of a line, where the plain
/// mean (or the window-weighted one) still holds a share of the line: up to A/(π d) for a line of
/// d periods in the record. Zeros for fewer than two samples.
pub fn weighted_fit(x: &[f64], s: &[f64], w: &[f64], freqs: &[f64]) -> (f64, Vec<Complex64>) {
    let n = x.len().min(s.len()).min(w.len());
    let k = freqs.len();
    if n < 2 {
        return (0.0, vec![Complex64::new(0.0, 0.0); k]);
    }
    let m = 2 * k + 1;
    let tau = std::f64::consts::TAU;
    let mut a = DMatrix::<f64>::zeros(m, m);
    let mut b = DVector::<f64>::zeros(m);
    let mut phi = vec![0.0; m];
    let mut sw = 0.0;
    for i in 0..n {
        phi[0] = 1.0;
        for (j, f) in freqs.iter().enumerate() {
            let (sn, c) = (tau * f * s[i]).sin_cos();
            phi[1 + 2 * j] = c;
            phi[2 + 2 * j] = sn;
        }
        sw += w[i];
        for r in 0..m {
            let wr = w[i] * phi[r];
            b[r] += wr * x[i];
            for c in r..m {
                a[(r, c)] += wr * phi[c];
            }
        }
    }
    a.fill_lower_triangle_with_upper_triangle();
    // Relative cut-off for the pseudo-inverse: the Gram matrix's scale is Σw (n/2 for Hann).
    let eps = 2e-12 * sw;
    // No SVD (a value that is not finite, e.g. the phase of an order of 1e308): NaN lines.
    let sol = match bounded_svd(a) {
        Some(svd) => svd.solve(&b, eps).unwrap_or_else(|_| DVector::zeros(m)),
        None => DVector::from_element(m, f64::NAN),
    };
    // c cos ωt + s sin ωt = A cos(ωt + φ) with A cos φ = c, A sin φ = −s.
    let lines = (0..k)
        .map(|j| Complex64::new(sol[1 + 2 * j], -sol[2 + 2 * j]))
        .collect();
    (sol[0], lines)
}

/// A peak of an amplitude curve over speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// The peak's speed [Hz], refined by the parabola through the three samples around it.
    pub speed_hz: f64,
    /// The parabola's value there (never below the highest sample).
    pub amplitude: f64,
    /// The highest sample's index.
    pub index: usize,
}

/// Interior local maxima of `amp` over ascending `speeds`, highest first. A sample (or a run of
/// equal samples) is a peak when the curve rises into it and falls after it; a single sample is
/// refined by the parabola through it and its neighbours, a flat top is reported at its middle.
/// Samples at the ends of the sweep are not peaks: the resonance may lie outside it.
pub fn peaks(speeds: &[f64], amp: &[f64]) -> Vec<Peak> {
    let n = speeds.len().min(amp.len());
    let mut out = Vec::new();
    let mut i = 1;
    while i + 1 < n {
        // The run of samples equal to amp[i].
        let mut j = i;
        while j + 1 < n && amp[j + 1] == amp[i] {
            j += 1;
        }
        let rises = amp[i] > amp[i - 1];
        let falls = j + 1 < n && amp[j + 1] < amp[j];
        if rises && falls {
            out.push(if j > i {
                Peak {
                    speed_hz: 0.5 * (speeds[i] + speeds[j]),
                    amplitude: amp[i],
                    index: i,
                }
            } else {
                refine(speeds, amp, i)
            });
        }
        i = j + 1;
    }
    out.sort_by(|p, q| q.amplitude.total_cmp(&p.amplitude));
    out
}

/// A sweep's spacing [share of the speed] above which a peak is flagged coarse: a peak's speed is
/// uncertain by up to half a step, and a roll's vertical and horizontal resonances lie 5–7 %
/// apart, so a sweep spaced wider than 5 % cannot tell them apart.
pub const COARSE_STEP: f64 = 0.05;

/// How well a sweep resolves one of its peaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolution {
    /// The sweep's spacing around the peak [Hz]: the larger of the steps to its neighbours. The
    /// peak's speed is uncertain by up to half of it.
    pub step_hz: f64,
    /// The step exceeds [`COARSE_STEP`] of the peak's speed.
    pub coarse: bool,
    /// The curve's largest sample lies at an end of the sweep and above this peak: the strongest
    /// response may lie outside the sweep.
    pub edge: bool,
}

impl Resolution {
    /// `coarse`, `edge`, both (`coarse, edge`) or "".
    pub fn note(&self) -> String {
        let mut v = Vec::new();
        if self.coarse {
            v.push("coarse");
        }
        if self.edge {
            v.push("edge");
        }
        v.join(", ")
    }
}

/// The resolution of `peak` on the curve `amp` over ascending `speeds` (module doc of
/// [`Resolution`]).
pub fn resolution(speeds: &[f64], amp: &[f64], peak: &Peak) -> Resolution {
    let n = speeds.len().min(amp.len());
    let i = peak.index.min(n.saturating_sub(1));
    let left = if i > 0 {
        speeds[i] - speeds[i - 1]
    } else {
        0.0
    };
    let right = if i + 1 < n {
        speeds[i + 1] - speeds[i]
    } else {
        0.0
    };
    let step_hz = left.max(right);
    let at_end = |j: usize| amp.get(j).is_some_and(|a| *a > peak.amplitude);
    Resolution {
        step_hz,
        coarse: step_hz > COARSE_STEP * peak.speed_hz.abs(),
        edge: n > 0 && (at_end(0) || at_end(n - 1)),
    }
}

/// The vertex of the parabola through samples i − 1, i, i + 1 (a strict local maximum at i).
fn refine(speeds: &[f64], amp: &[f64], i: usize) -> Peak {
    let (a, b, c) = (amp[i - 1], amp[i], amp[i + 1]);
    let (x0, x1, x2) = (speeds[i - 1], speeds[i], speeds[i + 1]);
    // The parabola in divided differences.
    let d1 = (b - a) / (x1 - x0);
    let d2 = (c - b) / (x2 - x1);
    let curv = (d2 - d1) / (x2 - x0);
    let (mut s, mut v) = (x1, b);
    if curv < 0.0 {
        let xv = 0.5 * (x0 + x1) - d1 / (2.0 * curv);
        // On evenly spaced samples the vertex lies within half a step of the highest sample and
        // at most max(b − a, b − c)/8 above it; unevenly spaced ones (a tracked record's block
        // speeds, noisy from the keyphasor's timing) can put a steep parabola's vertex far
        // above every sample: it is kept within those bounds.
        if (0.5 * (x0 + x1)..=0.5 * (x1 + x2)).contains(&xv) {
            s = xv;
            let rise = (b - a).max(b - c) / 8.0;
            v = (a + d1 * (xv - x0) + curv * (xv - x0) * (xv - x1)).min(b + rise);
        }
    }
    Peak {
        speed_hz: s,
        amplitude: v.max(b),
        index: i,
    }
}

/// The peaks ([`peaks`]) of a curve given as (speed [Hz], amplitude) points in any order, e.g.
/// a run-up's or coast-down's tracked blocks: sorted by speed, non-finite amplitudes left out,
/// and points at one speed (a hold before or after a ramp) counted once at their highest
/// amplitude, since a peak lies between distinct speeds.
pub fn curve_peaks(mut points: Vec<(f64, f64)>) -> Vec<Peak> {
    points.retain(|(_, a)| a.is_finite());
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.dedup_by(|later, kept| {
        let same = (later.0 - kept.0).abs() <= 1e-9 * kept.0.abs().max(1.0);
        if same {
            kept.1 = kept.1.max(later.1);
        }
        same
    });
    let (s, a): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
    peaks(&s, &a)
}

/// The 1× trial-mass response of one channel: the change of a job's complex 1× amplitude
/// against its baseline's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialResponse {
    /// |A| − |A_baseline|, the change of the amplitude.
    pub amplitude_change: f64,
    /// |A − A_baseline|, the size of the vector change (the response to the mass alone for a
    /// linear system).
    pub vector_change: f64,
    /// arg(A − A_baseline) [rad].
    pub vector_phase: f64,
}

/// The trial-mass response of `job` against `baseline` (both complex 1× amplitudes).
pub fn trial_response(job: Complex64, baseline: Complex64) -> TrialResponse {
    let d = job - baseline;
    TrialResponse {
        amplitude_change: job.norm() - baseline.norm(),
        vector_change: d.norm(),
        vector_phase: d.arg(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tone(n: usize, fs: f64, f: f64, a: f64, phi: f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let x = t
            .iter()
            .map(|t| a * (std::f64::consts::TAU * f * t + phi).cos())
            .collect();
        (x, t)
    }

    #[test]
    fn on_bin_tone_reads_its_amplitude() {
        // 8192 samples at 1 kHz (the source's record): bin 200 is 24.414 Hz; a 3.5 µm cosine there
        // plus a 1 µm mean reads 3.5 at bin 200 and 1.0 at 0 Hz (Hanning coherent gain ½ undone).
        let (n, fs) = (8192, 1000.0);
        let f = 200.0 * fs / n as f64;
        let (mut x, _) = tone(n, fs, f, 3.5, 0.7);
        x.iter_mut().for_each(|v| *v += 1.0);
        let s = spectrum(&x, fs);
        assert_eq!(s.amplitude.len(), n / 2 + 1);
        assert!((s.freq_hz[200] - f).abs() < 1e-12);
        assert!(
            (s.amplitude[200] - 3.5).abs() < 1e-9,
            "{}",
            s.amplitude[200]
        );
        assert!((s.amplitude[0] - 1.0).abs() < 1e-9);
        // Hanning leaks into the two neighbours at half amplitude, and nowhere else.
        assert!((s.amplitude[199] - 1.75).abs() < 1e-9);
        assert!(s.amplitude[205] < 1e-9);
    }

    #[test]
    fn half_bin_tone_shows_the_hanning_scalloping_loss() {
        // Half a bin off, both neighbours read A·8/(3π): the Hann window's closed-form scalloping
        // loss, 20·log10(8/(3π)) = −1.42 dB.
        let (n, fs) = (4096, 1000.0);
        let f = 100.5 * fs / n as f64;
        let (x, _) = tone(n, fs, f, 2.0, 0.0);
        let s = spectrum(&x, fs);
        let expect = 2.0 * 8.0 / (3.0 * std::f64::consts::PI);
        assert!((s.amplitude[100] - expect).abs() < 1e-3 * expect);
        assert!((s.amplitude[101] - expect).abs() < 1e-3 * expect);
    }

    #[test]
    fn lines_read_amplitude_and_phase_off_bin_and_close_together() {
        // 16.4 Hz × 2 over 8.192 s is between bins; the fit reads A e^{iφ} of a pure tone on a
        // mean to rounding (the model is exact for it).
        let (n, fs) = (8192, 1000.0);
        let (mut x, t) = tone(n, fs, 32.8, 113.0, -1.1);
        x.iter_mut().for_each(|v| *v += 40.0);
        let c = lines(&x, &t, &[32.8])[0];
        assert!((c.norm() - 113.0).abs() < 1e-8, "{}", c.norm());
        assert!((c.arg() + 1.1).abs() < 1e-10);
        // A roller line at 0.92 × 7.2 Hz, 4.7 bins below a 1× line 20 times stronger: fitted
        // together both are exact; a Hann DFT at 0.92 × 7.2 Hz would be off by up to 0.18 µm
        // (the sidelobe at 4.7 bins is 2.5e-3 of the 74 µm, computed with numpy).
        let (one, _) = tone(n, fs, 7.2, 74.0, 0.4);
        let (rol, _) = tone(n, fs, 0.92 * 7.2, 3.5, -2.0);
        let xy: Vec<f64> = one.iter().zip(&rol).map(|(a, b)| a + b).collect();
        let c = lines(&xy, &t, &[7.2, 0.92 * 7.2]);
        assert!((c[0].norm() - 74.0).abs() < 1e-8 && (c[0].arg() - 0.4).abs() < 1e-10);
        assert!((c[1].norm() - 3.5).abs() < 1e-8 && (c[1].arg() + 2.0).abs() < 1e-10);
        // A tone left out of the fit, 21.5 bins away, leaks through the Hann sidelobes
        // (envelope ∝ 1/k³: 1.6e-3 of its 50 µm), no more.
        let (y, _) = tone(n, fs, 0.92 * 32.8, 50.0, 0.3);
        let xy: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a + b).collect();
        assert!((lines(&xy, &t, &[32.8])[0].norm() - 113.0).abs() < 5e-3);
        // A record that starts later keeps the phase relative to t = 0.
        let t2: Vec<f64> = t.iter().map(|t| t + 3.0).collect();
        let x2: Vec<f64> = t2
            .iter()
            .map(|t| 113.0 * (std::f64::consts::TAU * 32.8 * t - 1.1).cos())
            .collect();
        assert!((lines(&x2, &t2, &[32.8])[0].arg() + 1.1).abs() < 1e-8);
        // The same frequency twice shares the line; too short a record gives zeros.
        let c = lines(&x2, &t2, &[32.8, 32.8]);
        assert!(((c[0] + c[1]).norm() - 113.0).abs() < 1e-6);
        assert_eq!(lines(&x2[..1], &t2[..1], &[32.8])[0].norm(), 0.0);
    }

    #[test]
    fn resonance_of_a_sampled_sdof_curve_is_refined_between_samples() {
        // |H| of a single-DOF oscillator, f_n = 16.23 Hz, ζ = 0.5 %, sampled every 0.2 Hz from 7.2
        // to 20 Hz (the sub-critical sweep). Its exact peak is at f_n·√(1 − 2ζ²) = 16.2296 Hz;
        // the parabola through the three samples around the maximum must land within 0.05 Hz
        // (a quarter of the step), where the highest sample alone is 0.03 Hz off here.
        let (fnat, z) = (16.23_f64, 0.005);
        let speeds: Vec<f64> = (0..=64).map(|i| 7.2 + 0.2 * i as f64).collect();
        let amp: Vec<f64> = speeds
            .iter()
            .map(|f| {
                let r = f / fnat;
                1.0 / ((1.0 - r * r).powi(2) + (2.0 * z * r).powi(2)).sqrt()
            })
            .collect();
        let p = peaks(&speeds, &amp)[0];
        let exact = fnat * (1.0 - 2.0 * z * z).sqrt();
        assert!((p.speed_hz - exact).abs() < 0.05, "{}", p.speed_hz);
        assert!(p.amplitude >= amp[p.index]);
    }

    #[test]
    fn uneven_samples_keep_the_vertex_near_the_highest_one() {
        // Three tracked blocks of a synthetic run-up (tracked 1× [µm] at block speeds [Hz]
        // that the keyphasor's 1 ms timing put 0.01 and 0.58 Hz apart): the parabola through
        // them peaks at 48.78 Hz with 4020 µm, four times every sample. Kept within half a step
        // of 48.49 Hz and max(158, 132)/8 µm above 918 µm, the bounds on even samples.
        let p = peaks(
            &[48.0, 48.48, 48.49, 49.07, 49.5],
            &[700.0, 760.0, 918.0, 786.0, 700.0],
        );
        assert_eq!(p.len(), 1);
        assert!((48.485..=48.78).contains(&p[0].speed_hz), "{:?}", p[0]);
        assert!(
            (918.0..=918.0 + 158.0 / 8.0).contains(&p[0].amplitude),
            "{:?}",
            p[0]
        );
        // Points in any order, a repeated speed counted once at its highest value.
        let c = curve_peaks(vec![
            (3.0, 1.0),
            (1.0, 1.0),
            (2.0, 5.0),
            (2.0, 4.0),
            (4.0, f64::NAN),
        ]);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].speed_hz, c[0].amplitude), (2.0, 5.0));
    }

    #[test]
    fn exact_parabola_is_recovered_and_ends_are_not_peaks() {
        // y = 5 − (x − 1.37)², sampled at 1.0, 1.2, … : the vertex (1.37, 5) exactly.
        let x: Vec<f64> = (0..8).map(|i| 1.0 + 0.2 * i as f64).collect();
        let y: Vec<f64> = x.iter().map(|x| 5.0 - (x - 1.37).powi(2)).collect();
        let p = peaks(&x, &y)[0];
        assert!((p.speed_hz - 1.37).abs() < 1e-12);
        assert!((p.amplitude - 5.0).abs() < 1e-12);
        // A monotone curve has no interior peak, not even through a plateau; a flat top is one
        // peak at its middle, at its own height.
        assert!(peaks(&x, &x).is_empty());
        let s5 = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert!(peaks(&s5[..4], &[1.0, 2.0, 2.0, 3.0]).is_empty());
        let flat = peaks(&s5, &[1.0, 2.0, 2.0, 2.0, 1.0]);
        assert_eq!(flat.len(), 1);
        assert_eq!((flat[0].speed_hz, flat[0].amplitude), (2.0, 2.0));
        // Two peaks come highest first.
        let two = [0.0, 2.0, 0.0, 3.0, 0.0];
        let ps = peaks(&[0.0, 1.0, 2.0, 3.0, 4.0], &two);
        assert_eq!(ps.iter().map(|p| p.index).collect::<Vec<_>>(), vec![3, 1]);
    }

    #[test]
    fn mean_is_apart_from_the_spectrum() {
        // 306 µm of sag under a 3.5 µm line on bin 200 (8192 samples at 1 kHz): the mean reads
        // 306, the line 3.5, and the first bins nothing of the sag. With the sag left in, bin 1
        // reads all of it: the Hann DFT of a constant m at bin 1 is m·n/4, times 2/Σw = 4/n.
        let (n, fs) = (8192, 1000.0);
        let (mut x, _) = tone(n, fs, 200.0 * fs / n as f64, 3.5, 0.2);
        x.iter_mut().for_each(|v| *v += 306.0);
        let (mean, s) = mean_and_spectrum(&x, fs);
        assert!((mean - 306.0).abs() < 1e-9, "{mean}");
        assert!((s.amplitude[200] - 3.5).abs() < 1e-9);
        assert!(
            s.amplitude[0] < 1e-9 && s.amplitude[1] < 1e-9,
            "{:?}",
            &s.amplitude[..2]
        );
        assert!((spectrum(&x, fs).amplitude[1] - 306.0).abs() < 1e-6);
        assert!(mean_and_spectrum(&[], fs).0.is_nan());
    }

    #[test]
    fn resolution_flags_coarse_sweeps_and_edges() {
        // A 4-speed sweep 10, 14, 18, 22 Hz peaking at 14 Hz: step 4 Hz, 29 % of the speed
        // (> 5 %): coarse. The same curve at 0.2 Hz spacing around 16 Hz (1.25 %) is not.
        let speeds = [10.0, 14.0, 18.0, 22.0];
        let amp = [1.0, 3.0, 2.0, 1.0];
        let p = peaks(&speeds, &amp)[0];
        let r = resolution(&speeds, &amp, &p);
        assert_eq!((r.step_hz, r.coarse, r.edge), (4.0, true, false));
        assert_eq!(r.note(), "coarse");
        let fine = [15.8, 16.0, 16.2];
        let p = peaks(&fine, &[1.0, 2.0, 1.5])[0];
        let r = resolution(&fine, &[1.0, 2.0, 1.5], &p);
        assert!((r.step_hz - 0.2).abs() < 1e-12 && !r.coarse && !r.edge);
        // A curve still rising at the sweep's end, above its interior peak: edge.
        let rising = [1.0, 2.0, 1.5, 5.0];
        let p = peaks(&speeds, &rising)[0];
        let r = resolution(&speeds, &rising, &p);
        assert!(r.edge && r.coarse);
        assert_eq!(r.note(), "coarse, edge");
    }

    #[test]
    fn trial_response_of_orthogonal_vectors() {
        // Baseline 3 µm at 0°, with the mass 3 + 4i µm: amplitude change 5 − 3 = 2 µm, vector 4 µm at 90°.
        let r = trial_response(Complex64::new(3.0, 4.0), Complex64::new(3.0, 0.0));
        assert!((r.amplitude_change - 2.0).abs() < 1e-12);
        assert!((r.vector_change - 4.0).abs() < 1e-12);
        assert!((r.vector_phase - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
