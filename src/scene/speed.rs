//! The spin speed of a run: the `[speed]` table validated into a [`SpeedProfile`], the
//! prescribed speed Ω(t) [rad/s] and its integral, the roll angle θ(t) [rad].
//!
//! In: the `[speed]` table as written (speeds in Hz, a constant one in Hz or rev/min, times in
//! s). Out: a [`SpeedProfile`] in
//! rad/s and s that gives (θ, Ω, Ω̇) at any time, or an [`InputError`] at the key; a speed above
//! [`MAX_SPEED_HZ`] is an error.
//!
//! Speed profiles (`[speed] profile`): `constant` (`hz`, or `rpm` in rev/min: one of the two);
//! `ramp` from `from_hz` to `to_hz`
//! starting at `ramp_start_s`, ending at `ramp_end_s` or running at `rate_hz_per_s` (a run-up
//! or, with `to_hz` < `from_hz`, a coast-down); `steps` (`times_s`, `steps_hz`); `table`, a
//! measured speed–time table (`times_s`, `table_hz`), linear between its points and constant
//! beyond them. The roll angle θ is the exact integral of Ω (θ(0) = 0: the keyphasor mark). The
//! integrators evaluate θ, Ω and Ω̇ at every stage time, so the step follows a changing speed
//! by the local error test alone (no speed schedule); at a ramp's or table's corner Ω̇ jumps
//! and the error test shortens the step there.

use std::f64::consts::PI;

use super::check::Check;
use super::file::SpeedFile;
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
    /// A speed–time table: linear between the points, `speeds[0]` before the first and the last
    /// speed after the last point.
    Table {
        /// Times [s], strictly ascending.
        times: Vec<f64>,
        /// Speeds [rad/s].
        speeds: Vec<f64>,
        /// θ at each time [rad] (θ(0) = 0), precomputed.
        angles: Vec<f64>,
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
            Self::Table {
                times,
                speeds,
                angles,
            } => {
                let last = times.len() - 1;
                if t <= times[0] {
                    let th0 = angles[0] + speeds[0] * (t - times[0]);
                    return (th0, speeds[0], 0.0);
                }
                if t >= times[last] {
                    return (
                        angles[last] + speeds[last] * (t - times[last]),
                        speeds[last],
                        0.0,
                    );
                }
                // The segment [times[i], times[i + 1]) holding t (t inside, so 0 ≤ i < last).
                let i = times.partition_point(|x| *x <= t) - 1;
                let a = (speeds[i + 1] - speeds[i]) / (times[i + 1] - times[i]);
                let dt = t - times[i];
                (
                    angles[i] + speeds[i] * dt + 0.5 * a * dt * dt,
                    speeds[i] + a * dt,
                    a,
                )
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

    /// The same profile with every speed (and so every angle and acceleration) times `factor`:
    /// a roll driven at equal surface speed through a nip (`factor` = −R_other/R_own, the
    /// minus for the opposite sense of turning).
    pub fn scaled(&self, factor: f64) -> SpeedProfile {
        let times = |v: &[f64]| v.iter().map(|x| x * factor).collect::<Vec<_>>();
        match self {
            Self::Constant(w) => Self::Constant(w * factor),
            Self::Ramp { from, to, t0, t1 } => Self::Ramp {
                from: from * factor,
                to: to * factor,
                t0: *t0,
                t1: *t1,
            },
            Self::Table {
                times: t,
                speeds,
                angles,
            } => Self::Table {
                times: t.clone(),
                speeds: times(speeds),
                angles: times(angles),
            },
            Self::Steps { times: t, speeds } => Self::Steps {
                times: t.clone(),
                speeds: times(speeds),
            },
        }
    }

    /// The speed Ω [rad/s] and roll-angle offset δ [rad] (θ = Ω t + δ) when Ω is constant over
    /// [t0, t1] (a ramp or step that ends before t0 counts); `None` when it changes there.
    pub fn constant_over(&self, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let constant = match self {
            Self::Constant(_) => true,
            Self::Ramp { t0: r0, t1: r1, .. } => *r1 <= t0 || *r0 >= t1,
            Self::Steps { times, .. } => !times.iter().any(|s| *s > t0 && *s < t1),
            Self::Table { times, speeds, .. } => {
                let w0 = self.at(t0).1;
                self.at(t1).1 == w0
                    && times
                        .iter()
                        .zip(speeds)
                        .all(|(t, w)| *t <= t0 || *t >= t1 || *w == w0)
            }
        };
        let (theta, w, _) = self.at(t0);
        constant.then_some((w, theta - w * t0))
    }

    /// A table profile from times [s] and speeds [rad/s] (validated by the caller: as many of
    /// each, times strictly ascending): θ integrated exactly (trapezoids), θ(0) = 0.
    pub fn table(times: Vec<f64>, speeds: Vec<f64>) -> Self {
        // θ at times[0] is the constant speeds[0] integrated from t = 0 (times[0] ≥ 0).
        let mut angles = vec![speeds[0] * times[0]];
        for i in 1..times.len() {
            let prev = angles[i - 1];
            angles.push(prev + 0.5 * (speeds[i - 1] + speeds[i]) * (times[i] - times[i - 1]));
        }
        Self::Table {
            times,
            speeds,
            angles,
        }
    }
}

/// Highest spin speed a scene may ask for, Hz (6 million rpm): far above any rotor this tool
/// models (a tube roll turns below 100 Hz, a turbocharger below 5 kHz), and far below where
/// 2π·f, Ω² and the centrifugal loads overflow (speed.hz = 1e308 was accepted).
pub const MAX_SPEED_HZ: f64 = 1e5;

/// Checks that `speed.times_s` ascends strictly and turns the speeds at `key` [Hz] into rad/s.
fn ascending_speeds(
    c: &Check,
    times: &[f64],
    speeds: &[f64],
    key: &str,
) -> Result<Vec<f64>, InputError> {
    if times
        .windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(c.err("speed.times_s", "must be strictly ascending"));
    }
    speeds
        .iter()
        .enumerate()
        .map(|(i, v)| Ok(2.0 * PI * c.range(&format!("{key}[{i}]"), *v, 0.0, MAX_SPEED_HZ)?))
        .collect()
}

