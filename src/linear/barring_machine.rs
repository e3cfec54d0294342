//! The barring stability map of a machine's viscoelastic nip, over speed × nip load.
//!
//! In: a [`Machine`] with a nip whose cover is viscoelastic (`cover_unrelaxed_modulus_mpa`,
//! `cover_relaxation_time_s`), the first roll's [`Model`], a [`MapRequest`]: the nip's name
//! (default: the first viscoelastic nip), the first roll's speeds [Hz] and the nip's line loads
//! [kN/m] (default: the file's). Out: a [`BarringMap`]: per load the static nip force [N] at
//! standstill, the rolls' modes on their supports with the nip open (undamped frequency [Hz],
//! damping ratio, share of the nip; information), and per speed the least stable barring root
//! ([`MapPoint`]: growth rate Re λ [1/s] and per revolution, frequency [Hz], waves per
//! revolution of the covered roll and the polygon order, the nip's share of the root, the closed
//! segments and largest penetration [µm] at the rolling equilibrium, the nip's quasi-static
//! rolling stiffness [N/m] and mean overlap μ) with the lowest unstable speed on the grid
//! ([`Onset`]); as JSON (`serde`) and as HDF5 ([`write_h5`]).
//!
//! Method: per load the machine (its nip's line load set) is brought to its static equilibrium at
//! standstill (as `rotorsweep linear`, [`MachineSystem::at_rest`]). Per speed, with the covered
//! roll at its revolution frequency f_c: (1) the steady rolling equilibrium
//! ([`MachineSystem::equilibrium_with`]): each closed segment carries the rolling cover's
//! steady force L F(δ_j) ([`rolling`], `dynamics/cover.rs`), stiffer than the relaxed law of the
//! standstill equilibrium, so the nip closes over fewer segments with other penetrations (the
//! time run's mean state); (2) the machine linearised there, the closed segments' static
//! tangent stiffness taken out of K (the rolls on their supports, the nip's viscous damping in
//! C); (3) the roots of the coupled characteristic equation
//! det[M λ² + C λ + K + Σ_j L_j H_j(λ) J_jᵀ J_j] = 0 over every coordinate of the machine
//! (`linear/barring_coupled.rs`; H_j the rolling cover's response at the vibration's own rate
//! with the memory of every revolution, `dynamics/cover_response.rs`, at segment j's rolling
//! state); the point's root is the rightmost with a nip share of at least [`ROOT_SHARE`] (the
//! rolls' own modes the nip does not touch left out); the polygon order is the nearest whole
//! number of waves per revolution. The earlier map (each of the rolls' modes without the nip
//! taken alone, at the standstill equilibrium) put unstable roots where the coupled time run
//! decays (docs/machines.md). Confirmed by time runs: a single-DOF roll on the cover's points
//! (tests/it/barring_time.rs, [`exact_root`] of a [`NipMode`]: within 3 %) and the coupled
//! two-roll machine (tests/it/barring_machine_time.rs). Assumptions: small vibration about the
//! steady rolling equilibrium; the linearisation at standstill otherwise (no gyroscopic or
//! circulatory terms: measured to move the roots of the shipped machine by at most 0.003 1/s);
//! the rightmost root among those Newton's method reaches from its starts.

use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

use super::barring::{BarringRoll, Root};
use super::barring_coupled::CoupledNip;
use super::modes::ZERO_RAD_S;
use crate::dynamics::bodies::{models, MachineSystem};
use crate::dynamics::cover::{rolling, Rolling};
use crate::dynamics::cover_response::response;
use crate::dynamics::model::Model;
use crate::dynamics::nip::SegmentState;
use crate::numerics::eigen;
use crate::scene::{CoverSpec, Machine, Nip, NipLaw};
use crate::text::number_text;

/// Modes kept: those whose static share of the nip is at least this part of the largest.
pub const MODE_SHARE: f64 = 0.01;

/// Most modes analysed per load.
pub const MAX_MODES: usize = 6;

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// What to map.
#[derive(Debug, Clone, Default)]
pub struct MapRequest {
    /// The nip's name (`None`: the first viscoelastic nip).
    pub nip: Option<String>,
    /// The first roll's speeds [Hz].
    pub speeds_hz: Vec<f64>,
    /// Line loads [kN/m] (`None`: the nip's own).
    pub loads_kn_per_m: Option<Vec<f64>>,
}

