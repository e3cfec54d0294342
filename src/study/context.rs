//! Where a study's errors point: the study file, the line of the key, the key.
//!
//! In: the study file's path and text, a dotted key of the study (`axes[1].values`,
//! `reference.solver.rtol`) and a reason. Out: an [`InputError`] naming the file, the key and
//! (when the key is found in the text) its line. Also the key a scene error raised by a job's
//! overrides is about ([`override_key`]).

use std::path::Path;

use crate::error::InputError;
use crate::scene::locate;

/// The study file being loaded, for its errors.
pub(super) struct Ctx<'a> {
    pub(super) path: &'a Path,
    pub(super) text: &'a str,
}

impl Ctx<'_> {
    pub(super) fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        let e = InputError::new(self.path, reason).with_key(key);
        match locate::line_of(self.text, key) {
            Some(l) => e.at_line(l),
            None => e,
        }
    }
}

/// The dotted key a scene error from overrides is about: its own key, or (for an unknown field,
/// whose key is the table) the override whose last part the reason names.
pub(super) fn override_key(e: &InputError, overrides: &[(String, toml::Value)]) -> String {
    e.key.clone().unwrap_or_else(|| {
        overrides
            .iter()
            .map(|(k, _)| k.as_str())
            .find(|k| {
                e.reason
                    .contains(&format!("`{}`", k.rsplit('.').next().unwrap_or(k)))
            })
            .unwrap_or_default()
            .to_string()
    })
}
