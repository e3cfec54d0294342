//! The time-simulation part of a scene: speed profile, modal damping, run window, solver and
//! outputs, validated into SI values.

use std::f64::consts::PI;

use super::file::{DampingFile, OutputsFile, SimulationFile, SolverFile, SpeedFile};
use super::Check;
use crate::error::InputError;

/// Prescribed spin speed Ω(t) [rad/s] and its integral, the roll angle θ(t) [rad].
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedProfile {
    /// Ω constant.
    Constant(f64),
    /// Ω from `from` to `to` linearly between `t0` and `t1`, constant outside.
    Ramp {
        /// Speed before the ramp [rad/s].
        from: f64,
        /// Speed after the ramp [rad/s].
        to: f64,
        /// Ramp start [s].
        t0: f64,
        /// Ramp end [s].
        t1: f64,
    },
    /// Piecewise constant: `speeds[i]` from `times[i]` on (`times[0]` = 0).
    Steps {
        /// Switch times [s], ascending, first 0.
        times: Vec<f64>,
        /// Speeds [rad/s].
        speeds: Vec<f64>,
    },
}

impl SpeedProfile {
    /// (θ, Ω, Ω̇) at time t.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        match self {
            Self::Constant(w) => (w * t, *w, 0.0),
            Self::Ramp { from, to, t0, t1 } => {
                if t <= *t0 {
                    (from * t, *from, 0.0)
                } else if t < *t1 {
                    let a = (to - from) / (t1 - t0);
                    let dt = t - t0;
                    (from * t0 + from * dt + 0.5 * a * dt * dt, from + a * dt, a)
                } else {
                    let th1 = from * t0 + 0.5 * (from + to) * (t1 - t0);
                    (th1 + to * (t - t1), *to, 0.0)
                }
            }
            Self::Steps { times, speeds } => {
                let mut theta = 0.0;
                for i in 0..times.len() {
                    let end = times.get(i + 1).copied().unwrap_or(f64::INFINITY);
                    if t < end {
                        return (theta + speeds[i] * (t - times[i]), speeds[i], 0.0);
                    }
                    theta += speeds[i] * (end - times[i]);
                }
                // Only a NaN t gets here: the last step runs to infinity.
                let last = speeds.len() - 1;
                (theta, speeds[last], 0.0)
            }
        }
    }

    /// The speed Ω [rad/s] and roll-angle offset δ [rad] (θ = Ω t + δ) when Ω is constant over
    /// [t0, t1] (a ramp or step that ends before t0 counts); `None` when it changes there.
    pub fn constant_over(&self, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let constant = match self {
            Self::Constant(_) => true,
            Self::Ramp { t0: r0, t1: r1, .. } => *r1 <= t0 || *r0 >= t1,
            Self::Steps { times, .. } => !times.iter().any(|s| *s > t0 && *s < t1),
        };
        let (theta, w, _) = self.at(t0);
        constant.then_some((w, theta - w * t0))
    }
}

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

/// Which integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Variable-step, variable-order BDF (1–5).
    Bdf,
    /// Generalized-α (Chung–Hulbert).
    GenAlpha,
    /// Explicit Dormand–Prince 5(4).
    Rk45,
}

impl IntegratorKind {
    /// The name used in scene files and results.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Bdf => "bdf",
            Self::GenAlpha => "gen-alpha",
            Self::Rk45 => "rk45",
        }
    }
}

/// Solver settings (meaning of each in `integrators`).
#[derive(Debug, Clone, PartialEq)]
pub struct SolverSettings {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Local error tolerance [m] of displacement (see `integrators`).
    pub tolerance: f64,
    /// Largest step [s].
    pub hmax: f64,
    /// Smallest step [s]: below it the run ends `diverged`.
    pub hmin: f64,
    /// First step [s].
    pub h0: f64,
    /// Highest BDF order (1–5).
    pub max_order: usize,
    /// Generalized-α spectral radius at infinity ρ∞ ∈ [0, 1].
    pub rho_inf: f64,
    /// Generalized-α with fixed step h = hmax (no error control).
    pub fixed_step: bool,
    /// Step budget: more accepted + rejected steps end the run with status `budget`.
    pub max_steps: u64,
    /// CPU budget [s].
    pub cpu_budget: Option<f64>,
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
}

