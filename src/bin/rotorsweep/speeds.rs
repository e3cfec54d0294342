//! Spin speeds given on the command line, range-checked where they enter: `--speed-hz F` and
//! `--max-speed-hz F` [Hz], and `--speeds START:STOP:COUNT` in Hz or, with a trailing `rpm`, in
//! revolutions per minute (`--speeds "0:6000:101 rpm"`).
//!
//! In: the option's name and value. Out: the speeds in Hz, or a message naming the option and
//! what is wrong with it. Method: every speed finite and within [0, `MAX_SPEED_HZ`] (the
//! scene's own limit, 1e5 Hz: at 1e308 Hz the eigen-solver was handed Ω² = inf and only said
//! that it did not converge); the sweep's form is the library's `parse_speeds`.

use rotorsweep::linear::request;
use rotorsweep::scene::MAX_SPEED_HZ;
use rotorsweep::text::number_text;

/// A speed [Hz] of option `flag`: finite and within [0, [`MAX_SPEED_HZ`]].
pub fn hz(flag: &str, v: f64) -> Result<f64, String> {
    if (0.0..=MAX_SPEED_HZ).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "--{flag} {}: a spin speed must lie in [0, {MAX_SPEED_HZ}] Hz ({} rpm)",
            number_text(v),
            60.0 * MAX_SPEED_HZ
        ))
    }
}

/// The speeds [Hz] of `--speeds START:STOP:COUNT`, in Hz or with a trailing `rpm` in rev/min
/// (a trailing `hz` is allowed too).
pub fn sweep(text: &str) -> Result<Vec<f64>, String> {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    let (body, per_hz) = if let Some(b) = lower.strip_suffix("rpm") {
        (&t[..b.len()], 60.0)
    } else if let Some(b) = lower.strip_suffix("hz") {
        (&t[..b.len()], 1.0)
    } else {
        (t, 1.0)
    };
    let speeds = request::parse_speeds(body.trim())
        .map_err(|e| format!("--{e} (or in rev/min: `START:STOP:COUNT rpm`)"))?;
    let speeds: Vec<f64> = speeds.iter().map(|s| s / per_hz).collect();
    let top = speeds.last().copied().unwrap_or(0.0);
    if top > MAX_SPEED_HZ {
        return Err(format!(
            "--speeds `{text}`: STOP is {} Hz, above the spin speed limit of {MAX_SPEED_HZ} Hz \
             ({} rpm)",
            number_text(top),
            60.0 * MAX_SPEED_HZ
        ));
    }
    Ok(speeds)
}

/// A speed as the tables print it: Hz, then rev/min beside it.
pub fn with_rpm(hz: f64) -> String {
    format!("{hz:7.2} Hz ({:8.1} rpm)", 60.0 * hz)
}