/// The constant profile's speed [rad/s]: `speed.hz`, or `speed.rpm` [rev/min] (not both: the
/// error says what the other is in the unit given, for a `--set` of the wrong one).
fn constant_hz(c: &Check, s: &SpeedFile) -> Result<f64, InputError> {
    let hz = match (s.hz, s.rpm) {
        (Some(hz), Some(rpm)) => {
            return Err(c.err_among(
                &["speed.rpm", "speed.hz"],
                format!(
                    "give speed.hz or speed.rpm, not both: speed.hz = {hz} is {} rpm, speed.rpm \
                     = {rpm} is {} Hz",
                    60.0 * hz,
                    rpm / 60.0
                ),
            ))
        }
        (None, Some(rpm)) => c.range("speed.rpm", rpm, 0.0, 60.0 * MAX_SPEED_HZ)? / 60.0,
        (Some(hz), None) => c.range("speed.hz", hz, 0.0, MAX_SPEED_HZ)?,
        (None, None) => {
            return Err(c.err(
                "speed.hz",
                "missing for this speed profile (or give speed.rpm)",
            ))
        }
    };
    Ok(2.0 * PI * hz)
}

pub(super) fn profile(c: &Check, s: &SpeedFile) -> Result<SpeedProfile, InputError> {
    let hz = |key: &str, v: Option<f64>| -> Result<f64, InputError> {
        let v = v.ok_or_else(|| c.err(key, "missing for this speed profile"))?;
        Ok(2.0 * PI * c.range(key, v, 0.0, MAX_SPEED_HZ)?)
    };
    if s.rpm.is_some() && s.profile != "constant" {
        return Err(c.err(
            "speed.rpm",
            format!(
                "only for the constant profile: a {} profile's speeds are in Hz (1 Hz = 60 rpm)",
                s.profile
            ),
        ));
    }
    match s.profile.as_str() {
        "constant" => Ok(SpeedProfile::Constant(constant_hz(c, s)?)),
        "ramp" => {
            let t0 = c.non_negative("speed.ramp_start_s", s.ramp_start_s.unwrap_or(0.0))?;
            let from = hz("speed.from_hz", s.from_hz)?;
            let to = hz("speed.to_hz", s.to_hz)?;
            let t1 = match (s.ramp_end_s, s.rate_hz_per_s) {
                (Some(t1), None) => t1,
                (None, Some(rate)) => {
                    let rate = c.range("speed.rate_hz_per_s", rate, 1e-9, MAX_SPEED_HZ)?;
                    if from == to {
                        return Err(c.err("speed.rate_hz_per_s", "needs from_hz ≠ to_hz"));
                    }
                    t0 + (to - from).abs() / (2.0 * PI * rate)
                }
                (Some(_), Some(_)) => {
                    return Err(c.err(
                        "speed.rate_hz_per_s",
                        "give either speed.ramp_end_s or speed.rate_hz_per_s, not both",
                    ))
                }
                (None, None) => {
                    return Err(c.err(
                        "speed.ramp_end_s",
                        "missing for a ramp (or give speed.rate_hz_per_s)",
                    ))
                }
            };
            if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
                return Err(c.err("speed.ramp_end_s", "must be after speed.ramp_start_s"));
            }
            Ok(SpeedProfile::Ramp { from, to, t0, t1 })
        }
        "table" => {
            let times = s
                .times_s
                .clone()
                .ok_or_else(|| c.err("speed.times_s", "missing for a table"))?;
            let speeds = s
                .table_hz
                .clone()
                .ok_or_else(|| c.err("speed.table_hz", "missing for a table"))?;
            if times.len() < 2 || times.len() != speeds.len() {
                return Err(c.err(
                    "speed.times_s",
                    "needs at least two entries, as many as speed.table_hz",
                ));
            }
            for (i, t) in times.iter().enumerate() {
                c.range(&format!("speed.times_s[{i}]"), *t, 0.0, 1e9)?;
            }
            let sp = ascending_speeds(c, &times, &speeds, "speed.table_hz")?;
            Ok(SpeedProfile::table(times, sp))
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
            let sp = ascending_speeds(c, &times, &speeds, "speed.steps_hz")?;
            Ok(SpeedProfile::Steps { times, speeds: sp })
        }
        other => Err(c.err(
            "speed.profile",
            format!("`{other}`: expected constant, ramp, steps or table"),
        )),
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
