//! A machine's external loads in time: loading-arm forces and web-tension line loads.
//!
//! In: a machine file's `[[rolls]]` arm keys (`arm_force_n` and the `arm_*` time keys) and its
//! `[[webs]]` (keys in `docs/scene-keys.md`), read by `machine.rs`. Out: a [`LoadHistory`] per
//! roll's arms [N per support node] and a [`Web`] per web (its roll, axial range [m] and line
//! load [N/m] in time), in the inertial frame (x, y up), or an [`InputError`] naming the file,
//! key and line.
//!
//! Method: a load is a vector F(t) in the inertial frame, one of
//! - `constant`: F(t) = F₀;
//! - `harmonic`: F(t) = F₀ + A sin(2π f t + φ) (with φ = 0 it starts at F₀, no step at t = 0);
//! - `table`: F(t) linear between the points (tᵢ, Fᵢ), t₀ = 0, held at the last value after it.
//!
//! Its *steady* part, the load of the static equilibrium that starts a run and of `linear`, is
//! F₀ (a table's: its value at t = 0). A web of tension T [N/m of width] wrapped over an angle θ
//! presses the roll with the resultant 2T sin(θ/2) per unit length along the wrap's bisector
//! (the capstan resultant of a belt without friction: e.g. Meriam & Kraige, *Engineering
//! Mechanics: Statics*, §6/9), applied as a uniform line load over [from_mm, to_mm]; T(t) is
//! constant, harmonic or a table as above, and may never fall below zero (a web cannot push).

use super::check::Check;
use super::machine_file::{MachineRollFile, WebFile};
use crate::error::InputError;
use crate::text::number_text;

/// How a load varies about its steady part (module doc).
#[derive(Debug, Clone, PartialEq)]
pub enum Variation {
    /// No variation.
    Constant,
    /// A sin(2π f t + φ) on top of the steady part: amplitude A (x, y), f [Hz], φ [rad].
    Harmonic {
        /// Amplitude (x, y) in the load's units.
        amplitude: [f64; 2],
        /// Frequency [Hz].
        frequency: f64,
        /// Phase [rad].
        phase: f64,
    },
    /// The load itself, linear between (time [s], value) points, held after the last.
    Table {
        /// Times [s], from 0, increasing.
        times: Vec<f64>,
        /// Values (x, y) at the times.
        values: Vec<[f64; 2]>,
    },
}

/// A load vector in time (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadHistory {
    /// The steady part (x, y): the load of the static equilibrium.
    pub steady: [f64; 2],
    /// Its variation in time.
    pub variation: Variation,
}

impl LoadHistory {
    /// A load without variation.
    pub fn constant(steady: [f64; 2]) -> Self {
        Self {
            steady,
            variation: Variation::Constant,
        }
    }

