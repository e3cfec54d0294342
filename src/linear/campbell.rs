//! Damped modes over spin speed: Campbell branches, critical speeds, stability threshold.
//!
//! In: a [`LinearSystem`], spin speeds [Hz] (ascending), an optional upper frequency [Hz].
//! Out: a [`CampbellData`]: the [`ModeSet`] per speed; branches, each one mode followed over
//! speed by its shape (M-weighted MAC between neighbouring speeds, greedy by best match, a
//! frequency change over 50 % never matches), not by rank; the critical speeds [Hz], where a
//! lateral branch's damped frequency equals the spin frequency, refined by regula falsi
//! (Illinois) to 1e-7 Hz following the branch's shape; the stability threshold [Hz], the lowest
//! speed at which some mode (overdamped ones included) has a negative damping ratio, refined the
//! same way; and warnings (zero-frequency modes: a support without stiffness).
//! Frame: stationary (module doc of [`crate::linear`]).

use nalgebra::{Complex, DMatrix, DVector};
use rayon::prelude::*;

use super::basis::Coordinates;
use super::modes::{damped_modes_in, mac, DampedMode, Kind, ModeSet, Split, Whirl, UNSTABLE_ZETA};
use crate::dynamics::linear_system::{LinearError, LinearSystem};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// One Campbell branch.
#[derive(Debug, Clone)]
pub struct Branch {
    /// Per speed: index of the branch's mode in that speed's [`ModeSet`], if present.
    pub mode: Vec<Option<usize>>,
    /// Kind of the branch (at its first speed).
    pub kind: Kind,
}

/// A critical speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Critical {
    /// Spin speed = whirl frequency [Hz].
    pub speed_hz: f64,
    /// Branch index.
    pub branch: usize,
    /// Whirl of the mode there.
    pub whirl: Whirl,
    /// Log decrement of the mode there.
    pub log_dec: f64,
}

/// Damped modes over speed (module doc).
#[derive(Debug, Clone)]
pub struct CampbellData {
    /// Spin speeds [Hz].
    pub speeds_hz: Vec<f64>,
    /// Modes per speed (limited to `max_freq_hz`).
    pub sets: Vec<ModeSet>,
    /// Branches.
    pub branches: Vec<Branch>,
    /// Critical speeds, ascending.
    pub critical: Vec<Critical>,
    /// Lowest unstable speed [Hz], if any in the range.
    pub threshold_hz: Option<f64>,
    /// Notes for the user.
    pub warnings: Vec<String>,
}

type C64 = Complex<f64>;

fn set_at(
    coords: &Coordinates,
    speed_hz: f64,
    max_freq_hz: Option<f64>,
) -> Result<ModeSet, LinearError> {
    let mut s = damped_modes_in(coords, TAU * speed_hz, Split::Whirl)?;
    if let Some(f) = max_freq_hz {
        s.modes.retain(|m| m.freq_hz <= f);
    }
    if let Some(c) = s.cutoff_hz {
        s.modes.retain(|m| m.freq_hz <= LISTED_OF_CUTOFF * c);
    }
    Ok(s)
}

/// A truncated basis lists the modes below this share of its cut-off (the ones near the cut
/// miss the coupling to the modes cut: on the hollow roll at a 3 kHz cut-off the modes below
/// 300 Hz are within 2.1e-5 of the full solve in frequency).
pub const LISTED_OF_CUTOFF: f64 = 0.1;

