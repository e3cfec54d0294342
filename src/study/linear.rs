//! A study's `[linear]` table as the linear stage's request.
//!
//! In: `[linear]` (module doc of [`crate::linear::request`]): `speeds` `START:STOP:COUNT` [Hz]
//! (default [`LINEAR_SPEEDS`]), `max_freq_hz` and `floquet_cutoff_hz` [Hz], `unbalance`
//! `MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM`, and the switches of the optional analyses. Out: a
//! [`Request`]; errors name the key of a malformed speed range or unbalance, or a frequency that
//! is not positive.

use super::context::Ctx;
use super::file::LinearFile;
use crate::error::InputError;
use crate::linear::request::{parse_speeds, PointUnbalance, Request};

/// The default speeds of a study's linear analyses [Hz] (the `modes` command's default range).
pub const LINEAR_SPEEDS: &str = "0:100:201";

/// The `[linear]` table as a request, its values checked.
pub(super) fn linear_request(c: &Ctx, l: &LinearFile) -> Result<Request, InputError> {
    let positive = |key: &str, v: Option<f64>| match v {
        Some(f) if !(f.is_finite() && f > 0.0) => Err(c.err(key, "must be a positive frequency")),
        _ => Ok(v),
    };
    Ok(Request {
        speeds_hz: parse_speeds(l.speeds.as_deref().unwrap_or(LINEAR_SPEEDS))
            .map_err(|e| c.err("linear.speeds", e))?,
        max_freq_hz: positive("linear.max_freq_hz", l.max_freq_hz)?,
        unbalance: l
            .unbalance
            .as_deref()
            .map(PointUnbalance::parse)
            .transpose()
            .map_err(|e| c.err("linear.unbalance", e))?,
        response: l.unbalance_response,
        floquet: l.floquet,
        floquet_cutoff_hz: positive("linear.floquet_cutoff_hz", l.floquet_cutoff_hz)?,
        statics: l.statics,
        critical_map: l.critical_map,
        shapes: l.shapes,
    })
}
