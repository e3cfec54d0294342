//! The error classes of the stability matrix and their colours.
//!
//! In: a job's status and its max runout error against the reference [µm]. Out: its class
//! ([`error_class`]): the status when the job did not end ok, `no reference` without an error,
//! else the decade of the error; and each class's background colour in the HTML stability
//! matrix ([`CLASS_COLOURS`]; their order ranks them: a matrix cell of several jobs takes the
//! class that comes last). `scripts/plots.py` colours its stability figure by the same classes
//! and colours.

/// Background colour of each class of [`error_class`] in the HTML stability matrix (the same as
/// `scripts/plots.py`'s).
pub(crate) const CLASS_COLOURS: [(&str, &str); 8] = [
    ("< 1 µm", "#a5d6a7"),
    ("1–10 µm", "#fff59d"),
    ("10–100 µm", "#ffcc80"),
    ("≥ 100 µm", "#ef9a9a"),
    ("no reference", "#b3e5fc"),
    ("untrusted", "#80cbc4"),
    ("diverged", "#ce93d8"),
    ("budget", "#bdbdbd"),
];

/// The class of a job's outcome, by which the stability matrix is coloured: its status when it
/// did not end ok (`untrusted`, `diverged`, `budget`), `no reference` without an error against one, else the decade of its max
/// runout error: `< 1 µm`, `1–10 µm`, `10–100 µm`, `≥ 100 µm` (a runout of a paper roll is
/// specified to a few µm: from 10 µm on a solver's error is as large as what is measured, from
/// 100 µm the run is wrong whatever its status). `scripts/plots.py` uses the same classes.
pub fn error_class(status: &str, error_max_um: f64) -> &str {
    match status {
        "ok" if !error_max_um.is_finite() => "no reference",
        "ok" if error_max_um < 1.0 => "< 1 µm",
        "ok" if error_max_um < 10.0 => "1–10 µm",
        "ok" if error_max_um < 100.0 => "10–100 µm",
        "ok" => "≥ 100 µm",
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_classes_by_decade() {
        // The case: an ok job 1.2e4 µm off is in the worst class, not "ok".
        assert_eq!(error_class("ok", 1.2e4), "≥ 100 µm");
        assert_eq!(error_class("ok", 0.5), "< 1 µm");
        assert_eq!(error_class("ok", 5.0), "1–10 µm");
        assert_eq!(error_class("ok", 50.0), "10–100 µm");
        assert_eq!(error_class("ok", f64::NAN), "no reference");
        assert_eq!(error_class("diverged", 0.1), "diverged");
    }
}
