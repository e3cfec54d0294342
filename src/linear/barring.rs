//! Barring stability: a roll pressed on a cover whose deformation comes back one revolution
//! later, a regenerative system with a delay (like machining chatter).
//!
//! In: a [`BarringRoll`], one mode of the roll in the nip direction: modal mass m [kg],
//! damping c [Ns/m], stiffness k [N/m], and the cover's overlap (memory) factor μ ∈ (0, 1]
//! (the share of the deformation still there one revolution later); the contact stiffness of
//! the nip k_c [N/m] (the cover's dF/dδ at the nip load); the revolution frequency of the
//! covered roll f [Hz] (T = 1/f = 60/rpm). The linearised motion in the nip direction is
//!
//!   m ẍ + c ẋ + k x = −k_c [x(t) − μ x(t − T)].
//!
//! Out: [`rightmost`]: its least stable characteristic root at (k_c, f) as a [`Root`]: growth
//! rate Re λ [1/s] (unstable when > 0), growth per revolution Re λ·T, frequency Im λ/2π [Hz],
//! waves per revolution Im λ·T/2π (the polygon's sides) and the lobe index (its whole part);
//! [`stability_limit`]: the limiting contact stiffness k_lim [N/m] at one speed with the root at
//! onset ([`LobePoint`]; `None` when stable up to [`K_MAX_FACTOR`]·k); [`lobes`]: that over
//! speed; [`growth_map`]: the growth rate on a speed × k_c grid.
//!
//! Method: the characteristic roots by Chebyshev collocation of the delay equation's generator
//! ([`dde_spectrum`], Breda, Maset & Vermiglio 2005) on the state y = (x, ẋ):
//! A₀ = [[0, 1], [−(k + k_c)/m, −c/m]], A₁ = [[0, 0], [μ k_c/m, 0]]. Every root with
//! Re λ ≥ 0 lies in the disk |λ| ≤ R = √((k + (1 + μ)k_c)/m) (there |e^{−λT}| ≤ 1 and
//! |mλ² + cλ| ≥ m|λ|² for c ≥ 0), so the rightmost root is taken among the eigenvalues with
//! |λ| ≤ 1.1R, the artefacts of the discretisation lying farther out. N starts at ⌈RT⌉ + 16
//! intervals and grows by half until the rightmost root moves less than [`ROOT_TOLERANCE`]
//! relative (at most [`dde_spectrum::MAX_INTERVALS`]). The limit: k_c doubled from
//! [`K_START_FACTOR`]·k until unstable (at most up to [`K_MAX_FACTOR`]·k; at k_c = 0 the roll
//! alone is stable, c > 0), then the growth's zero between the last stable and first unstable
//! value by the Illinois method (relative width [`LIMIT_TOLERANCE`], at most
//! [`LIMIT_ITERATIONS`] steps) at the number of intervals converged at the unstable end. The
//! onset found is the lowest on that factor-2 grid: an unstable window narrower than a factor 2
//! below it would be missed. No closed form is used; tests/it/barring.rs checks it against the
//! classical regenerative stability lobes (Tlusty; Altintas & Budak 1995).

use nalgebra::{Complex, DMatrix};
use serde::Serialize;

use crate::numerics::dde_spectrum::{self, DdeError, MAX_INTERVALS};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// Relative change of the rightmost root (to max(|λ|, 1/T)) at which N counts as converged.
pub const ROOT_TOLERANCE: f64 = 1e-6;

/// Relative width of the bracket at which the limit k_lim is accepted.
pub const LIMIT_TOLERANCE: f64 = 1e-6;

/// Most Illinois steps for the limit.
pub const LIMIT_ITERATIONS: usize = 80;

/// First contact stiffness tried, as a share of the roll's k.
pub const K_START_FACTOR: f64 = 1e-3;

/// Largest contact stiffness tried, as a multiple of the roll's k.
pub const K_MAX_FACTOR: f64 = 1e4;

/// One mode of the roll in the nip direction on a cover with memory (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BarringRoll {
    /// Modal mass m [kg].
    pub mass_kg: f64,
    /// Modal damping c [Ns/m].
    pub damping_ns_m: f64,
    /// Modal stiffness k [N/m].
    pub stiffness_n_m: f64,
    /// Overlap factor μ ∈ (0, 1]: the share of the cover's deformation left one revolution later.
    pub overlap: f64,
}

