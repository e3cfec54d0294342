//! The unbalance response's peaks near each critical speed, found without a fine sweep.
//!
//! In: a [`LinearSystem`], a modal unbalance per Ω² (as [`super::response`]), the planes (names
//! and u_x, u_y rows of Φ), the critical speeds [Hz] with their log decrements, and the sampled
//! sweep: speeds [Hz] (ascending) and the orbit's major semi-axis there per plane [m].
//! Out: per plane a [`Peak`] for every local maximum of the response near the critical speeds
//! inside the sweep: its speed [Hz] and major semi-axis [µm], the nearest critical speed, the
//! sweep's largest sample within that critical's band and the peak's half-power level and not
//! above the peak (none: 0), and `coarse` when that sample is more than [`COARSE`] below the
//! peak (the sweep's curve does not show it).
//!
//! Method: each critical speed c has the band c·(1 ± max(4ζ, 0.5 %)) (ζ = δ/√(4π² + δ²) from its
//! log decrement δ); overlapping bands are merged (a close pair's peaks are found once, each
//! with its nearest critical speed); [`SAMPLES`] speeds per critical speed across a band, then
//! golden-section search around every interior local maximum of the samples to 1e-7 of the
//! speed. A band whose samples rise to one of its ends has no peak there: the response keeps
//! rising into a neighbour's peak or to the sweep's end (towards the eccentricity above the
//! criticals); taking the end, or walking on from it, reported the reference roll's 100 Hz
//! sweep end as a peak and its 32.35 Hz peak twice.

use nalgebra::DVector;

use super::response::plane_response;
use crate::dynamics::linear_system::{LinearError, LinearSystem};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// Speeds sampled across a peak before the golden-section search.
pub const SAMPLES: usize = 41;

/// A sweep sample more than this share below the peak marks the peak `coarse`.
pub const COARSE: f64 = 0.01;

/// One response peak (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Peak {
    /// The plane's name.
    pub plane: String,
    /// The critical speed it belongs to [Hz].
    pub critical_hz: f64,
    /// The peak's speed [Hz].
    pub speed_hz: f64,
    /// The orbit's major semi-axis there [µm].
    pub major_um: f64,
    /// The sweep's largest sample of this peak [µm] (module doc; 0: none there).
    pub sampled_um: f64,
    /// Whether the sweep misses the peak by more than [`COARSE`].
    pub coarse: bool,
}

/// The peaks of the response near `critical` ((speed [Hz], log decrement)) (module doc).
pub fn peaks(
    sys: &LinearSystem,
    fc: &DVector<f64>,
    planes: &[(String, nalgebra::DMatrix<f64>)],
    critical: &[(f64, f64)],
    speeds_hz: &[f64],
    sampled_major: &[Vec<f64>],
) -> Result<Vec<Peak>, LinearError> {
    let (Some(&lo), Some(&hi)) = (speeds_hz.first(), speeds_hz.last()) else {
        return Ok(Vec::new());
    };
    // Each critical speed's band, overlapping bands merged: (a, b, [(critical, half-width)]).
    type Window = (f64, f64, Vec<(f64, f64)>);
    let mut windows: Vec<Window> = Vec::new();
    let mut inside: Vec<(f64, f64)> = critical
        .iter()
        .copied()
        .filter(|(c, _)| *c > lo && *c < hi)
        .collect();
    inside.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (c, log_dec) in inside {
        let zeta = (log_dec / (TAU * TAU + log_dec * log_dec).sqrt()).abs();
        let half = (4.0 * zeta).max(0.005) * c;
        let (a, b) = ((c - half).max(lo), (c + half).min(hi));
        match windows.last_mut() {
            Some(w) if a <= w.1 => {
                w.1 = w.1.max(b);
                w.2.push((c, half));
            }
            _ => windows.push((a, b, vec![(c, half)])),
        }
    }
    let mut out = Vec::new();
    for (p, plane) in planes.iter().enumerate() {
        let major = |s: f64| -> Result<f64, LinearError> {
            let r = plane_response(sys, TAU * s, fc, std::slice::from_ref(plane))?;
            Ok(r[0].major())
        };
        for (a, b, crit) in &windows {
            let count = SAMPLES * crit.len();
            let xs: Vec<f64> = (0..count)
                .map(|i| a + (b - a) * i as f64 / (count - 1) as f64)
                .collect();
            let ys = xs
                .iter()
                .map(|&x| major(x))
                .collect::<Result<Vec<_>, _>>()?;
            // Interior local maxima only: a band whose response still rises at an end holds
            // no peak of its own there (the maximum belongs to a neighbour or to the sweep).
            for i in 1..count - 1 {
                if !(ys[i] >= ys[i - 1] && ys[i] > ys[i + 1]) {
                    continue;
                }
                let (speed, peak) = golden(&major, xs[i - 1], xs[i + 1], xs[i], ys[i])?;
                let (c, half) = crit
                    .iter()
                    .copied()
                    .min_by(|x, y| (x.0 - speed).abs().total_cmp(&(y.0 - speed).abs()))
                    .expect("a critical speed per window");
                // The sweep's samples of this peak: near it, within its half-power band, not
                // above it (a higher sample belongs to another part of the curve).
                let sampled = speeds_hz
                    .iter()
                    .zip(&sampled_major[p])
                    .filter(|(s, y)| {
                        (**s - speed).abs() <= half
                            && **y >= peak / 2f64.sqrt()
                            && **y <= peak * (1.0 + 1e-9)
                    })
                    .map(|(_, y)| *y)
                    .fold(0.0, f64::max);
                out.push(Peak {
                    plane: plane.0.clone(),
                    critical_hz: c,
                    speed_hz: speed,
                    major_um: 1e6 * peak,
                    sampled_um: 1e6 * sampled,
                    coarse: sampled < (1.0 - COARSE) * peak,
                });
            }
        }
    }
    Ok(out)
}

/// Golden-section search for the maximum of `f` on [l, r] to 1e-7 of the speed, (x0, y0) the
/// sample it started from: the largest of the candidates.
fn golden(
    f: &impl Fn(f64) -> Result<f64, LinearError>,
    mut l: f64,
    mut r: f64,
    x0: f64,
    y0: f64,
) -> Result<(f64, f64), LinearError> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (r - g * (r - l), l + g * (r - l));
    let (mut f1, mut f2) = (f(x1)?, f(x2)?);
    for _ in 0..200 {
        if r - l <= 1e-7 * x0.abs().max(1e-3) {
            break;
        }
        if f1 >= f2 {
            r = x2;
            x2 = x1;
            f2 = f1;
            x1 = r - g * (r - l);
            f1 = f(x1)?;
        } else {
            l = x1;
            x1 = x2;
            f1 = f2;
            x2 = l + g * (r - l);
            f2 = f(x2)?;
        }
    }
    Ok([(x1, f1), (x2, f2), (x0, y0)]
        .into_iter()
        .max_by(|u, v| u.1.total_cmp(&v.1))
        .expect("three candidates"))
}