/// A mode of the rolls on their supports with the nip open, at one load (information).
#[derive(Debug, Clone, Serialize)]
pub struct MapMode {
    /// Undamped frequency with the nip open [Hz].
    pub freq_hz: f64,
    /// φᵀCφ/(2ω) [-].
    pub damping_ratio: f64,
    /// Its static share of the nip, Σ_j (J_j φ)²/ω², per the largest [-].
    pub nip_share: f64,
}

/// The least stable root at one speed and load.
#[derive(Debug, Clone, Serialize)]
pub struct MapPoint {
    /// The first roll's speed [Hz].
    pub speed_hz: f64,
    /// The covered roll's revolution frequency [Hz].
    pub cover_speed_hz: f64,
    /// Re λ < 0.
    pub stable: bool,
    /// Re λ [1/s].
    pub growth_per_s: f64,
    /// Re λ per revolution of the covered roll [-].
    pub growth_per_rev: f64,
    /// Im λ/2π [Hz].
    pub frequency_hz: f64,
    /// Im λ/(2π f_c): waves round the cover [-].
    pub waves_per_rev: f64,
    /// The nearest whole number of waves: the polygon's sides.
    pub polygon_order: u64,
    /// The nip's share of the root [-] (`linear/barring_coupled.rs`).
    pub nip_share: f64,
    /// Closed segments at the steady rolling equilibrium.
    pub closed_segments: usize,
    /// Largest penetration at the steady rolling equilibrium [µm].
    pub max_penetration_um: f64,
    /// The nip's quasi-static rolling stiffness Σ_j L_j k_c,j over its closed segments [N/m].
    pub contact_stiffness_n_per_m: f64,
    /// The k_c-weighted mean overlap μ of the closed segments [-].
    pub overlap: f64,
}

/// The lowest unstable speed on the grid at one load.
#[derive(Debug, Clone, Serialize)]
pub struct Onset {
    /// The first roll's speed [Hz].
    pub speed_hz: f64,
    /// The highest stable speed below it on the grid [Hz] (`None`: the grid's first speed).
    pub last_stable_hz: Option<f64>,
    /// The covered roll's revolution frequency there [Hz].
    pub cover_speed_hz: f64,
    /// The polygon order there.
    pub polygon_order: u64,
    /// Waves per revolution there.
    pub waves_per_rev: f64,
    /// Re λ there [1/s].
    pub growth_per_s: f64,
}

/// The map at one load.
#[derive(Debug, Clone, Serialize)]
pub struct LoadRow {
    /// Line load [kN/m].
    pub line_load_kn_per_m: f64,
    /// Static nip force [N].
    pub nip_force_n: f64,
    /// Closed segments at the static equilibrium at standstill.
    pub closed_segments: usize,
    /// Largest static penetration at standstill [µm].
    pub max_penetration_um: f64,
    /// The rolls' modes with the nip open, ranked by their static share of the nip.
    pub modes: Vec<MapMode>,
    /// One per speed.
    pub points: Vec<MapPoint>,
    /// The lowest unstable speed (`None`: stable over the grid).
    pub onset: Option<Onset>,
}

/// The barring map of one nip.
#[derive(Debug, Clone, Serialize)]
pub struct BarringMap {
    /// The nip's name.
    pub nip: String,
    /// The covered roll's name.
    pub covered_roll: String,
    /// The covered roll's revolution frequency per first-roll speed [-].
    pub cover_speed_per_speed: f64,
    /// The first roll's speeds [Hz].
    pub speeds_hz: Vec<f64>,
    /// The line loads [kN/m].
    pub loads_kn_per_m: Vec<f64>,
    /// One per load.
    pub loads: Vec<LoadRow>,
}

/// The nip's index and cover (module doc).
fn find_nip(machine: &Machine, name: Option<&str>) -> Result<(usize, CoverSpec), String> {
    let visco = |l: &NipLaw| match l {
        NipLaw::Viscoelastic { cover } => Some(*cover),
        _ => None,
    };
    match name {
        Some(n) => {
            let i = (machine.nips.iter().position(|x| x.name == n))
                .ok_or_else(|| format!("no nip named `{n}`"))?;
            let c = visco(&machine.nips[i].law).ok_or_else(|| {
                format!(
                    "nip `{n}` has no viscoelastic cover (cover_unrelaxed_modulus_mpa, \
                     cover_relaxation_time_s)"
                )
            })?;
            Ok((i, c))
        }
        None => (machine.nips.iter().enumerate())
            .find_map(|(i, x)| visco(&x.law).map(|c| (i, c)))
            .ok_or_else(|| {
                "the machine has no nip with a viscoelastic cover (cover_unrelaxed_modulus_mpa, \
                 cover_relaxation_time_s)"
                    .to_string()
            }),
    }
}