/// Why a barring analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BarringError {
    /// A value out of range, named by its key.
    #[error("barring: `{key}` = {value}: {why}")]
    Input {
        /// The input's key.
        key: &'static str,
        /// Its value.
        value: f64,
        /// The range it must be in.
        why: &'static str,
    },
    /// The collocation or the limit's refinement did not converge within its bound.
    #[error(
        "barring: at k_c = {kc} N/m, {speed_hz} Hz the rightmost root did not converge within \
         {MAX_INTERVALS} Chebyshev intervals or the limit within {LIMIT_ITERATIONS} steps"
    )]
    NotConverged {
        /// Contact stiffness [N/m].
        kc: f64,
        /// Revolution frequency [Hz].
        speed_hz: f64,
    },
    /// The delay equation's spectrum failed.
    #[error(transparent)]
    Spectrum(#[from] DdeError),
}

/// The least stable characteristic root at one contact stiffness and speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Root {
    /// Re λ [1/s]: unstable when positive.
    pub growth_per_s: f64,
    /// Re λ · T: the logarithmic growth per revolution.
    pub growth_per_rev: f64,
    /// |Im λ| / 2π [Hz].
    pub frequency_hz: f64,
    /// |Im λ| T / 2π: waves of the cover per revolution (the polygon's sides).
    pub waves_per_rev: f64,
    /// The lobe index: the whole part of `waves_per_rev`.
    pub lobe: usize,
    /// Chebyshev intervals used.
    pub intervals: usize,
}

/// The stability limit at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LobePoint {
    /// Revolution frequency of the covered roll [Hz].
    pub speed_hz: f64,
    /// The same in rpm.
    pub speed_rpm: f64,
    /// Limiting contact stiffness [N/m]; `None`: stable up to K_MAX_FACTOR·k.
    pub k_lim_n_m: Option<f64>,
    /// The root at onset (at k_lim); `None` with `k_lim_n_m`.
    pub onset: Option<Root>,
}

fn input(key: &'static str, value: f64, ok: bool, why: &'static str) -> Result<(), BarringError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(BarringError::Input { key, value, why })
    }
}

impl BarringRoll {
    /// Checks every value's range.
    pub fn validate(&self) -> Result<(), BarringError> {
        input("mass_kg", self.mass_kg, self.mass_kg > 0.0, "must be > 0")?;
        input(
            "damping_ns_m",
            self.damping_ns_m,
            self.damping_ns_m > 0.0,
            "must be > 0 (the roll alone must be stable)",
        )?;
        input(
            "stiffness_n_m",
            self.stiffness_n_m,
            self.stiffness_n_m > 0.0,
            "must be > 0",
        )?;
        input(
            "overlap",
            self.overlap,
            self.overlap > 0.0 && self.overlap <= 1.0,
            "must be in (0, 1]",
        )
    }

    /// Radius [1/s] of the disk holding every root with Re λ ≥ 0 (module doc).
    fn radius(&self, kc: f64) -> f64 {
        ((self.stiffness_n_m + (1.0 + self.overlap) * kc) / self.mass_kg).sqrt()
    }

    /// The rightmost collocated root in the disk |λ| ≤ 1.1R on `n` intervals.
    fn rightmost_on(&self, kc: f64, period: f64, n: usize) -> Result<Complex<f64>, BarringError> {
        let m = self.mass_kg;
        let a0 = DMatrix::from_row_slice(
            2,
            2,
            &[
                0.0,
                1.0,
                -(self.stiffness_n_m + kc) / m,
                -self.damping_ns_m / m,
            ],
        );
        let a1 = DMatrix::from_row_slice(2, 2, &[0.0, 0.0, self.overlap * kc / m, 0.0]);
        let disk = 1.1 * self.radius(kc);
        dde_spectrum::roots(&a0, &a1, period, n)?
            .into_iter()
            .filter(|l| l.norm() <= disk)
            .max_by(|a, b| a.re.total_cmp(&b.re))
            .map(|l| Complex::new(l.re, l.im.abs()))
            .ok_or(BarringError::NotConverged {
                kc,
                speed_hz: 1.0 / period,
            })
    }

    fn root(&self, l: Complex<f64>, period: f64, n: usize) -> Root {
        let waves = l.im * period / TAU;
        Root {
            growth_per_s: l.re,
            growth_per_rev: l.re * period,
            frequency_hz: l.im / TAU,
            waves_per_rev: waves,
            lobe: waves.floor() as usize,
            intervals: n,
        }
    }

