//! The rest of the time-simulation part of a scene: modal damping, run window, solver and
//! outputs, validated into SI values (the speed profile is [`super::speed`]).
//!
//! In: the `[damping]`, `[simulation]`, `[solver]` and `[outputs]` tables as written (units in
//! key names: `below_hz`, `t_end_s`, `sample_rate_hz`, `runout_bound_mm`, `gravity_m_s2`).
//! Out: [`DampingBands`] (band edges in Hz, ratios), [`SimulationSettings`] (s, Hz, m, m/s²),
//! the integrators' [`SolverSettings`] and [`Outputs`], or an [`InputError`] at the key.
//! Method: each value is checked where it is read; an absent `outputs.speed` records the speed
//! when it changes while recording ([`SpeedProfile::constant_over`]).

use super::check::Check;
use super::file::{DampingFile, OutputsFile, SimulationFile, SolverFile};
use super::speed::SpeedProfile;
use crate::error::InputError;
use crate::integrators::{IntegratorKind, SolverSettings};

/// Modal damping ratio by frequency band: ratio of the first band whose upper edge lies above
/// the mode's frequency, `above` beyond the last band. Rigid modes get none.
#[derive(Debug, Clone, PartialEq)]
pub struct DampingBands {
    /// (upper edge [Hz], ratio [-]), ascending.
    pub bands: Vec<(f64, f64)>,
    /// Ratio above the last edge.
    pub above: f64,
}

impl DampingBands {
    /// The source's comparison runs (thesis-data.md §4): 0.5 % < 250 Hz, 1 % < 1070 Hz, 100 % above.
    pub fn comparison() -> Self {
        Self {
            bands: vec![(250.0, 0.005), (1070.0, 0.01)],
            above: 1.0,
        }
    }

    /// ADAMS default, used in the source's timing runs: 1 % < 100 Hz, 10 % < 1000 Hz, 100 % above.
    pub fn adams_default() -> Self {
        Self {
            bands: vec![(100.0, 0.01), (1000.0, 0.10)],
            above: 1.0,
        }
    }

    /// Damping ratio of a mode at `f` [Hz].
    pub fn ratio(&self, f: f64) -> f64 {
        self.bands
            .iter()
            .find(|(edge, _)| f < *edge)
            .map(|b| b.1)
            .unwrap_or(self.above)
    }
}

/// Run window and sampling.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationSettings {
    /// End time [s].
    pub t_end: f64,
    /// Recording starts here [s].
    pub settle: f64,
    /// Output sample rate [Hz].
    pub sample_rate: f64,
    /// Start from the static equilibrium under gravity.
    pub static_start: bool,
    /// A journal or sensor displacement beyond this [m] ends the run `diverged`.
    pub runout_bound: f64,
    /// Gravitational acceleration [m/s²] (9.81; 0 for checks that need a time-invariant body frame).
    pub gravity: f64,
}

/// What a run records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outputs {
    /// Runout at the sensor planes, vertical and horizontal.
    pub runout: bool,
    /// Journal centre orbits (inertial x, y).
    pub journal_orbits: bool,
    /// Contact force per roller.
    pub contact_forces: bool,
    /// Stand displacement (x, y).
    pub stand_motion: bool,
    /// Modal coordinates.
    pub modal: bool,
    /// The spin speed and the roll angle (keyphasor) as channels `speed/hz` [Hz] and
    /// `speed/roll_angle` [rad, unwrapped, 0 at the keyphasor mark]; by default when the speed
    /// changes while recording.
    pub speed: bool,
}