    /// The load at time `t` [s].
    pub fn at(&self, t: f64) -> [f64; 2] {
        match &self.variation {
            Variation::Constant => self.steady,
            Variation::Harmonic {
                amplitude,
                frequency,
                phase,
            } => {
                let s = (2.0 * std::f64::consts::PI * frequency * t + phase).sin();
                [
                    self.steady[0] + amplitude[0] * s,
                    self.steady[1] + amplitude[1] * s,
                ]
            }
            Variation::Table { times, values } => {
                let i = times.partition_point(|x| *x <= t);
                if i == 0 {
                    return values[0];
                }
                if i == times.len() {
                    return values[i - 1];
                }
                let s = (t - times[i - 1]) / (times[i] - times[i - 1]);
                let (a, b) = (values[i - 1], values[i]);
                [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
            }
        }
    }

    /// Whether it varies in time.
    pub fn varies(&self) -> bool {
        self.variation != Variation::Constant
    }
}

/// A web's line load on one roll (module doc).
#[derive(Debug, Clone)]
pub struct Web {
    /// Its name.
    pub name: String,
    /// Index of its roll among the machine's rolls.
    pub roll: usize,
    /// Axial range [m] it wraps.
    pub z: (f64, f64),
    /// Tension T [N/m]: its steady part (a table's value at t = 0).
    pub tension: f64,
    /// Wrap angle θ [rad].
    pub wrap: f64,
    /// The line load [N/m] (x, y, inertial): 2 T(t) sin(θ/2) along the resultant's direction.
    pub load: LoadHistory,
}

/// The time keys of one load, their names and values as the file gives them.
struct TimeKeys<'a> {
    profile: (&'a str, Option<&'a str>),
    amplitude: (&'a str, Option<[f64; 2]>),
    frequency: (&'a str, Option<f64>),
    phase: (&'a str, Option<f64>),
    times: (&'a str, Option<&'a [f64]>),
    table: (&'a str, Option<Vec<[f64; 2]>>),
}

/// The variation the time keys give, the steady key (`steady`: its name and whether the file
/// gave it) checked against the profile: a table replaces it.
fn variation(c: &Check, k: TimeKeys, steady: (&str, bool)) -> Result<Variation, InputError> {
    let profile = k.profile.1.unwrap_or("constant");
    let only = |key: &str, given: bool, p: &str| {
        if given && profile != p {
            Err(c.err(key, format!("only for {} = \"{p}\"", k.profile.0)))
        } else {
            Ok(())
        }
    };
    only(k.amplitude.0, k.amplitude.1.is_some(), "harmonic")?;
    only(k.frequency.0, k.frequency.1.is_some(), "harmonic")?;
    only(k.phase.0, k.phase.1.is_some(), "harmonic")?;
    only(k.times.0, k.times.1.is_some(), "table")?;
    only(k.table.0, k.table.1.is_some(), "table")?;
    let required = |key: &str| {
        c.err(
            k.profile.0,
            format!("profile \"{profile}\" needs `{key}` too"),
        )
    };
    match profile {
        "constant" => Ok(Variation::Constant),
        "harmonic" => {
            let a = k.amplitude.1.ok_or_else(|| required(k.amplitude.0))?;
            for v in a {
                c.finite(k.amplitude.0, v)?;
            }
            let f = k.frequency.1.ok_or_else(|| required(k.frequency.0))?;
            let phase = c.finite(k.phase.0, k.phase.1.unwrap_or(0.0))?;
            Ok(Variation::Harmonic {
                amplitude: a,
                frequency: c.positive(k.frequency.0, f)?,
                phase: phase.to_radians(),
            })
        }
        "table" => {
            if steady.1 {
                return Err(c.err(
                    steady.0,
                    format!(
                        "not with {} = \"table\": the table gives the load from t = 0 on",
                        k.profile.0
                    ),
                ));
            }
            let times = k.times.1.ok_or_else(|| required(k.times.0))?;
            let values = k.table.1.ok_or_else(|| required(k.table.0))?;
            if times.len() < 2 || times.len() != values.len() {
                return Err(c.err(
                    k.times.0,
                    format!(
                        "needs two or more times, as many as {} has values ({} and {})",
                        k.table.0,
                        times.len(),
                        values.len()
                    ),
                ));
            }
            for (i, t) in times.iter().enumerate() {
                let t = c.finite(k.times.0, *t)?;
                let ok = if i == 0 { t == 0.0 } else { t > times[i - 1] };
                if !ok {
                    return Err(c.err(
                        k.times.0,
                        format!(
                            "must start at 0 and increase, got {} after {}",
                            number_text(t),
                            if i == 0 {
                                "nothing".to_string()
                            } else {
                                number_text(times[i - 1])
                            }
                        ),
                    ));
                }
            }
            for v in values.iter().flatten() {
                c.finite(k.table.0, *v)?;
            }
            Ok(Variation::Table {
                times: times.to_vec(),
                values,
            })
        }
        other => Err(c.err(
            k.profile.0,
            format!("unknown profile `{other}` (constant, harmonic, table)"),
        )),
    }
}

/// An [x, y] pair at `key`.
fn pair(c: &Check, key: &str, v: &[f64]) -> Result<[f64; 2], InputError> {
    match v {
        [x, y] => Ok([c.finite(key, *x)?, c.finite(key, *y)?]),
        _ => Err(c.err(key, format!("must be [x, y], got {} numbers", v.len()))),
    }
}

/// The loading-arm force of roll `i` [N per support node] in time.
pub(super) fn arm(c: &Check, i: usize, r: &MachineRollFile) -> Result<LoadHistory, InputError> {
    let key = |k: &str| format!("rolls[{i}].{k}");
    let (steady_key, amp_key, table_key) = (
        key("arm_force_n"),
        key("arm_amplitude_n"),
        key("arm_table_n"),
    );
    let steady = pair(
        c,
        &steady_key,
        r.arm_force_n.as_deref().unwrap_or(&[0.0, 0.0]),
    )?;
    let amplitude = match &r.arm_amplitude_n {
        Some(a) => Some(pair(c, &amp_key, a)?),
        None => None,
    };
    let table = match &r.arm_table_n {
        Some(rows) => Some(
            rows.iter()
                .map(|v| pair(c, &table_key, v))
                .collect::<Result<Vec<_>, _>>()?,
        ),
        None => None,
    };
    let keys = TimeKeys {
        profile: (&key("arm_profile"), r.arm_profile.as_deref()),
        amplitude: (&amp_key, amplitude),
        frequency: (&key("arm_frequency_hz"), r.arm_frequency_hz),
        phase: (&key("arm_phase_deg"), r.arm_phase_deg),
        times: (&key("arm_times_s"), r.arm_times_s.as_deref()),
        table: (&table_key, table),
    };
    let variation = variation(c, keys, (&steady_key, r.arm_force_n.is_some()))?;
    let steady = match &variation {
        Variation::Table { values, .. } => values[0],
        _ => steady,
    };
    Ok(LoadHistory { steady, variation })
}

/// Web `i` on the machine's rolls (`names`, each with its axial extent [m]).
pub(super) fn web(
    c: &Check,
    i: usize,
    w: &WebFile,
    names: &[&str],
    extents: &[(f64, f64)],
) -> Result<Web, InputError> {
    let key = |k: &str| format!("webs[{i}].{k}");
    let roll = names.iter().position(|n| *n == w.roll).ok_or_else(|| {
        c.err(
            &key("roll"),
            format!("unknown roll `{}` (rolls: {})", w.roll, names.join(", ")),
        )
    })?;
    let z0 = 1e-3 * c.finite(&key("from_mm"), w.from_mm)?;
    let z1 = 1e-3 * c.finite(&key("to_mm"), w.to_mm)?;
    if z1 <= z0 {
        return Err(c.err(&key("to_mm"), "must be beyond from_mm"));
    }
    let (lo, hi) = extents[roll];
    if z0 < lo - 1e-9 || z1 > hi + 1e-9 {
        return Err(c.err(
            &key("from_mm"),
            format!(
                "the range {}–{} mm must lie on roll `{}` ({}–{} mm)",
                number_text(w.from_mm),
                number_text(w.to_mm),
                w.roll,
                number_text(1e3 * lo),
                number_text(1e3 * hi)
            ),
        ));
    }
    let wrap = c.finite(&key("wrap_deg"), w.wrap_deg)?;
    if !(wrap > 0.0 && wrap <= 360.0) {
        return Err(c.err(
            &key("wrap_deg"),
            format!("must lie in (0, 360] degrees, got {}", number_text(wrap)),
        ));
    }
    let dir = c
        .finite(&key("resultant_deg"), w.resultant_deg)?
        .to_radians();
    // Line load [N/m] per tension [kN/m] along the resultant's direction.
    let per = 1e3 * 2.0 * (0.5 * wrap.to_radians()).sin();
    let along = |t: f64| [per * t * dir.cos(), per * t * dir.sin()];
    let tension_key = key("tension_kn_per_m");
    let tension = match w.tension_kn_per_m {
        Some(t) => c.non_negative(&tension_key, t)?,
        None if w.profile.as_deref() == Some("table") => 0.0,
        None => return Err(c.err(&tension_key, "required unless profile = \"table\"")),
    };
    let table_key = key("table_kn_per_m");
    if let Some(values) = &w.table_kn_per_m {
        for v in values {
            c.non_negative(&table_key, *v)?;
        }
    }
    let amp_key = key("amplitude_kn_per_m");
    if let Some(a) = w.amplitude_kn_per_m {
        let a = c.non_negative(&amp_key, a)?;
        if a > tension {
            return Err(c.err(
                &amp_key,
                format!(
                    "the tension {} ± {} kN/m would fall below zero: a web cannot push",
                    number_text(tension),
                    number_text(a)
                ),
            ));
        }
    }
    let keys = TimeKeys {
        profile: (&key("profile"), w.profile.as_deref()),
        amplitude: (&amp_key, w.amplitude_kn_per_m.map(along)),
        frequency: (&key("frequency_hz"), w.frequency_hz),
        phase: (&key("phase_deg"), w.phase_deg),
        times: (&key("times_s"), w.times_s.as_deref()),
        table: (
            &table_key,
            w.table_kn_per_m
                .as_ref()
                .map(|v| v.iter().map(|t| along(*t)).collect()),
        ),
    };
    let variation = variation(c, keys, (&tension_key, w.tension_kn_per_m.is_some()))?;
    let (tension, steady) = match (&variation, &w.table_kn_per_m) {
        (Variation::Table { values, .. }, Some(t)) => (1e3 * t[0], values[0]),
        _ => (1e3 * tension, along(tension)),
    };
    Ok(Web {
        name: w.name.clone(),
        roll,
        z: (z0, z1),
        tension,
        wrap: wrap.to_radians(),
        load: LoadHistory { steady, variation },
    })
}