/// The root λ = re + i·im as a [`Root`] at the revolution period `period` [s].
fn root_at(re: f64, im: f64, period: f64, intervals: usize) -> Root {
    let waves = im * period / TAU;
    Root {
        growth_per_s: re,
        growth_per_rev: re * period,
        frequency_hz: im / TAU,
        waves_per_rev: waves,
        lobe: waves.floor() as usize,
        intervals,
    }
}

/// Newton iterations of [`exact_root`] from each start.
pub const NEWTON_ITERATIONS: usize = 60;

/// One mode of a roll in a viscoelastic nip: m η̈ + c η̇ + k η = −Σ_j L_j p_j² ΔF_j/L_j with
/// p_j the mode's displacement at segment j along the nip direction (J_j φ).
#[derive(Debug, Clone)]
pub struct NipMode<'a> {
    /// Modal mass m [kg], damping c [N s/m] and stiffness k [N/m] (the roll without the nip).
    pub roll: BarringRoll,
    /// Per closed segment: its length L [m], p_j, and the cover's steady rolling state there.
    pub segments: Vec<(f64, f64, &'a Rolling)>,
}

/// Where [`exact_root`] starts Newton's method: the quasi-static root `near` shifted in
/// frequency by 0, ±½ and ±1 times the covered roll's revolution frequency `cover_hz` (the
/// delay's roots lie about a revolution frequency apart).
pub const START_SHIFTS: [f64; 5] = [-1.0, -0.5, 0.0, 0.5, 1.0];

/// The root of the mode's exact characteristic equation
/// m λ² + c λ + k + Σ_j L_j p_j² H_j(λ) = 0 (H of `dynamics/cover_response.rs`) found by
/// Newton's method (derivative by a central difference, the function is analytic) from
/// [`START_SHIFTS`] about the quasi-static root `near`; of those that converge (to 1e-10
/// relative) with a positive frequency, the one with the largest real part. `None` when none
/// converges.
pub fn exact_root(mode: &NipMode, cover: &CoverSpec, cover_hz: f64, near: &Root) -> Option<Root> {
    let l0 = Complex::new(near.growth_per_s, TAU * near.frequency_hz);
    let starts = START_SHIFTS.map(|n| l0 + Complex::new(0.0, n * TAU * cover_hz));
    let r = &mode.roll;
    let f = |l: Complex<f64>| {
        let nip: Complex<f64> = (mode.segments.iter())
            .map(|(len, p, roll)| response(cover, roll, cover_hz, l) * (len * p * p))
            .sum();
        l * l * r.mass_kg + l * r.damping_ns_m + r.stiffness_n_m + nip
    };
    let mut best: Option<Complex<f64>> = None;
    for start in starts {
        let mut l = start;
        for _ in 0..NEWTON_ITERATIONS {
            let h = 1e-7 * l.norm().max(1.0);
            let slope = (f(l + h) - f(l - h)) / (2.0 * h);
            let next = l - f(l) / slope;
            let done = (next - l).norm() <= 1e-10 * next.norm();
            l = next;
            if done {
                if l.im > 0.0 && l.re.is_finite() && best.is_none_or(|b| l.re > b.re) {
                    best = Some(l);
                }
                break;
            }
        }
    }
    best.map(|l| root_at(l.re, l.im, 1.0 / cover_hz, 0))
}

/// The indices of the closed segments (δ > 0) of nip `name`; none: an error naming where
/// (`at`) and which equilibrium (`which`).
fn closed_segments(
    seg: &[SegmentState],
    name: &str,
    at: &str,
    which: &str,
) -> Result<Vec<usize>, String> {
    let closed: Vec<usize> = (0..seg.len()).filter(|j| seg[*j].delta > 0.0).collect();
    if closed.is_empty() {
        return Err(format!(
            "at {at} the nip `{name}` is open at its {which} equilibrium"
        ));
    }
    Ok(closed)
}

/// (M, K, C, one nip's segment states, their rows J).
type Linearised = (
    DMatrix<f64>,
    DMatrix<f64>,
    DMatrix<f64>,
    Vec<SegmentState>,
    Vec<DVector<f64>>,
);