/// Greedy MAC matching of `prev` shapes to the modes of `next`: for each prev, the index in
/// next.
fn match_modes(
    m: &DMatrix<f64>,
    prev: &[(f64, &DVector<C64>)],
    next: &ModeSet,
) -> Vec<Option<usize>> {
    let mc = m.map(|x| C64::new(x, 0.0));
    let mb: Vec<DVector<C64>> = next.modes.iter().map(|md| &mc * &md.shape).collect();
    let mut pairs = Vec::new();
    for (i, (f, a)) in prev.iter().enumerate() {
        for (j, md) in next.modes.iter().enumerate() {
            if (md.freq_hz - f).abs() > 0.5 * f.abs().max(md.freq_hz.abs()) {
                continue;
            }
            pairs.push((a.dotc(&mb[j]).norm_sqr(), i, j));
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out = vec![None; prev.len()];
    let mut taken = vec![false; next.modes.len()];
    for (_, i, j) in pairs {
        if out[i].is_none() && !taken[j] {
            out[i] = Some(j);
            taken[j] = true;
        }
    }
    out
}

/// The mode at `speed_hz` that continues the shape `a` (best MAC near `f`): its frequency
/// [Hz], whirl and log decrement.
fn follow(
    coords: &Coordinates,
    speed_hz: f64,
    a: &DVector<C64>,
    f: f64,
) -> Result<Option<(f64, Whirl, f64)>, LinearError> {
    let sys = coords.system();
    let set = damped_modes_in(coords, TAU * speed_hz, Split::Whirl)?;
    let best = set
        .modes
        .iter()
        .filter(|m| (m.freq_hz - f).abs() <= 0.5 * f.abs().max(m.freq_hz))
        .map(|m| (mac(&sys.m, a, &m.shape), m))
        .max_by(|x, y| x.0.total_cmp(&y.0));
    Ok(best.map(|(_, m)| (m.freq_hz, m.whirl, m.log_dec)))
}

/// Regula falsi (Illinois) for g(lo) and g(hi) of opposite signs, to |hi − lo| ≤ tol.
fn illinois(
    mut lo: f64,
    mut hi: f64,
    mut glo: f64,
    mut ghi: f64,
    tol: f64,
    mut g: impl FnMut(f64) -> Result<Option<f64>, LinearError>,
) -> Result<f64, LinearError> {
    let mut side = 0;
    for _ in 0..100 {
        if (hi - lo).abs() <= tol {
            break;
        }
        let mut x = (lo * ghi - hi * glo) / (ghi - glo);
        if !(x > lo.min(hi) && x < lo.max(hi)) {
            x = 0.5 * (lo + hi);
        }
        let Some(gx) = g(x)? else {
            // The branch cannot be followed there: bisect.
            hi = 0.5 * (lo + hi);
            continue;
        };
        if gx == 0.0 {
            return Ok(x);
        }
        if (gx > 0.0) == (glo > 0.0) {
            lo = x;
            glo = gx;
            if side == -1 {
                ghi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            ghi = gx;
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Damped modes at `speeds_hz` (ascending) with branches, critical speeds and threshold.
pub fn sweep(
    sys: &LinearSystem,
    speeds_hz: &[f64],
    max_freq_hz: Option<f64>,
) -> Result<CampbellData, LinearError> {
    let range = speeds_hz
        .last()
        .copied()
        .unwrap_or(0.0)
        .max(max_freq_hz.unwrap_or(0.0));
    let coords = Coordinates::new(sys, Some(range))?;
    // Each speed's eigen-solve on the caller's rayon pool; collected in speed order, so the
    // first failing speed's error is the one reported, at any thread count.
    let sets = speeds_hz
        .par_iter()
        .map(|s| set_at(&coords, *s, max_freq_hz))
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let ns = speeds_hz.len();
    let mut branches: Vec<Branch> = Vec::new();
    if let Some(first) = sets.first() {
        for (j, m) in first.modes.iter().enumerate() {
            let mut mode = vec![None; ns];
            mode[0] = Some(j);
            branches.push(Branch { mode, kind: m.kind });
        }
    }
    for s in 1..ns {
        let active: Vec<usize> = (0..branches.len())
            .filter(|b| branches[*b].mode[s - 1].is_some())
            .collect();
        let prev: Vec<(f64, &DVector<C64>)> = active
            .iter()
            .map(|b| {
                let m = &sets[s - 1].modes[branches[*b].mode[s - 1].expect("active")];
                (m.freq_hz, &m.shape)
            })
            .collect();
        let matched = match_modes(&sys.m, &prev, &sets[s]);
        let mut taken = vec![false; sets[s].modes.len()];
        for (b, j) in active.iter().zip(&matched) {
            if let Some(j) = j {
                branches[*b].mode[s] = Some(*j);
                taken[*j] = true;
            }
        }
        for (j, t) in taken.iter().enumerate() {
            if !t {
                let mut mode = vec![None; ns];
                mode[s] = Some(j);
                branches.push(Branch {
                    mode,
                    kind: sets[s].modes[j].kind,
                });
            }
        }
    }
    let mut critical = Vec::new();
    for (bi, b) in branches.iter().enumerate() {
        if b.kind != Kind::Lateral {
            continue;
        }
        for s in 1..ns {
            let (Some(j0), Some(j1)) = (b.mode[s - 1], b.mode[s]) else {
                continue;
            };
            let (m0, m1) = (&sets[s - 1].modes[j0], &sets[s].modes[j1]);
            let g0 = m0.freq_hz - speeds_hz[s - 1];
            let g1 = m1.freq_hz - speeds_hz[s];
            if g0 == 0.0 && s == 1 {
                continue;
            }
            if (g0 > 0.0) == (g1 > 0.0) {
                continue;
            }
            let shape = m0.shape.clone();
            let f0 = m0.freq_hz;
            let mut last = (m0.whirl, m0.log_dec);
            let x = illinois(speeds_hz[s - 1], speeds_hz[s], g0, g1, 1e-7, |x| {
                Ok(follow(&coords, x, &shape, f0)?.map(|(f, w, d)| {
                    last = (w, d);
                    f - x
                }))
            })?;
            critical.push(Critical {
                speed_hz: x,
                branch: bi,
                whirl: last.0,
                log_dec: last.1,
            });
        }
    }
    critical.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    let growth = |set: &ModeSet| set.max_growth + UNSTABLE_ZETA;
    let mut threshold_hz = None;
    if let Some(i) = sets.iter().position(ModeSet::unstable) {
        threshold_hz = Some(if i == 0 {
            speeds_hz[0]
        } else {
            illinois(
                speeds_hz[i - 1],
                speeds_hz[i],
                growth(&sets[i - 1]),
                growth(&sets[i]),
                1e-7,
                |x| {
                    Ok(Some(growth(&damped_modes_in(
                        &coords,
                        TAU * x,
                        Split::Whirl,
                    )?)))
                },
            )?
        });
    }
    let mut warnings = Vec::new();
    if let Some(c) = sets.iter().find_map(|s| s.cutoff_hz) {
        warnings.push(format!(
            "damped modes on the undamped modes below {c:.0} Hz of the {} coordinates ({}× the \
             range): modes listed up to {:.0} Hz",
            sys.n(),
            super::basis::BASIS_FACTOR,
            LISTED_OF_CUTOFF * c
        ));
    }
    let mut rigid: Vec<String> = Vec::new();
    for k in sets.iter().flat_map(|s| &s.rigid) {
        if !rigid.contains(&k.to_string()) {
            rigid.push(k.to_string());
        }
    }
    if !rigid.is_empty() {
        warnings.push(format!(
            "rigid-body mode(s) ({}): a motion the supports and drive do not hold, set apart \
             (zero frequency; no critical speed, no instability)",
            rigid.join(", ")
        ));
    }
    if let Some(z) = sets.iter().map(|s| s.zero_lateral).max().filter(|z| *z > 0) {
        warnings.push(format!(
            "{z} lateral mode(s) at 0 Hz: the supports do not hold a rigid-body motion of the \
             rotor (a support with zero stiffness?); left out of the modes, the critical speeds \
             and the stability check"
        ));
    }
    Ok(CampbellData {
        speeds_hz: speeds_hz.to_vec(),
        sets,
        branches,
        critical,
        threshold_hz,
        warnings,
    })
}

/// Campbell data as the study store keeps it: whirl frequencies per speed and critical speeds.
#[derive(Debug, Clone)]
pub struct Campbell {
    /// Spin speeds [Hz].
    pub speeds_hz: Vec<f64>,
    /// Damped whirl frequencies [Hz] of the lateral modes per speed, ascending.
    pub whirl_hz: Vec<Vec<f64>>,
    /// Speeds [Hz] where a lateral branch crosses the 1× line, ascending.
    pub critical_hz: Vec<f64>,
}

/// Campbell data on `n` speeds from 0 to `max_hz` (branches followed by shape, supports and
/// damping at each speed), the critical speeds refined to 1e-7 Hz.
pub fn campbell(sys: &LinearSystem, max_hz: f64, n: usize) -> Result<Campbell, LinearError> {
    let speeds: Vec<f64> = (0..n)
        .map(|i| max_hz * i as f64 / (n.max(2) - 1) as f64)
        .collect();
    let data = sweep(sys, &speeds, None)?;
    Ok(Campbell {
        whirl_hz: data
            .sets
            .iter()
            .map(|s| {
                s.modes
                    .iter()
                    .filter(|m| m.kind == Kind::Lateral)
                    .map(|m| m.freq_hz)
                    .collect()
            })
            .collect(),
        critical_hz: data.critical.iter().map(|c| c.speed_hz).collect(),
        speeds_hz: speeds,
    })
}

/// What `campbell/whirl` codes mean.
pub const WHIRL_CODES: &str = "1 forward, -1 backward, 0 mixed";

/// A whirl direction as its `campbell/whirl` code.
pub fn whirl_code(w: Whirl) -> f64 {
    match w {
        Whirl::Forward => 1.0,
        Whirl::Backward => -1.0,
        Whirl::Mixed => 0.0,
    }
}

/// Per speed, the lateral modes ascending with their index in that speed's set, and the number
/// of them every speed has (the branches the stored arrays hold).
pub fn lateral_modes(c: &CampbellData) -> (Vec<Vec<(usize, &DampedMode)>>, usize) {
    let lateral: Vec<Vec<(usize, &DampedMode)>> = c
        .sets
        .iter()
        .map(|s| {
            s.modes
                .iter()
                .enumerate()
                .filter(|(_, m)| m.kind == Kind::Lateral)
                .collect()
        })
        .collect();
    let nb = lateral.iter().map(Vec::len).min().unwrap_or(0);
    (lateral, nb)
}