/// Highest spin speed a scene may ask for, Hz (6 million rpm): far above any rotor this tool
/// models (a tube roll turns below 100 Hz, a turbocharger below 5 kHz), and far below where
/// 2π·f, Ω² and the centrifugal loads overflow (speed.hz = 1e308 was accepted).
pub const MAX_SPEED_HZ: f64 = 1e5;

pub(super) fn speed(c: &Check, s: &SpeedFile) -> Result<SpeedProfile, InputError> {
    let hz = |key: &str, v: Option<f64>| -> Result<f64, InputError> {
        let v = v.ok_or_else(|| c.err(key, "missing for this speed profile"))?;
        Ok(2.0 * PI * c.range(key, v, 0.0, MAX_SPEED_HZ)?)
    };
    match s.profile.as_str() {
        "constant" => Ok(SpeedProfile::Constant(hz("speed.hz", s.hz)?)),
        "ramp" => {
            let t0 = c.non_negative("speed.ramp_start_s", s.ramp_start_s.unwrap_or(0.0))?;
            let t1 = s
                .ramp_end_s
                .ok_or_else(|| c.err("speed.ramp_end_s", "missing for a ramp"))?;
            if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
                return Err(c.err("speed.ramp_end_s", "must be after speed.ramp_start_s"));
            }
            Ok(SpeedProfile::Ramp {
                from: hz("speed.from_hz", s.from_hz)?,
                to: hz("speed.to_hz", s.to_hz)?,
                t0,
                t1,
            })
        }
        "steps" => {
            let times = s
                .times_s
                .clone()
                .ok_or_else(|| c.err("speed.times_s", "missing for steps"))?;
            let speeds = s
                .steps_hz
                .clone()
                .ok_or_else(|| c.err("speed.steps_hz", "missing for steps"))?;
            if times.is_empty() || times.len() != speeds.len() || times[0] != 0.0 {
                return Err(c.err(
                    "speed.times_s",
                    "needs as many entries as speed.steps_hz, starting at 0",
                ));
            }
            if times
                .windows(2)
                .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            {
                return Err(c.err("speed.times_s", "must be strictly ascending"));
            }
            let mut sp = Vec::new();
            for (i, v) in speeds.iter().enumerate() {
                let k = format!("speed.steps_hz[{i}]");
                sp.push(2.0 * PI * c.range(&k, *v, 0.0, MAX_SPEED_HZ)?);
            }
            Ok(SpeedProfile::Steps { times, speeds: sp })
        }
        other => Err(c.err(
            "speed.profile",
            format!("`{other}`: expected constant, ramp or steps"),
        )),
    }
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
        other => {
            return Err(c.err(
                "solver.integrator",
                format!("`{other}`: expected bdf, gen-alpha or rk45"),
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
    })
}

pub(super) fn outputs(o: &OutputsFile) -> Outputs {
    Outputs {
        runout: o.runout,
        journal_orbits: o.journal_orbits,
        contact_forces: o.contact_forces,
        stand_motion: o.stand_motion,
        modal: o.modal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_is_constant_over_a_record_after_a_ramp_and_the_angle_offset_follows() {
        // A ramp 0 → 10 rad/s over [1, 3] s: θ(3) = ½·10·2 = 10 rad, so after it θ = 10 t − 20.
        let ramp = SpeedProfile::Ramp {
            from: 0.0,
            to: 10.0,
            t0: 1.0,
            t1: 3.0,
        };
        let (w, d) = ramp
            .constant_over(4.0, 8.0)
            .expect("constant after the ramp");
        assert!((w - 10.0).abs() < 1e-12 && (d + 20.0).abs() < 1e-12);
        assert!(ramp.constant_over(2.0, 8.0).is_none());
        // Steps 5 then 7 rad/s from 2 s: constant over [3, 9] with θ = 7 t − 4 (θ(2) = 10).
        let steps = SpeedProfile::Steps {
            times: vec![0.0, 2.0],
            speeds: vec![5.0, 7.0],
        };
        let (w, d) = steps.constant_over(3.0, 9.0).unwrap();
        assert!((w - 7.0).abs() < 1e-12 && (d + 4.0).abs() < 1e-12);
        assert!(steps.constant_over(1.0, 9.0).is_none());
        assert_eq!(
            SpeedProfile::Constant(3.0).constant_over(0.5, 1.0),
            Some((3.0, 0.0))
        );
    }
}