    /// The rightmost root converged in N, starting from `n0` intervals (module doc).
    fn converged(&self, kc: f64, period: f64, n0: usize) -> Result<Root, BarringError> {
        let mut n = n0.max((self.radius(kc) * period).ceil() as usize + 16);
        if n > MAX_INTERVALS {
            return Err(BarringError::NotConverged {
                kc,
                speed_hz: 1.0 / period,
            });
        }
        let mut last = self.rightmost_on(kc, period, n)?;
        loop {
            let next_n = n + n / 2;
            if next_n > MAX_INTERVALS {
                return Err(BarringError::NotConverged {
                    kc,
                    speed_hz: 1.0 / period,
                });
            }
            let next = self.rightmost_on(kc, period, next_n)?;
            let scale = next.norm().max(1.0 / period);
            if (next - last).norm() <= ROOT_TOLERANCE * scale {
                return Ok(self.root(next, period, next_n));
            }
            (n, last) = (next_n, next);
        }
    }
}

fn check_speed(speed_hz: f64) -> Result<f64, BarringError> {
    input("speed_hz", speed_hz, speed_hz > 0.0, "must be > 0")?;
    Ok(1.0 / speed_hz)
}

/// The least stable root at contact stiffness `kc` [N/m] and revolution frequency `speed_hz`.
pub fn rightmost(roll: &BarringRoll, kc: f64, speed_hz: f64) -> Result<Root, BarringError> {
    roll.validate()?;
    input("kc", kc, kc >= 0.0, "must be >= 0")?;
    let period = check_speed(speed_hz)?;
    roll.converged(kc, period, 0)
}

/// The limiting contact stiffness at one speed and the root at onset (module doc).
pub fn stability_limit(roll: &BarringRoll, speed_hz: f64) -> Result<LobePoint, BarringError> {
    roll.validate()?;
    let period = check_speed(speed_hz)?;
    let k = roll.stiffness_n_m;
    let growth_zero = -roll.damping_ns_m / (2.0 * roll.mass_kg);
    let stable = LobePoint {
        speed_hz,
        speed_rpm: 60.0 * speed_hz,
        k_lim_n_m: None,
        onset: None,
    };
    // Bracket: the roll alone (k_c = 0, both roots at −c/2m ± i·…) is stable.
    let (mut lo, mut g_lo) = (0.0, growth_zero);
    let mut hi = K_START_FACTOR * k;
    let top = loop {
        let r = roll.converged(hi, period, 0)?;
        if r.growth_per_s > 0.0 {
            break r;
        }
        if hi >= K_MAX_FACTOR * k {
            return Ok(stable);
        }
        (lo, g_lo) = (hi, r.growth_per_s);
        hi = (2.0 * hi).min(K_MAX_FACTOR * k);
    };
    let n = top.intervals;
    let mut g_hi = top.growth_per_s;
    let (mut side, mut steps) = (0i8, 0);
    while hi - lo > LIMIT_TOLERANCE * hi && steps < LIMIT_ITERATIONS {
        steps += 1;
        let x = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        let x = if x > lo && x < hi { x } else { 0.5 * (lo + hi) };
        let g = roll.rightmost_on(x, period, n)?.re;
        if g > 0.0 {
            (hi, g_hi) = (x, g);
            if side == 1 {
                g_lo *= 0.5;
            }
            side = 1;
        } else {
            (lo, g_lo) = (x, g);
            if side == -1 {
                g_hi *= 0.5;
            }
            side = -1;
        }
    }
    if hi - lo > LIMIT_TOLERANCE * hi {
        return Err(BarringError::NotConverged { kc: hi, speed_hz });
    }
    let x = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    let k_lim = if x >= lo && x <= hi {
        x
    } else {
        0.5 * (lo + hi)
    };
    let onset = roll.converged(k_lim, period, n)?;
    Ok(LobePoint {
        k_lim_n_m: Some(k_lim),
        onset: Some(onset),
        ..stable
    })
}

/// The limit at every speed [Hz] (the stability lobes).
pub fn lobes(roll: &BarringRoll, speeds_hz: &[f64]) -> Result<Vec<LobePoint>, BarringError> {
    speeds_hz
        .iter()
        .map(|s| stability_limit(roll, *s))
        .collect()
}

/// The least stable root on the grid: one row per speed [Hz], one entry per k_c [N/m].
pub fn growth_map(
    roll: &BarringRoll,
    speeds_hz: &[f64],
    kcs: &[f64],
) -> Result<Vec<Vec<Root>>, BarringError> {
    speeds_hz
        .iter()
        .map(|s| kcs.iter().map(|kc| rightmost(roll, *kc, *s)).collect())
        .collect()
}
