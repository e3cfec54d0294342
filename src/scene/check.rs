//! The validation context of one scene: every value is checked where it is read, and an error
//! names the key and the line of the file that wrote it.
//!
//! In: the scene's [`Source`] (its files and where each key is written) and the keys set on the
//! command line (`--set`). Out: the checked value, unchanged (units are converted by the
//! caller), or an [`InputError`] at the key: in the file and line that wrote it, or at
//! `<command line --set>` when an override set it (of several keys that must go together, the
//! one an override set). Method: range checks (positive, zero or
//! positive, finite, within bounds, a count) and axial positions ([`Position`]) resolved on a
//! [`Frame`] in mm.

use std::path::Path;

use super::position::{Frame, Position};
use super::source::Source;
use crate::error::InputError;
use crate::text::number_text;

/// The dimensions a body may have [mm] ([`Check::size_mm`]).
pub(super) const SIZE_MM: (f64, f64) = (1e-3, 1e6);

/// Checks values and reports errors at their key and line, in the file that wrote the key.
pub(super) struct Check<'a> {
    pub file: &'a Path,
    pub source: &'a Source,
    pub overridden: &'a [String],
}

impl Check<'_> {
    pub(super) fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        if self.overridden.iter().any(|k| key.starts_with(k.as_str())) {
            return InputError::new(Path::new(super::overrides::COMMAND_LINE), reason)
                .with_key(key);
        }
        self.source.err(key, reason)
    }

    /// An error about how the values of several `keys` go together (a wall that does not fit
    /// the tube): at the first of them a `--set` override gave, else at the first key. So an
    /// override that breaks a relation with a file's value is blamed on the override.
    pub(super) fn err_among(&self, keys: &[&str], reason: impl Into<String>) -> InputError {
        let set = |k: &str| self.overridden.iter().any(|o| k.starts_with(o.as_str()));
        let key = keys.iter().copied().find(|k| set(k)).unwrap_or(keys[0]);
        self.err(key, reason)
    }

    /// An axial position (`position.rs`) in mm on the scene's axis.
    pub(super) fn position(
        &self,
        key: &str,
        p: &Position,
        frame: &Frame,
    ) -> Result<f64, InputError> {
        p.mm(frame).map_err(|r| self.err(key, r))
    }

    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("must be a positive number, got {}", number_text(v)),
            ))
        }
    }

    pub(super) fn non_negative(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("must be zero or positive, got {}", number_text(v)),
            ))
        }
    }

    pub(super) fn finite(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("must be a finite number, got {}", number_text(v)),
            ))
        }
    }

    pub(super) fn range(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, InputError> {
        if v.is_finite() && v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!(
                    "must lie in [{}, {}], got {}",
                    number_text(lo),
                    number_text(hi),
                    number_text(v)
                ),
            ))
        }
    }

    /// A body's dimension [mm] (a length, diameter or wall): within [`SIZE_MM`]. Smaller or
    /// larger ones are not a machine's: the element matrices lose their rank (a head of 1e-9
    /// mm left the reduction without its rigid modes) or overflow.
    pub(super) fn size_mm(&self, key: &str, v: f64) -> Result<f64, InputError> {
        let (lo, hi) = SIZE_MM;
        if v.is_finite() && (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!(
                    "must be a positive size in [{lo}, {hi:e}] mm (1 µm to 1 km), got {}",
                    number_text(v)
                ),
            ))
        }
    }

    /// A node the rotor names (`named`: its named points), as the key `key` gives it.
    pub(super) fn node(&self, key: &str, n: &str, named: &[&str]) -> Result<String, InputError> {
        if named.contains(&n) {
            Ok(n.to_string())
        } else {
            Err(self.err(
                key,
                format!("unknown node `{n}` (named nodes: {})", named.join(", ")),
            ))
        }
    }

    pub(super) fn count(
        &self,
        key: &str,
        v: usize,
        lo: usize,
        hi: usize,
    ) -> Result<usize, InputError> {
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be an integer in [{lo}, {hi}], got {v}")))
        }
    }
}