/// The machine linearised at rest about `q` ([`MachineSystem::at_rest`]) with nip `ni`'s
/// segments' static tangent stiffness taken out of K: (M, K, C, nip `ni`'s segment states,
/// their rows J).
fn without_nip(sys: &MachineSystem, ni: usize, q: &DVector<f64>) -> Linearised {
    let (m, mut k, c, mut states) = sys.at_rest(q);
    let seg = states.swap_remove(ni);
    let rows = sys.nip_rows_at_rest(ni, q);
    for (s, j) in seg.iter().zip(&rows) {
        if s.stiffness != 0.0 {
            k.ger(-s.stiffness, j, j, 1.0);
        }
    }
    (m, k, c, seg, rows)
}

/// The cover's steady rolling state at segment `j`'s penetration `delta` [m] with the covered
/// roll at `fc` [Hz] ([`rolling`]); not reached: an error naming the speed and the segment.
fn rolling_at(cover: &CoverSpec, delta: f64, fc: f64, j: usize) -> Result<Rolling, String> {
    rolling(cover, delta, fc)
        .ok_or_else(|| format!("the cover's rolling state at {fc} Hz, segment {j}, not reached"))
}

/// Roots whose nip share ([`super::barring_coupled::CoupledRoot::nip_share`]) is below this are the rolls' own modes,
/// which the nip does not touch, and are not barring roots.
pub const ROOT_SHARE: f64 = 0.01;

/// The machine's steady rolling equilibrium at the covered roll's revolution frequency `fc`
/// [Hz] from the standstill equilibrium `q0`: nip `ni`'s closed segments carry the rolling
/// cover's steady force L F(δ) ([`rolling`]; dF/dδ by a central difference of 1e-6 δ).
fn rolling_equilibrium(
    sys: &MachineSystem,
    (ni, len, cover): (usize, f64, &CoverSpec),
    q0: &DVector<f64>,
    fc: f64,
) -> Result<DVector<f64>, String> {
    sys.equilibrium_with(q0.clone(), ni, |j, d| {
        if d <= 0.0 {
            return Ok((0.0, 0.0));
        }
        let force = |x: f64| rolling_at(cover, x, fc, j).map(|r| r.force_n_per_m * len);
        let h = 1e-6 * d;
        Ok((force(d)?, (force(d + h)? - force(d - h)?) / (2.0 * h)))
    })
}

/// The point at the first roll's `speed` [Hz] (the covered roll at `fc` [Hz]): the machine at
/// its steady rolling equilibrium, linearised there, the nip's closed segments with the rolling
/// cover's H, and the rightmost root with a nip share of at least [`ROOT_SHARE`] (module doc).
fn rolling_point(
    sys: &MachineSystem,
    (ni, nip, cover): (usize, &Nip, &CoverSpec),
    q0: &DVector<f64>,
    fc: f64,
    speed: f64,
) -> Result<MapPoint, String> {
    let len = nip.segment_length;
    let q = rolling_equilibrium(sys, (ni, len, cover), q0, fc)?;
    let (m, k_free, c, seg, rows) = without_nip(sys, ni, &q);
    let closed = closed_segments(
        &seg,
        &nip.name,
        &format!("{} Hz", number_text(speed)),
        "rolling",
    )?;
    let states: Vec<Rolling> = (closed.iter())
        .map(|j| rolling_at(cover, seg[*j].delta, fc, *j))
        .collect::<Result<_, _>>()?;
    let coupled = CoupledNip {
        m,
        c,
        k: k_free,
        segments: (closed.iter().zip(&states))
            .map(|(j, r)| (len, rows[*j].clone(), r))
            .collect(),
    };
    let frozen = coupled.frozen(cover, fc)?;
    let root = (coupled.roots(cover, fc, &frozen).into_iter())
        .filter(|r| r.nip_share >= ROOT_SHARE)
        .max_by(|a, b| a.lambda.re.total_cmp(&b.lambda.re))
        .ok_or_else(|| format!("no barring root at {} Hz converged", number_text(speed)))?;
    let (nip_share, root) = (
        root.nip_share,
        root_at(root.lambda.re, root.lambda.im, 1.0 / fc, 0),
    );
    let kc: f64 = states.iter().map(|r| r.stiffness_n_per_m2 * len).sum();
    let mu = states
        .iter()
        .map(|r| r.overlap * r.stiffness_n_per_m2 * len)
        .sum::<f64>()
        / kc;
    Ok(MapPoint {
        speed_hz: speed,
        cover_speed_hz: fc,
        stable: root.growth_per_s < 0.0,
        growth_per_s: root.growth_per_s,
        growth_per_rev: root.growth_per_rev,
        frequency_hz: root.frequency_hz,
        waves_per_rev: root.waves_per_rev,
        polygon_order: root.waves_per_rev.round() as u64,
        nip_share,
        closed_segments: closed.len(),
        max_penetration_um: 1e6 * closed.iter().map(|j| seg[*j].delta).fold(0.0, f64::max),
        contact_stiffness_n_per_m: kc,
        overlap: mu,
    })
}

