//! The unbalance response's peaks near each critical speed, found without a fine sweep.
//!
//! In: a [`LinearSystem`], a modal unbalance per Ω² (as [`super::response`]), the planes (names
//! and u_x, u_y rows of Φ), the critical speeds [Hz] with their log decrements, and the sampled
//! sweep: speeds [Hz] (ascending) and the orbit's major semi-axis there per plane [m].
//! Out: per critical speed inside the sweep and per plane a [`Peak`]: the speed [Hz] and the
//! major semi-axis [µm] of the response's local maximum, the sweep's largest sample within the
//! peak's half-power band (none: 0), and `coarse` when that sample is more than
//! [`COARSE`] below the peak (the sweep's curve does not show it).
//!
//! Method: [`SAMPLES`] speeds across c·(1 ± max(4ζ, 0.5 %)) around the critical speed c
//! (ζ = δ/√(4π² + δ²) from its log decrement δ), then golden-section search on the bracket of
//! the best sample to 1e-7 of the speed. A peak at the bracket's edge (the maximum lies outside:
//! the response keeps rising, e.g. a split pair) is kept as found there.

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
    /// The sweep's largest sample within the half-power band [µm] (0: none there).
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
    let mut out = Vec::new();
    for &(c, log_dec) in critical.iter().filter(|(c, _)| *c > lo && *c < hi) {
        let zeta = (log_dec / (TAU * TAU + log_dec * log_dec).sqrt()).abs();
        let half = (4.0 * zeta).max(0.005) * c;
        let (a, b) = ((c - half).max(lo), (c + half).min(hi));
        for (p, plane) in planes.iter().enumerate() {
            let major = |s: f64| -> Result<f64, LinearError> {
                let r = plane_response(sys, TAU * s, fc, std::slice::from_ref(plane))?;
                Ok(r[0].major())
            };
            let xs: Vec<f64> = (0..SAMPLES)
                .map(|i| a + (b - a) * i as f64 / (SAMPLES - 1) as f64)
                .collect();
            let ys = xs
                .iter()
                .map(|&x| major(x))
                .collect::<Result<Vec<_>, _>>()?;
            let best = (0..SAMPLES)
                .max_by(|&i, &j| ys[i].total_cmp(&ys[j]))
                .unwrap_or(0);
            let (mut l, mut r) = (xs[best.saturating_sub(1)], xs[(best + 1).min(SAMPLES - 1)]);
            let g = 0.5 * (5f64.sqrt() - 1.0);
            let (mut x1, mut x2) = (r - g * (r - l), l + g * (r - l));
            let (mut f1, mut f2) = (major(x1)?, major(x2)?);
            for _ in 0..200 {
                if r - l <= 1e-7 * c {
                    break;
                }
                if f1 >= f2 {
                    r = x2;
                    x2 = x1;
                    f2 = f1;
                    x1 = r - g * (r - l);
                    f1 = major(x1)?;
                } else {
                    l = x1;
                    x1 = x2;
                    f1 = f2;
                    x2 = l + g * (r - l);
                    f2 = major(x2)?;
                }
            }
            let (speed, peak) = [(x1, f1), (x2, f2), (xs[best], ys[best])]
                .into_iter()
                .max_by(|u, v| u.1.total_cmp(&v.1))
                .expect("three candidates");
            let band = peak / 2f64.sqrt();
            let sampled = speeds_hz
                .iter()
                .zip(&sampled_major[p])
                .filter(|(s, y)| (**s - speed).abs() <= half && **y >= band)
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
    Ok(out)
}
