//! Numbers as text, the one way rotorsweep writes them: in reports, in the analysis's labels and
//! in the parameter texts stored with each job.
//!
//! In: an `f64` (any unit). Out: its text: [`number_text`] in the shortest round-trip form
//! (`1e-4` rather than `0.0001`, `16.4` as written), [`significant`] to a number of significant
//! digits; both scientific below 1e-3 and from 1e6. Also the unit and axis names of a result
//! read back from a saved run ([`static_name`]), which the result types hold as `&'static str`.

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

/// How many distinct names [`static_name`] keeps: a run's results use a few dozen (units, axis
/// names); more means the saved run it reads is not one of rotorsweep's.
const MAX_STATIC: usize = 1024;

/// A name the result types hold as `&'static str` (a unit, an axis name), read back from a
/// saved run: each distinct name is allocated once for the life of the program and shared by
/// every result read back (bounded: more than [`MAX_STATIC`] distinct names is an error).
pub fn static_name(s: String) -> Result<&'static str, String> {
    use std::collections::BTreeSet;
    use std::sync::Mutex;
    static KEPT: Mutex<BTreeSet<&'static str>> = Mutex::new(BTreeSet::new());
    let mut kept = KEPT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(k) = kept.get(s.as_str()) {
        return Ok(k);
    }
    if kept.len() >= MAX_STATIC {
        return Err(format!(
            "more than {MAX_STATIC} distinct unit or axis names"
        ));
    }
    let k: &'static str = Box::leak(s.into_boxed_str());
    kept.insert(k);
    Ok(k)
}