/// The barring map of `machine` (module doc); `first` is its first roll's model.
pub fn barring_map(
    machine: &Machine,
    first: &Model,
    req: &MapRequest,
) -> Result<BarringMap, String> {
    let (ni, cover) = find_nip(machine, req.nip.as_deref())?;
    if req.speeds_hz.is_empty() || req.speeds_hz.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err("speeds must be positive".into());
    }
    let mut machine = machine.clone();
    for r in &mut machine.rolls {
        r.scene.simulation.static_start = true;
    }
    let nip = machine.nips[ni].clone();
    let covered = if cover.on_b { nip.rolls.1 } else { nip.rolls.0 };
    let first_factor = machine.rolls[0].speed_factor;
    let cover_factor = (machine.rolls[covered].speed_factor / first_factor).abs();
    let loads = (req.loads_kn_per_m.clone()).unwrap_or_else(|| vec![1e-3 * nip.line_load]);
    if loads.is_empty() || loads.iter().any(|q| !(q.is_finite() && *q >= 0.0)) {
        return Err("line loads must be zero or positive".into());
    }
    let models = models(&machine, first)?;
    let mut rows = Vec::with_capacity(loads.len());
    for &q in &loads {
        machine.nips[ni].line_load = 1e3 * q;
        let sys = MachineSystem::new(&machine, &models);
        let q0 = sys.initial(&machine, &models, true)?;
        let (m, k_free, c, seg, jrows) = without_nip(&sys, ni, &q0);
        let k_sym = 0.5 * (&k_free + k_free.transpose());
        let eig = eigen::generalized_symmetric(&k_sym, &m).map_err(|e| e.to_string())?;
        let at = format!("{} kN/m", number_text(q));
        let closed = closed_segments(&seg, &nip.name, &at, "static")?;
        // Candidate modes: (ω, φ, static share Σ_j (J_j φ)²/ω² of the closed segments).
        let mut cand: Vec<(f64, DVector<f64>, f64)> = Vec::new();
        for i in 0..eig.values.len() {
            let w2 = eig.values[i];
            if w2 <= ZERO_RAD_S * ZERO_RAD_S {
                continue;
            }
            let phi = eig.vectors.column(i).into_owned();
            let share = (closed.iter())
                .map(|j| {
                    let p = jrows[*j].dot(&phi);
                    p * p
                })
                .sum::<f64>()
                / w2;
            cand.push((w2.sqrt(), phi, share));
        }
        cand.sort_by(|a, b| b.2.total_cmp(&a.2));
        let top = cand.first().map_or(0.0, |c| c.2);
        cand.retain(|c| c.2 >= MODE_SHARE * top);
        cand.truncate(MAX_MODES);
        let modes: Vec<MapMode> = (cand.iter())
            .map(|(w, phi, share)| MapMode {
                freq_hz: w / TAU,
                damping_ratio: phi.dot(&(&c * phi)) / (2.0 * w),
                nip_share: share / top,
            })
            .collect();
        let mut points = Vec::with_capacity(req.speeds_hz.len());
        for &speed in &req.speeds_hz {
            points.push(rolling_point(
                &sys,
                (ni, &nip, &cover),
                &q0,
                speed * cover_factor,
                speed,
            )?);
        }
        let onset = points.iter().position(|p| !p.stable).map(|i| {
            let p = &points[i];
            Onset {
                speed_hz: p.speed_hz,
                last_stable_hz: i.checked_sub(1).map(|j| points[j].speed_hz),
                cover_speed_hz: p.cover_speed_hz,
                polygon_order: p.polygon_order,
                waves_per_rev: p.waves_per_rev,
                growth_per_s: p.growth_per_s,
            }
        });
        rows.push(LoadRow {
            line_load_kn_per_m: q,
            nip_force_n: seg.iter().map(|s| s.force).sum(),
            closed_segments: closed.len(),
            max_penetration_um: 1e6 * seg.iter().map(|s| s.delta).fold(0.0, f64::max),
            modes,
            points,
            onset,
        });
    }
    Ok(BarringMap {
        nip: nip.name.clone(),
        covered_roll: machine.rolls[covered].name.clone(),
        cover_speed_per_speed: cover_factor,
        speeds_hz: req.speeds_hz.clone(),
        loads_kn_per_m: loads,
        loads: rows,
    })
}