pub(super) fn damping(c: &Check, d: &DampingFile) -> Result<DampingBands, InputError> {
    match (d.schedule.as_deref(), &d.bands) {
        (Some("comparison") | None, None) => Ok(DampingBands::comparison()),
        (Some("adams-default"), None) => Ok(DampingBands::adams_default()),
        (Some("custom") | None, Some(bands)) => {
            let mut out = Vec::new();
            for (i, b) in bands.iter().enumerate() {
                let k = format!("damping.bands[{i}]");
                let edge = c.positive(&format!("{k}.below_hz"), b.below_hz)?;
                if out.last().is_some_and(|(e, _)| edge <= *e) {
                    return Err(c.err(&format!("{k}.below_hz"), "band edges must ascend"));
                }
                out.push((edge, c.range(&format!("{k}.ratio"), b.ratio, 0.0, 10.0)?));
            }
            Ok(DampingBands {
                bands: out,
                above: c.range(
                    "damping.above_ratio",
                    d.above_ratio.unwrap_or(1.0),
                    0.0,
                    10.0,
                )?,
            })
        }
        (Some(other), None) => Err(c.err(
            "damping.schedule",
            format!("`{other}`: expected comparison, adams-default or custom (with bands)"),
        )),
        (Some(_), Some(_)) => Err(c.err(
            "damping.bands",
            "bands go with schedule = \"custom\" (or no schedule)",
        )),
    }
}

pub(super) fn simulation(c: &Check, s: &SimulationFile) -> Result<SimulationSettings, InputError> {
    let t_end = c.positive("simulation.t_end_s", s.t_end_s)?;
    let settle = c.non_negative("simulation.settle_s", s.settle_s)?;
    if settle >= t_end {
        return Err(c.err("simulation.settle_s", "must be before simulation.t_end_s"));
    }
    Ok(SimulationSettings {
        t_end,
        settle,
        sample_rate: c.positive("simulation.sample_rate_hz", s.sample_rate_hz)?,
        static_start: s.static_start,
        runout_bound: 1e-3 * c.positive("simulation.runout_bound_mm", s.runout_bound_mm)?,
        gravity: c.non_negative("simulation.gravity_m_s2", s.gravity_m_s2)?,
    })
}

pub(super) fn solver(c: &Check, s: &SolverFile) -> Result<SolverSettings, InputError> {
    let integrator = match s.integrator.as_str() {
        "bdf" => IntegratorKind::Bdf,
        "gen-alpha" => IntegratorKind::GenAlpha,
        "rk45" => IntegratorKind::Rk45,
        #[cfg(feature = "cvode")]
        "cvode" => IntegratorKind::Cvode,
        #[cfg(not(feature = "cvode"))]
        "cvode" => {
            return Err(c.err(
                "solver.integrator",
                "`cvode`: this rotorsweep was built without CVODE \
                 (cargo build --release --features cvode; docs/solvers.md, CVODE)",
            ))
        }
        other => {
            return Err(c.err(
                "solver.integrator",
                format!("`{other}`: expected bdf, gen-alpha, rk45 or cvode"),
            ))
        }
    };
    let hmax = c.positive("solver.hmax", s.hmax)?;
    let hmin = c.positive("solver.hmin", s.hmin)?;
    if hmin > hmax {
        return Err(c.err("solver.hmin", "must not exceed solver.hmax"));
    }
    if hmin > s.h0 {
        return Err(c.err(
            "solver.hmin",
            format!("must not exceed solver.h0 = {}", s.h0),
        ));
    }
    Ok(SolverSettings {
        integrator,
        tolerance: c.positive("solver.tolerance", s.tolerance)?,
        hmax,
        hmin,
        h0: c.positive("solver.h0", s.h0)?.min(hmax),
        max_order: c.count("solver.max_order", s.max_order, 1, 5)?,
        rho_inf: c.range("solver.rho_inf", s.rho_inf, 0.0, 1.0)?,
        fixed_step: s.fixed_step,
        max_steps: s.max_steps.max(1),
        cpu_budget: s
            .cpu_budget_s
            .map(|b| c.positive("solver.cpu_budget_s", b))
            .transpose()?,
        contact_events: s.contact_events,
    })
}

pub(super) fn outputs(o: &OutputsFile, speed: &SpeedProfile, sim: &SimulationSettings) -> Outputs {
    Outputs {
        speed: o
            .speed
            .unwrap_or_else(|| speed.constant_over(sim.settle, sim.t_end).is_none()),
        runout: o.runout,
        journal_orbits: o.journal_orbits,
        contact_forces: o.contact_forces,
        stand_motion: o.stand_motion,
        modal: o.modal,
    }
}
