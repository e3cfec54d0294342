//! Numbers as text, the one way rotorsweep writes them: in reports, in the analysis's labels and
//! in the parameter texts stored with each job.
//!
//! In: an `f64` (any unit). Out: its text: [`number_text`] in the shortest round-trip form
//! (`1e-4` rather than `0.0001`, `16.4` as written), [`significant`] to a number of significant
//! digits; both scientific below 1e-3 and from 1e6.

/// A parameter's value as text, the one way the report and the analysis write numbers: `1e-4`
/// rather than `0.0001`, `16.4` as written (shortest round-trip form; scientific below 1e-3 and
/// from 1e6, as [`significant`]).
pub fn number_text(x: f64) -> String {
    if scientific(x) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Whether a number is written in scientific notation: nonzero and below 1e-3 or from 1e6 in
/// magnitude.
pub fn scientific(x: f64) -> bool {
    x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6)
}

/// A measured value to `sig` significant digits (scientific below 1e-3 and from 1e6, as
/// [`number_text`]).
pub fn significant(x: f64, sig: usize) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let mag = x.abs().log10().floor();
    if !(-3.0..6.0).contains(&mag) {
        return format!("{x:.*e}", sig - 1);
    }
    let decimals = (sig as f64 - 1.0 - mag).max(0.0) as usize;
    format!("{x:.decimals$}")
}
